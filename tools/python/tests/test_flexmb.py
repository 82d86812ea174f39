"""The Python front end against the command line: the same recipe and the same writer give the same
files; user functions against the built-in loads they replace; bad input, user-function errors and
Ctrl-C as the module documents them. Run by ctest (python_tests) with PYTHONPATH=<build>/python and
FLEXMB=<build>/flexmb."""

import concurrent.futures
import filecmp
import os
import re
import signal
import subprocess
import threading
import time

import numpy as np
import pytest
import scipy.io

import flexmb

SRC = os.environ.get("FLEXMB_SOURCE_DIR", os.path.join(os.path.dirname(__file__), "..", "..", ".."))
CLI = os.environ.get("FLEXMB", os.path.join(SRC, "build", "flexmb"))


def model_path(*parts):
    return os.path.join(SRC, *parts)


def cli(*args):
    done = subprocess.run([CLI, *args], capture_output=True, text=True)
    assert done.returncode == 0, f"flexmb {' '.join(args)}: {done.stderr}"
    return done.stdout


def same_bytes(a, b):
    assert os.path.exists(a) and os.path.exists(b), (a, b)
    assert filecmp.cmp(a, b, shallow=False), f"{a} and {b} differ"


# ---- models ----------------------------------------------------------------------------------------
def test_read_exposes_the_model():
    m = flexmb.read(model_path("datfiles", "straight_guidance.dat"))
    assert m.ndof == len(m.dofs) == 17
    assert m.nx == len(m.coordinates) == m.x0.shape[0]
    assert m.ne == len(m.deformations)
    assert m.elements[0]["type"] == "PLBEAM" and len(m.elements[0]["nodes"]) == 4
    assert not m.x0.flags.writeable


def test_check_reports_as_the_command_line():
    good = flexmb.check(flexmb.read(model_path("datfiles", "straight_guidance.dat")))
    assert good["well_posed"] and "degrees of freedom" in good["kinematics"]
    for name in ["overconstrained", "underconstrained"]:
        path = model_path("datfiles", "tests", f"{name}.dat")
        bad = flexmb.check(flexmb.read(path))
        assert not bad["well_posed"], name
        done = subprocess.run([CLI, "check", path], capture_output=True, text=True)
        assert done.returncode == 1 and bad["kinematics"].strip() in done.stdout, name


def test_input_errors_name_file_line_and_reason():
    text = "PLBEAM 1 1 2 3 4\nX 1 0 0\nX 3 1 0\nFIX 1\nFIX 2\nFOO 1 2\nEND\nEND\n"
    with pytest.raises(flexmb.InputError) as err:
        flexmb.parse(text, "bad.dat")
    assert err.value.file == "bad.dat" and err.value.line == 6 and "FOO" in str(err.value)
    assert isinstance(err.value, ValueError)
    with pytest.raises(flexmb.InputError):
        flexmb.read(model_path("datfiles", "no_such_model.dat"))


def test_bad_arguments_raise_type_and_value_errors_naming_the_argument():
    m = flexmb.read(model_path("datfiles", "straight_guidance.dat"))
    cases = [
        (lambda: flexmb.static("model.dat"), TypeError, "model"),
        (lambda: flexmb.modes(m, nev=0), ValueError, "nev"),
        (lambda: flexmb.modes(m, nev=2.5), TypeError, "nev"),
        (lambda: flexmb.simulate(m, t_end=-1), ValueError, "t_end"),
        (lambda: flexmb.simulate(m, reltol="1e-3"), TypeError, "reltol"),
        (lambda: flexmb.simulate(m, integrator="rk4"), ValueError, "integrator"),
        (lambda: flexmb.simulate(m, usersig=3), TypeError, "usersig"),
        (lambda: flexmb.simulate(m, integrator="galpha", rho_inf=1.5), ValueError, "rho_inf"),
        (lambda: flexmb.simulate(m, integrator="ode45", rho_inf=0.5), ValueError, "rho_inf"),
        (lambda: flexmb.simulate(m, integrator=""), ValueError, "integrator"),
        (lambda: flexmb.simulate(m, integrator=3), TypeError, "integrator"),
        (lambda: flexmb.modes(m, basis=np.zeros((5, 2))), ValueError, "basis"),
        (lambda: flexmb.modes(m, basis="no_such_basis.csv"), ValueError, "basis"),
        (lambda: flexmb.reduce(m, method="pod"), ValueError, "method"),
        (lambda: flexmb.reduce(m, target=2.0), ValueError, "target"),
        (lambda: flexmb.sweep(m, node=6, start=0.0, stop=float("nan")), ValueError, "stop"),
    ]
    for call, kind, name in cases:
        with pytest.raises(kind, match=name):
            call()


