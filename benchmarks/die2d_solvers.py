#!/usr/bin/env python3
"""Direct against iterative linear solvers on die2d N1 (the default deck:
Newtonian, contact with Coulomb friction) at growing sizes: wall time, the
linear-solve share, peak memory, Newton iterations, linear solves and Krylov
iterations per size, the fitted growth exponent of wall time against
unknowns for each method, and the crossover (the first size at which the
iterative method is faster), if any.

  direct:    the penalty method (lambda = 1e7 eta), CHOLMOD/UMFPACK
  iterative: degree 1, the augmented Lagrangian (r = 1e3 x cell
             viscosity), AMG-preconditioned CG/GMRES; degree 2, the mixed
             form by GMRES with the block-triangular AMG / pressure-mass
             preconditioner (one AMG V-cycle on the velocity block); both
             fall back to direct where they fail
  inner:     degree 2, the same with an inner Krylov solve of the velocity
             block (Velocity block = inner solve) and flexible GMRES

Each run is a process of its own (peak memory is that run's) with a time
limit; a method that exceeds it at one size is not run at the larger ones.
The methods take turns at each size (direct, iterative, then the next
size), so that a machine whose speed drifts during the study (a shared
one) slows both alike and the crossover compares like with like.

    benchmarks/die2d_solvers.py [--across 24,48,96,144,212] [--limit 900]
                                [--degree 1] [--methods direct,iterative]
                                [--nested] [--extra 'deck text']
                                [--program build/dieflow]

(--extra: entries appended to the deck, e.g. another material, penalty or
friction, for the iteration-count tables. --nested: each size is run as
two cycles, half the cells across and then its global refinement, so that
the fine mesh starts from the coarse answer; the figures are those of the
whole run, the unknowns the fine mesh's.)

Its per decade: the Krylov iterations over the decades by which the
iterative (degree 2) solves reduced their residuals (summary.json's
residual_decades): the preconditioner's rate, which the forcing term does
not change (later Newton solves ask more decades on finer meshes).

Memory is also given per unknown (peak KB per unknown, KB = 1024 bytes,
as the kernel counts it). The growth exponent is
fitted to the sizes from 40,000 unknowns on, where set-up costs no longer
dominate.

Not a test: the figures depend on the machine, which the report names.
"""
import argparse, math, os, re, time

from die2d_levels import machine, run_die2d


def run(program, base, across, method, limit):
    start = time.time()
    entries = {"inner": " set Method = iterative\n set Velocity block = inner solve\n"}.get(
        method, " set Method = %s\n" % method)
    result = run_die2d(program, base, across, "subsection Linear solver\n" + entries + "end\n", limit)
    if result is None:
        return None
    status, s = result
    cycles = s["cycles"]
    c = cycles[-1]
    total = lambda key: sum(k["linear_solver"].get(key, 0) for k in cycles)
    return dict(status=status, dofs=c["dofs"], its=sum(k["nonlinear_iterations"] for k in cycles),
                solves=sum(k["linear_solves"] for k in cycles), krylov=total("krylov_iterations"),
                inner=total("inner_iterations"), decades=total("residual_decades"), fallbacks=total("direct_fallbacks"),
                partial=total("partial_steps"), wall=time.time() - start,
                solve=s["stage_wall_time"].get("linear solve", 0), memory=s["peak_memory_mb"],
                ram=c["boundary_force"]["1"][0], div=c["divergence_ratio"])


def exponent(rows, from_dofs=40000):
    """Least-squares slope of log(wall) against log(dofs) over the sizes
    from @p from_dofs on, and how many sizes that is."""
    rows = [r for r in rows if r["dofs"] >= from_dofs]
    if len(rows) < 2:
        return float("nan"), len(rows)
    x = [math.log(r["dofs"]) for r in rows]
    y = [math.log(r["wall"]) for r in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x), len(rows)


