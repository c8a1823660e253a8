"""The rooms of the source tree (doc/design.md, issue 47), checked: every
file opens with a line saying what it is; no source file over 800 lines;
the problem class's header under 250; no two area folders that include each
other (directly or round a longer cycle); the contact and flow headers
include nothing from postprocess/ and not the nonlinear solver.

    python3 tests/structure.py [ROOT]     (ctest runs it; exit 1 on a breach)

Prints the folders' include graph in a fixed order, so that a new edge
shows in the test's output."""
import os, re, sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), ".."))
LONGEST_SOURCE = 800
LONGEST_PROBLEM_HEADER = 250
INCLUDE = re.compile(r'#include <dieflow/([^>]+)>')


def files():
    for top in ("include/dieflow", "source"):
        for folder, _, names in os.walk(os.path.join(ROOT, top)):
            for name in sorted(names):
                if name.endswith((".h", ".cc")):
                    yield os.path.join(folder, name)


def area(path):
    """The area folder of a file under include/dieflow/ or source/ ("" at the top)."""
    relative = os.path.relpath(path, ROOT).split(os.sep)
    inner = relative[2:] if relative[0] == "include" else relative[1:]
    return inner[0] if len(inner) > 1 else ""


def main():
    breaches = []
    edges = {}
    for path in files():
        name = os.path.relpath(path, ROOT)
        lines = open(path).read().split("\n")
        if not lines[0].startswith("// "):
            breaches.append("%s: does not open with a line saying what it is" % name)
        if len(lines) - 1 > LONGEST_SOURCE:
            breaches.append("%s: %d lines (at most %d)" % (name, len(lines) - 1, LONGEST_SOURCE))
        here = area(path)
        for included in INCLUDE.findall("\n".join(lines)):
            there = included.split("/")[0] if "/" in included else ""
            if here and there and there != here:
                edges.setdefault(here, set()).add(there)
            if path.endswith(".h") and here in ("contact", "flow") and (
                    there == "postprocess" or included == "solvers/nonlinear_solver.h"):
                breaches.append("%s includes %s" % (name, included))
    header = os.path.join(ROOT, "include/dieflow/problem/problem.h")
    n = len(open(header).read().split("\n")) - 1
    if n >= LONGEST_PROBLEM_HEADER:
        breaches.append("include/dieflow/problem/problem.h: %d lines (under %d)" % (n, LONGEST_PROBLEM_HEADER))

    # Cycles among the folders: a folder that reaches itself.
    def reaches(start):
        seen, todo = set(), list(edges.get(start, ()))
        while todo:
            folder = todo.pop()
            if folder not in seen:
                seen.add(folder)
                todo += edges.get(folder, ())
        return seen
    for folder in sorted(edges):
        if folder in reaches(folder):
            breaches.append("folder %s/ reaches itself through its includes" % folder)

    print("area folders and the folders they include:")
    for folder in sorted(edges):
        print("  %-13s -> %s" % (folder, ", ".join(sorted(edges[folder]))))
    for breach in breaches:
        print("BREACH: " + breach)
    print("structure: %s" % ("kept" if not breaches else "%d breaches" % len(breaches)))
    return 1 if breaches else 0


if __name__ == "__main__":
    sys.exit(main())
