"""flexmb from Python: SPACAR .dat models, their analyses, NumPy results.

    import flexmb
    model = flexmb.read("datfiles/straight_guidance.dat")
    run = flexmb.simulate(model, t_end=0.1)
    run.x[:, 3]            # nodal coordinate 4 over time (model order, as the CSV tables)
    run.write("out/guidance")   # the files `flexmb simulate` writes

Every analysis is the command line's recipe, and every `write` its writer: the same model gives
the same files. Arrays are read-only views on the result's memory (no copies). Analyses release
the GIL, so threads run variants in parallel. Ctrl-C raises KeyboardInterrupt with the results so
far as its `.result`.
"""

import numbers

import numpy as np


class InputError(ValueError):
    """A model that cannot be read: `file`, `line` and `reason` say where and why."""

    file = None
    line = None
    reason = None


class UserFunctionError(RuntimeError):
    """A Python user function raised or returned the wrong shape; the message holds the time and
    the traceback, `.result` the run up to there."""

    result = None


from . import _core  # noqa: E402  (the exceptions above must exist before the native part raises them)

Model = _core.Model


def read(path, *, refine=1, refined_results=False):
    """The model of a SPACAR .dat file (both dialects; the last analysis stage). refine=N splits every
    flexible beam in N elements (`--refine N`; `Model.refined(N)`); the files its results write
    hold the original nodes and elements, every node with refined_results=True
    (`--refined-results`)."""
    if not isinstance(path, (str, bytes)) and not hasattr(path, "__fspath__"):
        raise TypeError(f"path: expected a file name, got {type(path).__name__}")
    import os

    return _refined(_core.read(os.fsdecode(os.fspath(path))), refine, refined_results)


def parse(text, name="<string>", *, refine=1, refined_results=False):
    """The model of a .dat text; errors name `name` and the line. refine, refined_results: as read's."""
    _need(text, str, "text")
    _need(name, str, "name")
    return _refined(_core.parse(text, name), refine, refined_results)


def variant(template, name="<template>", **parameters):
    """The model of a design-study template (`{expression}` placeholders, as `flexmb study` takes
    them) with the given parameter values, without touching the disk."""
    _need(template, str, "template")
    values = []
    for key, value in parameters.items():
        values.append((key, _real(value, key)))
    text = _core.instantiate(template, name, values)
    return _core.parse(text, name)


def study(template, variants, *, name="<template>", modes=0, static=False, nev=6, simulate=False, t_end=None,
          reltol=None, refine=1, error_estimate=False, accuracy=None, max_seconds=300.0, reduce=False):
    """A design study in this process (`flexmb study`'s recipe without its folder and workers): the
    template (`{expression}` placeholders) with each dict of parameter values in `variants`, the same
    analyses on each (modes=N frequencies, static=True, simulate=True with t_end, reltol). Returns a
    dict: `variants`, one dict per variant (its parameters, the summary's quantities, `status`,
    `reason`; None where a quantity is not available), and `accuracy`.
    accuracy=EPS / error_estimate=True (`study --accuracy`): the mesh ladder runs on the first variant
    (the nominal design) and the last (the other end of the range), every variant on the larger
    refinement; each gets discretization_error (measured at the two ends, not per variant),
    integration_error, reduction_error, total_error_estimate and accuracy_met (1 or 0); `accuracy`
    holds the study's record (target, refinement chosen, tolerance, where D was measured).
    reduce=True (with accuracy and simulate): each variant reduced with basis auto, target EPS / 4.
    max_seconds bounds the ladders together."""
    _need(template, str, "template")
    _need(name, str, "name")
    rows = []
    for k, values in enumerate(variants):
        if not isinstance(values, dict) or not values:
            raise TypeError(f"variants[{k}]: expected a dict of parameter values")
        rows.append([(key, _real(v, key)) for key, v in values.items()])
    if not rows:
        raise ValueError("variants: give at least one")
    if any([n for n, _ in r] != [n for n, _ in rows[0]] for r in rows):
        raise ValueError("variants: every variant gives the same parameters, in the same order")
    estimate, eps, seconds = _accuracy(error_estimate, accuracy, max_seconds)
    if not isinstance(reduce, bool):
        raise TypeError(f"reduce: expected True or False, got {type(reduce).__name__}")
    if reduce and not (eps > 0 and simulate):
        raise ValueError("reduce: goes with accuracy= and simulate=True (it splits EPS)")
    return _core.study(template, name, rows, _count(modes, "modes", 0), bool(static), _count(nev, "nev", 1),
                       bool(simulate), None if t_end is None else _positive(t_end, "t_end"),
                       None if reltol is None else _positive(reltol, "reltol"), _count(refine, "refine", 1),
                       estimate, eps, seconds, reduce)


