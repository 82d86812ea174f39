"""A parallel leaf-spring stage in SPACAR Light's terms, built with flexmb.light: two leaves of
length L, w x t section, clamped at their feet and joined at their tips by a rigid stage; the stage
translates along x with stiffness 2 x 12 EI / L^3 = 24 EI / L^3 (each leaf clamped-guided).

    PYTHONPATH=build/python python3 tools/python/examples/parallel_leaf_stage.py [--nbeams 10] [--dat stage.dat]
"""

import argparse
import sys

import flexmb
from flexmb import light

L, A, W, T, E, G, RHO = 0.05, 0.05, 0.05, 0.2e-3, 210e9, 70e9, 7800.0


def inputs(nbeams=10, force=1.0):
    nodes = [[0, 0, 0],    # 1: foot of leaf 1
             [0, 0, L],    # 2: tip of leaf 1, one end of the stage (the force acts here)
             [A, 0, 0],    # 3: foot of leaf 2
             [A, 0, L]]    # 4: tip of leaf 2
    elements = [[1, 2], [3, 4], [2, 4]]
    nprops = {1: {"fix": True}, 3: {"fix": True}, 2: {"force": [force, 0, 0]}}
    leaves = {"elems": [1, 2], "emod": E, "smod": G, "dens": RHO, "cshape": "rect", "dim": [W, T],
              "orien": [0, 1, 0], "nbeams": nbeams, "flex": [1, 2, 3, 4, 5, 6], "color": "grey"}
    stage = {"elems": [3], "dens": RHO, "cshape": "rect", "dim": [0.02, 0.02], "orien": [0, 1, 0],
             "color": "darkblue"}
    return nodes, elements, nprops, [leaves, stage], {"filename": "leafstage", "loadsteps": 2}


def stiffness(b):
    """The stage's stiffness along x: 1 / compliance at user node 2 in the unloaded state."""
    st = flexmb.static(b.model, nev=0, compliance=[b.node(2)[0]])
    return 1 / st.compliance[b.node(2)[0]][0][0, 0]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--nbeams", type=int, default=10)
    ap.add_argument("--dat", help="write the .dat here")
    args = ap.parse_args()
    b = light.build(*inputs(args.nbeams))
    if args.dat:
        b.write(args.dat)
    k, EI = stiffness(b), E * W * T**3 / 12
    print(b, "releases", b.releases)
    print(f"stiffness along x {k:.2f} N/m; 24 EI / L^3 = {24 * EI / L**3:.2f} N/m")
    return 0 if abs(k / (24 * EI / L**3) - 1) < 1e-3 else 1  # shear and elongation: 7e-5 here


if __name__ == "__main__":
    sys.exit(main())
