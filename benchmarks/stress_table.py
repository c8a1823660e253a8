#!/usr/bin/env python3
"""Run the numerical stress suite (tests/stress_*.prm) through dieflow and
tabulate exit status, Newton iterations, divergence ratio, ram force and
wall time of each deck.

Each deck is copied into a temporary directory without its
"subsection Test" block (read only by the test driver; dieflow rejects it),
with its Output directory pointed into that directory and a relative Gmsh
file resolved against tests/. Decks run one after the other.

    python3 benchmarks/stress_table.py [--dieflow build/dieflow] [--write doc/stress.md]

Prints the Markdown table; with --write, writes the whole document (the
table, footnotes, machine and date), keeping its section on the fuzz
corpus (written by hand from benchmarks/fuzz_table.py). Build first: ./setup.sh run, or a
Release build in build/. Not a test: the checks live in the decks.
"""
import argparse, datetime, glob, json, math, os, re, subprocess, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PREFIX = "# Numerical stress suite: "
# Where the fuzz corpus's section of the document starts (kept by --write).
FUZZ_MARKER = "## The fuzz corpus"
# Bounds of the decks' own contact checks: a value above one is flagged.
CONTACT_BOUNDS = {"penetration": 1e-6, "tension": 1e-6, "friction_excess": 1e-12,
                  "friction_power": 1e-12, "stick_slip_rate": 1e-8}


def logical_lines(text):
    """Group physical lines into statements (a trailing backslash continues)."""
    group = []
    for line in text.splitlines(keepends=True):
        group.append(line)
        if not line.rstrip("\n").rstrip().endswith("\\"):
            yield group
            group = []
    if group:
        yield group


def prepare_deck(source, out_dir):
    """The deck's text without 'subsection Test', its top-level Output
    directory set to out_dir and a relative Gmsh file made absolute."""
    kept, depth, skip_from, has_output = [], 0, None, False
    for group in logical_lines(open(source).read()):
        words = group[0].split()
        if words[:1] == ["subsection"]:
            if depth == 0 and words[1:] == ["Test"]:
                skip_from = depth
            depth += 1
        elif words[:1] == ["end"]:
            depth -= 1
            if skip_from == depth:
                skip_from = None
                continue
        if skip_from is not None:
            continue
        statement = "".join(group)
        if depth == 0 and re.match(r"\s*set\s+Output directory\s*=", statement):
            statement, has_output = "set Output directory = %s\n" % out_dir, True
        gmsh = re.match(r"(\s*set\s+Gmsh file\s*=\s*)(\S+)", statement)
        if gmsh and not os.path.isabs(gmsh.group(2)):
            path = os.path.join(os.path.dirname(os.path.abspath(source)), gmsh.group(2))
            statement = gmsh.group(1) + path + "\n"
        kept.append(statement)
    if not has_output:
        kept.insert(0, "set Output directory = %s\n" % out_dir)
    return "".join(kept)


def what_is_hard(source):
    """The purpose from the deck's header: its first clause after the prefix."""
    first = open(source).readline().strip()
    text = first[len(PREFIX):] if first.startswith(PREFIX) else first.lstrip("# ")
    return re.split(r"; |\. ", text.rstrip("."))[0]


def is_die_case(source):
    """die2d is the default mesh source; box and gmsh decks have no ram."""
    sources = re.findall(r"^\s*set\s+Source\s*=\s*(\S+)", open(source).read(), re.M)
    return not sources or sources[0] == "die2d"