def check(model, *, refine=1):
    """Mode 0 (`flexmb check`): a dict with `well_posed`, the kinematic report (`kinematics`: rank,
    degrees of freedom, redundant or missing equations), deformations that move without stiffness,
    values that overflow, the initial assembly's problem, massless degrees of freedom, notes and
    warnings."""
    _model(model)
    model = _refined(model, refine)
    return _core.check(model)


def static(model, *, nev=6, load_steps=0, buckling=0, compliance=(), refine=1, error_estimate=False, accuracy=None,
           max_seconds=300.0):
    """Mode 10: equilibrium over the load steps (`flexmb static`); eigenfrequencies (Hz) and, with
    buckling > 0, buckling load factors in each. Arrays have one row per step. Per step also the
    von Mises stress of each element with a VISUALIZATION section (`.stress`, Pa, columns
    `.stress_elements`; `.stressmax`), the support reactions (`.reactions`, columns
    `.reaction_names`) and, for the node labels in `compliance`, the compliance matrices
    (`.compliance[node]`: one matrix per step, rows and columns `.compliance_names[node]`).
    error_estimate=True: also the discretization error of the model's mesh against the converged
    model (runs on meshes split in 2 and 4, Richardson's extrapolation; `.error_estimate`).
    accuracy=EPS: the mesh refined (and for simulate the tolerance tightened to EPS / 20) until the
    total error estimate is at most EPS; the finest mesh's results (`.error_estimate["refine"]`);
    max_seconds bounds the time it may spend (`flexmb ... --accuracy EPS`)."""
    _model(model)
    model = _refined(model, refine)
    nodes = [_count(n, "compliance", 0) for n in compliance]
    return _core.static(model, _count(nev, "nev", 0), _count(load_steps, "load_steps", 0),
                        _count(buckling, "buckling", 0), nodes, *_accuracy(error_estimate, accuracy, max_seconds))


def modes(model, *, nev=6, basis=None, reference=None, reference_node=None, damping_ratio=None, rayleigh=None,
          refine=1, error_estimate=False, accuracy=None, max_seconds=300.0):
    """Eigenfrequencies (Hz, `.freq`) and mode shapes (`.modes` in q, `.modex` in x) in the initial
    configuration (`flexmb modes`), and per global direction (`.directions`: x, y, rz or x, y, z,
    rx, ry, rz) the participation factors `.gamma` and effective masses `.meff` (modes by
    directions), what all the modes carry `.meff_total`, the whole model's rigid-body mass matrix
    `.rigid_body_mass`, `.mass` and `.centre_of_mass`. Rotations are about `reference` (x, y[, z];
    default the origin) or the position node `reference_node`. `.zeta`: each mode's damping ratio
    from the model's EDAMP and damping_ratio / rayleigh (as `transfer`'s); empty when undamped.
    error_estimate=True: also the discretization error of the model's mesh against the converged
    model (runs on meshes split in 2 and 4, Richardson's extrapolation; `.error_estimate`).
    accuracy=EPS: the mesh refined (and for simulate the tolerance tightened to EPS / 20) until the
    total error estimate is at most EPS; the finest mesh's results (`.error_estimate["refine"]`);
    max_seconds bounds the time it may spend (`flexmb ... --accuracy EPS`)."""
    _model(model)
    model = _refined(model, refine)
    point = np.zeros(3)
    node = 0
    if reference is not None and reference_node is not None:
        raise ValueError("reference and reference_node name the same point: give one")
    if reference is not None:
        values = [_real(v, "reference") for v in reference]
        if len(values) not in (2, 3):
            raise ValueError(f"reference: expected (x, y) or (x, y, z), got {len(values)} values")
        point[:len(values)] = values
    if reference_node is not None:
        node = _count(reference_node, "reference_node", 1)
    ratios, alpha, beta = _damping(damping_ratio, rayleigh)
    asked = _accuracy(error_estimate, accuracy, max_seconds)
    if basis is not None and (asked[0] or asked[1] > 0):
        raise ValueError("basis: a basis belongs to one mesh; error_estimate and accuracy run the full model")
    return _core.modes(model, _count(nev, "nev", 1), _basis(basis, model), point, node, ratios, alpha, beta, *asked)


