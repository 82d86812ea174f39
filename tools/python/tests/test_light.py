"""Issue 53 item 5: flexmb.light, SPACAR Light's model description in Python. Always: the parallel
leaf-spring stage built with it translates with 24 EI / L^3 and has 2 nbeams + 1 beams; the section
constants are the closed forms; bad inputs are refused by name. With a copy of SPACAR Light
(FLEXMB_SPALIGHT_DIR or tools/octave/public/spalight, tools/octave/fetch_public_scripts.sh) and
octave-cli: spacarlight.m, run in Octave with flexmb's spacar mex, writes its .dat for SPACAR Light's
own example and for models that use the other fields, and the builder's .dat for the same inputs is
compared statement by statement: keyword for keyword, integer for integer, and every number equal
to SPACAR Light's (digits="spacarlight") or within half a unit of its last printed decimal (full
precision). Comments and spacing are not compared. Run by ctest (python_tests)."""

import math
import os
import re
import shutil
import subprocess
import sys

import numpy as np
import pytest

import flexmb
from flexmb import light

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))
sys.path.insert(0, os.path.join(SRC, "tools", "python", "examples"))
import parallel_leaf_stage  # noqa: E402
import spacarlight_example  # noqa: E402


# ---- always ----------------------------------------------------------------------------------------


@pytest.mark.parametrize("nbeams", [1, 4, 10])
def test_leaf_stage_translates_with_24EI_over_L3(nbeams):
    b = light.build(*parallel_leaf_stage.inputs(nbeams))
    assert [len(x) for x in b.beams] == [nbeams, nbeams, 1]
    assert len(b.model.elements) == 2 * nbeams + 1
    assert b.dat.count("\nBEAM ") == 2 * nbeams + 1 and "BEAMW" not in b.dat
    assert sum(map(len, b.releases)) == 6  # one closed loop: six deformations released
    s = parallel_leaf_stage
    EI = s.E * s.W * s.T**3 / 12
    # Beam theory without shear and axial compliance; flexmb's beams carry both (7e-5 here).
    assert parallel_leaf_stage.stiffness(b) == pytest.approx(24 * EI / s.L**3, rel=2e-4)


def test_example_is_well_posed_with_spacarlights_releases():
    b = light.build(*spacarlight_example.inputs())
    assert flexmb.check(b.model)["well_posed"]
    assert b.releases == [[2, 4, 6], [], [3, 4, 6]]  # what spacarlight.m chose (test below)
    assert b.beams == [[1, 2, 3], [4], [5, 6, 7]]
    assert b.dat.count("\nBEAMW ") == 7
    # The rigid warping body: its warping nodes fixed, as the clamps'.
    fixes = re.findall(r"^FIX\s+(\d+)\s+# warping", b.dat, re.M)
    assert fixes == ["3", "6", "9", "12"]


def test_section_constants_are_the_closed_forms():
    w, t, E, G, rho = 0.05, 0.2e-3, 210e9, 70e9, 7800.0
    e = {"cshape": "rect", "dim": np.array([w, t]), "emod": E, "smod": G, "dens": rho}
    k = light.stiffness(e)
    assert k[0] == pytest.approx(E * w * t, rel=1e-15)
    assert k[2] == pytest.approx(E * w * t**3 / 12, rel=1e-15) and k[3] == pytest.approx(E * t * w**3 / 12, rel=1e-15)
    # Thin strip: It = w t^3 / 3 (1 - 0.630 t / w) to O((t/w)^5).
    assert k[1] / G == pytest.approx(w * t**3 / 3 * (1 - 0.6302 * t / w), rel=1e-5)
    nu = E / (2 * G) - 1
    assert k[4] == pytest.approx(k[2] / (G * w * t * 10 * (1 + nu) / (12 + 11 * nu)), rel=1e-15)
    assert k[6] == pytest.approx(E * (w * t) ** 3 / 144, rel=1e-15)
    m = light.inertia(e)
    assert m[:4] == pytest.approx([rho * w * t, rho * w * t * (w**2 + t**2) / 12, rho * w * t**3 / 12,
                                   rho * t * w**3 / 12], rel=1e-14)
    d = 0.01
    c = light.stiffness({"cshape": "circ", "dim": np.array([d]), "emod": E, "smod": G})
    assert c[1] / G == pytest.approx(math.pi * d**4 / 32, rel=1e-15) and c[6] == 0


