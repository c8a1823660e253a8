#!/usr/bin/env python3
"""The ring-compression test (parameters/ring-compression.prm, 100 steps to
50 % reduction) for several friction coefficients: the change of the inner
diameter against the height reduction, and the cost of each run (wall time,
Newton iterations, new meshes). The inner diameter is the mean over the
inner surface: 2 x boundary area of id 3 / (2 pi h), h the current half
height.

Usage: benchmarks/ring_compression.py [--program build/dieflow] [--mu 0,0.05,0.1,0.2]
                                      [--subdivisions 8,12] [--remesh 0.3]"""
import argparse, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from deck_variant import run_variant
from ring_geometry import inner_diameter_curve

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--program", default="build/dieflow")
parser.add_argument("--deck", default="parameters/ring-compression.prm")
parser.add_argument("--mu", default="0,0.05,0.1,0.2")
parser.add_argument("--subdivisions", default="8,12", help="cells across the wall and along the height")
parser.add_argument("--remesh", default="0.3", help="Incremental/Remesh below Jacobian (0: never)")
args = parser.parse_args()

rows = {}
for mu in args.mu.split(","):
    status, summary = run_variant(args.program, args.deck,
                                  {"Friction coefficients": "2: " + mu, "Subdivisions": args.subdivisions,
                                   "Remesh below Jacobian": args.remesh})
    cycles = summary["cycles"]
    curve = inner_diameter_curve(summary)
    newton = sum(c["nonlinear_iterations"] for c in cycles)
    rows[mu] = curve
    totals = summary["incremental"]
    print("mu = %-5s exit %d: %d cells, %d steps, %d Newton iterations, %d new meshes, wall %.2f s, peak %.0f MB, "
          "volume change %.2e, smallest scaled Jacobian %.3f"
          % (mu, status, cycles[0]["cells"], len(cycles) - 1, newton, totals["remeshings"], summary["wall_time"],
             summary["peak_memory_mb"], totals["volume_change"], totals["smallest_scaled_jacobian"]))

print("\nchange of the inner diameter (%) against the height reduction (%)")
print("reduction " + " ".join("mu=%-6s" % mu for mu in rows))
n = min(len(c) for c in rows.values())
for i in range(0, n, 10):
    print("%9.1f " % rows[next(iter(rows))][i][0] + " ".join("%9.2f" % rows[mu][i][1] for mu in rows))
