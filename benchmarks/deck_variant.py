"""Runs a shipped deck with some entries changed, in a scratch output
directory, without VTU: run_variant(program, deck, {"Die angle": "8"})
returns (exit status, summary.json as a dict). Each entry is replaced
wherever 'set NAME = ...' appears in the deck. A run that stops on an
error mid-way (exit 2: a new mesh Gmsh could not make) writes its message
to stderr, not into summary.json: it goes into the dict's "failure"."""
import json, os, re, subprocess, tempfile


def run_variant(program, deck, entries):
    text = open(deck).read()
    for name, value in dict(entries, **{"Write VTU": "false"}).items():
        text = re.sub(r"set %s\s*=.*" % re.escape(name), "set %s = %s" % (name, value), text)
    with tempfile.TemporaryDirectory() as tmp:
        text = re.sub(r"set Output directory\s*=.*", "set Output directory = %s" % tmp, text)
        path = os.path.join(tmp, "deck.prm")
        open(path, "w").write(text)
        run = subprocess.run([program, path], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        errors = [line for line in run.stderr.splitlines() if line.strip()]
        if not os.path.exists(os.path.join(tmp, "summary.json")):
            raise RuntimeError("%s stopped (exit %d) before it wrote summary.json: %s"
                               % (program, run.returncode, errors[-1] if errors else "no message"))
        summary = json.load(open(os.path.join(tmp, "summary.json")))
        if run.returncode != 0 and errors and not summary.get("failure"):
            summary["failure"] = errors[-1]
        return run.returncode, summary