def run_case(dieflow, source, work):
    name = os.path.basename(source)[:-len(".prm")]
    out_dir = os.path.join(work, name)
    deck = os.path.join(work, name + ".prm")
    with open(deck, "w") as f:
        f.write(prepare_deck(source, out_dir))
    start = time.perf_counter()
    proc = subprocess.run([dieflow, deck], cwd=work, capture_output=True, text=True)
    wall = time.perf_counter() - start
    summary_file = os.path.join(out_dir, "summary.json")
    summary = json.load(open(summary_file)) if os.path.exists(summary_file) else {}
    message = next((l for l in proc.stderr.splitlines() if l.startswith("dieflow:")), None)
    if message is None and summary.get("failure"):
        message = summary["failure"]  # exit 2 reports on stdout and in summary.json
    penalty = re.search(r"^\s*set\s+Penalty factor\s*=\s*(\S+)", open(source).read(), re.M)
    return dict(name=name, hard=what_is_hard(source), die=is_die_case(source),
                penalty=penalty.group(1) if penalty else None,
                status=proc.returncode, wall=wall, message=message, summary=summary)


def significant(x, digits):
    """x to `digits` significant digits, without an exponent for moderate x."""
    if x is None:
        return "—"
    if math.isnan(x) or math.isinf(x):
        return str(x)
    if x == 0:
        return "0"
    exponent = math.floor(math.log10(abs(x)))
    if digits == 2 and abs(exponent) > 2:
        return "%.1e" % x
    decimals = digits - 1 - exponent
    return "%.*f" % (max(decimals, 0), round(x, decimals))


def row(result, footnote):
    s = result["summary"]
    c = s.get("cycles", [{}])[-1]
    converged = {True: "yes", False: "no"}.get(s.get("converged"), "—")
    status = "%d / %s" % (result["status"], converged) + (" [^%d]" % footnote if footnote else "")
    force = c.get("boundary_force", {}).get("1", [None])[0] if result["die"] else None
    return "| `%s` | %s | %s | %s | %s / %s | %s | %s | %.2f (%.3f) |" % (
        result["name"], result["hard"], status, c.get("nonlinear_iterations", "—"),
        c.get("linear_solves", "—"), c.get("contact_assemblies", "—"),
        significant(c.get("divergence_ratio"), 2), significant(force, 4), result["wall"],
        s.get("wall_time", float("nan")))


def table(results):
    """The Markdown table and its footnotes (the message of each failed run)."""
    lines = ["| case | what is hard | exit status / converged | Newton iterations | linear solves / contact assemblies | divergence ratio | ram force F_x[1] [N/mm] | wall time [s] (solver) |",
             "|---|---|---|---|---|---|---|---|"]
    notes = []
    for r in results:
        footnote = None
        if r["status"] != 0 and r["message"]:
            notes.append("[^%d]: `%s`: %s" % (len(notes) + 1, r["name"], r["message"].splitlines()[0]))
            footnote = len(notes)
        lines.append(row(r, footnote))
    return "\n".join(lines) + ("\n\n" + "\n".join(notes) if notes else "")


def oddities(results):
    """NaN, slow runs, large divergence ratios, violated contact bounds."""
    odd = []
    for r in results:
        c = r["summary"].get("cycles", [{}])[-1]
        values = [v for v in c.get("boundary_force", {}).get("1", [])] + [c.get("divergence_ratio")]
        if any(isinstance(v, float) and math.isnan(v) for v in values):
            odd.append("`%s`: NaN in the summary" % r["name"])
        if r["wall"] > 60:
            odd.append("`%s`: slow, %.0f s" % (r["name"], r["wall"]))
        if (c.get("divergence_ratio") or 0) > 1e-5:
            why = " (of order 1/penalty factor = 1/%s, set in the deck)" % r["penalty"] if r["penalty"] else ""
            odd.append("`%s`: divergence ratio %.2g above 1e-5%s" % (r["name"], c["divergence_ratio"], why))
        for key, bound in CONTACT_BOUNDS.items():
            value = c.get("contact_checks", {}).get(key)
            if value is not None and (math.isnan(value) or value > bound):
                last = "" if r["summary"].get("converged") else " (the last, unconverged iterate)"
                odd.append("`%s`: contact check %s = %.2g above %g%s" % (r["name"], key, value, bound, last))
    return odd