def test_variant_from_a_template_equals_the_instantiated_file(tmp_path):
    template = open(model_path("datfiles", "spatial", "cross_spring_pivot_study.dat")).read()
    m = flexmb.variant(template, "pivot.dat", t=0.2e-3)
    coarse = flexmb.read(model_path("datfiles", "spatial", "cross_spring_pivot_coarse.dat"))
    f1 = flexmb.modes(m, nev=3).freq
    f2 = flexmb.modes(coarse, nev=3).freq
    assert np.allclose(f1, f2, rtol=1e-5)
    with pytest.raises(flexmb.InputError, match="w2"):
        flexmb.variant(template, "pivot.dat", t=0.2e-3, w2=1.0)


# ---- the command line's files ----------------------------------------------------------------------
@pytest.fixture
def work(tmp_path):
    (tmp_path / "cli").mkdir()
    (tmp_path / "py").mkdir()
    return tmp_path


@pytest.mark.parametrize("name", ["straight_guidance", "cantilever"])
def test_static_writes_the_command_lines_table(work, name):
    path = model_path("datfiles", f"{name}.dat")
    cli("static", path, "--out", str(work / "cli" / "s.csv"), "--buckling", "2", "-q")
    r = flexmb.static(flexmb.read(path), buckling=2)
    r.write(str(work / "py" / "s.csv"))
    same_bytes(work / "cli" / "s.csv", work / "py" / "s.csv")
    table = np.genfromtxt(work / "cli" / "s.csv", delimiter=",", names=True)
    assert np.array_equal(np.atleast_1d(table["load_factor"]), r.load_factor)


def test_static_stability_is_the_kinetic_verdict_under_dead_moments(tmp_path):
    # A cantilever of equal bending stiffnesses under a dead end torque flutters at any torque
    # (analysis/tests/test_dead_moment_stability.cpp); load step 0 carries no torque.
    n = 4
    lines = [f"X {2 * i - 1} {(i - 1) / n} 0 0" for i in range(1, n + 2)]
    lines += [f"BEAM {e} {2 * e - 1} {2 * e} {2 * e + 1} {2 * e + 2} 0 1 0" for e in range(1, n + 1)]
    lines += [f"DYNE {e} 1 2 3 4 5 6" for e in range(1, n + 1)]
    lines += ["FIX 1", "FIX 2", "END", "HALT"]
    for e in range(1, n + 1):
        lines += [f"ESTIFF {e} 1e7 10 1 1 0 0", f"EM {e} 1 1e-3 1e-3 1e-3 0"]
    lines += [f"DELXF {2 * (n + 1)} 1 0 0", "ITERSTEP 50 2", "END", "END"]
    path = tmp_path / "torque.dat"
    path.write_text("\n".join(lines) + "\n")
    r = flexmb.static(flexmb.read(str(path)), nev=2)
    assert len(r.stable) == len(r.stability) == len(r.load_factor) == 3
    assert r.stable[0] and r.stability[0] == "stable"
    assert not r.stable[-1]
    assert r.stability[-1].startswith("flutter (lambda = ") and r.stability[-1].endswith("under the dead moments")
    g = flexmb.static(flexmb.read(model_path("datfiles", "straight_guidance.dat")), nev=1)
    assert all(g.stable) and set(g.stability) == {"stable"}


