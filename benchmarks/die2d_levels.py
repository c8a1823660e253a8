#!/usr/bin/env python3
"""Wall time and peak memory of die2d with material P (Norton-Hoff, m = 0.2,
free outlet) at several mesh levels, split into assembly, linear solve and
the rest, with dofs and iterations. The walls are the contact walls of case
P1 (the paper's friction), or frictionless slip walls with --walls slip.
Each level runs in a process of its own, so the peak memory is that level's.

    benchmarks/die2d_levels.py [--levels 4] [--walls contact|slip] [--m 0.2]
                               [--tangent primal-dual|standard] [--program build/dieflow]

--m sets the rate sensitivity (0.05: nearly rigid-plastic).

Not a test: the figures depend on the machine, which the report names.
"""
import argparse, json, os, platform, subprocess, sys, tempfile

def machine():
    model = "unknown CPU"
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return "%s, %d cores, %s" % (model, os.cpu_count(), platform.platform())

def run_die2d(program, base, across, extra="", timeout=None):
    """Runs deck @p base with the die2d mesh @p across cells across plus the
    deck text @p extra, in a directory of its own; returns (exit status,
    summary.json), or None past @p timeout seconds."""
    with tempfile.TemporaryDirectory() as work:
        deck = os.path.join(work, "deck.prm")
        with open(deck, "w") as f:
            f.write(base)
            f.write("\nset Output directory = %s\nset Write VTU = false\n" % work)
            f.write("subsection Mesh\n subsection Die2d\n  set Cells across = %d\n end\nend\n" % across)
            f.write(extra)
        try:
            status = subprocess.run([program, deck], stdout=subprocess.DEVNULL, timeout=timeout).returncode
        except subprocess.TimeoutExpired:
            return None
        return status, json.load(open(os.path.join(work, "summary.json")))

def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(here)
    parser = argparse.ArgumentParser()
    parser.add_argument("--levels", type=int, default=4)
    parser.add_argument("--cells-across", type=int, default=8)
    parser.add_argument("--program", default=os.path.join(root, "build", "dieflow"))
    parser.add_argument("--tangent", default="primal-dual", choices=["primal-dual", "standard"])
    parser.add_argument("--walls", default="contact", choices=["contact", "slip"])
    parser.add_argument("--m", type=float, default=0.2)
    args = parser.parse_args()

    # The land holding the metal (as measured before the deck's free surface).
    base = open(os.path.join(root, "parameters", "die2d-P1.prm")).read()
    base = base.replace("set Traction free ids       = 2, 6", "set Traction free ids       = 2")
    base += "\nsubsection Free surface\n set Iterations = 0\nend\n"
    base += "\nsubsection Material\n set Rate sensitivity m = %g\nend\n" % args.m
    if args.walls == "slip":
        base += "\nsubsection Boundary conditions\n set Slip wall ids = 3, 4\nend\nsubsection Contact\n set Die ids =\nend\n"
    print("die2d, material P (Norton-Hoff m = %g), %s walls; %s Newton from a Newtonian start" % (args.m,
        "frictionless slip" if args.walls == "slip" else "contact with the paper's friction (P1)", args.tangent))
    print("machine: " + machine())
    print()
    print("| level | cells across | cells | dofs | Newton its | linear solves | wall [s] | assembly [s] | linear solve [s] | rest [s] | peak memory [MB] | ram force [N/mm] |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for level in range(args.levels):
        across = args.cells_across * 2**level
        status, s = run_die2d(args.program, base, across,
                              "subsection Nonlinear solver\n set Newton tangent = %s\nend\n" % args.tangent)
        c = s["cycles"][0]
        stages = s["stage_wall_time"]
        assembly, solve = stages.get("assembly", 0), stages.get("linear solve", 0)
        rest = s["wall_time"] - assembly - solve
        its = "%d" % c["nonlinear_iterations"] if status == 0 else "not converged (%d)" % c["nonlinear_iterations"]
        print("| %d | %d | %d | %d | %s | %d | %.2f | %.2f | %.2f | %.2f | %.0f | %.4f |" % (
            level, across, c["cells"], c["dofs"], its, c["linear_solves"],
            s["wall_time"], assembly, solve, rest, s["peak_memory_mb"], c["boundary_force"]["1"][0]))
        sys.stdout.flush()

if __name__ == "__main__":
    main()
