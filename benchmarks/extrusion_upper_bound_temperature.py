#!/usr/bin/env python3
"""Hot plane-strain extrusion (parameters/die2d-hot.prm) against Johnson
and Kudo's upper-bound temperatures: W. Johnson and H. Kudo, "The use of
upper-bound solutions for the determination of temperature distributions
in fast hot rolling and axi-symmetric extrusion processes", Int. J. Mech.
Sci. 1 (1960) 175-191 (the method: the plastic work of a kinematically
admissible field with velocity discontinuities, each discontinuity heating
the metal that crosses it adiabatically; the flow stress at each line read
at the temperature the metal has there).

The field, computed here (W. Johnson, "Extrusion through wedge-shaped
dies", J. Mech. Phys. Solids 3 (1955) 218-223: the single-triangle field):
the half billet of height H0 enters at v0, crosses the straight line C'P
(C' on the container wall at x_c <= 0, P on the axis) into a triangle
C'PD that slides rigidly along C'D, and crosses PD (D the die's exit) into
the extrudate of height H1 at v1 = v0 H0/H1. With x_c < 0 the metal
between C'D and the die is a dead zone and C'D shears at k; with x_c = 0
the triangle slides on the die face. The power per unit depth
    J = k1 |dv1| L1 + k2 |dv2| L2 + k |u2| L_C'D (dead zone only)
is minimised over x_c and x_P; the ram force of the half billet is
F = J / v0. A particle crossing a line of slip |dv| at normal speed v_n
heats by beta k |dv| / (rho c v_n), the same all along a straight line:
the metal leaves uniformly hot (the core), and the dead zone's shear heat
goes into the layer that slides along it; the mean rise is beta J /
(rho c v0 H0). The flow stress is Sellars and Tegart's at a mean strain
rate (the equivalent strain of the two lines over the time the metal
spends in the triangle, area / flux), k = sigma / sqrt 3, line 1 at the
mean of its inlet and outlet temperatures, line 2 likewise from line 1's
outlet (solved by fixed point). The rate is a choice: the script also
prints the answer with half and twice that rate.

The program: the same deck frictionless (die and container), so that the
field's smooth die face matches: the ram force F_x[1], the exit temperature
(flux-weighted mean and range over the outlet) and the adiabatic rise of
the program's own heat (summary.json).

Usage: benchmarks/extrusion_upper_bound_temperature.py [--program build/dieflow]
           [--speeds 19,190,1900] [--frictional]"""
import argparse, math, os, sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from deck_variant import run_variant

parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
parser.add_argument("--program", default="build/dieflow")
parser.add_argument("--deck", default="parameters/die2d-hot.prm")
parser.add_argument("--speeds", default="19,190,1900", help="ram speeds (mm/s)")
parser.add_argument("--frictional", action="store_true",
                    help="also run the deck with its own friction (the upper bound stays frictionless)")
parser.add_argument("--no-program", action="store_true", help="the upper bound only")
args = parser.parse_args()

# die2d-hot.prm's scene and AA6063's constants (mm, s, MPa, K).
H0, H1, ANGLE, CONTAINER = 19.0, 4.75, 70.0, 20.0
XD = (H0 - H1) / math.tan(math.radians(ANGLE))
ST_ALPHA, ST_N, ST_Q, ST_LNA = 0.040, 5.385, 141550.0, 22.5
RHO_C = 2700 * 900 * 1e-6  # N/(mm^2 K)
BETA, T_IN = 0.9, 723.15
GAS = 8.314462618


def flow_stress(rate, temperature):
    """Sellars-Tegart: sigma = asinh((Z/A)^(1/n)) / alpha, Z = rate exp(Q / (R T))."""
    z_over_a = math.exp(math.log(rate) + ST_Q / (GAS * temperature) - ST_LNA)
    return math.asinh(z_over_a ** (1 / ST_N)) / ST_ALPHA


def field(xc, xp, v0):
    """The single-triangle field's lines: (slip, normal speed, length) of C'P and PD,
    the triangle's speed, the length of C'D and the triangle's area; None if inadmissible."""
    c, p, d = (xc, H0), (xp, 0.0), (XD, H1)
    ld = math.hypot(d[0] - c[0], d[1] - c[1])
    t = ((d[0] - c[0]) / ld, (d[1] - c[1]) / ld)
    flux = v0 * H0
    cross = abs(t[0] * (p[1] - c[1]) - t[1] * (p[0] - c[0]))
    if cross < 1e-12:
        return None
    s = flux / cross
    u2 = (s * t[0], s * t[1])
    v1 = flux / H1
    lines = []
    for (a, b), upstream, downstream in (((c, p), (v0, 0.0), u2), ((p, d), u2, (v1, 0.0))):
        length = math.hypot(b[0] - a[0], b[1] - a[1])
        normal = (b[1] - a[1]) / length, -(b[0] - a[0]) / length
        if normal[0] < 0:  # the downstream side: the metal goes in +x
            normal = (-normal[0], -normal[1])
        vn_up = upstream[0] * normal[0] + upstream[1] * normal[1]
        vn_down = downstream[0] * normal[0] + downstream[1] * normal[1]
        if vn_up <= 0 or abs(vn_up - vn_down) > 1e-9 * abs(vn_up):
            return None
        slip = math.hypot(downstream[0] - upstream[0], downstream[1] - upstream[1])
        lines.append((slip, vn_up, length))
    area = 0.5 * abs((d[0] - c[0]) * (p[1] - c[1]) - (d[1] - c[1]) * (p[0] - c[0]))
    return lines, s, ld, area


