#!/usr/bin/env python3
"""Direct against iterative linear solvers on die2d N1 (the default deck:
Newtonian, contact with Coulomb friction) at growing sizes: wall time, the
linear-solve share, peak memory, Newton iterations, linear solves and Krylov
iterations per size, the fitted growth exponent of wall time against
unknowns for each method, and the crossover (the first size at which the
iterative method is faster), if any.

  direct:    the penalty method (lambda = 1e7 eta), CHOLMOD/UMFPACK
  iterative: the augmented Lagrangian (r = 1e3 x cell viscosity), AMG-
             preconditioned CG/GMRES, falling back to direct where it fails

Each run is a process of its own (peak memory is that run's) with a time
limit; an iterative size that exceeds it ends the iterative series.

    benchmarks/die2d_solvers.py [--across 24,48,96,144,212] [--limit 900]
                                [--program build/dieflow]

Not a test: the figures depend on the machine, which the report names.
"""
import argparse, math, os, time

from die2d_levels import machine, run_die2d


def run(program, base, across, method, limit):
    start = time.time()
    result = run_die2d(program, base, across, "subsection Linear solver\n set Method = %s\nend\n" % method, limit)
    if result is None:
        return None
    status, s = result
    c = s["cycles"][0]
    return dict(status=status, dofs=c["dofs"], its=c["nonlinear_iterations"], solves=c["linear_solves"],
                krylov=c["linear_solver"]["krylov_iterations"], fallbacks=c["linear_solver"]["direct_fallbacks"],
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


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    parser = argparse.ArgumentParser()
    parser.add_argument("--across", default="24,48,96,144,212")
    parser.add_argument("--limit", type=float, default=900)
    parser.add_argument("--program", default=os.path.join(root, "build", "dieflow"))
    args = parser.parse_args()
    base = open(os.path.join(root, "parameters", "die2d.prm")).read()
    # What doc/benchmarks.md measured: the degree-1 deck on the old built-in
    # mesh (the default deck now grades its corners and takes degree 2).
    base += "\nsubsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Layout = blocks\n  end\nend\nsubsection Discretisation\n  set Velocity degree = 1\nend\n"

    print("die2d N1 (Newtonian, contact with Coulomb friction), one mesh per run")
    print("machine: " + machine())
    print()
    print("| method | cells across | dofs | exit | Newton its | linear solves | Krylov its | direct fallbacks "
          "| wall [s] | linear solve [s] | peak memory [MB] | ram force [N/mm] | divergence ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    results = {"direct": [], "iterative": []}
    for method in ("direct", "iterative"):
        for across in [int(a) for a in args.across.split(",")]:
            r = run(args.program, base, across, method, args.limit)
            if r is None:
                print("| %s | %d | | over %.0f s | | | | | | | | | |" % (method, across, args.limit), flush=True)
                break
            results[method].append(r)
            print("| %s | %d | %d | %d | %d | %d | %d | %d | %.2f | %.2f | %.0f | %.2f | %.1e |" % (
                method, across, r["dofs"], r["status"], r["its"], r["solves"], r["krylov"], r["fallbacks"],
                r["wall"], r["solve"], r["memory"], r["ram"], r["div"]), flush=True)
    print()
    for method, rows in results.items():
        print("%s: wall time grows as N^%.2f over %d sizes" % (method, exponent(rows), len(rows)))
    crossover = [i["dofs"] for d, i in zip(results["direct"], results["iterative"]) if i["wall"] < d["wall"]]
    print("crossover: " + ("iterative faster from %d dofs" % crossover[0] if crossover else
                           "none: the direct method is faster at every size both ran"))


if __name__ == "__main__":
    main()
