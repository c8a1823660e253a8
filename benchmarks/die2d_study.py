#!/usr/bin/env python3
"""Time against error: uniform and adaptive mesh sequences of die2d (cases
N1 and P1) and of an exact-solution case, each run as one dieflow run with
refinement cycles. For the die cases the error of each cycle is that of the
ram force F_x[1] against the best estimate of its converged value (the
Richardson estimate of the finest adaptive sequence); for the exact case the
H1 error of the velocity. Prints, per strategy, the cycles and the dofs and
wall time needed to reach 1% and 0.1%, and plots error against dofs and
against wall time (gnuplot PNG).

    benchmarks/die2d_study.py [--case N1|P1|exact] [--images doc/images]
                              [--adaptive-cycles 14] [--strategies uniform,adaptive kelly,...]

Not a test: the times are this machine's.
"""
import argparse, json, math, os, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

EXACT = """set Write VTU = false
subsection Mesh
  set Source = box
  subsection Box
    set Lower corner = 0, 0
    set Upper corner = 2, 1
    set Subdivisions = 4, 2
  end
end
subsection Material
  set Law                 = Norton-Hoff
  set Consistency K       = 1
  set Rate sensitivity m  = 0.2
  set Minimum strain rate = 1e-6
end
subsection Boundary conditions
  set Prescribed velocity ids = 1, 2, 4
  set Symmetry ids            = 3
  set Slip wall ids           =
  set Traction free ids       =
  set Body force              = 1; 0
  subsection Prescribed velocity 1
    set Velocity  = n/(n+1)*(G*3^((1+n)/2)/K)^(1/n)*(1-abs(y)^(1+1/n)); 0
    set Constants = n=0.2, G=1, K=1
  end
  subsection Prescribed velocity 2
    set Velocity  = n/(n+1)*(G*3^((1+n)/2)/K)^(1/n)*(1-abs(y)^(1+1/n)); 0
    set Constants = n=0.2, G=1, K=1
  end
  subsection Prescribed velocity 4
    set Velocity = 0; 0
  end
end
subsection Contact
  set Die ids =
end
subsection Verification
  set Exact velocity = n/(n+1)*(G*3^((1+n)/2)/K)^(1/n)*(1-abs(y)^(1+1/n)); 0
  set Constants      = n=0.2, G=1, K=1
end
"""

STRATEGIES = {
    # name: (strategy, cycles, extra refinement entries)
    "uniform": ("global", 6, ""),
    "adaptive kelly": ("adaptive", 14, "  set Indicator = kelly\n"),
    "adaptive combined": ("adaptive", 14, "  set Indicator = combined\n"),
}


def deck_for(case, strategy, cycles, extra, work):
    if case == "exact":
        base = EXACT
    else:
        name = "die2d-held-land.prm" if case == "N1" else "die2d-%s.prm" % case
        base = open(os.path.join(ROOT, "parameters", name)).read()
        base += "\nsubsection Mesh\n subsection Die2d\n  set Cells across = 4\n end\nend\n"
        # What doc/benchmarks.md measured: the degree-1 default deck on the
        # old built-in mesh (the default deck now grades its corners and
        # takes velocity degree 2).
        base += "\nsubsection Mesh\n  set Corner refinements = 0\n  subsection Die2d\n    set Layout = blocks\n  end\nend\nsubsection Discretisation\n  set Velocity degree = 1\nend\n"
    base += "\nset Output directory = %s\nset Write VTU = false\n" % work
    base += "subsection Refinement\n  set Cycles = %d\n  set Strategy = %s\n" % (cycles, strategy)
    if strategy == "adaptive":
        base += "  set Marking = fixed number\n  set Refine fraction = 0.3\n"
    base += extra + "end\n"
    return base


def run(program, case, name, work):
    strategy, cycles, extra = STRATEGIES[name]
    deck = os.path.join(work, "deck.prm")
    open(deck, "w").write(deck_for(case, strategy, cycles, extra, work))
    subprocess.run([program, deck], stdout=subprocess.DEVNULL, check=True)
    s = json.load(open(os.path.join(work, "summary.json")))
    rows, elapsed = [], 0.0
    for c in s["cycles"]:
        elapsed += c["wall_time"]
        value = c["velocity_h1_error"] if case == "exact" else c["quantities"]["F_x[1]"]
        rows.append((c["cycle"], c["dofs"], elapsed, value, c["nonlinear_iterations"]))
    extrapolated = {name: v for name, v in s["extrapolated"].items()} if isinstance(s["extrapolated"], dict) else {}
    return rows, extrapolated


