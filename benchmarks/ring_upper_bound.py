#!/usr/bin/env python3
"""The ring-compression test with a constant friction factor m (Tresca,
|tau| <= m k) against the mathematical calibration curves of the 6:3:2 ring:
Avitzur's upper-bound solution (B. Avitzur, "Forging of hollow discs",
Israel J. Technol. 2 (1964) 295-304), with which Male and DePierre computed
the ring test's calibration curves for constant m (A. T. Male and
V. DePierre, "The validity of mathematical solutions for determining
friction from the ring compression test", J. Lubr. Technol. 92 (1970)
389-397).

The upper bound, computed here: a ring of radii R_i < R_o and thickness T
between platens closing at U; the field v_z = -U z / T,
v_r = U (r - R_n^2 / r) / (2 T) (uniform through the thickness: no bulge),
whose neutral radius R_n minimises the power
  J / (2 pi sigma_0 U / sqrt(3)) = int_Ri^Ro r sqrt(3 + R_n^4 / r^4) dr
                                   + (m / T) int_Ri^Ro |r^2 - R_n^2| dr
(the plastic work of the field, and the friction m sigma_0 / sqrt(3) times
the slip |v_r| on both platens); the radii then move with v_r (midpoint
rule in 500 steps to 50 %; 250 or 2000 steps, 100 or 400 Simpson
intervals give the same curves to 0.001 points).

The program: parameters/ring-compression.prm (Norton-Hoff m = 0.1, 8 x 12
cells of the upper half, 100 steps) with Friction law = Tresca on the
platen, k = sigma_0 / sqrt(3), sigma_0 the mean axial stress of the
frictionless run at 25 % (the flow stress at the mean strain rate; it
rises 7 % from the first step to the last with the rate).

Usage: benchmarks/ring_upper_bound.py [--program build/dieflow] [--m 0,0.1,0.2,0.4]
                                      [--subdivisions 8,12] [--curves FILE]"""
import argparse, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from deck_variant import run_variant
from ring_geometry import inner_diameter_curve

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--program", default="build/dieflow")
parser.add_argument("--deck", default="parameters/ring-compression.prm")
parser.add_argument("--m", default="0,0.1,0.2,0.4")
parser.add_argument("--subdivisions", default="8,12", help="cells across the wall and along the height")
parser.add_argument("--curves", help="also write the whole curves here, for the figure (doc/make_figures.sh): "
                    "one block per m of 'reduction  upper bound  program' every 1 %%, blocks apart by two blank lines")
args = parser.parse_args()


def simpson(f, a, b, n=200):
    h = (b - a) / n
    return h / 3 * (f(a) + f(b) + sum((4 if i % 2 else 2) * f(a + i * h) for i in range(1, n)))


def power(rn, ri, ro, t, m):
    plastic = simpson(lambda r: r * math.sqrt(3 + rn ** 4 / r ** 4), ri, ro)
    # |r^2 - R_n^2| integrated in closed form on each side of R_n.
    def below(a, b):
        return rn ** 2 * (b - a) - (b ** 3 - a ** 3) / 3
    c = min(max(rn, ri), ro)
    friction = below(ri, c) + (-below(c, ro))
    return plastic + m / t * friction


def neutral_radius(ri, ro, t, m):
    # Golden section on [0, R_o]: the power is convex in R_n.
    a, b = 0.0, ro
    g = (math.sqrt(5) - 1) / 2
    for _ in range(60):
        c, d = b - g * (b - a), a + g * (b - a)
        if power(c, ri, ro, t, m) < power(d, ri, ro, t, m):
            b = d
        else:
            a = c
    return (a + b) / 2


def upper_bound_curve(m, reductions, ri=15.0, ro=30.0, t=20.0, steps=500):
    t0, ri0, curve = t, ri, {}
    dt = 0.5 * t0 / steps
    targets = sorted(reductions)
    for k in range(steps + 1):
        reduction = 100 * (1 - t / t0)
        for target in targets:
            if target not in curve and reduction >= target - 1e-9:
                curve[target] = 100 * (ri / ri0 - 1)
        if k == steps:
            break
        # Midpoint: the rates at the half step (the platens close at 1).
        rn = neutral_radius(ri, ro, t, m)
        vr = lambda r, rn=rn, t=t: (r - rn ** 2 / r) / (2 * t)
        rim, rom, tm = ri + 0.5 * dt * vr(ri), ro + 0.5 * dt * vr(ro), t - 0.5 * dt
        rn = neutral_radius(rim, rom, tm, m)
        ri += dt * (rim - rn ** 2 / rim) / (2 * tm)
        ro += dt * (rom - rn ** 2 / rom) / (2 * tm)
        t -= dt
    return curve


def program_curve(m, k):
    law = "Tresca\n  set Tresca friction factors = 2: %s\n  set Shear flow stress = %s" % (m, k)
    status, summary = run_variant(args.program, args.deck,
                                  {"Friction law": law, "Subdivisions": args.subdivisions})
    curve = {round(reduction, 6): change for reduction, change in inner_diameter_curve(summary)}
    return status, summary, curve


reductions = [10, 20, 30, 40, 50]
# sigma_0 of the metal at the test's rates: the frictionless ring's mean axial stress at 25 %.
status, summary, _ = program_curve(0, 1)
quarter = next(c for c in summary["cycles"] if c["step"]["stroke"] >= 2.5 - 1e-9)
h = 10 - quarter["step"]["stroke"]
area = math.pi * (30 ** 2 - 15 ** 2) * 10 / h
sigma0 = abs(quarter["boundary_force"]["1"][0]) / area
k = sigma0 / math.sqrt(3)
print("sigma_0 = %.2f MPa (the frictionless ring at 25 %%), k = %.3f MPa" % (sigma0, k))
print("change of the inner diameter (%%) at %s %% reduction: upper bound (Avitzur) / program" % reductions)
curves = open(args.curves, "w") if args.curves else None
for m in args.m.split(","):
    bound = upper_bound_curve(float(m), reductions)
    status, summary, curve = program_curve(m, k)
    if curves:
        every = list(range(0, 51))
        whole = upper_bound_curve(float(m), every)
        curves.write("# m = %s: reduction (%%), change of the inner diameter (%%): upper bound, program\n" % m)
        for r in every:
            curves.write("%g %.4f %s\n" % (r, whole[r], ("%.4f" % curve[r]) if r in curve else "?"))
        curves.write("\n\n")
    totals = summary["incremental"]
    cells = ", ".join("%+.2f / %s" % (bound[r], ("%+.2f" % curve[r]) if r in curve else "-") for r in reductions)
    print("m = %-4s exit %d, %d new meshes, wall %.1f s: %s" % (m, status, totals["remeshings"], summary["wall_time"], cells))
