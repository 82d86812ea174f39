"""refine= (every flexible beam split in N, `--refine N`): the same model as read(path, refine=N) and
as the command line's, the original nodes under their labels, bad values refused."""

import os
import subprocess

import numpy as np
import pytest

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))
GUIDANCE = os.path.join(SRC, "datfiles", "straight_guidance.dat")


def test_modes_refine_two(tmp_path):
    m = flexmb.read(GUIDANCE)
    r = flexmb.modes(m, refine=2)
    assert r.freq.shape == (6,)
    same = flexmb.modes(flexmb.read(GUIDANCE, refine=2))
    np.testing.assert_array_equal(r.freq, same.freq)
    assert m.refined(2).ndof == 20 * 2 - 3  # every flexure bending but the 3 released ones
    assert m.ndof == 17  # the model itself is unchanged
    # The first frequency of the paper's guidance hardly moves (a cubic beam is nearly exact), and
    # a finer mesh never raises it.
    coarse = flexmb.modes(m).freq[0]
    assert r.freq[0] <= coarse * (1 + 1e-12)
    assert abs(r.freq[0] - coarse) < 1e-3 * coarse
    # The command line's `modes --refine 2` prints the same frequencies.
    out = subprocess.run([CLI, "modes", GUIDANCE, "--refine", "2", "--out", str(tmp_path / "g")],
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    assert "refined: every flexible beam split in 2" in out.stderr
    printed = [float(line.split()[1]) for line in out.stdout.splitlines()
               if line.strip() and line.split()[0] in {"1", "2", "3", "4", "5", "6"} and len(line.split()) == 3]
    np.testing.assert_allclose(printed, r.freq, rtol=1e-7)


def test_refine_keeps_the_original_nodes():
    m = flexmb.read(GUIDANCE)
    r = m.refined(4)
    assert list(r.nodes)[: len(m.nodes)] == list(m.nodes)
    s = flexmb.static(m, nev=0, refine=4)
    assert s.x.shape[1] == r.nx


@pytest.mark.parametrize("bad", [0, -1])
def test_refine_refuses_bad_values(bad):
    with pytest.raises(ValueError, match="refine"):
        flexmb.modes(flexmb.read(GUIDANCE), refine=bad)
    with pytest.raises(TypeError):
        flexmb.read(GUIDANCE, refine=1.5)


def _header(path):
    with open(path) as f:
        return f.readline().strip().split(",")


def test_refined_files_hold_the_original_nodes(tmp_path):
    # write() of a refined run: the unrefined file's columns, the refined run's values there (the
    # leading entries of r.x, which holds every node); refined_results=True: every node, as the
    # command line's --refined-results.
    plain = flexmb.simulate(flexmb.read(GUIDANCE), t_end=0.01)
    fine = flexmb.simulate(flexmb.read(GUIDANCE, refine=2), t_end=0.01)
    every = flexmb.simulate(flexmb.read(GUIDANCE, refine=2, refined_results=True), t_end=0.01)
    plain.write(str(tmp_path / "a"), mat=False)
    fine.write(str(tmp_path / "b"), mat=False)
    every.write(str(tmp_path / "c"), mat=False)
    ha, hb, hc = (_header(tmp_path / f"{p}_x.csv") for p in "abc")
    assert hb == ha
    assert len(hc) > len(ha) and hc[: len(ha)] == ha
    assert fine.x.shape[1] == len(hc) - 1  # in memory: every node of the refined model
    xb = np.loadtxt(tmp_path / "b_x.csv", delimiter=",", skiprows=1, ndmin=2)
    np.testing.assert_array_equal(xb[:, 1:], fine.x[:, : len(ha) - 1])
    np.testing.assert_array_equal(xb[:, 0], fine.time)
    cli = subprocess.run([CLI, "simulate", GUIDANCE, "--t-end", "0.01", "--refine", "2", "--format", "csv", "-q",
                          "--out", str(tmp_path / "d")], capture_output=True, text=True)
    assert cli.returncode == 0, cli.stderr
    assert (tmp_path / "d_x.csv").read_bytes() == (tmp_path / "b_x.csv").read_bytes()
    with pytest.raises(TypeError, match="refined_results"):
        flexmb.read(GUIDANCE, refine=2, refined_results="yes")
