#!/usr/bin/env python3
"""Round-bar extrusion (parameters/roundbar-held-land.prm, Geometry = axisymmetric):
ram-force error against dofs and cumulative wall time, Kelly-adaptive
cycles from the deck's graded start, for velocity degree 1 and 2, as
benchmarks/die2d_degree.py does for die2d.

The reference is the deck's own degree-2 sequence carried further (--cycles
for the reference, fraction 0.5) and extrapolated by the program
(Richardson on its last three cycles; its printed uncertainty is reported).
Prints the reference, one table per degree (dofs, cumulative time, F_x[1],
error) and the dofs and time each degree needs for 1 %, 0.1 % and 0.05 %.

    python3 benchmarks/roundbar_degree.py [--program build/dieflow] [--reference-cycles 12]

Not a test: the times are this machine's (run one benchmark at a time).
"""
import argparse, os, platform

from deck_variant import run_variant

LEVELS = (0.01, 0.001, 0.0005)


def run(program, degree, cycles):
    return run_variant(program, "parameters/roundbar-held-land.prm", {"Velocity degree": "%d" % degree, "Cycles": "%d" % cycles})


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default="build/dieflow")
    parser.add_argument("--reference-cycles", type=int, default=12)
    args = parser.parse_args()
    print("machine:", platform.processor() or platform.machine(), os.cpu_count(), "cores")

    status, ref = run(args.program, 2, args.reference_cycles)
    extrapolated = ref["extrapolated"]["F_x[1]"]
    reference, uncertainty = extrapolated["value"], extrapolated["error"]
    last = ref["cycles"][-1]
    print("reference: degree 2, %d Kelly cycles (exit %d), last %.1f N at %d dofs, extrapolated %.1f +- %.1f N (%.3f %%)"
          % (args.reference_cycles, status, last["quantities"]["F_x[1]"], last["dofs"], reference, uncertainty,
             100 * uncertainty / reference))

    reach = {}
    for degree, cycles in ((1, 10), (2, 8)):
        status, s = run(args.program, degree, cycles)
        print("\n### degree %d (exit %d)\n" % (degree, status))
        print("| cycle | dofs | cumulative time [s] | F_x[1] [N] | error |")
        print("|---|---|---|---|---|")
        elapsed = 0
        for c in s["cycles"]:
            elapsed += c["wall_time"]
            value = c["quantities"]["F_x[1]"]
            error = abs(value / reference - 1)
            print("| %d | %d | %.2f | %.1f | %.4f %% |" % (c["cycle"], c["dofs"], elapsed, value, 100 * error))
            for level in LEVELS:
                if error <= level and (degree, level) not in reach:
                    reach[(degree, level)] = (c["dofs"], elapsed)
    print("\n| error | degree 1: dofs, time [s] | degree 2: dofs, time [s] |")
    print("|---|---|---|")
    for level in LEVELS:
        cells = ["%d, %.2f" % reach[(d, level)] if (d, level) in reach else "not reached" for d in (1, 2)]
        print("| %g %% | %s | %s |" % (100 * level, cells[0], cells[1]))


if __name__ == "__main__":
    main()
