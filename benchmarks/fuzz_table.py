#!/usr/bin/env python3
"""Summarise the fuzz corpus of the suite (tests/fuzz_*.cc) for doc/stress.md.

Runs the built test programs fuzz_mutated_decks and fuzz_extreme_decks_{a,b,c}
(build/tests/NAME.release/NAME.release) in a temporary directory, the extreme
ones with FUZZ_TABLE set so that they list every deck, and prints a Markdown
section: the verdicts, the exit statuses of the extreme decks by seed, how
they ended (the first words of each failure), and the wall time.

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
    args = parser.parse_args()
    lines = []
    with tempfile.TemporaryDirectory() as work:
        start = time.time()
        out = subprocess.run([program(args.build, "fuzz_mutated_decks")], cwd=work,
                             capture_output=True, text=True).stdout
        lines.append("Mutated decks (`fuzz_mutated_decks`, %.1f s):\n" % (time.time() - start))
        lines += ["    " + l for l in out.splitlines()]
        lines.append("")
        rows = []
        for part in "abc":
            table = os.path.join(work, "table-%s.md" % part)
            start = time.time()
            out = subprocess.run([program(args.build, "fuzz_extreme_decks_" + part)], cwd=work,
                                 capture_output=True, text=True,
                                 env=dict(os.environ, FUZZ_TABLE=table)).stdout
            seconds = time.time() - start
            decks = [r.split("|") for r in open(table).read().splitlines()]
            status = collections.Counter(r[12].strip() for r in decks)
            lines.append("Extreme decks `fuzz_extreme_decks_%s` (%.1f s): exit 0: %d, exit 2: %d, other: %d. %s"
                         % (part, seconds, status["0"], status["2"],
                            len(decks) - status["0"] - status["2"], out.strip()))
            rows += decks
    lines.append("")
    lines.append("| deck (seed/index) | die angle | reduction % | container mm | land mm | cells across | degree "
                 "| mu container, die | ram speed mm/s | penalty factor | law | exit | mass loss | F_x[1] N/mm | checks |")
    lines.append("|" + "---|" * 15)
    for r in rows[:24]:
        lines.append("|".join(r))
    lines.append("")
    lines.append("(the first 24 of %d decks; all of them: FUZZ_TABLE=FILE build/tests/fuzz_extreme_decks_a.release/"
                 "fuzz_extreme_decks_a.release)" % len(rows))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
