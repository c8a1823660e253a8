"""Runs every deck of parameters/ (or those named) with two builds of dieflow
and compares what they write: summary.json value by value, but for the
wall times and the memory (wall_time, stage_wall_time, peak_memory_mb),
and the text outputs (study.txt but for its wall-time column, die profiles
and surfaces, load-stroke.txt) line by line; paths into the scratch output
folders count as equal. A change of structure (issue 47) must leave them identical.

    python3 benchmarks/compare_summaries.py BEFORE AFTER [DECK.prm ...]

BEFORE, AFTER: the two programs (e.g. a copy of build/dieflow made before
the change, and build/dieflow). Both runs of a deck write into scratch
folders, without VTU. Prints one line per deck and the wall time of both
runs (back to back on the same machine); exits 1 if any deck differs."""
import json, os, re, subprocess, sys, tempfile, time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
# What a run may change without a change of behaviour: the clocks and the memory.
VOLATILE = {"wall_time", "stage_wall_time", "peak_memory_mb"}
TEXT_OUTPUTS = re.compile(r"(study\.txt|load-stroke\.txt|die-profile-\d+\.dat|die-surface-\d+\.dat)$")


def run(program, deck, work):
    """Runs @p deck with its Output directory in @p work, VTU off; returns (exit status, seconds)."""
    text = open(deck).read()
    text = re.sub(r"set Output directory\s*=.*", "set Output directory = %s" % work, text)
    if re.search(r"set Write VTU\s*=", text):
        text = re.sub(r"set Write VTU\s*=.*", "set Write VTU = false", text)
    else:
        text = "set Write VTU = false\n" + text
    # Relative mesh and die files stay relative to the deck's own folder.
    path = os.path.join(os.path.dirname(os.path.abspath(deck)), ".compare-%d.prm" % os.getpid())
    with open(path, "w") as f:
        f.write(text)
    try:
        start = time.time()
        status = subprocess.run([program, path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
        return status, time.time() - start
    finally:
        os.remove(path)


def without_times(text):
    """study.txt without its wall-time column (the header names it "time")."""
    rows = [line.split("|") for line in text.splitlines()]
    header = next((r for r in rows if len(r) > 1), None)
    if header is None or not any(c.strip().startswith("time") for c in header):
        return text
    column = next(i for i, c in enumerate(header) if c.strip().startswith("time"))
    return "\n".join("|".join(c for i, c in enumerate(r) if i != column) if len(r) > column else "|".join(r)
                     for r in rows)


def normalised(value, folder):
    """@p value with the scratch output folder @p folder written as OUTPUT (paths in summary.json)."""
    if isinstance(value, dict):
        return {k: normalised(v, folder) for k, v in value.items()}
    if isinstance(value, list):
        return [normalised(v, folder) for v in value]
    if isinstance(value, str):
        return value.replace(folder, "OUTPUT")
    return value


def differences(a, b, where=""):
    """The paths at which the JSON values @p a and @p b differ (volatile keys skipped)."""
    if isinstance(a, dict) and isinstance(b, dict):
        found = []
        for key in sorted(set(a) | set(b)):
            if key in VOLATILE:
                continue
            if key not in a or key not in b:
                found.append(where + "/" + key + " (only in one)")
            else:
                found += differences(a[key], b[key], where + "/" + key)
        return found
    if isinstance(a, list) and isinstance(b, list):
        if len(a) != len(b):
            return [where + " (lengths %d, %d)" % (len(a), len(b))]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, "%s[%d]" % (where, i))]
    return [] if a == b else ["%s: %r != %r" % (where, a, b)]


def compare(before, after, deck):
    with tempfile.TemporaryDirectory() as one, tempfile.TemporaryDirectory() as two:
        status_a, time_a = run(before, deck, one)
        status_b, time_b = run(after, deck, two)
        found = [] if status_a == status_b else ["exit status %d != %d" % (status_a, status_b)]
        files = sorted(f for f in set(os.listdir(one)) | set(os.listdir(two))
                       if f == "summary.json" or TEXT_OUTPUTS.search(f))
        for name in files:
            a, b = os.path.join(one, name), os.path.join(two, name)
            if not (os.path.exists(a) and os.path.exists(b)):
                found.append(name + " written by one run only")
            elif name == "summary.json":
                found += [name + d for d in differences(normalised(json.load(open(a)), one),
                                                        normalised(json.load(open(b)), two))]
            elif without_times(open(a).read()) != without_times(open(b).read()):
                found.append(name + " differs")
        return found, status_a, time_a, time_b, len(files)


def main():
    if len(sys.argv) < 3:
        raise SystemExit(__doc__)
    before, after = (os.path.abspath(p) for p in sys.argv[1:3])
    decks = sys.argv[3:] or sorted(os.path.join(ROOT, "parameters", f)
                                   for f in os.listdir(os.path.join(ROOT, "parameters")) if f.endswith(".prm"))
    failed = 0
    print("%-34s %5s %6s %10s %10s  %s" % ("deck", "exit", "files", "before [s]", "after [s]", "verdict"))
    for deck in decks:
        found, status, time_a, time_b, n_files = compare(before, after, deck)
        print("%-34s %5d %6d %10.2f %10.2f  %s" % (os.path.basename(deck), status, n_files, time_a, time_b,
                                                   "identical" if not found else "DIFFERENT"))
        for d in found[:20]:
            print("    " + d)
        failed += bool(found)
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
