"""Strong scaling of a deck on this machine: one process of 1 and of 2
threads against 2 processes of 1 thread (mpirun), from each run's
summary.json: wall time, the stages (assembly, linear solve and the
solvers' set-up within it, ...), Newton
iterations, the largest process's peak memory, the ram force's gap
from the first run's, and the last cycle's linear solver with its direct
fallbacks (doc/parallel.md).

    python3 benchmarks/mpi_scaling.py [DECK.prm] [--set "Entry = value" ...]

DECK defaults to parameters/rectbar3d.prm; each --set replaces that entry's
line in the deck (it must be there). Runs one after the other, Write VTU off."""
import json, os, re, subprocess, sys, tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
PROGRAM = os.path.join(ROOT, "build", "dieflow")


def deck_text(deck, changes):
    text = open(deck).read()
    for change in changes + ["Write VTU = false"]:
        entry = change.split("=")[0].strip()
        pattern = re.compile(r"^(\s*)set %s\s*=.*$" % re.escape(entry), re.M)
        if not pattern.search(text):
            sys.exit("%s has no entry %s" % (deck, entry))
        text = pattern.sub(lambda m: m.group(1) + "set " + change, text, count=1)
    return text


def run(text, processes, threads, work):
    os.makedirs(work, exist_ok=True)
    text = re.sub(r"set Output directory\s*=.*", "set Output directory = %s" % work, text)
    path = os.path.join(work, "deck.prm")
    open(path, "w").write(text)
    env = dict(os.environ, DEAL_II_NUM_THREADS=str(threads), OMPI_ALLOW_RUN_AS_ROOT="1",
               OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    command = [PROGRAM, path] if processes == 1 else \
        ["mpirun", "--bind-to", "none", "-np", str(processes), PROGRAM, path]
    status = subprocess.run(command, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            cwd=os.path.dirname(os.path.abspath(DECK))).returncode
    return status, json.load(open(os.path.join(work, "summary.json")))


args = sys.argv[1:]
DECK = args.pop(0) if args and not args[0].startswith("--") else os.path.join(ROOT, "parameters", "rectbar3d.prm")
changes = [args[i + 1] for i in range(len(args)) if args[i] == "--set"]
text = deck_text(DECK, changes)
print("%s %s" % (os.path.relpath(DECK, ROOT), "; ".join(changes)))
print("| processes x threads | dofs (last cycle) | Newton its | wall [s] | assembly [s] | linear solve [s] | of which set-up [s] | rest [s] | peak memory, largest process [MB] | F_x[1] against the first | linear solver (last cycle) |")
print("|---|---|---|---|---|---|---|---|---|---|---|")
first = None
with tempfile.TemporaryDirectory() as scratch:
    for processes, threads in [(1, 1), (1, 2), (2, 1)]:
        status, s = run(text, processes, threads, os.path.join(scratch, "%dx%d" % (processes, threads)))
        stages = s["stage_wall_time"]
        last = s["cycles"][-1]
        force = last["quantities"].get("F_x[1]")
        first = first if first is not None else force
        rest = s["wall_time"] - stages.get("assembly", 0) - stages.get("linear solve", 0)
        solver = last["linear_solver"]
        setup = sum(c["linear_solver"]["setup_wall_time"] for c in s["cycles"])
        print("| %d x %d%s | %d | %d | %.2f | %.2f | %.2f | %.2f | %.2f | %.0f | %.1e | %s, %d direct fallbacks |" % (
            processes, threads, "" if status == 0 else " (exit %d)" % status, last["dofs"],
            sum(c["nonlinear_iterations"] for c in s["cycles"]), s["wall_time"], stages.get("assembly", 0),
            stages.get("linear solve", 0), setup, rest, s["peak_memory_mb"], abs(force / first - 1),
            solver["method"], solver["direct_fallbacks"]))