def sweep(model, *, node, component=1, start, stop, steps=10, nev=4, basis=None, t=0.0, refine=1,
          error_estimate=False, accuracy=None, max_seconds=300.0):
    """Eigenfrequencies over a range of motion (`flexmb sweep`): coordinate `component` of `node`
    prescribed from `start` to `stop` in `steps` configurations.
    error_estimate / accuracy / max_seconds: as static's, on the frequencies of every configuration."""
    _model(model)
    model = _refined(model, refine)
    asked = _accuracy(error_estimate, accuracy, max_seconds)
    if basis is not None and (asked[0] or asked[1] > 0):
        raise ValueError("basis: a basis belongs to one mesh; error_estimate and accuracy run the full model")
    return _core.sweep(model, _count(node, "node", 1), _count(component, "component", 1), _real(start, "start"),
                       _real(stop, "stop"), _count(steps, "steps", 2), _count(nev, "nev", 1), _basis(basis, model),
                       _real(t, "t"), *asked)


def transfer(model, *, nev=6, load_steps=0, damping_ratio=None, rayleigh=None, refine=1):
    """Mode 9: the state-space model A, B, C, D between the transfer block's inputs and outputs at
    the last load step (`flexmb transfer`); `.write(prefix, bode=True)` writes its files (A..D CSV,
    SPACAR's .sbd/.sbm/.ltv, the Bode diagrams). nev: eigenfrequencies per load step in the .sbm.
    damping_ratio: modal relative damping added to the model's EDAMP, one ratio for every mode or a
    list for modes 1, 2, ... (the last for the higher ones); rayleigh: (alpha, beta) adds
    alpha M + beta K (beta K is EDAMP = beta * ESTIFF)."""
    _model(model)
    model = _refined(model, refine)
    ratios, alpha, beta = _damping(damping_ratio, rayleigh)
    return _core.transfer(model, _count(nev, "nev", 0), _count(load_steps, "load_steps", 0), ratios, alpha, beta)


def reduce(model, *, method="modal", modes=3, normalise="mass", configs=10, weight=0.0, threshold=0.01, count=0,
           node=0, component=1, start=0.0, stop=0.0, large=None, target=None, operators=True, track=None,
           track_elements=None, refine=1):
    """A reduction basis q = V eta (`flexmb reduce`): `.V` (ndof x k), its reduced operators
    (`.operators` says what was built), `.write(path)` the basis file and the operators beside it.
    With `target` the smallest basis of `method` whose reduction error estimate meets it (`.tried`
    lists the candidates; `.full` when none does). `track` / `track_elements`: node / element labels
    whose outputs the operators also fit. `.messages`: what the job said."""
    _model(model)
    model = _refined(model, refine)
    o = _core.ReductionOptions()
    if method not in ("modal", "svd-modal"):
        raise ValueError(f"method: 'modal' or 'svd-modal', not {method!r}")
    if normalise not in ("mass", "unit"):
        raise ValueError(f"normalise: 'mass' or 'unit', not {normalise!r}")
    o.method, o.normalise = method, normalise
    o.modes = _count(modes, "modes", 1)
    o.configs = _count(configs, "configs", 1)
    o.weight = _real(weight, "weight")
    o.threshold = _positive(threshold, "threshold")
    o.count = _count(count, "count", 0)
    o.node = _count(node, "node", 0)
    o.component = _count(component, "component", 1)
    o.start, o.stop = _real(start, "start"), _real(stop, "stop")
    if large is not None:
        o.large = [_count(i, "large", 1) - 1 for i in large]
        if any(i >= model.ndof for i in o.large):
            raise ValueError(f"large: indices 1 to {model.ndof} (the degrees of freedom)")
    if target is not None:
        target = _real(target, "target")
        if not 0 < target < 1:
            raise ValueError(f"target: expected 0 < target < 1, got {target}")
    track = [_count(i, "track", 1) for i in (track or [])]
    track_elements = [_count(i, "track_elements", 1) for i in (track_elements or [])]
    return _core.reduce(model, o, target, bool(operators), track, track_elements)


