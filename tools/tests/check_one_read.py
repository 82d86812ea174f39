#!/usr/bin/env python3
"""Every command opens its .dat file once (issue 51: a probe read and a second parse made two, --mode 3
three). Runs each front end under strace and counts the opens of the model file: the command line
(simulate, --mode 3 of a dynamic and of a static file, static, modes), Python (read + simulate) and
spacar() in Octave, each given only when its program is there. Exit 1 on a count other than one, 77
(skipped) without strace. Run by ctest (dat_opened_once).

usage: check_one_read.py FLEXMB SOURCE_DIR WORK_DIR [PYTHONPATH] [OCTAVE_CLI GATEWAY_DIR]"""
import os
import re
import shutil
import subprocess
import sys

flexmb, src, work = sys.argv[1:4]
pythonpath = sys.argv[4] if len(sys.argv) > 4 and sys.argv[4] else None
octave, gateway = (sys.argv[5], sys.argv[6]) if len(sys.argv) > 6 and sys.argv[5] else (None, None)
strace = shutil.which("strace")
if not strace:
    print("check_one_read: no strace (apt install strace): skipped")
    sys.exit(77)
os.makedirs(work, exist_ok=True)
dat = os.path.join(src, "datfiles")


def opens(name, command, model, env=None):
    """The number of successful open/openat calls of `model` (by its file name) while `command` runs."""
    log = os.path.join(work, name + ".strace")
    run = subprocess.run([strace, "-f", "-qq", "-e", "trace=open,openat", "-o", log] + command, cwd=work,
                         env=dict(os.environ, **(env or {})), capture_output=True, text=True, timeout=600)
    if run.returncode != 0:
        print(f"{name}: exit {run.returncode}\n{run.stdout[-2000:]}\n{run.stderr[-2000:]}")
        return -1
    base = os.path.basename(model)
    pattern = re.compile(r'open(at)?\(.*"([^"]*/)?' + re.escape(base) + r'".*= \d+$')
    with open(log, errors="replace") as f:
        return sum(1 for line in f if pattern.search(line.strip()))


guidance = os.path.join(dat, "straight_guidance.dat")
cantilever = os.path.join(dat, "cantilever.dat")
pivot = os.path.join(dat, "spatial", "cross_spring_pivot_coarse.dat")  # no TIMESTEP: a static file
short = ["--t-end", "0.01", "-q", "--format", "none"]
cases = [
    ("simulate", [flexmb, "simulate", guidance] + short, guidance, None),
    ("mode3_dynamic", [flexmb, "--mode", "3", guidance, "--t-end", "0.01", "-q", "--out", "m3"], guidance, None),
    ("mode3_static", [flexmb, "--mode", "3", pivot, "-q", "--out", "m3s"], pivot, None),
    ("static", [flexmb, "static", cantilever, "-q", "--out", "st"], cantilever, None),
    ("modes", [flexmb, "modes", guidance, "-q", "--out", "mo"], guidance, None),
]
if pythonpath:
    code = ("import flexmb, sys; m = flexmb.read(sys.argv[1]); r = flexmb.simulate(m, t_end=0.01); "
            "assert r.completed")
    cases.append(("python", [sys.executable, "-c", code, guidance], guidance, {"PYTHONPATH": pythonpath}))
if octave:
    shutil.copy(guidance, os.path.join(work, "oct_guidance.dat"))
    code = (f"addpath('{gateway}'); r = spacar(-1, 'oct_guidance', struct('tend', 0.01)); "
            "assert(numel(r.time) > 1)")
    cases.append(("spacar", [octave, "--no-gui", "--norc", "--quiet", "--eval", code],
                  os.path.join(work, "oct_guidance.dat"), None))
bad = 0
for name, command, model, env in cases:
    n = opens(name, command, model, env)
    print(f"{name}: {n} open(s) of {os.path.basename(model)}")
    bad += n != 1
print(f"dat opened once: {len(cases) - bad} passed, {bad} failed")
sys.exit(1 if bad else 0)
