#!/usr/bin/env python3
"""Heat in time, explicit against trapezoid step coupling (Heat/Step
coupling) on parameters/upsetting-hot.prm: for each time step, the mean and
range of T and the platen force at the end, the heat solves and Newton
iterations of the run and its wall time; the isothermal run's wall time
at the deck's step for the ratio.

Usage: benchmarks/heat_step_coupling.py [--program build/dieflow] [--dt 0.02,0.01,0.005,0.0025] [--repeat 3]"""
import argparse, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from deck_variant import run_variant

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--program", default="build/dieflow")
parser.add_argument("--deck", default="parameters/upsetting-hot.prm")
parser.add_argument("--dt", default="0.02,0.01,0.005,0.0025")
parser.add_argument("--repeat", type=int, default=3, help="runs per case; the median wall time")
args = parser.parse_args()


def median_run(entries):
    runs = [run_variant(args.program, args.deck, entries) for _ in range(args.repeat)]
    times = sorted(s["wall_time"] for _, s in runs)
    status, summary = runs[0]
    return status, summary, times[len(times) // 2]


status, summary, wall = median_run({"Model": "off"})
print("isothermal, dt 0.01: exit %d, F_n[2] %.1f N, wall %.2f s (median of %d)"
      % (status, summary["cycles"][-1]["quantities"]["F_n[2]"], wall, args.repeat))
for coupling in ("explicit", "trapezoid"):
    for dt in args.dt.split(","):
        status, summary, wall = median_run({"Step coupling": coupling, "Time step": dt})
        last = summary["cycles"][-1]
        heat_solves = sum(c.get("heat", {}).get("solves", 0) for c in summary["cycles"])
        newton = sum(c["nonlinear_iterations"] for c in summary["cycles"])
        print("%-9s dt %-6s: exit %d, %d steps, T mean %.3f K (%.2f - %.2f), F_n[2] %.1f N, %d heat solves, "
              "%d Newton iterations, wall %.2f s"
              % (coupling, dt, status, len(summary["cycles"]) - 1, last["heat"]["T_mean"], last["heat"]["T_min"],
                 last["heat"]["T_max"], last["quantities"]["F_n[2]"], heat_solves, newton, wall))
