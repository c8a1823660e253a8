#!/usr/bin/env python3
"""die2d with contact and friction: the iteration histories of N1 and N3,
the forces of N0, N1, N3 (and P1) against the frictionless case, the
separation on the land and its convergence with the mesh, and the plots of
the contact pressure and friction stress along the die (gnuplot PNG).

    benchmarks/die2d_contact.py [--cells-across 32] [--series 8,16,32,64,128]
                                [--images doc/images] [--program build/dieflow]

Prints Markdown (the tables of doc/contact.md). Not a test.
"""
import argparse, json, math, os, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
X_D = 14.25 / math.tan(math.radians(70))


def run(program, case, across, work):
    deck_name = "die2d-held-land.prm" if case == "N1" else "die2d-%s.prm" % case
    base = open(os.path.join(ROOT, "parameters", deck_name)).read()
    # What doc/contact.md measured: one degree-1 mesh of the old built-in
    # layout (the default deck now grades its corners, refines in cycles and
    # takes velocity degree 2).
    base += "\nsubsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Layout = blocks\n  end\nend\nsubsection Discretisation\n  set Velocity degree = 1\nend\nsubsection Refinement\n  set Cycles = 1\nend\n"
    out = os.path.join(work, "%s-%d" % (case, across))
    deck = out + ".prm"
    with open(deck, "w") as f:
        f.write(base)
        f.write("\nset Output directory = %s\nset Write VTU = false\n" % out)
        f.write("subsection Mesh\n subsection Die2d\n  set Cells across = %d\n end\nend\n" % across)
    subprocess.run([program, deck], check=True, stdout=subprocess.DEVNULL)
    return out, json.load(open(os.path.join(out, "summary.json")))


def profile(directory, die_id):
    rows = []
    for line in open(os.path.join(directory, "die-profile-%d.dat" % die_id)):
        if line.startswith("#"):
            continue
        rows.append([float(v) for v in line.split()])
    return rows


def separation(directory):
    """Extent (mm) of the separated part of the land next to the die exit."""
    xs = [r[1] for r in profile(directory, 4) if r[7] == 0 and abs(r[2] - 4.75) < 1e-9 and r[1] >= X_D - 1e-9]
    return (max(xs) - X_D) if xs else 0.0


def history_table(name, summary):
    c = summary["cycles"][-1]
    print("\n%s: %d cells, %d dofs, %d Newton iterations, %d linear solves\n" % (
        name, c["cells"], c["dofs"], c["nonlinear_iterations"], c["linear_solves"]))
    print("| iteration | relative residual | active-set changes | stick/slip changes |")
    print("|---|---|---|---|")
    for k, (r, a, t) in enumerate(zip(c["residual_history"], c["active_set_changes"], c["stick_slip_changes"])):
        print("| %d | %.2e | %d | %d |" % (k, r, a, t))


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--cells-across", type=int, default=32)
    parser.add_argument("--series", default="8,16,32,64,128")
    parser.add_argument("--images", default=os.path.join(ROOT, "doc", "images"))
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "dieflow"))
    args = parser.parse_args()

    with tempfile.TemporaryDirectory() as work:
        results = {}
        for case in ["N0", "N1", "N3", "P1"]:
            results[case] = run(args.program, case, args.cells_across, work)

        print("## Forces against the frictionless case (%d cells across)\n" % args.cells_across)
        print("| case | ram force [N/mm] | vs N0 | die normal 3 / 4 [N/mm] | die friction 3 / 4 [N/mm] | separated / stick / slip nodes | land flux [% of inflow] | exit speed [mm/s] |")
        print("|---|---|---|---|---|---|---|---|")
        ram0 = results["N0"][1]["cycles"][-1]["boundary_force"]["1"][0]
        for case in ["N0", "N1", "N3", "P1"]:
            c = results[case][1]["cycles"][-1]
            ram = c["boundary_force"]["1"][0]
            n = c["contact_nodes"]
            vs = "" if case in ("N0", "P1") else "%+.1f%%" % (100 * (ram / ram0 - 1))
            print("| %s | %.1f | %s | %.1f / %.1f | %.2f / %.2f | %d / %d / %d | %.2f | %.1f |" % (
                case, ram, vs, c["die_normal_force"]["3"], c["die_normal_force"]["4"],
                c["die_friction_force"]["3"], c["die_friction_force"]["4"],
                n["separated"], n["stick"], n["slip"], -100 * c["flux"]["4"] / 3610, c["flux"]["2"] / 4.75))

        print("\n## Iteration histories")
        for case in ["N1", "N3"]:
            history_table(case, results[case][1])

        print("\n## N1: the separated land and the forces against the mesh\n")
        print("| cells across | dofs | separated length [mm] | land flux [% of inflow] | exit speed [mm/s] | ram force [N/mm] | Newton its |")
        print("|---|---|---|---|---|---|---|")
        for across in [int(a) for a in args.series.split(",")]:
            out, s = run(args.program, "N1", across, work)
            c = s["cycles"][-1]
            print("| %d | %d | %.2f | %.2f | %.1f | %.1f | %d |" % (
                across, c["dofs"], separation(out), -100 * c["flux"]["4"] / 3610, c["flux"]["2"] / 4.75,
                c["boundary_force"]["1"][0], c["nonlinear_iterations"]))

        # Plots along the die face and land (id 4), and the container (id 3).
        os.makedirs(args.images, exist_ok=True)
        for quantity, column, label, name in [(4, 3, "contact pressure (MPa)", "die2d-contact-pressure.png"),
                                              (5, 4, "friction stress (MPa)", "die2d-friction-stress.png")]:
            script = os.path.join(work, "plot.gp")
            with open(script, "w") as f:
                f.write('set terminal pngcairo size 1000,520 font "sans,11"\n')
                f.write("set output '%s'\n" % os.path.join(args.images, name))
                f.write("set xlabel 'arc length along the die from the entry C (mm): die face to %.2f, then the land'\n" % (14.25 / math.sin(math.radians(70))))
                f.write("set ylabel '%s'\nset key top right\nset grid\n" % label)
                f.write("set title 'die2d, %d cells across: %s along the die face and land (id 4)'\n" % (args.cells_across, label))
                face = 14.25 / math.sin(math.radians(70))
                f.write("set arrow from %.4f, graph 0 to %.4f, graph 1 nohead dt 2\n" % (face, face))
                plots = []
                for case, style in [("N0", "lw 2"), ("N1", "lw 2"), ("N3", "lw 2")]:
                    plots.append("'%s' using 1:%d with linespoints pt 7 ps 0.4 %s title '%s'" % (
                        os.path.join(results[case][0], "die-profile-4.dat"), column + 1, style, case))
                f.write("plot " + ", ".join(plots) + "\n")
            subprocess.run(["gnuplot", script], check=True)
        print("\nplots: %s/die2d-contact-pressure.png, die2d-friction-stress.png" % args.images)


if __name__ == "__main__":
    main()