def reached(rows, errors, level):
    for row, e in zip(rows, errors):
        if e < level:
            return row
    return None


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--case", default="N1", choices=["N1", "P1", "exact"])
    parser.add_argument("--images", default=os.path.join(ROOT, "doc", "images"))
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "dieflow"))
    parser.add_argument("--adaptive-cycles", type=int, default=14)
    parser.add_argument("--strategies", default=",".join(STRATEGIES))
    args = parser.parse_args()
    for name in list(STRATEGIES):
        if name not in args.strategies.split(","):
            del STRATEGIES[name]
        elif name != "uniform":
            STRATEGIES[name] = (STRATEGIES[name][0], args.adaptive_cycles, STRATEGIES[name][2])

    results = {}
    with tempfile.TemporaryDirectory() as work:
        for name in STRATEGIES:
            out = os.path.join(work, name.replace(" ", "-"))
            os.makedirs(out)
            results[name] = run(args.program, args.case, name, out)

    if args.case == "exact":
        reference, reference_error = 0.0, 0.0
        label = "H1 error of the velocity"
    else:
        best = min(results, key=lambda n: results[n][0][-1][1] if n != "uniform" else 1e30)
        e = results[best][1]["F_x[1]"]
        reference, reference_error = e["value"], e["error"]
        label = "ram force error (vs its extrapolated converged value)"

    print("# %s: %s\n" % (args.case, label))
    if args.case != "exact":
        print("best estimate of the converged ram force: %.2f +- %.2f N/mm (%.3f%%), Richardson from the last "
              "cycles of the finest adaptive run\n" % (reference, reference_error, 100 * reference_error / reference))
    summary = []
    for name, (rows, _) in results.items():
        if args.case == "exact":
            errors = [r[3] for r in rows]
            scale = rows[0][3]
        else:
            errors = [abs(r[3] / reference - 1) for r in rows]
        print("## %s\n" % name)
        print("| cycle | dofs | wall time (cumulative) [s] | value | error | Newton its |")
        print("|---|---|---|---|---|---|")
        for r, e in zip(rows, errors):
            print("| %d | %d | %.2f | %.6g | %s | %d |" % (r[0], r[1], r[2], r[3],
                  ("%.3g" % e) if args.case == "exact" else ("%.3f%%" % (100 * e)), r[4]))
        print()
        if args.case != "exact":
            one, tenth = reached(rows, errors, 0.01), reached(rows, errors, 0.001)
            summary.append((name, one, tenth))
        with open(os.path.join("/tmp", "study-%s-%s.dat" % (args.case, name.replace(" ", "-"))), "w") as f:
            for r, e in zip(rows, errors):
                f.write("%d %.6g %.6g\n" % (r[1], r[2], e))

    if summary:
        print("| strategy | dofs to 1% | time to 1% [s] | dofs to 0.1% | time to 0.1% [s] |")
        print("|---|---|---|---|---|")
        for name, one, tenth in summary:
            cell = lambda r, i: ("%d" % r[1] if i == 1 else "%.2f" % r[2]) if r else "not reached"
            print("| %s | %s | %s | %s | %s |" % (name, cell(one, 1), cell(one, 2), cell(tenth, 1), cell(tenth, 2)))

    os.makedirs(args.images, exist_ok=True)
    for axis, column, xlabel in [("dofs", 1, "unknowns (dofs)"), ("time", 2, "cumulative wall time (s)")]:
        script = "/tmp/study.gp"
        with open(script, "w") as f:
            f.write('set terminal pngcairo size 800,560 font "sans,11"\n')
            f.write("set output '%s'\n" % os.path.join(args.images, "study-%s-%s.png" % (args.case, axis)))
            f.write("set logscale xy\nset grid\nset key bottom left\n")
            f.write("set xlabel '%s'\nset ylabel '%s'\n" % (xlabel, label))
            f.write("set title 'die2d %s: uniform against adaptive refinement'\n" % args.case
                    if args.case != "exact" else "set title 'power-law Poiseuille (exact): uniform against adaptive'\n")
            plots = ["'/tmp/study-%s-%s.dat' using %d:3 with linespoints pt 7 lw 2 title '%s'" % (
                args.case, name.replace(" ", "-"), column, name) for name in results]
            f.write("plot " + ", ".join(plots) + "\n")
        subprocess.run(["gnuplot", script], check=True)
    print("\nplots: %s/study-%s-dofs.png, study-%s-time.png" % (args.images, args.case, args.case))


if __name__ == "__main__":
    main()