def test_write_and_unpack(tmp_path):
    dat, model = b = light.build(*parallel_leaf_stage.inputs(2))
    path = b.write(tmp_path / "stage.dat")
    assert open(path).read() == dat
    assert len(flexmb.read(path).elements) == len(model.elements) == 5


@pytest.mark.parametrize("change, message", [
    (lambda n, e, p, s, o: s[0].update(cshape="square"), "cshape"),
    (lambda n, e, p, s, o: s[0].update(colour="red"), "unknown field 'colour'"),
    (lambda n, e, p, s, o: s[0].update(flex=[1, 7]), "flex"),
    (lambda n, e, p, s, o: s[0].pop("emod"), "needs emod"),
    (lambda n, e, p, s, o: s[1].update(elems=[2]), "already has properties"),
    (lambda n, e, p, s, o: s[0].update(orien=[0, 0, 1]), "along element"),
    (lambda n, e, p, s, o: p.update({9: {"fix": True}}), "node 9 does not exist"),
    (lambda n, e, p, s, o: n.append([1, 1, 1]), r"nodes \[5\] belong to no element"),
    (lambda n, e, p, s, o: p[2].update(rot_x=0.1, rot_z=0.2), "more than one rotational input"),
    (lambda n, e, p, s, o: o.update(mode=4), "mode"),
    (lambda n, e, p, s, o: o.update(transfer=[True, 0.01]), "no nprops force"),
    (lambda n, e, p, s, o: o.update(speed=1), "unknown field 'speed'"),
])
def test_bad_inputs_are_refused_by_name(change, message):
    args = parallel_leaf_stage.inputs(2)
    change(*args)
    with pytest.raises(ValueError, match=message):
        light.build(*args)


def test_a_rigid_loop_is_refused():
    nodes, elements, nprops, eprops, opt = parallel_leaf_stage.inputs(2)
    eprops[0]["flex"] = [4]  # leaves that only bend about one axis cannot close the loop
    with pytest.raises(ValueError, match="overconstraint"):
        light.build(nodes, elements, nprops, eprops, opt)


# ---- against SPACAR Light ------------------------------------------------------------------------------

SPALIGHT = os.environ.get("FLEXMB_SPALIGHT_DIR") or os.path.join(SRC, "tools", "octave", "public", "spalight")
MEX = os.path.join(os.path.dirname(os.path.abspath(CLI)), "octave")
OCTAVE = shutil.which("octave-cli")
needs_spalight = pytest.mark.skipif(
    not (OCTAVE and os.path.isfile(os.path.join(SPALIGHT, "spacarlight.m")) and
         os.path.isfile(os.path.join(MEX, "spacar.mex"))),
    reason=f"SKIPPED (comparison with SPACAR Light): needs octave-cli, flexmb's spacar mex in {MEX} and "
           f"spacarlight.m in {SPALIGHT} (tools/octave/fetch_public_scripts.sh or FLEXMB_SPALIGHT_DIR)")


def statements(text):
    """The .dat as (keyword, tokens) per line, comments and blank lines dropped."""
    out = []
    for line in text.splitlines():
        tokens = line.split("#", 1)[0].split()
        if tokens:
            out.append(tokens)
    return out


