#!/usr/bin/env python3
"""Follow, by hand's judgement, the advice of the extreme decks that exit 2.

The fuzz tests (tests/fuzz_extreme.h) follow only advice that needs no
judgement ("a or b": b). This script runs every extreme deck of the corpus
(written by the fuzz tests with FUZZ_DECKS=DIR), and for each one that
exits 2 runs it again with each remedy the failure messages name:

    tresca    Contact/Friction law = Tresca, Tresca friction factors 1 on
              both dies, Shear flow stress 0.5 MPa (about K / sqrt(3) of
              the corpus's Norton-Hoff law at unit rate)
    regular   Contact/Friction law = regularised Coulomb (the deck's mu)
    finer     Mesh/Die2d/Cells across doubled
    picard    Nonlinear solver/Method = Picard then Newton
    iterations Nonlinear solver/Maximum iterations = 200

and prints, by how the deck ended, how many converge with each.

    python3 benchmarks/advice_followed.py [--build build] [--decks DIR]

Without --decks the corpus is written to a temporary directory first (the
six fuzz_extreme_decks programs, about 5 minutes on 2 cores). Not a test.
"""
import argparse, glob, os, re, subprocess, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PARTS = ["a", "e", "b", "c", "f", "d"]
REMEDIES = {
    "tresca": [("Contact", "Friction law", "Tresca"),
               ("Contact", "Tresca friction factors", "3: 1, 4: 1"),
               ("Contact", "Shear flow stress", "0.5")],
    "regular": [("Contact", "Friction law", "regularised Coulomb")],
    "finer": [("Die2d", "Cells across", None)],
    "picard": [("Nonlinear solver", "Method", "Picard then Newton")],
    "iterations": [("Nonlinear solver", "Maximum iterations", "200")],
}


def edited(text, changes):
    """The deck with each (section, entry, value) set; value None doubles it."""
    for section, entry, value in changes:
        pattern = re.compile(r"(\n *)set %s *= *([^\n]*)" % re.escape(entry))
        match = pattern.search(text)
        if value is None:
            value = str(2 * int(match.group(2)))
        if match:
            text = pattern.sub(lambda m: m.group(1) + "set %s = %s" % (entry, value), text, count=1)
        else:
            text += "subsection %s\n  set %s = %s\nend\n" % (section, entry, value)
    return text


def run(dieflow, text, work):
    with open(os.path.join(work, "deck.prm"), "w") as f:
        f.write(text)
    p = subprocess.run([dieflow, "deck.prm"], cwd=work, capture_output=True, text=True, timeout=900)
    failure = ""
    for line in p.stdout.splitlines():
        if line.startswith("NOT converged:"):
            failure = line
    return p.returncode, failure


def kind(failure):
    for words in ["the contact did not settle", "the iteration diverges", "no convergence in",
                  "the penalty lost", "breaks the contact"]:
        if words in failure:
            return words
    return "other"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--decks", help="the corpus's decks (FUZZ_DECKS=DIR of the fuzz tests)")
    args = parser.parse_args()
    dieflow = os.path.join(args.build, "dieflow")
    with tempfile.TemporaryDirectory() as work:
        decks = args.decks
        if not decks:
            decks = os.path.join(work, "decks")
            os.mkdir(decks)
            for part in PARTS:
                name = "fuzz_extreme_decks_" + part
                exe = os.path.join(args.build, "tests", name + ".release", name + ".release")
                subprocess.run([exe], cwd=work, env=dict(os.environ, FUZZ_DECKS=decks),
                               capture_output=True, timeout=3600)
        rows = {}
        for path in sorted(glob.glob(os.path.join(decks, "*.prm"))):
            text = open(path).read()
            status, failure = run(dieflow, text, work)
            if status != 2:
                continue
            how = kind(failure)
            outcome = {r: run(dieflow, edited(text, c), work)[0] == 0 for r, c in REMEDIES.items()}
            rows.setdefault(how, []).append((os.path.basename(path)[:-4], outcome))
            print("%s: %s; %s" % (os.path.basename(path), how,
                                  ", ".join(r for r, ok in outcome.items() if ok) or "none converges"), flush=True)
        print("\n| how the deck ended | decks | " + " | ".join(REMEDIES) + " |")
        print("|---|---|" + "---|" * len(REMEDIES))
        for how, items in rows.items():
            print("| %s | %d | " % (how, len(items)) +
                  " | ".join(str(sum(o[r] for _, o in items)) for r in REMEDIES) + " |")


if __name__ == "__main__":
    main()
