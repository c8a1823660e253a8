#!/usr/bin/env python3
"""The genuinely 3D die (parameters/rectbar3d.prm, degree 2) at growing mesh
sizes, with the direct and the iterative linear solver: unknowns, wall time,
linear-solve time, peak memory, Newton iterations and the ram force F_x[1],
and the ram force extrapolated from the three finest sizes (Richardson with
the observed order, cells across doubling), against which each size's error
is given.

    python3 benchmarks/rectbar3d.py [--program build/dieflow] [--across 4 8 16] [--direct-limit 60000]

Cells in depth is half of Cells across (the bar is about half as wide as
high). The direct solver is run up to --direct-limit unknowns (its 3D
factorisation grows far faster than the iterative solver's memory).
Not a test: the times are this machine's (run one benchmark at a time).
"""
import argparse, math, os, platform, tempfile

from deck_variant import run_variant


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default="build/dieflow")
    parser.add_argument("--across", type=int, nargs="+", default=[4, 8, 16])
    parser.add_argument("--direct-limit", type=int, default=60000)
    args = parser.parse_args()
    print("machine:", platform.processor() or platform.machine(), os.cpu_count(), "cores")
    print()
    print("| cells across x depth | unknowns | solver | wall time [s] | linear solves [s] | peak memory [MB] "
          "| Newton its | F_x[1] [N] |")
    print("|---|---|---|---|---|---|---|---|")
    finest = {}
    for across in args.across:
        size = {"Cells across": "%d" % across, "Cells in depth": "%d" % max(1, across // 2)}
        methods = ["iterative", "direct"]
        for method in methods:
            if method == "direct" and across in finest and finest[across]["dofs"] > args.direct_limit:
                print("| %d x %d | %d | direct | (skipped: above %d unknowns) | | | | |"
                      % (across, max(1, across // 2), finest[across]["dofs"], args.direct_limit))
                continue
            # "Method" names the nonlinear solver's entry too: replace the linear solver's line only.
            with tempfile.NamedTemporaryFile("w", suffix=".prm", delete=False) as deck:
                deck.write(open("parameters/rectbar3d.prm").read().replace("set Method = auto", "set Method = " + method))
            status, s = run_variant(args.program, deck.name, size)
            os.unlink(deck.name)
            c = s["cycles"][-1]
            solve = sum(t for name, t in s["stage_wall_time"].items() if "solve" in name.lower())
            force = c["quantities"]["F_x[1]"]
            print("| %d x %d | %d | %s%s | %.1f | %.1f | %.0f | %d | %.2f |"
                  % (across, max(1, across // 2), c["dofs"], c["linear_solver"]["method"],
                     "" if status == 0 else " (exit %d)" % status, s["wall_time"], solve, s["peak_memory_mb"],
                     c["nonlinear_iterations"], force))
            if status == 0:  # only converged runs enter the extrapolation
                finest.setdefault(across, {"dofs": c["dofs"], "force": force})
            else:
                finest.setdefault(across, {"dofs": c["dofs"], "force": None})
    finest = {k: f for k, f in finest.items() if f["force"] is not None}
    if len(finest) < 3:
        print("\nfewer than three converged sizes: no extrapolation")
    else:
        a = sorted(finest)[-3:]
        f1, f2, f3 = (finest[k]["force"] for k in a)
        ratio = (f1 - f2) / (f2 - f3) if f2 != f3 else float("inf")
        print()
        if ratio > 1:
            order = math.log(ratio, 2)
            limit = f3 - (f2 - f3) / (ratio - 1)
            print("Richardson on %s cells across: observed order %.2f in h, extrapolated ram force %.1f N"
                  % (", ".join(map(str, a)), order, limit))
            for k in sorted(finest):
                print("  %d across: error %.2f %%" % (k, 100 * (finest[k]["force"] / limit - 1)))
        else:
            print("the ram force does not converge monotonically over %s cells across: no extrapolation" % a)


if __name__ == "__main__":
    main()
