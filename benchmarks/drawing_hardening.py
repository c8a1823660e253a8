#!/usr/bin/env python3
"""Cold wire drawing of a strain-hardening metal: dieflow's drawing stress
(parameters/wiredrawing-cold.prm with K = 1: sigma = (eps_0 + eps)^n
epsdot^m, m = 0.05, eps_0 = 0.01; the steady strain field v.grad eps =
epsdot_eq coupled to the flow) against Sachs' slab method for a hardening
metal:

  mean flow stress  sigma_d = Y_m (1+B)/B (1 - (A_f/A_0)^B),  B = mu cot(alpha),
                    Y_m = (1/eps_1) int_0^eps_1 Y(eps) d eps over the ideal
                    strain eps_1 = ln(A_0/A_f)
  slab ODE          d sigma/d eps = (1+B) Y(eps) - B sigma along the die, so
                    sigma_d = (1+B) int_0^eps_1 Y(eps) e^(-B (eps_1 - eps)) d eps

(for mu = 0 both are the ideal work int_0^eps_1 Y d eps). Also the ratio
sigma_d(n) / sigma_d(n = 0) of dieflow's runs with and without hardening
(the same rate factor epsdot^m in both) against Y_m, the mean flow stress
over the ideal strain, and against Y_m at eps_exit, the mean over the
strain the wire leaves with (redundant shear included).

sigma_d = F_x[2] / (pi R_f^2) at the last of three Kelly cycles (16 cells
across). Not a test: a comparison with an approximate theory.

    benchmarks/drawing_hardening.py [--program build/dieflow] [--held-land]
"""
import argparse, math, time

from deck_variant import run_variant

R0, RF, EPS0, M = 5.0, 5.0 * math.sqrt(0.8), 0.01, 0.05


def flow_stress(eps, n):
    return (EPS0 + eps) ** n


def mean_flow_stress(eps1, n):
    return ((EPS0 + eps1) ** (n + 1) - EPS0 ** (n + 1)) / ((n + 1) * eps1)


def sachs(alpha_deg, mu, n, steps=20000):
    eps1 = math.log((R0 / RF) ** 2)
    B = mu / math.tan(math.radians(alpha_deg))
    Ym = mean_flow_stress(eps1, n)
    mean = Ym * eps1 if B == 0 else Ym * (1 + B) / B * (1 - (RF / R0) ** (2 * B))
    h = eps1 / steps
    ode = (1 + B) * sum(flow_stress((i + 0.5) * h, n) * math.exp(-B * (eps1 - (i + 0.5) * h)) for i in range(steps)) * h
    return eps1, Ym, mean, ode


# The land holding the wire instead of the deck's free surface.
HELD_LAND = {"Traction free ids": "", "Free surface ids": "", "Iterations": "0"}


def run(program, deck, alpha, mu, n, held_land):
    start = time.time()
    entries = {"Die angle": "%g" % alpha, "Consistency K": "1", "Hardening exponent n": "%g" % n,
               "Friction coefficients": "4: %g" % mu}
    status, summary = run_variant(program, deck, dict(entries, **(HELD_LAND if held_land else {})))
    wall = time.time() - start
    c = summary["cycles"][-1]
    eps_exit = c["strain"]["eps_exit"] if "strain" in c else float("nan")
    return status, c["boundary_force"]["2"][0] / (math.pi * RF ** 2), eps_exit, wall


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--program", default="build/dieflow")
    parser.add_argument("--deck", default="parameters/wiredrawing-cold.prm")
    parser.add_argument("--held-land", action="store_true",
                        help="the land holds the wire (the deck's free surface off)")
    args = parser.parse_args()
    print("| alpha [deg] | mu | n | Sachs, Y_m | slab ODE | dieflow | eps_exit | dieflow / (n = 0) | Y_m | Y_m at eps_exit | time [s] (n = 0) |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for alpha in (6, 8, 12):
        for mu in (0., 0.05):
            status0, base, _, wall0 = run(args.program, args.deck, alpha, mu, 0, args.held_land)
            for n in (0.26, 0.5):
                eps1, Ym, mean, ode = sachs(alpha, mu, n)
                status, sigma, eps_exit, wall = run(args.program, args.deck, alpha, mu, n, args.held_land)
                print("| %g | %g | %g | %.4f | %.4f | %.4f%s | %.4f | %.4f | %.4f | %.4f | %.1f (%.1f) |"
                      % (alpha, mu, n, mean, ode, sigma, "" if status == 0 else " exit %d" % status, eps_exit,
                         sigma / base, Ym, mean_flow_stress(eps_exit, n), wall, wall0))


if __name__ == "__main__":
    main()