def test_modes_write_the_command_lines_table(work):
    path = model_path("datfiles", "manipulator.dat")
    cli("modes", path, "--nev", "4", "--out", str(work / "cli" / "m"))
    r = flexmb.modes(flexmb.read(path), nev=4)
    r.write(str(work / "py" / "m"))
    same_bytes(work / "cli" / "m_modes.csv", work / "py" / "m_modes.csv")
    assert r.freq.shape == (4,) and np.all(np.diff(r.freq) >= 0)
    assert not r.modes.flags.owndata  # a view on the result's memory


def test_sweep_writes_the_command_lines_table(work):
    path = model_path("datfiles", "straight_guidance.dat")
    cli("sweep", path, "--node", "6", "--comp", "1", "--from", "0", "--to", "0.05", "--steps", "4", "--out",
        str(work / "cli" / "w"), "-q")
    r = flexmb.sweep(flexmb.read(path), node=6, component=1, start=0.0, stop=0.05, steps=4)
    r.write(str(work / "py" / "w.csv"))
    same_bytes(work / "cli" / "w.csv", work / "py" / "w.csv")
    assert r.freq.shape == (4, 4)


def test_refusals_and_messages_are_the_jobs_words_as_the_command_line_says_them(tmp_path):
    # The same job behind both: the refusal's words, with the option in each front end's spelling.
    path = model_path("datfiles", "straight_guidance.dat")
    done = subprocess.run([CLI, "sweep", path, "--node", "99", "--from", "0", "--to", "0.01", "--out",
                           str(tmp_path / "w")], capture_output=True, text=True)
    assert done.returncode == 1
    with pytest.raises(ValueError) as e:
        flexmb.sweep(flexmb.read(path), node=99, start=0.0, stop=0.01)
    assert str(e.value) in done.stderr and "no node 99 with component 1" in str(e.value)
    steps = tmp_path / "steps.dat"
    steps.write_text(open(model_path("datfiles", "cantilever.dat")).read())
    with pytest.raises(ValueError, match=r"load steps are too many.*\(option load_steps=\)"):
        flexmb.static(flexmb.read(str(steps)), load_steps=10**9)
    # A range that misses the node's initial value is said beside the result, as on the command line.
    r = flexmb.sweep(flexmb.read(path), node=6, start=0.5, stop=0.6, steps=2)
    assert any(kind == "note" and "absolute coordinates" in text for kind, text in r.messages)


@pytest.mark.parametrize("name", ["straight_guidance", "slider_crank_s95"])
def test_simulate_writes_the_command_lines_files(work, name):
    path = model_path("datfiles", f"{name}.dat")
    cli("simulate", path, "--t-end", "0.05", "--out", str(work / "cli" / name), "-q", "--format", "both")
    r = flexmb.simulate(flexmb.read(path), t_end=0.05)
    written = r.write(str(work / "py" / name))
    assert written[-1].endswith("_run.txt")
    for suffix in ["_x.csv", "_xd.csv", "_xdd.csv", "_e.csv", "_ed.csv", "_edd.csv", "_sig.csv", ".mat", ".sbd"]:
        same_bytes(work / "cli" / (name + suffix), work / "py" / (name + suffix))
    x = np.loadtxt(work / "cli" / f"{name}_x.csv", delimiter=",", skiprows=1, ndmin=2)
    assert np.array_equal(x[:, 0], r.time) and np.array_equal(x[:, 1:], r.x)
    sig = np.loadtxt(work / "cli" / f"{name}_sig.csv", delimiter=",", skiprows=1, ndmin=2)
    assert np.array_equal(sig[:, 1:], r.sig)
    assert r.completed and r.nfevals > 0 and not r.x.flags.writeable


def test_simulate_write_plots_the_command_lines_history(work):
    path = model_path("datfiles", "straight_guidance.dat")
    cli("simulate", path, "--t-end", "0.02", "--out", str(work / "cli" / "h"), "-q",
        "--plot", "node6.x,sig:PLBEAM3.e2_bending_p")
    r = flexmb.simulate(flexmb.read(path), t_end=0.02)
    written = r.write(str(work / "py" / "h"), mat=False, plot="node6.x, sig:PLBEAM3.e2_bending_p")
    assert str(work / "py" / "h_history.svg") in written
    same_bytes(work / "cli" / "h_history.svg", work / "py" / "h_history.svg")
    with pytest.raises(ValueError, match="'node6.q' is not a quantity.*node6.x"):
        r.write(str(work / "py" / "bad"), plot=["node6.q"])


