#!/usr/bin/env python3
"""Assembly on one thread against two: die2d N1 (the default deck's
material and contact, velocity degree 2, the built-in mesh without corner
grading, one mesh per run, direct solver) at the sizes given, each run
repeated and the fastest kept. Prints per thread count the stage wall
times of summary.json: assembly (the flow cells and the Newton residuals,
deal.II's WorkStream), contact (the contact elements and the nodal
residual they need), postprocess (forces, Kelly), and the speed-up of each,
and checks that the results are bitwise the same (the ram force and every
die force to all digits summary.json writes).

    benchmarks/threads.py [--across 32,64,128] [--repeat 3] [--program build/dieflow]

The thread count is set through DEAL_II_NUM_THREADS (threads.h). Not a
test: the figures depend on the machine, which the report names.
"""
import argparse, os

from die2d_levels import machine, run_die2d
from die2d_solvers import ungraded_die2d


def run(program, base, across, threads):
    os.environ["DEAL_II_NUM_THREADS"] = str(threads)
    status, s = run_die2d(program, base, across)
    c = s["cycles"][-1]
    results = (c["boundary_force"], c["die_normal_force"], c["die_friction_force"], c["nonlinear_iterations"])
    return status, s["threads"], c["dofs"], s["stage_wall_time"], s["wall_time"], results


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    parser = argparse.ArgumentParser()
    parser.add_argument("--across", default="32,64,128")
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--program", default=os.path.join(root, "build", "dieflow"))
    args = parser.parse_args()
    base = ungraded_die2d(root, 2)

    print("die2d N1, velocity degree 2, direct solver, one mesh per run; fastest of %d runs" % args.repeat)
    print("machine: " + machine())
    print()
    stages = ["assembly", "contact", "postprocess"]
    print("| cells across | dofs | threads | " + " | ".join("%s [s]" % s for s in stages) +
          " | wall [s] | same results (every digit of summary.json) |")
    print("|---|---|---|" + "---|" * len(stages) + "---|---|")
    for across in [int(a) for a in args.across.split(",")]:
        best, reference = {}, None
        for threads in (1, 2):
            runs = [run(args.program, base, across, threads) for _ in range(args.repeat)]
            status, used, dofs, _, _, results = runs[0]
            times = {s: min(r[3].get(s, 0) for r in runs) for s in stages}
            times["wall"] = min(r[4] for r in runs)
            best[threads] = times
            same = all(r[5] == results for r in runs) and (reference is None or results == reference)
            reference = reference or results
            print("| %d | %d | %d | " % (across, dofs, used) + " | ".join("%.3f" % times[s] for s in stages) +
                  " | %.2f | %s |" % (times["wall"], "yes" if same and status == 0 else "NO"), flush=True)
        print("| | | speed-up | " + " | ".join("%.2f" % (best[1][s] / best[2][s]) for s in stages) +
              " | %.2f | |" % (best[1]["wall"] / best[2]["wall"]))


if __name__ == "__main__":
    main()