def machine():
    cores = subprocess.run(["nproc"], capture_output=True, text=True).stdout.strip()
    lscpu = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
    model = next((l.split(":", 1)[1].strip() for l in lscpu.splitlines() if l.startswith("Model name")), "unknown CPU")
    return "%s (%s cores)" % (model, cores)


INTRODUCTION = """# The numerical stress suite

The decks `tests/stress_*.prm` push the solver in one hard direction at a
time: the rate sensitivity m down to 0.02 (near rigid-plastic), friction
from mu = 0 to sticking (mu = 1, Tresca m = 1), the penalty factor from 1e3
to 1e10, the minimum strain rate down to 1e-10, a flat die, a 95% reduction
and a zero ram speed, all on the die2d scene (8 or 16 cells across); and
stretched (aspect ratio 50) and strongly distorted cells on the homogeneous
plane-strain compression, whose exact solution is known. Each must converge
and keep its laws (the checks in its `subsection Test`, run by
`./setup.sh test`), or stop with exit status 2 and say what failed and what
to change; never NaN, a hang or a crash. `stress_mu_1_coarse` ran out of its 30
Newton iterations until 2026-12-05 (exit status 2; 47 were needed, linear
once Coulomb's bound was frozen where the states cycled); with the bounds
coupled again once the states settle, Newton's own path takes 36
(`stress_mu_1_coarse_advice`), and the 30-iteration deck converges through
the friction continuation to the same force. `stress_penalty_1e3`'s penalty alone loses 7.5 %
of the flow: once Newton has converged it turns augmented (Uzawa steps,
solved directly) and converges incompressible (doc/user-guide.md, "When a
converged iteration is still not converged").

This page shows what each deck costs and how it ends. Exit status 0 means
converged, 2 not converged (summary.json is still written), 1 bad input.
Iterations, divergence ratio and ram force are from the last cycle of
`summary.json`; the ram force is the x reaction on the inlet (boundary id 1,
sign as reported), "—" for the compression cases, which have no ram. Zero
Newton iterations means the Newtonian start already met the tolerance (the
homogeneous compression field does not depend on the law; at zero speed
nothing moves). Wall time is the whole process, start-up included; in
brackets the time dieflow reports for its own work (`wall_time`).
"""


def document(results, body, load):
    odd = oddities(results)
    if odd:
        remarks = "Flagged by the script:\n\n" + "\n".join("- " + o for o in odd)
    else:
        remarks = ("Flagged by the script: nothing (no NaN, no run over 60 s, no divergence "
                   "ratio above 1e-5, every contact check within the decks' bounds).")
    note = ("Measured %s on %s, one deck at a time (load average %.2f at the start;\n"
            "another build may share the machine, so the times are an upper bound).\n"
            "Reproduce, after `./setup.sh run` or a Release build in `build/`:\n\n"
            "    python3 benchmarks/stress_table.py --write doc/stress.md\n"
            % (datetime.date.today().isoformat(), machine(), load))
    return "\n\n".join([INTRODUCTION.rstrip(), body, remarks, note])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dieflow", default=os.path.join(ROOT, "build", "dieflow"))
    parser.add_argument("--write", metavar="FILE", help="write the document (e.g. doc/stress.md)")
    args = parser.parse_args()
    dieflow = os.path.abspath(args.dieflow)
    load = os.getloadavg()[0]
    with tempfile.TemporaryDirectory() as work:
        results = [run_case(dieflow, deck, work)
                   for deck in sorted(glob.glob(os.path.join(ROOT, "tests", "stress_*.prm")))]
    body = table(results)
    print(body)
    if args.write:
        # The fuzz corpus's section (benchmarks/fuzz_table.py) is kept.
        kept = ""
        if os.path.exists(args.write):
            text = open(args.write).read()
            if FUZZ_MARKER in text:
                kept = "\n\n" + text[text.index(FUZZ_MARKER):].rstrip() + "\n"
        with open(args.write, "w") as f:
            f.write(document(results, body, load).rstrip() + "\n" + kept)


if __name__ == "__main__":
    main()
