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
limit; an iterative size that exceeds it ends the iterative series.

    benchmarks/die2d_solvers.py [--across 24,48,96,144,212] [--limit 900]
                                [--degree 1] [--methods direct,iterative]
                                [--extra 'deck text'] [--program build/dieflow]

(--extra: entries appended to the deck, e.g. another material, penalty or
friction, for the iteration-count tables.)

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
    c = s["cycles"][0]
    return dict(status=status, dofs=c["dofs"], its=c["nonlinear_iterations"], solves=c["linear_solves"],
                krylov=c["linear_solver"]["krylov_iterations"],
                inner=c["linear_solver"].get("inner_iterations", 0), fallbacks=c["linear_solver"]["direct_fallbacks"],
                wall=time.time() - start, solve=s["stage_wall_time"].get("linear solve", 0),
                memory=s["peak_memory_mb"], ram=c["boundary_force"]["1"][0], div=c["divergence_ratio"])


def exponent(rows):
    """Least-squares slope of log(wall) against log(dofs)."""
    if len(rows) < 2:
        return float("nan")
    x = [math.log(r["dofs"]) for r in rows]
    y = [math.log(r["wall"]) for r in rows]
    mx, my = sum(x) / len(x), sum(y) / len(y)
    return sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)


def ungraded_die2d(root, degree, extra=""):
    """The default deck as doc/benchmarks.md measured the solvers: the
    built-in mesh without corner grading, one mesh per run, velocity degree
    @p degree, plus the deck text @p extra."""
    # The deck refuses an entry set twice: the entries set here and in
    # extra leave the default deck first.
    own = {"Corner refinements", "Velocity degree", "Cycles", "Cells across", "Layout", "Output directory", "Write VTU"}
    own |= set(re.findall(r"set\s+([^=\n]+?)\s*=", extra))
    base = "".join(line for line in open(os.path.join(root, "parameters", "die2d.prm")).readlines()
                   if not any(re.match(r"\s*set\s+%s\s*=" % re.escape(key), line) for key in own))
    return base + ("\nsubsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Layout = blocks\n"
                   "  end\nend\nsubsection Discretisation\n  set Velocity degree = %d\nend\n"
                   "subsection Refinement\n  set Cycles = 1\nend\n" % degree) + extra


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
    args = parser.parse_args()
    base = ungraded_die2d(root, args.degree, args.extra.replace("\\n", "\n") + "\n")

    print("die2d N1 (Newtonian, contact with Coulomb friction), velocity degree %d, one mesh per run" % args.degree)
    if args.extra:
        print("deck additions: " + args.extra)
    print("machine: " + machine())
    print()
    print("| method | cells across | dofs | exit | Newton its | linear solves | Krylov its | inner its | direct fallbacks "
          "| wall [s] | linear solve [s] | peak memory [MB] | ram force [N/mm] | divergence ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    results = {m: [] for m in args.methods.split(",")}
    for method in results:
        for across in [int(a) for a in args.across.split(",")]:
            r = run(args.program, base, across, method, args.limit)
            if r is None:
                print("| %s | %d | | over %.0f s | | | | | | | | | | |" % (method, across, args.limit), flush=True)
                break
            results[method].append(r)
            print("| %s | %d | %d | %d | %d | %d | %d | %d | %d | %.2f | %.2f | %.0f | %.2f | %.1e |" % (
                method, across, r["dofs"], r["status"], r["its"], r["solves"], r["krylov"], r["inner"], r["fallbacks"],
                r["wall"], r["solve"], r["memory"], r["ram"], r["div"]), flush=True)
    print()
    for method, rows in results.items():
        print("%s: wall time grows as N^%.2f over %d sizes" % (method, exponent(rows), len(rows)))
    for method in [m for m in results if m != "direct"]:
        crossover = [i["dofs"] for d, i in zip(results.get("direct", []), results[method]) if i["wall"] < d["wall"]]
        print("crossover, %s: " % method + ("faster than direct from %d dofs" % crossover[0] if crossover else
                                            "none: the direct method is faster at every size both ran"))


if __name__ == "__main__":
    main()