def simulate(model, *, t_end=None, reltol=None, abstol=None, max_step=None, intervals=None, integrator=None,
             basis=None, full_kinematics=False, usersig=None, userinp=None, accuracy_check=False, rho_inf=None,
             refine=1, rayleigh=None, damping_ratio=None, error_estimate=False, accuracy=None, max_seconds=300.0):
    """Mode 1: forward dynamics (`flexmb simulate`). Unset options come from the file.

    integrator: "auto", "ode45", "bdf" or "galpha" (generalized-alpha). Default (None): auto, which runs
    galpha from the start on a model whose highest frequency would bound ode45's step, else ode45 until
    its step is bound by stability (reduced runs alike; ode45 throughout with USERSIG). "ode45" is
    MATLAB's ode45 step by step (SPACAR's integrator). rho_inf (0 ... 1, default 0.8): galpha's
    spectral radius at infinite step (with galpha or auto only; given alone, it asks for auto).

    basis: a reduced run q = V eta. An array (ndof x k) runs Eq. 19; a basis file (`flexmb reduce`'s)
    or a `flexmb.reduce` result run with their reduced operators, as `flexmb simulate --basis` does
    (full_kinematics=True: Eq. 19 all the same).
    usersig: a callable f(t, x, xd, e, ed) returning sig (ne stresses, added to the model's) or
    (sig, f) with f (nx nodal forces); arrays in model order, read-only, valid during the call only.
    userinp: a callable f(t, order) returning one value per input (model.inputs) of that order
    (0 positions, 1 rates, 2 accelerations), replacing the file's input motions.
    An exception in either stops the run: UserFunctionError with the time, the traceback and the
    results so far (`.result`). A driven rigid mechanism (no degrees of freedom) gets its
    kinematics and the forces its inputs need (`.fxt`), as `flexmb simulate` does.
    rayleigh=(0, beta): beta K added as element damping (EDAMP = beta * ESTIFF), as `flexmb simulate
    --rayleigh 0,BETA`; an alpha or a damping_ratio has no form in a nonlinear time run: ValueError
    saying why (modes and transfer take them).
    error_estimate=True: also the discretization error of the model's mesh against the converged
    model (runs on meshes split in 2 and 4, Richardson's extrapolation; `.error_estimate`).
    accuracy=EPS: the mesh refined (and for simulate the tolerance tightened to EPS / 20) until the
    total error estimate is at most EPS; the finest mesh's results (`.error_estimate["refine"]`);
    max_seconds bounds the time it may spend (`flexmb ... --accuracy EPS`).
    With either, the accuracy check runs (it gives the integration error) and no basis is taken.
    """
    _model(model)
    model = _refined(model, refine)
    ratios, alpha, beta = _damping(damping_ratio, rayleigh)
    for name, f in (("usersig", usersig), ("userinp", userinp)):
        if f is not None and not callable(f):
            raise TypeError(f"{name}: expected a callable, got {type(f).__name__}")
    if userinp is not None and not model.inputs:
        raise ValueError(f"userinp: {model.file} has no inputs (INPUTX / INPUTE) to drive")
    if integrator is not None:
        _need(integrator, str, "integrator")
    if rho_inf is not None:
        if integrator is None:
            integrator = "auto"  # galpha's setting: auto even with reduced operators
        if integrator not in ("galpha", "auto"):
            raise ValueError(f"rho_inf: needs integrator='galpha' or 'auto', not {integrator!r}")
        if isinstance(rho_inf, bool) or not isinstance(rho_inf, (int, float)) or not 0 <= rho_inf <= 1:
            raise ValueError(f"rho_inf: expected a number in [0, 1], got {rho_inf!r}")
    array, path, reduced = None, None, None
    if isinstance(basis, _core.ReduceResult):
        reduced = basis
    elif isinstance(basis, (str, bytes)) or hasattr(basis, "__fspath__"):
        import os

        path = os.fsdecode(os.fspath(basis))
    else:
        array = _basis(basis, model)
    o = _core.SimulateOptions()
    o.t_end, o.reltol, o.abstol = _positive(t_end, "t_end"), _positive(reltol, "reltol"), _positive(abstol, "abstol")
    o.max_step = _positive(max_step, "max_step")
    o.intervals = None if intervals is None else _count(intervals, "intervals", 0)
    o.integrator, o.rho_inf = integrator, None if rho_inf is None else float(rho_inf)
    o.basis, o.basis_file, o.reduced = array, path, reduced
    o.full_kinematics, o.accuracy_check = bool(full_kinematics), bool(accuracy_check)
    o.usersig, o.userinp = usersig, userinp
    o.damping_ratio, o.alpha, o.beta = ratios, alpha, beta
    o.error_estimate, o.accuracy, o.max_seconds = _accuracy(error_estimate, accuracy, max_seconds)
    if o.error_estimate or o.accuracy > 0:
        if basis is not None:
            raise ValueError("basis: a basis belongs to one mesh; error_estimate and accuracy run the full model")
        if o.intervals == 0:
            raise ValueError("intervals: error_estimate and accuracy compare the meshes at the output times, not 0")
        o.accuracy_check = True
    return _core.simulate(model, o)


