#!/usr/bin/python3
"""SPACAR-shaped results (io/results.md), read back with scipy: runs the flexmb CLI on the paper's
models and a static cantilever, then checks that
  * x(:, lnp(n, k)) is coordinate k of node n and e(:, le(el, j)) deformation j of element el,
    bit for bit equal to the CLI's CSV tables (17 significant digits read back exactly);
  * every per-step quantity has the documented shape, the counts add up (nxp, nep, ndof, nddof);
  * sig equals the CSV stresses on the elastic (dynamic and released) deformations;
  * fxt equals the applied load on the free coordinates; in statics the reactions balance it;
  * the .sbm matrices of mode 3 equal the ones of <out>_linear.mat.
Usage: check_spacar_results.py FLEXMB SOURCE_DIR WORK_DIR"""
import csv, math, os, re, subprocess, sys
import numpy as np
import scipy.io as sio

flexmb, src, work = sys.argv[1], sys.argv[2], sys.argv[3]
os.makedirs(work, exist_ok=True)
failures = []

def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)

def run(args):
    # simulate writes SPACAR's .sbd/.mat on request (its default is the CSV tables)
    r = subprocess.run([flexmb] + args + ["-q", "--format", "both"] if args[0] == "simulate" else [flexmb] + args,
                       cwd=work, capture_output=True, text=True)
    if r.returncode != 0:
        print(r.stdout, r.stderr)
        raise SystemExit("flexmb failed: " + " ".join(args))

def read_csv(path):
    with open(path) as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(v) for v in r] for r in rows[1:]])

def check_topology(d, name):
    nx, ne = int(d["nx"][0, 0]), int(d["ne"][0, 0])
    nxp, nep = d["nxp"].ravel().astype(int), d["nep"].ravel().astype(int)
    check(nxp.sum() == nx and nep.sum() == ne, f"{name}: nxp {nxp} / nep {nep} do not add up to nx {nx} / ne {ne}")
    check(int(d["ndof"][0, 0]) == nxp[2] + nxp[3] + nep[2] + nep[3], f"{name}: ndof")
    check(int(d["nddof"][0, 0]) == nxp[3] + nep[3], f"{name}: nddof")
    lnp, le = d["lnp"].astype(int), d["le"].astype(int)
    used = np.sort(lnp[lnp > 0])
    check(np.array_equal(used, np.arange(1, nx + 1)), f"{name}: lnp is not a permutation of 1..nx")
    usede = np.sort(le[le > 0])
    check(np.array_equal(usede, np.arange(1, ne + 1)), f"{name}: le is not a permutation of 1..ne")
    tdef = int(d["tdef"][0, 0])
    for v, n in (("x", nx), ("xd", nx), ("xdd", nx), ("fxt", nx), ("e", ne), ("ed", ne), ("edd", ne), ("sig", ne)):
        check(d[v].shape == (tdef, n), f"{name}: {v} is {d[v].shape}, expected {(tdef, n)}")
    check(d["time"].shape == (tdef, 1), f"{name}: time shape")
    return nx, ne, nxp, nep, lnp, le

def by_node(header):
    """CSV coordinate columns grouped by node label, in component order."""
    nodes = {}
    for c, h in enumerate(header[1:], start=1):
        m = re.match(r"node(\d+)\.", h)
        if not m:
            continue
        nodes.setdefault(int(m.group(1)), []).append(c)
    return nodes

def by_element(header):
    els = {}
    for c, h in enumerate(header[1:], start=1):
        m = re.match(r"[A-Za-z]+(\d+)\.e(\d+)_", h)
        els.setdefault(int(m.group(1)), {})[int(m.group(2))] = c
    return els