def power(xc, xp, v0, k):
    f = field(xc, xp, v0)
    if f is None:
        return float("inf")
    lines, s, ld, _ = f
    dead = s * ld if xc < -1e-12 else 0.0
    return k * (sum(slip * length for slip, _, length in lines) + dead)


def optimal_field(v0):
    """Minimise J over (x_c, x_P) by a grid and then nested golden sections (k = 1)."""
    def golden(f, a, b, tol=1e-7):
        g = (math.sqrt(5) - 1) / 2
        x1, x2 = b - g * (b - a), a + g * (b - a)
        f1, f2 = f(x1), f(x2)
        while b - a > tol:
            if f1 < f2:
                b, x2, f2 = x2, x1, f1
                x1 = b - g * (b - a)
                f1 = f(x1)
            else:
                a, x1, f1 = x1, x2, f2
                x2 = a + g * (b - a)
                f2 = f(x2)
        return (a + b) / 2

    def best_xp(xc):
        lo, hi = xc - 40, XD + 40
        xps = [lo + (hi - lo) * i / 800 for i in range(1, 800)]
        x0 = min(xps, key=lambda x: power(xc, x, v0, 1.0))
        step = (hi - lo) / 800
        return golden(lambda x: power(xc, x, v0, 1.0), x0 - step, x0 + step)

    xcs = [-CONTAINER * i / 200 for i in range(0, 201)]
    xc0 = min(xcs, key=lambda xc: power(xc, best_xp(xc), v0, 1.0))
    step = CONTAINER / 200
    xc = golden(lambda xc: power(xc, best_xp(xc), v0, 1.0), max(-CONTAINER, xc0 - step), min(0.0, xc0 + step))
    if power(0.0, best_xp(0.0), v0, 1.0) <= power(xc, best_xp(xc), v0, 1.0):
        xc = 0.0
    return xc, best_xp(xc)


def upper_bound(v0, rate_factor=1.0):
    xc, xp = optimal_field(v0)
    lines, s, ld, area = field(xc, xp, v0)
    strain = sum(slip / vn for slip, vn, _ in lines) / math.sqrt(3)
    rate = rate_factor * strain * v0 * H0 / area
    # Line by line: k at the mean of the line's inlet and outlet temperatures.
    temperature, ks, rises = T_IN, [], []
    for slip, vn, _ in lines:
        rise = 0.0
        for _ in range(100):
            k = flow_stress(rate, temperature + rise / 2) / math.sqrt(3)
            new = BETA * k * slip / (RHO_C * vn)
            if abs(new - rise) < 1e-12:
                break
            rise = new
        ks.append(k)
        rises.append(rise)
        temperature += rise
    dead_power = 0.0
    if xc < -1e-12:
        # The dead zone's boundary shears at the flow stress of the metal beside it
        # (its rate and the core's mean temperature).
        dead_power = flow_stress(rate, T_IN + sum(rises) / 2) / math.sqrt(3) * s * ld
    j = sum(k * slip * length for k, (slip, _, length) in zip(ks, lines)) + dead_power
    return {"xc": xc, "xp": xp, "strain": strain, "rate": rate, "k": ks, "force": j / v0,
            "core_rise": sum(rises), "mean_rise": BETA * j / (RHO_C * v0 * H0)}


speeds = [float(v) for v in args.speeds.split(",")]
print("Upper bound (Johnson and Kudo 1960; single-triangle field of Johnson 1955), die2d-hot frictionless:")
for v0 in speeds:
    ub = upper_bound(v0)
    half, double = upper_bound(v0, 0.5), upper_bound(v0, 2.0)
    print("  v0 %7.1f mm/s: C' at x = %.3f, P at x = %.3f mm; equivalent strain %.3f at %.1f 1/s; "
          "k %.2f, %.2f MPa; F %.1f N/mm; rise: core %.1f K, mean %.1f K "
          "(rate x 0.5: F %.1f, mean %.1f K; x 2: F %.1f, mean %.1f K)"
          % (v0, ub["xc"], ub["xp"], ub["strain"], ub["rate"], ub["k"][0], ub["k"][1], ub["force"],
             ub["core_rise"], ub["mean_rise"], half["force"], half["mean_rise"], double["force"],
             double["mean_rise"]))

if args.no_program:
    sys.exit(0)

cases = [("frictionless", {"Friction coefficients": "3: 0, 4: 0"})]
if args.frictional:
    cases.append(("deck's friction", {}))
print("The program (%s, Heat/Model = steady; the last cycle):" % args.deck)
for name, entries in cases:
    for v0 in speeds:
        status, summary = run_variant(args.program, args.deck, dict(entries, Velocity="%g; 0" % v0))
        last = summary["cycles"][-1]
        heat = last["heat"]
        made = heat["plastic_heat"] + heat["friction_heat"]
        adiabatic = made / (RHO_C * v0 * H0)
        print("  %-15s v0 %7.1f mm/s: exit %d, F_x[1] %.1f N/mm, T_exit %.2f K (%.2f - %.2f): rise %.1f K, "
              "adiabatic rise %.1f K, T_max %.2f K"
              % (name, v0, status, last["quantities"]["F_x[1]"], heat["T_exit"], heat["T_exit_min"],
                 heat["T_exit_max"], heat["T_exit"] - T_IN, adiabatic, heat["T_max"]))
