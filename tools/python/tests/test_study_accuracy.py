"""flexmb.study(..., accuracy=, error_estimate=) (`flexmb study --accuracy EPS`): the mesh measured on
the first and the last variant, every variant within EPS of closed forms, the nominal's mesh as the
single job chooses it; bad values refused."""

import os

import numpy as np
import pytest

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CANTILEVER = os.path.join(SRC, "datfiles", "cantilever.dat")
GUIDANCE = os.path.join(SRC, "datfiles", "straight_guidance.dat")


def cantilever_template(old, new):
    with open(CANTILEVER) as f:
        text = f.read()
    assert old in text
    return text.replace(old, new)


def test_modes_study_meets_euler_bernoulli_in_every_variant():
    template = cantilever_template("8.4e6  2.8", "8.4e6  {EI}")
    stiffnesses = [1.4, 2.8, 5.6]
    r = flexmb.study(template, [{"EI": v} for v in stiffnesses], modes=4, accuracy=1e-3)
    beta_l = np.array([1.8751040687, 4.6940911330, 7.8547574382, 10.9955407349])
    for ei, row in zip(stiffnesses, r["variants"]):
        assert row["status"] == "ok"
        exact = beta_l**2 * np.sqrt(ei / 0.312) / (2 * np.pi)
        freq = np.array([row[f"f{i}_Hz"] for i in range(1, 5)])
        assert np.max(np.abs(freq / exact - 1)) <= 1e-3
        assert row["total_error_estimate"] <= 1e-3 and row["accuracy_met"] == 1
        assert row["integration_error"] == 0 and row["reduction_error"] == 0
    # The nominal's mesh: what flexmb.modes(accuracy=) chooses for it.
    nominal = flexmb.modes(flexmb.variant(template, EI=1.4), nev=4, accuracy=1e-3)
    chosen = r["accuracy"]["refinement chosen"]
    assert f"(the larger of variant 1 {nominal.error_estimate['refine']}," in chosen
    assert int(chosen.split()[0]) >= nominal.error_estimate["refine"] > 1
    assert "not per variant" in r["accuracy"]["discretization measured"]


def test_simulate_study_error_columns():
    with open(GUIDANCE) as f:
        template = f.read().replace("? 50*(1-cos", "? {F/2}*(1-cos")
    r = flexmb.study(template, [{"F": 100.0}, {"F": 140.0}], simulate=True, accuracy=1e-2)
    assert "RelTol 0.0005" in r["accuracy"]["integrator tolerance"]
    for row in r["variants"]:
        assert row["status"] == "ok"
        parts = [row[c] for c in ("discretization_error", "integration_error", "reduction_error")]
        assert all(np.isfinite(parts)) and parts[0] > 0 and parts[1] > 0
        assert row["total_error_estimate"] == pytest.approx(sum(parts))
        assert row["total_error_estimate"] <= 1e-2 and row["accuracy_met"] == 1


def test_error_estimate_keeps_the_mesh_and_sets_no_target():
    template = cantilever_template("DELXF 5  0.0  -0.1", "DELXF 5  0.0  {-P}")
    r = flexmb.study(template, [{"P": 0.1}, {"P": 2.0}], static=True, error_estimate=True)
    assert r["accuracy"]["refinement chosen"].startswith("1 part per flexible beam")
    for row in r["variants"]:
        assert row["discretization_error"] > 1e-4 and row["accuracy_met"] is None
    plain = flexmb.study(template, [{"P": 2.0}], static=True)
    assert plain["accuracy"] is None and "discretization_error" not in plain["variants"][0]


def test_bad_values_are_refused():
    template = cantilever_template("DELXF 5  0.0  -0.1", "DELXF 5  0.0  {-P}")
    with pytest.raises(ValueError):
        flexmb.study(template, [{"P": 1.0}], static=True, accuracy=2)
    with pytest.raises(ValueError):
        flexmb.study(template, [{"P": 1.0}], static=True, accuracy=1e-2, reduce=True)  # no simulate
    with pytest.raises(ValueError):
        flexmb.study(template, [], static=True)
    with pytest.raises(ValueError):
        flexmb.study(template, [{"P": 1.0}, {"Q": 1.0}], static=True)
    with pytest.raises(TypeError):
        flexmb.study(template, [3], static=True)
