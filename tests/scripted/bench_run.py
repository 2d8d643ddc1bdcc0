"""What the scripted veil-bench tests share: the checks they print and count, and one run of
veil-bench that returns its JSON (standard library only; imported from the scripts' folder)."""
import json
import os
import subprocess

failures = []


def check(ok, what):
    print(("ok   " if ok else "FAIL ") + what, flush=True)
    if not ok:
        failures.append(what)


def run_bench(cmd, out, cwd, timeout):
    """Runs `cmd` (which writes `out`): (its JSON, the process), or (None, the process) when it
    failed."""
    if os.path.exists(out):
        os.remove(out)
    p = subprocess.run(cmd, capture_output=True, text=True, cwd=cwd, timeout=timeout)
    if p.returncode != 0:
        return None, p
    with open(out) as f:
        return json.load(f), p