def test_transfer_writes_the_command_lines_files(work):
    path = model_path("datfiles", "spatial", "cross_spring_pivot_transfer.dat")
    cli("transfer", path, "--out", str(work / "cli" / "t"), "-q")
    r = flexmb.transfer(flexmb.read(path))
    r.write(str(work / "py" / "t"))
    for suffix in ["_A.csv", "_B.csv", "_C.csv", "_D.csv", ".sbd", ".sbm", ".ltv", "_bode_in1_out1.svg"]:
        same_bytes(work / "cli" / ("t" + suffix), work / "py" / ("t" + suffix))
    ltv = scipy.io.loadmat(str(work / "cli" / "t.ltv"))
    for name in "ABCD":
        assert np.array_equal(ltv[name], getattr(r, name)), name
    gain = r.static_gain()
    assert gain.shape == (2, 1) and gain[0, 0] > 0


def test_reduce_and_a_reduced_run_write_the_command_lines_files(work):
    path = model_path("datfiles", "straight_guidance.dat")
    cli("reduce", path, "--modes", "3", "--out", str(work / "cli" / "m3.csv"), "-q")
    m = flexmb.read(path)
    r = flexmb.reduce(m, modes=3)
    assert r.V.shape == (m.ndof, 3) and "terms" in r.operators
    r.write(str(work / "py" / "m3.csv"))
    same_bytes(work / "cli" / "m3.csv", work / "py" / "m3.csv")
    cli("simulate", path, "--t-end", "0.05", "--basis", str(work / "cli" / "m3.csv"), "--out", str(work / "cli" / "g"),
        "-q", "--format", "both")
    run = flexmb.simulate(m, t_end=0.05, basis=str(work / "cli" / "m3.csv"))
    assert run.reduced_dynamics.startswith("reduced operators")
    assert run.integrator in ("ode45", "galpha")  # auto, the default, on the reduced operators
    run.write(str(work / "py" / "g"))
    for suffix in ["_x.csv", "_sig.csv", ".sbd"]:
        same_bytes(work / "cli" / ("g" + suffix), work / "py" / ("g" + suffix))
    eq19 = flexmb.simulate(m, t_end=0.05, basis=r.V)
    assert eq19.reduced_dynamics == "Eq. 19"
    assert np.max(np.abs(eq19.x - run.x)) < 1e-3  # operators fitted to 1e-3 of the forces
    in_memory = flexmb.simulate(m, t_end=0.05, basis=r)
    assert np.array_equal(in_memory.x, run.x)


def test_the_default_integrator_is_auto():
    # Issue 48, item 2: galpha from the start where the highest frequency at rest bounds ode45's
    # step (the guidance with 20 elements per leaf), ode45 on the 5-element guidance until its step
    # is bound by stability; rho_inf alone asks for auto.
    fine = flexmb.read(model_path("datfiles", "tests", "straight_guidance_20.dat"))
    r = flexmb.simulate(fine)  # over its 0.2 s: more than 10,000 ode45 steps
    assert r.integrator == "galpha" and r.completed
    m = flexmb.read(model_path("datfiles", "straight_guidance.dat"))
    assert flexmb.simulate(m, t_end=0.01, rho_inf=0.5).integrator in ("ode45+galpha", "galpha")
    assert flexmb.simulate(m, t_end=0.01, integrator="ode45").integrator == "ode45"


# ---- user functions ----------------------------------------------------------------------------------
ARM = model_path("tools", "octave", "tests", "data", "arm_expr.dat")


def arm_without_loads():
    text = open(ARM).read()
    stripped = re.sub(r"^(XFT|ESIGT) .*$", "", text, flags=re.M)
    assert stripped != text
    return flexmb.parse(stripped, "arm_usersig.dat")


