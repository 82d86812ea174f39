#!/usr/bin/env python3
"""Effectivity of `simulate --basis auto --target T` on models the estimate was not calibrated on
(issue 49 item 4).

For each model: a full reference run at RelTol 1e-8 (AbsTol 1e-10, the default integrator), then
`flexmb simulate MODEL --basis auto --target T` at each target. From the run's manifest: the basis
chosen and the estimate it printed (the `basis auto estimate` line: reduction + integration error,
relative to the motion; older builds print only the reduction estimate, then that is used). The true
error is the same measure against the reference: the largest |x_run - x_ref| of any position
coordinate over the output times, relative to the reference's motion (the largest displacement of
a position coordinate from its start). Process time is the child's user + system time.

    /usr/bin/python3 tools/bench/basis_auto_effectivity.py [--flexmb build/flexmb] [--models a,b]
        [--targets 1e-2,1e-3] [--out DIR] [--markdown]

Run it under the build lock when the times matter (flock /tmp/flexmb-build.lock ...).
"""
import argparse
import csv
import os
import re
import resource
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))

# name, model file (from the repository root), extra options for every run of it.
MODELS = [
    ("guidance", "datfiles/straight_guidance.dat", []),
    ("manipulator", "datfiles/manipulator.dat", []),
    ("fourbar-flex", "datfiles/tests/fourbar_flexible.dat", []),
    ("pivot-pulse", "datfiles/tests/pivot_coarse_pulse.dat", []),
    ("leaf-stage-step", "datfiles/tests/leaf_stage_step.dat", []),
    ("elbow-6s", "datfiles/spatial/elbow.dat", ["--t-end", "6", "--intervals", "60"]),
]


def run(flexmb, model, extra, out):
    """Runs flexmb simulate; returns (process seconds, exit code, manifest text)."""
    cmd = [flexmb, "simulate", os.path.join(ROOT, model), "-q", "--out", out] + extra
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    seconds = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    manifest = ""
    if os.path.exists(out + "_run.txt"):
        with open(out + "_run.txt") as f:
            manifest = f.read()
    return seconds, p.returncode, manifest


def positions(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    head = rows[0]
    cols = [i for i, n in enumerate(head) if n.endswith((".x", ".y", ".z"))]
    data = [[float(r[i]) for i in cols] for r in rows[1:]]
    return [head[i] for i in cols], data


def true_error(run_csv, ref_csv):
    names_a, a = positions(run_csv)
    names_b, b = positions(ref_csv)
    if names_a != names_b or len(a) != len(b):
        return float("nan"), float("nan")
    motion = max(abs(r[i] - b[0][i]) for r in b for i in range(len(names_b)))
    worst = max(abs(x - y) for ra, rb in zip(a, b) for x, y in zip(ra, rb))
    return worst / motion, motion


def setting(manifest, name):
    m = re.search(r"^" + re.escape(name) + r": (.*)$", manifest, re.M)
    return m.group(1) if m else ""


def printed_estimate(manifest):
    """The estimate the run printed, relative to the motion: the basis auto estimate (reduction +
    integration), else the reduction estimate alone."""
    line = setting(manifest, "basis auto estimate")
    if line:
        m = re.match(r"([0-9.eE+-]+)", line)
        return float(m.group(1)) if m else float("nan")
    line = setting(manifest, "reduction error estimate")
    m = re.match(r"([0-9.eE+-]+)", line)
    return float(m.group(1)) if m else float("nan")


def chosen(manifest):
    basis = setting(manifest, "basis")
    m = re.match(r"auto: (\d+) columns", basis)
    if m:
        return m.group(1) + " col"
    if "the full model" in basis:
        return "full"
    return basis[:30] or "?"


def tried(manifest):
    basis = setting(manifest, "basis")
    m = re.search(r"tried (.*?); choosing took", basis)
    return m.group(1) if m else ""


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--flexmb", default=os.path.join(ROOT, "build", "flexmb"))
    ap.add_argument("--models", default="")
    ap.add_argument("--targets", default="1e-2,1e-3")
    ap.add_argument("--out", default="")
    ap.add_argument("--markdown", action="store_true")
    args = ap.parse_args()
    targets = [float(t) for t in args.targets.split(",")]
    wanted = set(args.models.split(",")) if args.models else None
    out = args.out or tempfile.mkdtemp(prefix="flexmb_eff_")
    os.makedirs(out, exist_ok=True)
    rows = []
    for name, model, extra in MODELS:
        if wanted and name not in wanted:
            continue
        ref = os.path.join(out, name + "_ref")
        ref_s, rc = float("nan"), 0
        if not os.path.exists(ref + "_x.csv"):  # kept in --out: the references take minutes on the spatial models
            ref_s, rc, _ = run(args.flexmb, model, extra + ["--reltol", "1e-8", "--abstol", "1e-10",
                                                            "--no-accuracy-check"], ref)
        if rc != 0:
            print(f"{name}: reference failed (exit {rc})", file=sys.stderr)
            continue
        for t in targets:
            o = os.path.join(out, f"{name}_{t:g}")
            s, rc, man = run(args.flexmb, model, extra + ["--basis", "auto", "--target", f"{t:g}"], o)
            err, motion = true_error(o + "_x.csv", ref + "_x.csv") if rc == 0 else (float("nan"), float("nan"))
            est = printed_estimate(man)
            eff = est / err if err > 0 else float("nan")
            rows.append((name, t, chosen(man), est, err, eff, s, err <= t, ref_s, tried(man), rc))
            print(f"{name} {t:g}: {chosen(man)} est {est:.2g} true {err:.2g} eff {eff:.2g} {s:.2f} s "
                  f"(ref {ref_s:.2f} s) met {err <= t} exit {rc}; tried {tried(man)}", file=sys.stderr)
    if args.markdown:
        print("| model | target | basis chosen | estimate printed | true error | effectivity | process [s] | "
              "met? | full reference at 1e-8 [s] |")
        print("|---|---:|---|---:|---:|---:|---:|---|---:|")
        for r in rows:
            print(f"| {r[0]} | {r[1]:g} | {r[2]} | {r[3]:.2g} | {r[4]:.2g} | {r[5]:.2g} | {r[6]:.2f} | "
                  f"{'yes' if r[7] else 'NO'} | {r[8]:.2f} |")
    else:
        print(f"{'model':16} {'target':>7} {'basis':>8} {'estimate':>9} {'true':>9} {'eff':>6} {'proc s':>7} met")
        for r in rows:
            print(f"{r[0]:16} {r[1]:7g} {r[2]:>8} {r[3]:9.2g} {r[4]:9.2g} {r[5]:6.2g} {r[6]:7.2f} "
                  f"{'yes' if r[7] else 'NO'}")


if __name__ == "__main__":
    main()
