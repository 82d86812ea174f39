"""Issue 53 item 1 from Python: static's von Mises stresses, support reactions and compliance matrices
(analysis/StaticDesign.hpp) on datfiles/cantilever.dat with a 20 x 2 mm section, against beam theory
and the command line's files. Run by ctest (python_tests) with PYTHONPATH=<build>/python and
FLEXMB=<build>/flexmb."""

import csv
import os
import subprocess

import numpy as np
import pytest

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))
EA, EI, L = 8.4e6, 2.8, 1.0


def sectioned(tmp_path):
    with open(os.path.join(SRC, "datfiles", "cantilever.dat")) as f:
        text = f.read()
    path = tmp_path / "cantilever.dat"
    path.write_text(text + "VISUALIZATION\nBEAMPROPS 1 2 3 4\nCROSSTYPE RECT\nCROSSDIM 0.02 0.002\n")
    return str(path)


def test_compliance_reactions_and_stress_are_beam_theory(tmp_path):
    r = flexmb.static(flexmb.read(sectioned(tmp_path)), nev=0, compliance=[5])
    assert r.compliance_names[5] == ["x", "y", "angle"]
    C0 = r.compliance[5][0]  # load step 0: unloaded
    assert C0[0, 0] == pytest.approx(L / EA, rel=1e-9)
    assert C0[1, 1] == pytest.approx(L**3 / (3 * EI), rel=1e-9)
    assert C0[1, 2] == pytest.approx(L**2 / (2 * EI), rel=1e-9)
    assert C0[2, 2] == pytest.approx(L / EI, rel=1e-9)
    names = r.reaction_names
    assert names == ["R.F.node1.x", "R.F.node1.y", "R.M.node101.angle"]
    assert r.reactions[-1, 1] == pytest.approx(0.1, abs=1e-12)  # the tip load -0.1 N along y
    assert r.stress_elements == [1, 2, 3, 4]
    I = 0.02 * 0.002**3 / 12
    assert r.stressmax[-1] == pytest.approx(0.1 * L * 0.001 / I, rel=1e-4)
    assert r.stress[-1, 0] == r.stressmax[-1]


def test_same_as_the_command_line(tmp_path):
    model = sectioned(tmp_path)
    r = flexmb.static(flexmb.read(model), nev=0, compliance=[5])
    subprocess.run([CLI, "static", model, "--nev", "0", "--compliance", "5", "--out", str(tmp_path / "s.csv"), "-q"],
                   check=True, capture_output=True)
    with open(tmp_path / "s_compliance.csv") as f:
        rows = [row for row in csv.DictReader(f) if row["load_step"] == "1"]
    cli = np.array([[float(row[c]) for c in ("x", "y", "angle")] for row in rows])
    np.testing.assert_allclose(r.compliance[5][-1], cli, rtol=1e-12)


def test_unknown_node_is_refused(tmp_path):
    with pytest.raises(Exception, match="77"):
        flexmb.static(flexmb.read(sectioned(tmp_path)), compliance=[77])


def test_sweep_table_has_the_largest_stress_and_reactions(tmp_path):
    """The sweep's columns in Python are the CSV's: max_stress and the reactions per configuration."""
    m = flexmb.read(os.path.join(SRC, "datfiles", "spatial", "cross_spring_pivot.dat"))
    sw = flexmb.sweep(m, node=4, component=3, start=-0.1, stop=0.1, steps=5)
    t = sw.table
    assert len(t["max_stress"]) == 5
    sw.write(str(tmp_path / "pv.csv"))
    with open(tmp_path / "pv.csv") as f:
        rows = list(csv.DictReader(f))
    for k, row in enumerate(rows):
        assert t["max_stress"][k] == pytest.approx(float(row["max_stress"]), rel=1e-9)
        assert t["R.F.node1.z"][k] == pytest.approx(float(row["R.F.node1.z"]), rel=1e-9, abs=1e-15)
    # The pivot's von Mises stress grows with the rotation: the ends exceed the middle.
    assert t["max_stress"][0] > t["max_stress"][2] and t["max_stress"][4] > t["max_stress"][2]


def test_static_write_plots_as_the_command_line(tmp_path):
    """write(path, plot=[...]) draws the force-deflection plot static --plot draws, byte for byte."""
    model = sectioned(tmp_path)
    r = flexmb.static(flexmb.read(model), nev=0)
    assert r.write(str(tmp_path / "py.csv"), plot=["node5.y"]) == str(tmp_path / "py.csv")
    subprocess.run([CLI, "static", model, "--nev", "0", "--plot", "node5.y", "--out", str(tmp_path / "cli.csv"), "-q"],
                   check=True, capture_output=True)
    py = (tmp_path / "py_force_deflection.svg").read_text()
    cli = (tmp_path / "cli_force_deflection.svg").read_text()
    assert py == cli
    with pytest.raises(ValueError, match="node99"):
        r.write(str(tmp_path / "bad.csv"), plot=["node99.y"])