def arm_loads(m):
    tip = m.coordinates.index(next(c for c in m.coordinates if re.search(r"node 3\b.*y", c)))
    elbow = next(i for i, d in enumerate(m.deformations) if "101" in d)

    def usersig(t, x, xd, e, ed):
        sig = np.zeros(m.ne)
        f = np.zeros(m.nx)
        sig[elbow] = 0.3 * np.cos(3 * t)
        f[tip] = 2 * np.sin(5 * t)
        return sig, f

    return usersig


def test_usersig_equals_the_built_in_loads():
    builtin = flexmb.simulate(flexmb.read(ARM), t_end=0.3)
    m = arm_without_loads()
    r = flexmb.simulate(m, t_end=0.3, usersig=arm_loads(m))
    assert r.completed and r.time.shape == builtin.time.shape
    assert np.allclose(r.x, builtin.x, rtol=0, atol=1e-12)
    assert np.allclose(r.sig, builtin.sig, rtol=0, atol=1e-9)
    unloaded = flexmb.simulate(m, t_end=0.3)
    assert np.max(np.abs(unloaded.x - builtin.x)) > 1e-4  # the loads matter


def test_an_exception_in_usersig_stops_the_run_with_time_traceback_and_results():
    m = arm_without_loads()

    def failing(t, x, xd, e, ed):
        if t > 0.1:
            raise ZeroDivisionError("the user's bug")
        return np.zeros(m.ne)

    with pytest.raises(flexmb.UserFunctionError) as err:
        flexmb.simulate(m, t_end=0.3, usersig=failing)
    text = str(err.value)
    assert "ZeroDivisionError" in text and "the user's bug" in text and "Traceback" in text
    assert re.search(r"t = 0\.1", text)
    kept = err.value.result
    assert kept is not None and not kept.completed and 0 < kept.time[-1] <= 0.1 + 1e-9


def test_a_usersig_of_the_wrong_shape_names_the_expected_one():
    m = arm_without_loads()
    with pytest.raises(flexmb.UserFunctionError, match=rf"expected shape \({m.ne},\)"):
        flexmb.simulate(m, t_end=0.1, usersig=lambda t, x, xd, e, ed: np.zeros(m.ne + 1))


def test_userinp_equals_the_files_input_motion():
    m = flexmb.read(ARM)
    assert m.inputs == ["e(PLHINGE 100, 1 relative rotation)"]
    builtin = flexmb.simulate(m, t_end=0.3)

    def crank(t, order):  # the file's INPUTET 100 1 "0.5*sin(2*t)" "cos(2*t)" "-2*sin(2*t)"
        return np.array([[0.5 * np.sin(2 * t), np.cos(2 * t), -2 * np.sin(2 * t)][order]])

    r = flexmb.simulate(m, t_end=0.3, userinp=crank)
    assert r.completed and np.allclose(r.x, builtin.x, rtol=0, atol=1e-12)
    still = flexmb.simulate(m, t_end=0.3, userinp=lambda t, order: np.zeros(1))
    assert np.max(np.abs(still.x - builtin.x)) > 1e-3
    with pytest.raises(flexmb.UserFunctionError, match=r"USERINP.*expected shape \(1,\)"):
        flexmb.simulate(m, t_end=0.3, userinp=lambda t, order: np.zeros(2))
    with pytest.raises(flexmb.UserFunctionError, match="KeyError"):
        flexmb.simulate(m, t_end=0.3, userinp=lambda t, order: {}["x"])
    with pytest.raises(ValueError, match="userinp"):
        flexmb.simulate(flexmb.read(model_path("datfiles", "straight_guidance.dat")), userinp=crank)


def test_a_driven_rigid_mechanism_gives_the_command_lines_forces(work):
    path = model_path("datfiles", "slider_crank_rigid.dat")
    cli("simulate", path, "--out", str(work / "cli" / "sc"), "-q", "--format", "both")
    r = flexmb.simulate(flexmb.read(path))
    assert r.nfevals == 0 and r.fxt.shape == (len(r.time), r.x.shape[1])
    r.write(str(work / "py" / "sc"))
    for suffix in ["_fxt.csv", "_x.csv", "_sig.csv", ".sbd"]:
        same_bytes(work / "cli" / ("sc" + suffix), work / "py" / ("sc" + suffix))
    with pytest.raises(ValueError, match="driven rigid mechanism"):
        flexmb.simulate(flexmb.read(path), basis=np.zeros((0, 1)))