def validate(source, out, *, sweep_steps=21, quiet=True):
    """`flexmb validate`: the paper's validation report (report.md with its figures and tables) in the
    folder `out` from the paper's models in `source`/datfiles (a flexmb source tree). Returns 0 when
    every acceptance check holds, 1 when one failed (the report says which), 3 when an analysis
    stopped."""
    import os

    for name, value in (("source", source), ("out", out)):
        if not isinstance(value, (str, bytes)) and not hasattr(value, "__fspath__"):
            raise TypeError(f"{name}: expected a folder name, got {type(value).__name__}")
    source, out = os.fsdecode(os.fspath(source)), os.fsdecode(os.fspath(out))
    if not os.path.isdir(os.path.join(source, "datfiles")):
        raise ValueError(f"source: {source} has no datfiles/ folder")
    return _core.validate(source, out, _count(sweep_steps, "sweep_steps", 2), bool(quiet))


def _write_simulation(self, prefix, *, csv=True, mat=True, linearize=0, matrices=False, vtk=False, html=False,
                      plot=()):
    """The files `flexmb simulate --out prefix` writes (CSV tables, .mat, SPACAR's .sbd, ...); plot: the
    columns of `--plot` ("node6.x,sig:PLBEAM3.e2_bending_p" or a list) drawn in <prefix>_history.svg."""
    _need(prefix, str, "prefix")
    if isinstance(plot, str):
        plot = [c.strip() for c in plot.split(",") if c.strip()]
    plot = list(plot)
    for c in plot:
        _need(c, str, "plot")
    return _core.SimulationResult._write(self, prefix, bool(csv), bool(mat), _count(linearize, "linearize", 0),
                                         bool(matrices), bool(vtk), bool(html), plot)


_core.SimulationResult._write = _core.SimulationResult.write
_core.SimulationResult.write = _write_simulation


def _write_transfer(self, prefix, *, bode=True):
    """The files `flexmb transfer --out prefix` writes."""
    _need(prefix, str, "prefix")
    return _core.TransferResult._write(self, prefix, bool(bode))


_core.TransferResult._write = _core.TransferResult.write
_core.TransferResult.write = _write_transfer


