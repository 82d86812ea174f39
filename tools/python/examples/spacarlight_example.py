"""SPACAR Light's own example (spacarexample.m: a cross-spring pivot of two warping leaf springs and
a rigid body, under gravity, a moment from -0.025 to 0.025 N m and 1 N), written for flexmb.light:
the same nodes, elements, nprops, eprops and opt as Python lists and dicts. Run it to build the .dat
and turn the body through the load steps with flexmb:

    PYTHONPATH=build/python python3 tools/python/examples/spacarlight_example.py [--dat crosshinge.dat]
"""

import argparse
import math

import flexmb
from flexmb import light


def inputs():
    nodes = [[0.0, 0.0, 0.0],   # node 1: clamp of leaf 1
             [0.0, 0.1, 0.0],   # node 2
             [0.1, 0.1, 0.0],   # node 3: the body's end, loaded
             [0.1, 0.0, 0.0]]   # node 4: clamp of leaf 2
    elements = [[1, 3],         # leaf 1
                [2, 3],         # the rigid body
                [2, 4]]         # leaf 2
    nprops = {1: {"fix": True},
              3: {"force": [0, 1, 0],              # N, reached at the last load step
                  "moment_initial": [0, 0, -0.025],  # N m at load step 0 ...
                  "moment": [0, 0, 0.05],           # ... plus this: -0.025 -> 0.025 N m
                  "mass": 0.1},
              4: {"fix": True}}
    leaf = {"elems": [1, 3], "emod": 210e9, "smod": 70e9, "dens": 7800, "cshape": "rect", "dim": [50e-3, 0.2e-3],
            "orien": [0, 0, 1], "nbeams": 3, "flex": [1, 2, 3, 4, 5, 6], "color": "grey", "opacity": 0.7,
            "warping": True}
    body = {"elems": [2], "dens": 3000, "cshape": "rect", "dim": [50e-3, 10e-3], "orien": [0, 0, 1], "nbeams": 1,
            "color": "darkblue", "warping": True}
    opt = {"filename": "crosshinge", "gravity": [0, 0, -9.81]}
    return nodes, elements, nprops, [leaf, body], opt


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--dat", help="write the .dat here")
    args = ap.parse_args()
    b = light.build(*inputs())
    if args.dat:
        b.write(args.dat)
    print(b, "releases", b.releases)
    st = flexmb.static(b.model, nev=1)
    # The body's orientation: Euler parameters of SPACAR node 8 (user node 3's orientation node).
    lam = [b.model.coordinates.index(f"x(node 8, lambda{c})") for c in (0, 3)]
    turns = [2 * math.atan2(x[lam[1]], x[lam[0]]) for x in st.x]
    print(f"{len(turns)} load steps: the body turns from {turns[0]:.5f} to {turns[-1]:.5f} rad about z; "
          f"lowest frequency at the end {st.freq[-1][0]:.3f} Hz")


if __name__ == "__main__":
    main()