def ungraded_die2d(root, degree, extra="", cycles=1, layout="blocks"):
    """The default deck as doc/benchmarks.md measured the solvers: the
    built-in mesh without corner grading, its blocks joined as @p layout
    says, velocity degree @p degree, plus
    the deck text @p extra; one mesh per run, or @p cycles meshes, each the
    global refinement of the one before."""
    # The deck refuses an entry set twice: the entries set here and in
    # extra leave the default deck first.
    own = {"Corner refinements", "Velocity degree", "Cycles", "Strategy", "Cells across", "Layout", "Output directory",
           "Write VTU"}
    own |= set(re.findall(r"set\s+([^=\n]+?)\s*=", extra))
    base = "".join(line for line in open(os.path.join(root, "parameters", "die2d-held-land.prm")).readlines()
                   if not any(re.match(r"\s*set\s+%s\s*=" % re.escape(key), line) for key in own))
    return base + ("\nsubsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Layout = %s\n"
                   "  end\nend\nsubsection Discretisation\n  set Velocity degree = %d\nend\n"
                   "subsection Refinement\n  set Cycles = %d\n  set Strategy = global\nend\n" % (layout, degree, cycles)) + extra


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    parser = argparse.ArgumentParser()
    parser.add_argument("--across", default="24,48,96,144,212")
    parser.add_argument("--limit", type=float, default=900)
    parser.add_argument("--program", default=os.path.join(root, "build", "dieflow"))
    parser.add_argument("--degree", type=int, default=1)
    parser.add_argument("--methods", default="direct,iterative")
    parser.add_argument("--extra", default="")
    parser.add_argument("--nested", action="store_true")
    # blocks: the layout of the tables before 2026-11-29; bisected: the
    # deck's default, whose cells at the die corners are not flattened.
    parser.add_argument("--layout", default="blocks", choices=("blocks", "bisected"))
    args = parser.parse_args()
    base = ungraded_die2d(root, args.degree, args.extra.replace("\\n", "\n") + "\n", 2 if args.nested else 1, args.layout)

    print("die2d N1 (Newtonian, contact with Coulomb friction), velocity degree %d, layout %s, %s" % (
        args.degree, args.layout, "two cycles per run: half the cells across, then refined globally" if args.nested else
        "one mesh per run"))
    if args.extra:
        print("deck additions: " + args.extra)
    print("machine: " + machine())
    print()
    print("| method | cells across | dofs | exit | Newton its | linear solves | Krylov its | its per decade | inner its | direct fallbacks "
          "| partial steps | wall [s] | linear solve [s] | peak memory [MB] | KB per unknown | ram force [N/mm] "
          "| divergence ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    results = {m: {} for m in args.methods.split(",")}
    stopped = set()
    for across in [int(a) for a in args.across.split(",")]:
        for method in results:
            if method in stopped:
                continue
            r = run(args.program, base, across // 2 if args.nested else across, method, args.limit)
            if r is None:
                print("| %s | %d | | over %.0f s | | | | | | | | | | | | | |" % (method, across, args.limit), flush=True)
                stopped.add(method)
                continue
            results[method][across] = r
            rate = "%.2f" % (r["krylov"] / r["decades"]) if r["decades"] > 0 else "-"
            print("| %s | %d | %d | %d | %d | %d | %d | %s | %d | %d | %d | %.2f | %.2f | %.0f | %.2f | %.2f | %.1e |" % (
                method, across, r["dofs"], r["status"], r["its"], r["solves"], r["krylov"], rate, r["inner"], r["fallbacks"],
                r["partial"], r["wall"], r["solve"], r["memory"], 1024 * r["memory"] / r["dofs"],
                r["ram"], r["div"]), flush=True)
    print()
    for method, rows in results.items():
        print("%s: wall time grows as N^%.2f over the %d sizes from 40,000 unknowns" % (
            (method,) + exponent(list(rows.values()))))
    for method in [m for m in results if m != "direct"]:
        both = [a for a in results[method] if a in results.get("direct", {})]
        crossover = [results[method][a]["dofs"] for a in both if results[method][a]["wall"] < results["direct"][a]["wall"]]
        print("crossover, %s: " % method + ("faster than direct from %d dofs" % crossover[0] if crossover else
                                            "none: the direct method is faster at every size both ran"))


if __name__ == "__main__":
    main()
