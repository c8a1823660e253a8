#!/usr/bin/env python3
"""The metal leaving the die against the land holding it: die2d N0, N1, N3,
P1 and the round bar, each run as the shipped deck (free surface:
parameters/die2d.prm, parameters/roundbar.prm; held land: their
-held-land twins) with the case's material and friction and more adaptive
cycles. Prints per case and model the cycles (dofs, cumulative wall time,
the ram force and its error against the run's own Richardson limit, the
jet's least half thickness h_jet, where the metal comes onto the land
again, the free surface's moves), the limit with its uncertainty, and the
dofs / wall time to reach 0.1 % and 0.01 % of it.

    benchmarks/free_surface_study.py [--cases N0,N1,N3,P1,roundbar]
                                     [--models free,held] [--cycles 10]

Not a test: the times are this machine's (doc/benchmarks.md).
"""
import argparse, json, os, re, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(ROOT, "build", "dieflow")
DECKS = {("die2d", "free"): "die2d.prm", ("die2d", "held"): "die2d-held-land.prm",
         ("roundbar", "free"): "roundbar.prm", ("roundbar", "held"): "roundbar-held-land.prm"}
# Each case: the scene, the friction coefficients and the material (in place
# of the deck's Newtonian law).
CASES = {
    "N0": ("die2d", "3: 0, 4: 0", ""),
    "N1": ("die2d", "3: 0.001, 4: 0.1", ""),
    "N3": ("die2d", "3: 0.3, 4: 0.3", ""),
    "P1": ("die2d", "3: 0.001, 4: 0.1",
           "  set Law = Norton-Hoff\n  set Consistency K = 0.834\n  set Rate sensitivity m = 0.2\n"),
    "roundbar": ("roundbar", "3: 0.001, 4: 0.1", ""),
}


def run(case, model, cycles):
    scene, friction, material = CASES[case]
    text = open(os.path.join(ROOT, "parameters", DECKS[(scene, model)])).read()
    text = re.sub(r"set Friction coefficients\s*=.*", "set Friction coefficients = " + friction, text)
    text = re.sub(r"set Cycles\s*=.*", "set Cycles = %d" % cycles, text)
    text = re.sub(r"set Write VTU\s*=.*", "set Write VTU = false", text)
    if material:
        text = re.sub(r"  set Law\s*=.*\n  set Viscosity\s*=.*\n", material, text)
    with tempfile.TemporaryDirectory() as tmp:
        text = re.sub(r"set Output directory\s*=.*", "set Output directory = " + tmp, text)
        path = os.path.join(tmp, "deck.prm")
        open(path, "w").write(text)
        status = subprocess.run([PROGRAM, path], stdout=subprocess.DEVNULL).returncode
        summary = json.load(open(os.path.join(tmp, "summary.json")))
    return status, summary


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--cases", default="N0,N1,N3,P1,roundbar")
    parser.add_argument("--models", default="free,held")
    parser.add_argument("--cycles", type=int, default=10)
    args = parser.parse_args()
    limits = []
    for case in args.cases.split(","):
        for model in args.models.split(","):
            status, summary = run(case, model, args.cycles)
            limit = summary["extrapolated"]["F_x[1]"]
            value, error = limit["value"], limit["error"]
            title = "free surface" if model == "free" else "land held"
            print(f"\n### {case}, {title} (exit {status}; limit {value:.6g} +- {error:.2g})\n")
            print("| cycle | dofs | wall time (cumulative) [s] | F_x[1] | error | estimated | h_jet | onto the land at x | moves |")
            print("|---|---|---|---|---|---|---|---|---|")
            elapsed, reach = 0.0, {}
            for c in summary["cycles"]:
                elapsed += c["wall_time"]
                if not c["converged"]:
                    print(f"| {c['cycle']} | {c['dofs']} | {elapsed:.1f} | not converged | | | | | |")
                    break
                f = c["quantities"]["F_x[1]"]
                e = c["estimated_errors"].get("F_x[1]")
                fs = c.get("free_surface")
                h = c["quantities"].get("h_jet")
                onto = [l["to"][0] for l in fs["lines"] if l["ends"] in (3, 4)] if fs else []
                print(f"| {c['cycle']} | {c['dofs']} | {elapsed:.2f} | {f:.6g} | {100 * (f / value - 1):+.4f}% | "
                      + ("-" if e is None else f"{100 * e / abs(f):.3f}%") + " | "
                      + ("-" if h is None else f"{h:.5f}") + " | "
                      + (f"{max(onto):.3f}" if onto else "-") + " | "
                      + (str(fs["moves"]) if fs else "-") + " |")
                for level in (1e-3, 1e-4):
                    # Reached when the error with the limit's uncertainty is within the level.
                    if level not in reach and abs(f - value) + error <= level * abs(value):
                        reach[level] = f"{c['dofs']} / {elapsed:.2f} s"
            limits.append((case, title, value, error, reach))
    print("\n### Limits, and the dofs / cumulative wall time to reach 0.1 % and 0.01 % of them\n")
    print("| case | model | F_x[1] limit | +- | 0.1 % | 0.01 % |")
    print("|---|---|---|---|---|---|")
    for case, title, value, error, reach in limits:
        print(f"| {case} | {title} | {value:.6g} | {error:.2g} | {reach.get(1e-3, 'not reached')} | "
              f"{reach.get(1e-4, 'not reached')} |")


if __name__ == "__main__":
    main()
