#!/usr/bin/env python3
"""Single-run economics (issue 49 item 6): process time against the error to the full model.

On the paper's guidance (5 PLBEAM per leaf), the guidance with 20 per leaf and the manipulator, runs
`flexmb simulate MODEL -q` as a user would: the full model (the default integrator and galpha at
RelTol 1e-3, 1e-4, 1e-5) and `--basis auto --target T` at 1e-2, 1e-3, 1e-4. Each command is timed
whole (the child's user + system time, median of --repeats). Error: the largest position difference
over the output times to a full run at RelTol 1e-7 (AbsTol 1e-10) of the same model, relative to its
motion (the measure of the target; tools/bench/basis_auto_effectivity.py). Prints a Markdown table
with the goal of item 6 (on the 20-element guidance, `--basis auto --target 1e-3` in at most half of
galpha at RelTol 1e-5, within 1e-3) and writes it to --out.

    python3 tools/bench/single_run_economics.py [--flexmb build/flexmb] [--repeats 3] [--out FILE]
"""
import argparse
import os
import statistics
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from basis_auto_effectivity import ROOT, chosen, printed_estimate, run, true_error  # noqa: E402

MODELS = [("guidance 5", "datfiles/straight_guidance.dat"),
          ("guidance 20", "datfiles/tests/straight_guidance_20.dat"),
          ("manipulator", "datfiles/manipulator.dat")]
FULL = ([("full, default integrator", [])]
        + [(f"full, galpha RelTol {t}", ["--integrator", "galpha", "--reltol", t]) for t in ("1e-3", "1e-4", "1e-5")])
AUTO = [(f"--basis auto --target {t}", ["--basis", "auto", "--target", t]) for t in ("1e-2", "1e-3", "1e-4")]
GOAL_MODEL, GOAL_AUTO, GOAL_FULL = "guidance 20", "--basis auto --target 1e-3", "full, galpha RelTol 1e-5"


def timed(flexmb, model, extra, out, repeats):
    """The median process time of `repeats` runs, with the last run's exit code and manifest."""
    times, rc, manifest = [], 0, ""
    for _ in range(repeats):
        seconds, rc, manifest = run(flexmb, model, extra, out)
        times.append(seconds)
    return statistics.median(times), rc, manifest


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--flexmb", default=os.path.join(ROOT, "build", "flexmb"))
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", default="")
    args = ap.parse_args()
    work = tempfile.mkdtemp(prefix="flexmb_economics_")
    lines = ["| model | command | process [s] | error to the full model | basis auto's choice | estimate printed |",
             "|---|---|---:|---:|---|---:|"]
    seconds = {}
    for name, model in MODELS:
        ref = os.path.join(work, name.replace(" ", "_") + "_ref")
        _, rc, _ = run(args.flexmb, model, ["--reltol", "1e-7", "--abstol", "1e-10", "--no-accuracy-check"], ref)
        if rc != 0:
            print(f"{name}: the reference run failed (exit {rc})", file=sys.stderr)
            continue
        for label, extra in FULL + AUTO:
            out = os.path.join(work, "run")
            s, rc, manifest = timed(args.flexmb, model, extra, out, args.repeats)
            err = true_error(out + "_x.csv", ref + "_x.csv")[0] if rc == 0 else float("nan")
            auto = "--basis" in extra
            seconds[(name, label)] = s
            lines.append(f"| {name} | `{label}` | {s:.2f} | {err:.2g} | {chosen(manifest) if auto else ''} | "
                         f"{printed_estimate(manifest):.2g} |" if auto else
                         f"| {name} | `{label}` | {s:.2f} | {err:.2g} | | |")
            if rc != 0:
                lines[-1] += f" (exit {rc})"
    a, f = seconds.get((GOAL_MODEL, GOAL_AUTO)), seconds.get((GOAL_MODEL, GOAL_FULL))
    if a is not None and f:
        lines.append("")
        lines.append(f"Item 6's goal on the 20-element guidance: `{GOAL_AUTO}` {a:.2f} s against `{GOAL_FULL}` "
                     f"{f:.2f} s: {a / f:.2f} of it (goal: at most 0.5; "
                     f"{'met' if a <= 0.5 * f else 'not met: the full model runs at once there, see tools/bench/README.md'}).")
    table = "\n".join(lines) + "\n"
    print(table)
    if args.out:
        with open(args.out, "w") as fh:
            fh.write(table)


if __name__ == "__main__":
    main()