def compare(mine, theirs, exact):
    """Differences between the builder's .dat and SPACAR Light's, one line each (empty: none)."""
    a, b = statements(mine), statements(theirs)
    diffs = []
    if len(a) != len(b):
        diffs.append(f"{len(a)} statements against SPACAR Light's {len(b)}")
    for i, (x, y) in enumerate(zip(a, b)):
        same = len(x) == len(y)
        for u, v in zip(x, y):
            if not same:
                break
            if u == v:
                continue
            try:
                fu, fv = float(u), float(v)
            except ValueError:
                same = False
                break
            decimals = len(v.split(".")[1]) if "." in v else 0
            same = not exact and abs(fu - fv) <= 0.5 * 10.0**-decimals * (1 + 1e-9) + 1e-15 * abs(fv)
        if not same:
            diffs.append(f"statement {i + 1}: {' '.join(x)}  /  SPACAR Light: {' '.join(y)}")
    return diffs


def m_value(v):
    """A Python value as an Octave literal."""
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, str):
        return f"'{v}'"
    if isinstance(v, (list, tuple)) and v and all(isinstance(x, str) for x in v):
        return "{" + ", ".join(f"'{x}'" for x in v) + "}"
    a = np.asarray(v, dtype=float)
    if a.ndim == 0:
        return repr(float(a))
    if a.ndim == 1:
        return "[" + " ".join(repr(float(x)) for x in a) + "]"
    return "[" + "; ".join(" ".join(repr(float(x)) for x in row) for row in a) + "]"


def spacarlight_dat(tmp_path, nodes, elements, nprops, eprops, opt):
    """Runs spacarlight.m on the inputs in Octave (flexmb's spacar) and returns the .dat it wrote."""
    lines = [f"nodes = {m_value(nodes)};", f"elements = {m_value(elements)};"]
    items = nprops.items() if isinstance(nprops, dict) else enumerate(nprops, 1)
    for n, p in items:
        lines += [f"nprops({n}).{k} = {m_value(v)};" for k, v in (p or {}).items()]
    for i, e in enumerate(eprops, 1):
        lines += [f"eprops({i}).{k} = {m_value(v)};" for k, v in e.items()]
    for k, v in opt.items():
        if k == "transfer":
            lines.append(f"opt.transfer = {{{m_value(v[0])} {m_value(v[1])}}};")
        elif k == "rls":
            lines += [f"opt.rls({i}).def = {m_value(r)};" for i, r in enumerate(v, 1)]
        elif k.startswith("custom"):
            lines.append(f"opt.{k} = {m_value(list(v))};")
        else:
            lines.append(f"opt.{k} = {m_value(v)};")
    lines += ["opt.spavisual = false;", "try", "  out = spacarlight(nodes, elements, nprops, eprops, opt);",
              "catch err", "  disp(err.message);", "end"]
    (tmp_path / "run_light.m").write_text("\n".join(lines) + "\n")
    return run_octave(tmp_path, "run_light", opt.get("filename", "spacar_file") + ("_3" if opt.get("mode") == 3 else ""))


def run_octave(tmp_path, script, name):
    cmd = [OCTAVE, "--no-gui", "--norc", "--quiet", "--eval",
           f"addpath('{MEX}'); addpath('{SPALIGHT}'); warning('off', 'all'); cd('{tmp_path}'); {script}"]
    r = subprocess.run(cmd, capture_output=True, text=True, timeout=300)
    path = tmp_path / f"{name}.dat"
    assert path.exists(), f"spacarlight.m wrote no {path.name}:\n{r.stdout[-2000:]}\n{r.stderr[-2000:]}"
    return path.read_text()


def check_both(theirs, args):
    for digits in ("spacarlight", "full"):
        b = light.build(*args, digits=digits)
        diffs = compare(b.dat, theirs, exact=digits == "spacarlight")
        assert not diffs, f"digits={digits}:\n" + "\n".join(diffs[:20])
    return b


