"""error_estimate= and accuracy= (`--error-estimate`, `--accuracy EPS`): the same ladder and budget
as the command line's, checked against closed forms (Euler-Bernoulli frequencies) and the command
line's own figures; bad values refused."""

import os
import subprocess

import numpy as np
import pytest

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))
GUIDANCE = os.path.join(SRC, "datfiles", "straight_guidance.dat")
CANTILEVER = os.path.join(SRC, "datfiles", "cantilever.dat")


def test_modes_accuracy_meets_euler_bernoulli():
    beta_l = np.array([1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349])
    exact = beta_l**2 * np.sqrt(2.8 / 0.312) / (2 * np.pi)  # Hz
    r = flexmb.modes(flexmb.read(CANTILEVER), nev=4, accuracy=1e-3)
    e = r.error_estimate
    assert e["met"] and e["total"] <= 1e-3 and e["refine"] > 1
    assert np.max(np.abs(r.freq / exact - 1)) <= 1e-3
    # The model's own mesh: the estimate holds its true error within 1 to 10.
    own = flexmb.modes(flexmb.read(CANTILEVER), nev=4, error_estimate=True)
    true = np.max(np.abs(np.log(own.freq / exact)))
    assert 1 <= own.error_estimate["discretization"] / true <= 10
    assert own.error_estimate["refine"] == 1
    assert flexmb.modes(flexmb.read(CANTILEVER), nev=4).error_estimate is None


def test_simulate_error_estimate_matches_the_command_line(tmp_path):
    r = flexmb.simulate(flexmb.read(GUIDANCE), error_estimate=True)
    e = r.error_estimate
    assert e["estimated"] and e["refine"] == 1
    assert 0.02 < e["discretization"] < 0.05  # the 5-element guidance: 0.033 off the converged beam
    assert 1.5 < e["observed_order"] < 2.5
    out = subprocess.run([CLI, "simulate", GUIDANCE, "--error-estimate", "--format", "none", "--out",
                          str(tmp_path / "g")], capture_output=True, text=True, check=True).stdout
    line = next(l for l in out.splitlines() if l.startswith("discretization error estimate:"))
    assert float(line.split()[3]) == pytest.approx(e["discretization"], rel=0.05)
    assert any("total error estimate" in text for _, text in r.messages)


def test_bad_values_are_refused():
    m = flexmb.read(GUIDANCE)
    with pytest.raises(ValueError, match="accuracy"):
        flexmb.simulate(m, accuracy=0)
    with pytest.raises(ValueError, match="not both"):
        flexmb.static(m, accuracy=1e-2, error_estimate=True)
    with pytest.raises(TypeError, match="error_estimate"):
        flexmb.static(m, error_estimate="yes")
    with pytest.raises(ValueError, match="one mesh"):
        flexmb.modes(m, basis=np.eye(m.ndof)[:, :3], accuracy=1e-2)
    with pytest.raises(ValueError, match="intervals"):
        flexmb.simulate(m, intervals=0, error_estimate=True)


def test_sweep_accuracy_meets_its_target_on_every_configuration():
    m = flexmb.read(GUIDANCE)
    r = flexmb.sweep(m, node=6, component=1, start=-0.0833, stop=0.0833, steps=3, nev=2, accuracy=1e-2)
    e = r.error_estimate
    assert e["met"] and e["discretization"] <= 0.7e-2 and e["refine"] >= 2
    assert r.freq.shape == (3, 2)
    # The same sweep on a far finer mesh: the frequencies written are within the target of it.
    fine = flexmb.sweep(m, node=6, component=1, start=-0.0833, stop=0.0833, steps=3, nev=2, refine=16)
    true = np.max(np.abs(np.log(r.freq / fine.freq)))
    assert true <= 1e-2
    assert 1 <= e["discretization"] / true <= 10, (e["discretization"], true)