def _damping(damping_ratio, rayleigh):
    """modes' and transfer's damping_ratio (a ratio or a list per mode) and rayleigh (alpha, beta)."""
    ratios = []
    if damping_ratio is not None:
        ratios = [_real(damping_ratio, "damping_ratio")] if isinstance(damping_ratio, numbers.Real) else \
            [_real(z, "damping_ratio") for z in damping_ratio]
        if not ratios or min(ratios) < 0:
            raise ValueError(f"damping_ratio: expected ratios of at least 0, got {damping_ratio}")
    alpha = beta = 0.0
    if rayleigh is not None:
        ab = [_real(v, "rayleigh") for v in rayleigh]
        if len(ab) != 2 or min(ab) < 0:
            raise ValueError(f"rayleigh: expected (alpha, beta), both at least 0, got {rayleigh}")
        alpha, beta = ab
    return ratios, alpha, beta


def _need(value, kind, name):
    if not isinstance(value, kind):
        raise TypeError(f"{name}: expected {kind.__name__}, got {type(value).__name__}")


def _model(model):
    if not isinstance(model, Model):
        raise TypeError(f"model: expected a flexmb.Model (flexmb.read or flexmb.parse), got {type(model).__name__}")


def _refined(model, refine, refined_results=False):
    # Every flexible beam split in `refine` elements (1: the model itself); see read().
    parts = _count(refine, "refine", 1)
    if not isinstance(refined_results, bool):
        raise TypeError(f"refined_results: expected True or False, got {type(refined_results).__name__}")
    return model if parts == 1 else model.refined(parts, refined_results=refined_results)


def _accuracy(error_estimate, accuracy, max_seconds):
    # error_estimate= / accuracy= / max_seconds= as the native part takes them (accuracy 0: not asked).
    if not isinstance(error_estimate, bool):
        raise TypeError(f"error_estimate: expected True or False, got {type(error_estimate).__name__}")
    eps = 0.0
    if accuracy is not None:
        eps = _real(accuracy, "accuracy")
        if not 1e-10 <= eps < 1:  # analysis/AccuracyTarget.hpp kSmallestAccuracy
            raise ValueError(f"accuracy: expected a number from 1e-10 (finer than double precision integrates) "
                             f"to below 1, got {eps}")
        if error_estimate:
            raise ValueError("accuracy estimates the error itself: give accuracy or error_estimate, not both")
    return error_estimate, eps, _positive(max_seconds, "max_seconds")


def _real(value, name):
    if isinstance(value, bool) or not isinstance(value, numbers.Real):
        raise TypeError(f"{name}: expected a number, got {type(value).__name__}")
    if not np.isfinite(value):
        raise ValueError(f"{name}: expected a finite number, got {value}")
    return float(value)


def _positive(value, name):
    if value is None:
        return None
    v = _real(value, name)
    if v <= 0:
        raise ValueError(f"{name}: expected a positive number, got {value}")
    return v


def _count(value, name, least):
    if isinstance(value, bool) or not isinstance(value, numbers.Integral):
        raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
    if value < least:
        raise ValueError(f"{name}: expected at least {least}, got {value}")
    return int(value)


def _basis(basis, model):
    if basis is None:
        return None
    if isinstance(basis, (str, bytes)) or hasattr(basis, "__fspath__"):
        import os

        return _core.read_basis(os.fsdecode(os.fspath(basis)), model.ndof)
    if isinstance(basis, _core.ReduceResult):
        return basis.V
    v = np.asarray(basis, dtype=float)
    if v.ndim != 2 or v.shape[0] != model.ndof or v.shape[1] < 1:
        raise ValueError(f"basis: expected shape ({model.ndof}, k) (the degrees of freedom by the basis vectors), "
                         f"got {v.shape}")
    return v


__all__ = ["read", "parse", "variant", "check", "static", "modes", "sweep", "transfer", "reduce", "simulate", "validate", "Model", "InputError",
           "UserFunctionError"]
from . import light  # noqa: E402,F401  (SPACAR Light's inputs as a .dat: flexmb.light.build)
