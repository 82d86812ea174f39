"""A cross-spring pivot tuned with scipy.optimize: the leaf thickness t and width w that give a target
rotational stiffness with the lowest bending stress at the pivot's stroke, under a stress limit.

    PYTHONPATH=build/python python3 tools/python/examples/pivot_stiffness.py [--plot pivot.png]

The model is the design-study template datfiles/spatial/cross_spring_pivot_study.dat (leaf sections
computed from t and w, gravity, the template's loads), instantiated in memory for every design
(flexmb.variant: no files). Per design two analyses:
  * stiffness: flexmb.transfer with a moment about z on the platform (node 4) as input and its
    rotation as output; the static gain is the compliance, its inverse the stiffness (N m/rad);
  * stress: flexmb.static with the moment k * stroke on the platform (it turns by about the stroke); the leaves' bending moments
    (generalised stresses times the element length, analysis/Study.cpp) give sigma = 6 M / (w t^2).
Exits with 1 when the optimum misses the target stiffness by more than 0.1 % or the limit.
"""

import argparse
import math
import os
import sys

import numpy as np
import scipy.optimize

import flexmb

SRC = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..")
TARGET = 0.5  # N m/rad
STROKE = 0.1  # rad
LIMIT = 300e6  # Pa
E = 210e9

template = open(os.path.join(SRC, "datfiles", "spatial", "cross_spring_pivot_study.dat")).read()
# The platform's moment as a parameter, and a transfer block (SPACAR mode 9) after the static one.
moment_line = next(ln for ln in template.splitlines() if ln.split()[:2] == ["DELXF", "4"])
template = template.replace(moment_line, "DELXF 4 0 0 {M ?= 0}")
head, tail = template.split("\nEND\nEND\n", 1)
transfer_template = head + "\nEND\nHALT\nINPUTF 1 4 3\nOUTX 1 4 3\nEND\nEND\n" + tail
static_template = template


def stiffness(t, w):
    run = flexmb.transfer(flexmb.variant(transfer_template, "pivot.dat", t=t, w=w))
    return 1.0 / run.static_gain()[0, 0]


def leaf_stress(t, w, k):
    """The largest bending stress in the leaves with the platform turned by STROKE (moment k STROKE)."""
    m = flexmb.variant(static_template, "pivot.dat", t=t, w=w, M=k * STROKE)
    run = flexmb.static(m, nev=0)
    if not run.completed:
        raise RuntimeError(run.stop_reason)
    x0 = m.x0
    worst = 0.0
    for el in m.elements[:6]:  # the leaves (element 7 is the platform)
        first = m.deformations.index(f"e(BEAM {el['number']}, 1 elongation)")
        # Element length from its end nodes' initial positions (position nodes: x, y, z).
        a, b = (m.coordinates.index(f"x(node {n}, x)") for n in (el["nodes"][0], el["nodes"][2]))
        length = np.linalg.norm(x0[b:b + 3] - x0[a:a + 3])
        bending = run.sig[-1, first + 2:first + 4] * length  # bending about the local y axis: in the plane
        worst = max(worst, np.max(np.abs(bending)) * 6 / (w * t * t))
    return worst


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--plot", help="write the stiffness and stress over t to this PNG (matplotlib)")
    args = parser.parse_args()

    scale = np.array([1e-3, 1e-2])  # variables in mm and cm: comparable magnitudes for SLSQP
    evaluations = [0]

    def k_of(z):
        evaluations[0] += 1
        t, w = z * scale
        return stiffness(t, w)

    def stress_of(z):
        t, w = z * scale
        return leaf_stress(t, w, stiffness(t, w))

    result = scipy.optimize.minimize(
        lambda z: 10 * stress_of(z) / LIMIT, x0=np.array([0.3, 3.0]), method="SLSQP",
        bounds=[(0.05, 1.0), (1.0, 5.0)],
        constraints=[{"type": "eq", "fun": lambda z: k_of(z) / TARGET - 1.0},
                     {"type": "ineq", "fun": lambda z: 1.0 - stress_of(z) / LIMIT}],
        options={"ftol": 1e-9, "maxiter": 100, "eps": 1e-5})
    t, w = result.x * scale
    k = stiffness(t, w)
    sigma = leaf_stress(t, w, k)
    print(f"{result.message} ({result.nit} iterations, {evaluations[0]} stiffness evaluations)")
    print(f"leaf thickness t = {t * 1e3:.4f} mm, width w = {w * 1e3:.2f} mm")
    print(f"rotational stiffness {k:.6g} N m/rad (target {TARGET}), bending stress at {STROKE} rad "
          f"{sigma / 1e6:.1f} MPa (limit {LIMIT / 1e6:.0f} MPa)")
    ok = abs(k / TARGET - 1) < 1e-3 and sigma <= LIMIT * (1 + 1e-6)

    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        ts = np.linspace(0.5 * t, 1.5 * t, 15)
        ks = [stiffness(ti, w) for ti in ts]
        ss = [leaf_stress(ti, w, ki) / 1e6 for ti, ki in zip(ts, ks)]
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.plot(ts * 1e3, ks, "b-", label="stiffness")
        ax.axhline(TARGET, color="b", ls=":", lw=0.8)
        ax.plot([t * 1e3], [k], "bo")
        ax.set_xlabel(f"leaf thickness t [mm] (w = {w * 1e3:.1f} mm)")
        ax.set_ylabel("rotational stiffness [N m/rad]", color="b")
        ax2 = ax.twinx()
        ax2.plot(ts * 1e3, ss, "r-", label="stress")
        ax2.axhline(LIMIT / 1e6, color="r", ls=":", lw=0.8)
        ax2.set_ylabel(f"bending stress at {STROKE} rad [MPa]", color="r")
        ax.set_title("Cross-spring pivot tuned with scipy.optimize (flexmb)")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=100)
        print(f"wrote {args.plot}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
