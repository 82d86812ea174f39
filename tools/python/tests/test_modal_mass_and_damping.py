"""Issue 53 items 3 and 4 from Python: effective masses per direction (their sums over all the modes,
the same table as `flexmb modes`) and the damping a designer states in `transfer` (a modal ratio's
closed form on a mass on a spring, Rayleigh's beta against EDAMP = beta * ESTIFF). Run by ctest
(python_tests) with PYTHONPATH=<build>/python and FLEXMB=<build>/flexmb."""

import filecmp
import os
import subprocess

import numpy as np
import pytest

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))
GUIDANCE = os.path.join(SRC, "datfiles", "straight_guidance.dat")


def spring_mass(m, k, d, block="INPUTF 1 2 1\nOUTX 1 2 1\n"):
    edamp = f"EDAMP 1 {d!r}\n" if d > 0 else ""
    return (f"PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\nESTIFF 1 {k!r}\n{edamp}"
            f"XM 2 {m!r}\nITERSTEP 10 1\nEND\nHALT\n{block}END\nEND\n")


def test_effective_masses_sum_to_what_all_modes_carry():
    model = flexmb.read(GUIDANCE)
    r = flexmb.modes(model, nev=model.ndof, reference=(0.1, 0.2))
    assert r.directions == ["x", "y", "rz"]
    assert r.meff.shape == (model.ndof, 3) and r.gamma.shape == (model.ndof, 3)
    assert np.allclose(r.meff.sum(axis=0)[[0, 2]], r.meff_total[[0, 2]], rtol=1e-9)
    assert r.mass == pytest.approx(6.84 * 0.2 + 2 * 0.228 * 0.2, rel=1e-12)
    assert r.meff[0, 0] > 0.95 * r.meff_total[0]  # the stroke mode
    assert np.allclose(r.reference, [0.1, 0.2, 0.0])
    node = flexmb.modes(model, nev=3, reference_node=6)  # node 6 is at (0, 0.2)
    assert np.allclose(node.reference, [0.0, 0.2, 0.0])
    with pytest.raises(ValueError, match="reference"):
        flexmb.modes(model, reference=(1.0,))
    with pytest.raises(ValueError, match="reference"):
        flexmb.modes(model, reference=(0, 0), reference_node=6)


def test_participation_table_is_the_command_lines(tmp_path):
    done = subprocess.run([CLI, "modes", GUIDANCE, "--nev", "4", "--reference", "0.1,0.2", "--out",
                           str(tmp_path / "cli")], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    assert "effective masses" in done.stdout
    paths = flexmb.modes(flexmb.read(GUIDANCE), nev=4, reference=(0.1, 0.2)).write(str(tmp_path / "py"))
    assert paths[1].endswith("py_participation.csv")
    assert filecmp.cmp(tmp_path / "cli_participation.csv", tmp_path / "py_participation.csv", shallow=False)


def test_modal_ratio_gives_the_closed_form_peak():
    m, k, zeta = 4.0, 400.0, 0.05
    w = np.sqrt(k / m)
    ss = flexmb.transfer(flexmb.parse(spring_mass(m, k, 0.0)), damping_ratio=zeta)
    assert ss.A[1, 1] == pytest.approx(-2 * zeta * w, rel=1e-12)
    h = ss.frequency_response(np.array([w]))
    assert abs(np.ravel(h)[0]) == pytest.approx(1 / (2 * zeta * k), rel=1e-12)


def test_rayleigh_beta_is_edamp():
    m, k, beta = 4.0, 400.0, 2e-3
    by_edamp = flexmb.transfer(flexmb.parse(spring_mass(m, k, beta * k)))
    by_beta = flexmb.transfer(flexmb.parse(spring_mass(m, k, 0.0)), rayleigh=(0.0, beta))
    assert np.allclose(by_beta.A, by_edamp.A, rtol=1e-12, atol=0)
    with pytest.raises(ValueError, match="damping_ratio"):
        flexmb.transfer(flexmb.parse(spring_mass(m, k, 0.0)), damping_ratio=-0.1)
    with pytest.raises(ValueError, match="rayleigh"):
        flexmb.transfer(flexmb.parse(spring_mass(m, k, 0.0)), rayleigh=(1.0,))


def test_modes_say_each_modes_damping_ratio():
    model = flexmb.read(GUIDANCE)
    assert flexmb.modes(model, nev=3).zeta.size == 0  # no EDAMP, nothing added
    alpha, beta = 0.5, 1e-4
    r = flexmb.modes(model, nev=3, rayleigh=(alpha, beta))
    w = 2 * np.pi * r.freq
    assert np.allclose(r.zeta, alpha / (2 * w) + beta * w / 2, rtol=1e-9)
    assert np.allclose(flexmb.modes(model, nev=3, damping_ratio=[0.01, 0.04]).zeta, [0.01, 0.04, 0.04], rtol=1e-9)

def test_simulate_rayleigh_beta_is_the_damped_step_response():
    # A mass 4 on a spring 400 (w = 10 rad/s) from rest under a step force 1e-3: with beta 4e-3 as
    # element damping, zeta = beta w / 2 = 0.02 and x = F/k (1 - exp(-zeta w t) (cos wd t + ...)).
    step = "XF 2 0.001 0\nTIMESTEP 2 200\nEND\nEND\n"
    body = "PLTRUSS 1 1 2\nX 1 0 0\nX 2 1 0\nFIX 1\nFIX 2 2\nDYNE 1 1\nEND\nHALT\nESTIFF 1 400\n"
    tight = dict(integrator="ode45", reltol=1e-10, abstol=1e-15)
    run = flexmb.simulate(flexmb.parse(body + "XM 2 4\n" + step), rayleigh=(0.0, 4e-3), **tight)
    by_edamp = flexmb.simulate(flexmb.parse(body + "EDAMP 1 1.6\nXM 2 4\n" + step), **tight)
    w, zeta, xs = 10.0, 0.02, 1e-3 / 400
    wd, t = w * np.sqrt(1 - zeta ** 2), run.time
    exact = 1 + xs * (1 - np.exp(-zeta * w * t) * (np.cos(wd * t) + zeta / np.sqrt(1 - zeta ** 2) * np.sin(wd * t)))
    assert len(t) == 201
    assert np.max(np.abs(run.x[:, 2] - exact)) < 1e-6 * xs
    assert np.max(np.abs(run.x[:, 2] - by_edamp.x[:, 2])) < 1e-12 * xs
    model = flexmb.parse(body + "XM 2 4\n" + step)
    with pytest.raises(ValueError, match="no form in a nonlinear time run"):
        flexmb.simulate(model, damping_ratio=0.02)
    with pytest.raises(ValueError, match="alpha M"):
        flexmb.simulate(model, rayleigh=(0.5, 4e-3))
