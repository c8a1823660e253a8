#!/usr/bin/env python3
"""Wire drawing: the drawing stress of dieflow (Geometry = axisymmetric,
parameters/wiredrawing.prm: Norton-Hoff m = 0.05, 20 % reduction, a
0.2 mm land) against three classical results, for several die semi-angles
alpha and Coulomb coefficients mu:

  ideal work  sigma_d/sigma_0 = ln(A_0/A_f)
  Sachs       sigma_d/sigma_0 = (1+B)/B (1 - (A_f/A_0)^B),  B = mu cot(alpha)
              (slab method: no redundant work, friction on the die face)
  Avitzur     upper bound with his spherical velocity field and a constant
              friction factor m_f = sqrt(3) mu (tau = mu sigma_0, which
              over-states Coulomb friction where the die pressure is below
              sigma_0), his land term included:
              2 f(alpha) ln(R_0/R_f) + (2/sqrt 3)(alpha/sin^2 alpha - cot alpha)
              + (2 m_f/sqrt 3)(cot alpha ln(R_0/R_f) + L/R_f)

sigma_d = F_x[2] / (pi R_f^2) at the last of three Kelly cycles, on two
starting meshes (16 and 32 cells across) to show the discretisation error.

    benchmarks/drawing_stress.py [--program build/dieflow] [--curve MU]

Not a test: a comparison with approximate theories (the report says where
and why they differ).
"""
import argparse, math

from deck_variant import run_variant

R0, RF, LAND = 5.0, 5.0 * math.sqrt(0.8), 0.2


def f_avitzur(a):
    s2 = math.sin(a) ** 2
    q = math.sqrt(11. / 12.)
    return (1 - math.cos(a) * math.sqrt(1 - q * q * s2)
            + 1 / math.sqrt(132.) * math.log((1 + q) / (q * math.cos(a) + math.sqrt(1 - q * q * s2)))) / s2


def theories(alpha_deg, mu):
    a = math.radians(alpha_deg)
    ideal = math.log((R0 / RF) ** 2)
    B = mu / math.tan(a)
    sachs = ideal if B == 0 else (1 + B) / B * (1 - (RF / R0) ** (2 * B))
    m_f = math.sqrt(3) * mu
    upper = (2 * f_avitzur(a) * math.log(R0 / RF) + 2 / math.sqrt(3) * (a / math.sin(a) ** 2 - 1 / math.tan(a))
             + 2 * m_f / math.sqrt(3) * (math.log(R0 / RF) / math.tan(a) + LAND / RF))
    return ideal, sachs, upper


def run(program, deck, alpha, mu, across):
    status, summary = run_variant(program, deck, {"Die angle": "%g" % alpha, "Cells across": "%d" % across,
                                                  "Friction coefficients": "4: %g" % mu})
    c = summary["cycles"][-1]
    return status, c["dofs"], c["boundary_force"]["2"][0] / (math.pi * RF ** 2)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default="build/dieflow")
    parser.add_argument("--deck", default="parameters/wiredrawing.prm")
    parser.add_argument("--curve", type=float, metavar="MU",
                        help="columns alpha, ideal, Sachs, Avitzur, dieflow for alpha = 4..20 at this mu (for gnuplot)")
    args = parser.parse_args()
    if args.curve is not None:
        print("# alpha ideal Sachs Avitzur dieflow (mu = %g, 16 cells across)" % args.curve)
        for alpha in range(4, 22, 2):
            status, dofs, sigma = run(args.program, args.deck, alpha, args.curve, 16)
            print("%g %.5f %.5f %.5f %.5f" % ((alpha,) + theories(alpha, args.curve) + (sigma,)))
        return
    print("| alpha [deg] | mu | ideal | Sachs | Avitzur (m_f = sqrt 3 mu) | dieflow, 16 across (dofs) | dieflow, 32 across (dofs) |")
    print("|---|---|---|---|---|---|---|")
    for alpha in (6, 8, 12, 15):
        for mu in (0., 0.05, 0.1):
            ideal, sachs, upper = theories(alpha, mu)
            cells = []
            for across in (16, 32):
                status, dofs, sigma = run(args.program, args.deck, alpha, mu, across)
                cells.append("%.4f (%d)%s" % (sigma, dofs, "" if status == 0 else " exit %d" % status))
            print("| %g | %g | %.4f | %.4f | %.4f | %s | %s |" % (alpha, mu, ideal, sachs, upper, cells[0], cells[1]))


if __name__ == "__main__":
    main()
