"""Two builds of the program on the same shipped decks, in turn: whether a
change made one process slower. Each round runs every deck with both
binaries, the order alternating between rounds (this machine's speed
drifts within the hour, so only runs close in time compare); wall time and
peak memory from summary.json, the medians at the end, and whether the
forces agree (doc/parallel.md, "One process after the shared mesh").

    python3 benchmarks/compare_builds.py OLD/dieflow NEW/dieflow [--rounds 3] [DECK.prm ...]

DECKs default to the shipped die2d.prm, die2d-held-land.prm, roundbar.prm,
die2d-hot.prm and rectbar3d.prm; each is run as shipped but with Write VTU
off and its output in a temporary folder. One process (no mpirun), the
threads the machine has."""
import json, os, statistics, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DECKS = ["die2d.prm", "die2d-held-land.prm", "roundbar.prm", "die2d-hot.prm", "rectbar3d.prm"]


def run(program, deck, output):
    """Runs @p deck (a path) with @p program into @p output; its summary.json."""
    lines = []
    for line in open(deck).read().split("\n"):
        if line.strip().startswith("set Output directory"):
            line = "set Output directory = " + output
        elif line.strip().startswith("set Write VTU"):
            line = "set Write VTU = false"
        lines.append(line)
    # Beside the shipped deck, so that the files it names are found.
    with tempfile.NamedTemporaryFile("w", suffix=".prm", dir=os.path.dirname(deck), delete=False) as f:
        f.write("\n".join(lines))
    try:
        subprocess.run([program, f.name], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    finally:
        os.remove(f.name)
    return json.load(open(os.path.join(output, "summary.json")))


def main():
    args = sys.argv[1:]
    rounds = 3
    if "--rounds" in args:
        at = args.index("--rounds")
        rounds = int(args[at + 1])
        del args[at : at + 2]
    if len(args) < 2:
        sys.exit(__doc__)
    programs = {"old": os.path.abspath(args[0]), "new": os.path.abspath(args[1])}
    decks = args[2:] or [os.path.join(ROOT, "parameters", d) for d in DECKS]
    env_threads = os.environ.get("DEAL_II_NUM_THREADS", "all")
    print("threads: %s; %d rounds" % (env_threads, rounds))
    times, forces = {}, {}
    with tempfile.TemporaryDirectory() as scratch:
        for r in range(rounds):
            for deck in decks:
                for name in (["old", "new"] if r % 2 == 0 else ["new", "old"]):
                    summary = run(programs[name], deck, os.path.join(scratch, name))
                    last = summary["cycles"][-1]["quantities"]
                    key = os.path.basename(deck)
                    times.setdefault((key, name), []).append(summary["wall_time"])
                    forces.setdefault((key, name), []).append(
                        {q: v for q, v in last.items() if q.startswith("F_")})
                    print("round %d  %-22s %s  wall %7.2f s  peak %7.1f MB  converged %s"
                          % (r, key, name, summary["wall_time"], summary.get("peak_memory_mb", 0),
                             summary["converged"]), flush=True)
    print("\n| deck | old: median wall [s] | new: median wall [s] | forces agree (1e-9) |\n|---|---|---|---|")
    for deck in decks:
        key = os.path.basename(deck)
        old, new = times[(key, "old")], times[(key, "new")]
        agree = all(abs(a[q] - b[q]) <= 1e-9 * max(1.0, abs(a[q]))
                    for a, b in zip(forces[(key, "old")], forces[(key, "new")]) for q in a)
        print("| %s | %.2f (%.2f-%.2f) | %.2f (%.2f-%.2f) | %s |"
              % (key, statistics.median(old), min(old), max(old), statistics.median(new), min(new), max(new),
                 "yes" if agree else "NO"))


if __name__ == "__main__":
    main()
