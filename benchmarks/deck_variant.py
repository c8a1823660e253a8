"""Runs a shipped deck with some entries changed, in a scratch output
directory, without VTU: run_variant(program, deck, {"Die angle": "8"})
returns (exit status, summary.json as a dict). Each entry is replaced
wherever 'set NAME = ...' appears in the deck."""
import json, os, re, subprocess, tempfile


def run_variant(program, deck, entries):
    text = open(deck).read()
    for name, value in dict(entries, **{"Write VTU": "false"}).items():
        text = re.sub(r"set %s\s*=.*" % re.escape(name), "set %s = %s" % (name, value), text)
    with tempfile.TemporaryDirectory() as tmp:
        text = re.sub(r"set Output directory\s*=.*", "set Output directory = %s" % tmp, text)
        path = os.path.join(tmp, "deck.prm")
        open(path, "w").write(text)
        status = subprocess.run([program, path], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL).returncode
        return status, json.load(open(os.path.join(tmp, "summary.json")))