def check_against_csv(model, base, expect_nddof):
    d = sio.loadmat(os.path.join(work, base + ".sbd"))
    nx, ne, nxp, nep, lnp, le = check_topology(d, base)
    check(int(d["nddof"][0, 0]) == expect_nddof, f"{base}: nddof {int(d['nddof'][0, 0])}, expected {expect_nddof}")
    hx, X = read_csv(os.path.join(work, base + "_x.csv"))
    check(np.array_equal(d["time"][:, 0], X[:, 0]), f"{base}: time differs from the CSV")
    checked = 0
    for q in ("x", "xd", "xdd"):
        h, T = read_csv(os.path.join(work, f"{base}_{q}.csv"))
        for n, cols in by_node(h).items():
            for k, c in enumerate(cols):
                ok = np.array_equal(d[q][:, lnp[n - 1, k] - 1], T[:, c])
                check(ok, f"{base}: {q}(:, lnp({n},{k + 1})) differs from CSV column {h[c]}")
                checked += 1
    elastic = set(range(nep[0] + nep[2] + 1, ne + 1))  # dynamic and released places (1-based)
    for q in ("e", "ed", "edd", "sig"):
        h, T = read_csv(os.path.join(work, f"{base}_{q}.csv"))
        for el, cols in by_element(h).items():
            for j, c in cols.items():
                place = le[el - 1, j - 1]
                if q == "sig" and place not in elastic:
                    continue
                check(np.array_equal(d[q][:, place - 1], T[:, c]), f"{base}: {q}(:, le({el},{j})) differs from {h[c]}")
                checked += 1
    print(f"{base}: {checked} columns equal to the CSV bit for bit; nx {nx}, ne {ne}, nxp {nxp}, nep {nep}")
    return d

# 1. Paper models, mode 1 (shortened where long) and mode 3 for the guidance.
models = [("straight_guidance", [], 17), ("manipulator", ["--t-end", "0.05"], None),
          ("slider_crank_s95", ["--t-end", "0.5"], None)]
for name, extra, nddof in models:
    run(["simulate", os.path.join(src, "datfiles", name + ".dat")] + extra)
    d = sio.loadmat(os.path.join(work, name + ".sbd"))
    check_against_csv(name, name, nddof if nddof is not None else int(d["nxp"][0, 3] + d["nep"][0, 3]))

# Straight guidance: fxt on free coordinates is the applied load (Eq. 24 at node 6, x).
d = sio.loadmat(os.path.join(work, "straight_guidance.sbd"))
t = d["time"][:, 0]
f = np.where(t <= 0.1, 50.0 * (1 - np.cos(20 * np.pi * t)), 0.0)
lnp = d["lnp"].astype(int)
free = np.arange(int(d["nxp"][0, 0]), int(d["nx"][0, 0]))  # 0-based places after the fixed ones
expected = np.zeros((len(t), int(d["nx"][0, 0])))
expected[:, lnp[5, 0] - 1] = f
err = np.abs(d["fxt"][:, free] - expected[:, free]).max()
check(err <= 1e-9 * 100, f"straight_guidance: fxt on free coordinates differs from the applied load by {err}")
print(f"straight_guidance: fxt on free coordinates equals the applied load (max diff {err:.3g} N)")

# Mode 3: .sbm equals <out>_linear.mat.
run(["--mode", "3", os.path.join(src, "datfiles", "straight_guidance.dat"), "--t-end", "0.02", "--out", "sg3"])
m = sio.loadmat(os.path.join(work, "sg3.sbm"))
lin = sio.loadmat(os.path.join(work, "sg3_linear.mat"))
for v in ("M0", "K0", "G0", "C0", "D0", "N0"):
    check(m[v].shape == lin[v].shape and np.array_equal(m[v], lin[v]), f"sg3: {v} differs from _linear.mat")
check(m[v].shape[0] == 17, "sg3: matrices are not nddof x nddof")
print(f"sg3: M0..N0 {m['M0'].shape} equal to _linear.mat")