def test_a_spacar95_file_runs_its_stages_as_the_command_line(work):
    path = model_path("datfiles", "tests", "slider_crank_manual_s95.dat")
    cli("simulate", path, "--out", str(work / "cli" / "s95"), "-q", "--format", "both")
    r = flexmb.simulate(flexmb.read(path))
    r.write(str(work / "py" / "s95"))
    for suffix in ["_x.csv", "_e.csv", ".sbd"]:
        same_bytes(work / "cli" / ("s95" + suffix), work / "py" / ("s95" + suffix))


def test_validate_writes_the_papers_report(tmp_path):
    assert flexmb.validate(SRC, tmp_path / "report", sweep_steps=3) == 0
    report = (tmp_path / "report" / "report.md").read_text()
    assert "Boer et al. (2013)" in report and "| guidance full | 17 | 45667 |" in report
    with pytest.raises(ValueError, match="source"):
        flexmb.validate(tmp_path, tmp_path / "r2")


# ---- Ctrl-C and threads ---------------------------------------------------------------------------------
def test_ctrl_c_raises_keyboard_interrupt_and_keeps_the_results():
    m = flexmb.read(model_path("datfiles", "straight_guidance.dat"))
    timer = threading.Timer(0.3, lambda: os.kill(os.getpid(), signal.SIGINT))
    timer.start()
    start = time.monotonic()
    with pytest.raises(KeyboardInterrupt) as err:
        flexmb.simulate(m, t_end=1000.0, reltol=1e-8, abstol=1e-10, integrator="ode45")
    timer.join()
    assert time.monotonic() - start < 60
    kept = err.value.result
    assert not kept.completed and len(kept.time) >= 1 and kept.time[-1] < 1000.0
    # Python's own handler is back: the next Ctrl-C is an ordinary KeyboardInterrupt.
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler


def test_threads_run_variants_in_parallel_with_the_serial_results():
    template = open(model_path("datfiles", "spatial", "cross_spring_pivot_study.dat")).read()
    thicknesses = [0.15e-3, 0.2e-3, 0.25e-3, 0.3e-3]
    serial = [flexmb.static(flexmb.variant(template, t=t), nev=2).freq for t in thicknesses]
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        parallel = list(pool.map(lambda t: flexmb.static(flexmb.variant(template, t=t), nev=2).freq, thicknesses))
    for a, b in zip(serial, parallel):
        assert np.array_equal(a, b)


def test_generalized_alpha_runs_the_elbow_to_its_reference():
    """integrator="galpha" (issue 38): the elbow of Simo & Vu-Quoc against its stored converged response."""
    m = flexmb.read(model_path("datfiles", "spatial", "elbow.dat"))
    r = flexmb.simulate(m, integrator="galpha", rho_inf=0.8)
    assert r.integrator == "galpha"
    ref = np.loadtxt(model_path("datfiles", "spatial", "elbow_reference.csv"), delimiter=",", comments="#", skiprows=5)
    tip = list(m.coordinates).index("x(node 41, z)")
    x = np.asarray(r.x)
    assert x.shape[0] == ref.shape[0]
    assert np.max(np.abs(x[:, tip] - ref[:, 2])) < 0.01 * (ref[:, 2].max() - ref[:, 2].min())


def test_elements_are_the_files_as_show_counts_them():
    # Issue 51: the spatial stage has 22 elements; the 21 normalisation constraints flexmb adds to
    # its Euler parameters are not the file's (check and show say 22 too).
    m = flexmb.read(model_path("datfiles", "spatial", "parallel_leaf_stage.dat"))
    assert len(m.elements) == 22 and "22 elements" in repr(m)
    assert all(e["type"] != "L2MIN1" for e in m.elements)
