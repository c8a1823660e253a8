#!/usr/bin/env python3
"""Summarise the fuzz corpus of the suite (tests/fuzz_*.cc) for doc/stress.md.

Runs the built test programs fuzz_mutated_decks and fuzz_extreme_decks_{a,e,b,c,f,d}
(build/tests/NAME.release/NAME.release) in a temporary directory, the extreme
ones with FUZZ_TABLE and FUZZ_COUNTS set so that they list every deck, and
prints a Markdown section: the verdicts, the exit statuses of the extreme
decks by seed, how those that exit 2 ended (the first words of each
failure) and whether their advice, followed, converged, and the wall time.

    python3 benchmarks/fuzz_table.py [--build build]

Build first: cmake --build build (the test programs are built with it).
"""
import argparse, collections, os, subprocess, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def program(build, name):
    return os.path.join(build, "tests", name + ".release", name + ".release")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--tables", help="keep each part's table of every deck in this directory")
    args = parser.parse_args()
    lines = []
    with tempfile.TemporaryDirectory() as work:
        if args.tables:
            os.makedirs(args.tables, exist_ok=True)
            work = args.tables
        start = time.time()
        out = subprocess.run([program(args.build, "fuzz_mutated_decks")], cwd=work,
                             capture_output=True, text=True).stdout
        lines.append("Mutated decks (`fuzz_mutated_decks`, %.1f s):\n" % (time.time() - start))
        lines += ["    " + l for l in out.splitlines()]
        lines.append("")
        rows = []
        for part in "aebcfd":
            table = os.path.join(work, "table-%s.md" % part)
            if os.path.exists(table):
                os.remove(table)
            start = time.time()
            out = subprocess.run([program(args.build, "fuzz_extreme_decks_" + part)], cwd=work,
                                 capture_output=True, text=True,
                                 env=dict(os.environ, FUZZ_TABLE=table, FUZZ_COUNTS="1")).stdout
            seconds = time.time() - start
            decks = [r.split("|") for r in open(table).read().splitlines()]
            status = collections.Counter(r[12].strip() for r in decks)
            lines.append("Extreme decks `fuzz_extreme_decks_%s` (%.1f s): exit 0: %d, exit 2: %d, other: %d.\n\n    %s\n"
                         % (part, seconds, status["0"], status["2"],
                            len(decks) - status["0"] - status["2"], out.strip().replace("\n", "\n    ")))
            rows += decks
    # How the decks that exit 2 ended (the failure's first words), and
    # whether the advice, followed, converged (tests/fuzz_extreme.h).
    kinds = collections.defaultdict(lambda: [0, 0, 0])
    for r in rows:
        if r[12].strip() != "2":
            continue
        why = r[16].strip()
        kind = ("the penalty lost the flow" if "penalty lost" in why else
                "the contact did not settle" if "did not settle" in why else
                "the iteration diverges" if "diverges" in why else
                "the converged state breaks the contact conditions" if "breaks the contact" in why else
                why.split(":")[1].strip()[:50] if ":" in why else why[:50])
        kinds[kind][0] += 1
        kinds[kind][1] += r[17].strip() != ""
        kinds[kind][2] += r[17].strip() == "0"
    lines.append("")
    lines.append("| how the decks that exit 2 ended | decks | advice followed | then converged |")
    lines.append("|---|---|---|---|")
    for kind, (n, followed, good) in sorted(kinds.items(), key=lambda k: -k[1][0]):
        lines.append("| %s | %d | %d | %d |" % (kind, n, followed, good))
    lines.append("")
    lines.append("| deck (seed/index) | die angle | reduction % | container mm | land mm | cells across | degree "
                 "| mu container, die | ram speed mm/s | penalty factor | law | exit | mass loss | F_x[1] N/mm | checks "
                 "| failure (exit 2) | exit with the advice followed |")
    lines.append("|" + "---|" * 17)
    for r in rows[:24]:
        lines.append("|".join(r))
    lines.append("")
    lines.append("(the first 24 of %d decks; all of them: FUZZ_TABLE=FILE build/tests/fuzz_extreme_decks_a.release/"
                 "fuzz_extreme_decks_a.release)" % len(rows))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