# 2. Statics: reactions balance the applied loads in every load step; e, sig shapes; modes file.
cant = os.path.join(src, "tools", "tests", "data", "cantilever_static.dat")
run(["static", cant, "--out", os.path.join(work, "cant_static.csv")])
d = sio.loadmat(os.path.join(work, "cantilever_static.sbd"))
nx, ne, nxp, nep, lnp, le = check_topology(d, "cantilever_static")
fxt, x = d["fxt"], d["x"]
for k in range(fxt.shape[0]):
    fx = sum(fxt[k, lnp[n - 1, 0] - 1] for n in (1, 2, 3))
    fy = sum(fxt[k, lnp[n - 1, 1] - 1] for n in (1, 2, 3))
    mz = sum(fxt[k, lnp[n - 1, 0] - 1] for n in (101, 102, 103))
    mz += sum(x[k, lnp[n - 1, 0] - 1] * fxt[k, lnp[n - 1, 1] - 1] - x[k, lnp[n - 1, 1] - 1] * fxt[k, lnp[n - 1, 0] - 1]
              for n in (1, 2, 3))
    check(max(abs(fx), abs(fy), abs(mz)) < 1e-8, f"cantilever step {k + 1}: unbalanced {fx} {fy} {mz}")
check(np.allclose(fxt[-1, lnp[2, :] - 1], [2.0, -5.0]) and abs(fxt[-1, lnp[102, 0] - 1] - 0.5) < 1e-12,
      "cantilever: applied tip load not in fxt")
check(d["bigd"].shape == (ne, nx, fxt.shape[0]), "cantilever: bigd shape")
csvh, C = read_csv(os.path.join(work, "cant_static.csv"))
for n, cols in by_node(csvh).items():
    for k, c in enumerate(cols):
        check(np.array_equal(x[:, lnp[n - 1, k] - 1], C[:, c]), f"cantilever: x(:, lnp({n},{k + 1})) differs from CSV")
print(f"cantilever_static: {fxt.shape[0]} load steps, reactions balance the loads; x equals the CSV")
run(["modes", cant, "--out", "cant_modes", "--nev", "3"])
m = sio.loadmat(os.path.join(work, "cant_modes.sbm"))
check(m["modeq"].shape == (6, 3) and m["modex"].shape == (9, 3), f"modes: shapes {m['modeq'].shape} {m['modex'].shape}")
# Mode shapes in x are F_q times those in q: the fixed coordinates do not move.
check(np.abs(m["modex"][:3, :]).max() == 0.0, "modes: fixed coordinates move in modex")

# 3. The integrator statistics in <out>.mat: bdf adds njacevals and nlinsetups, ode45 has none.
guid = os.path.join(src, "datfiles", "straight_guidance.dat")
for integ in ("ode45", "bdf"):
    run(["simulate", guid, "--t-end", "0.02", "--intervals", "4", "--integrator", integ, "--out", "sgi_" + integ])
    d = sio.loadmat(os.path.join(work, f"sgi_{integ}.mat"))
    check(d["nsteps"][0, 0] > 0 and d["nfevals"][0, 0] >= d["nsteps"][0, 0], f"{integ}: nsteps/nfevals in .mat")
    if integ == "bdf":
        check("njacevals" in d and d["njacevals"][0, 0] > 0, "bdf: njacevals missing or 0 in .mat")
        check("nlinsetups" in d and d["nlinsetups"][0, 0] >= d["njacevals"][0, 0], "bdf: nlinsetups in .mat")
    else:
        check("njacevals" not in d, "ode45: njacevals in .mat")
    check(np.array_equal(sio.loadmat(os.path.join(work, f"sgi_{integ}.sbd"))["nfevals"], d["nfevals"]),
          f"{integ}: nfevals of .sbd and .mat differ")
print("integrator statistics in <out>.mat: ode45 and bdf as documented")

if failures:
    print(f"{len(failures)} failures")
    sys.exit(1)
print("all SPACAR-shaped result checks passed")