@needs_spalight
def test_spacarlights_own_example_gives_the_same_dat(tmp_path):
    # spacarexample.m as published (the figure switched off: not part of the .dat).
    script = open(os.path.join(SPALIGHT, "spacarexample.m")).read().replace("\nclc", "\n")
    script = script.replace("%% CALL SPACAR_LIGHT", "opt.spavisual = false;\n%% CALL SPACAR_LIGHT")
    (tmp_path / "published.m").write_text(script)
    theirs = run_octave(tmp_path, "published", "crosshinge")
    b = check_both(theirs, spacarlight_example.inputs())
    assert "RLSE" in theirs and b.releases == [[2, 4, 6], [], [3, 4, 6]]


@needs_spalight
@pytest.mark.parametrize("nbeams", [1, 5])
def test_leaf_stage_gives_the_same_dat(tmp_path, nbeams):
    args = parallel_leaf_stage.inputs(nbeams)
    check_both(spacarlight_dat(tmp_path, *args), args)


def variant_inputs(kind):
    """Models that use SPACAR Light's other fields (loads, inputs, fixes, sections, options)."""
    nodes, elements, nprops, eprops, opt = parallel_leaf_stage.inputs(3)
    opt = {"filename": f"v_{kind}"}
    if kind == "transfer":
        nprops = {1: {"fix": True}, 3: {"fix": True}, 2: {"transfer_in": ["force_x", "force_z"], "mass": 0.2,
                                                          "mominertia": [1e-4, 0, 0, 2e-4, 0, 3e-4]},
                  4: {"transfer_out": ["displ_x", "veloc_x", "displ_z"]}}
        opt.update(transfer=[True, 0.02], gravity=[0, 0, -9.81])
    elif kind == "mode3":
        nprops = {1: {"fix": True}, 3: {"fix": True}, 2: {"force_initial": [0.5, 0, 0], "moment": [0, 0.01, 0],
                                                          "mass": 0.2}}
        opt.update(mode=3, loadsteps=4)
    elif kind == "motions":
        # A driven stage: node 2 moved along x (initial and increment), leaf 2's foot turned about
        # y; fixes per direction; a round stage; an element outside every set; custom commands.
        nodes = np.vstack([nodes, [[A, 0.0, L + 0.02] for A, L in [(0.05, 0.05)]]])
        elements = np.vstack([elements, [[4, 5]]])
        nprops = {1: {"fix": True}, 2: {"displ_initial_x": 1e-4, "displ_x": 2e-3},
                  3: {"fix_pos": True, "rot_initial_y": 0.001, "fix_warp": False},
                  4: {"fix_z": True, "force": [0, 0.3, 0]}, 5: {"mass": 0.05, "moment_initial": [0, 0, 0.001]}}
        eprops[1].update(cshape="circ", dim=[0.01], hide=True, opacity=0.5)
        eprops[0].update(color=[255, 0, 0], nbeams=2)
        opt.update(loadsteps=3, gravity=[0, -9.81, 0], customdyn=["EDAMP 1 0.001"], customvis=["NODESIZE 2"])
    elif kind == "rls":
        opt.update(rls=[[1, 2, 3, 4, 5, 6]])
        eprops[0]["warping"] = True
        eprops[1]["warping"] = True
        eprops[0]["color"] = 3
    return nodes, elements, nprops, eprops, opt


@needs_spalight
@pytest.mark.parametrize("kind", ["transfer", "mode3", "motions", "rls"])
def test_other_fields_give_the_same_dat(tmp_path, kind):
    args = variant_inputs(kind)
    check_both(spacarlight_dat(tmp_path, *args), args)


def test_comparison_can_fail():
    # The comparison itself: a changed number, keyword or statement count is reported.
    b = light.build(*spacarlight_example.inputs(), digits="spacarlight")
    assert compare(b.dat, b.dat, exact=True) == []
    assert compare(b.dat.replace("0.100000", "0.100001", 1), b.dat, exact=True)
    assert compare(b.dat.replace("DELXF", "XF", 1), b.dat, exact=False)
    assert compare(b.dat.replace("XM", "# XM"), b.dat, exact=False)
    full = light.build(*spacarlight_example.inputs()).dat
    assert compare(full, b.dat, exact=False) == [] and compare(full, b.dat, exact=True)
