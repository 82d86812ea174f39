"""SPACAR Light's way of describing a flexure model, in Python: nodes, elements, node properties
(`nprops`) and element properties (`eprops`, with `nbeams`, `flex`, `cshape`/`dim`, `warping`, ...)
become the SPACAR .dat that SPACAR Light's spacarlight.m writes for the same inputs, and a flexmb
model of it.

    from flexmb import light
    b = light.build(nodes, elements, nprops, eprops, {"gravity": [0, 0, -9.81]})
    b.dat, b.model             # the .dat text and flexmb.Model (also: dat, model = b)
    b.beams[0]                 # SPACAR's BEAM numbers of user element 1 (nbeams of them)
    b.releases                 # per user element the deformations released (RLSE) to close loops
    b.write("stage.dat")

Field names and meanings are SPACAR Light's (spacar.nl): a user node i becomes SPACAR's position
node 3i-2, orientation node 3i-1 and warping node 3i; an element with nbeams = n is split into n
equal beams through new nodes numbered on from 3N+1; `flex` lists the deformation modes that are
compliant (DYNE), the others are rigid; `warping` makes the beams BEAMW. As SPACAR Light does, the
loops of the model are closed by releasing (RLSE) deformations of the last beam of a flexible
element, found from the singular vectors of D's calculable block in the kinematic analysis (mode
0); `opt["rls"]` gives them by hand instead. Numbers are written in full precision; `digits=
"spacarlight"` writes them with SPACAR Light's fixed decimals instead (6, and 15 for ESTIFF and EM).
"""

import math
import numbers

import numpy as np

NODE_FIELDS = ("fix", "fix_x", "fix_y", "fix_z", "fix_pos", "fix_orien", "fix_warp", "displ_x", "displ_y", "displ_z",
               "rot", "rot_x", "rot_y", "rot_z", "force", "moment", "mass", "mominertia", "force_initial",
               "moment_initial", "displ_initial_x", "displ_initial_y", "displ_initial_z", "rot_initial",
               "rot_initial_x", "rot_initial_y", "rot_initial_z", "transfer_in", "transfer_out")
ELEMENT_FIELDS = ("elems", "emod", "smod", "dens", "cshape", "dim", "orien", "nbeams", "flex", "color", "hide",
                  "opacity", "cw", "warping")
OPTIONS = ("filename", "gravity", "silent", "calcbuck", "showinputonly", "loadsteps", "rls", "mode", "transfer",
           "calccompl", "customvis", "customdyn", "customkin", "spavisual", "rigidstress", "stressperelement")
# SPACAR Light's named colours (RGB 0..255); a set without a colour takes them in turn.
COLORS = {"blue": (162, 195, 214), "grey": (198, 198, 198), "darkblue": (0, 124, 176), "darkgrey": (112, 112, 112),
          "green": (128, 194, 143), "darkgreen": (90, 137, 101)}
NO_SET_COLOR = (206, 109, 116)
TRANSFER_IN = {"force_x": 1, "force_y": 2, "force_z": 3}
TRANSFER_OUT = {"displ_x": ("OUTX", 1), "displ_y": ("OUTX", 2), "displ_z": ("OUTX", 3),
                "veloc_x": ("OUTXP", 1), "veloc_y": ("OUTXP", 2), "veloc_z": ("OUTXP", 3)}


class LightModel:
    """What `build` makes: `.dat` (text), `.model` (flexmb.Model), `.beams` (per user element the
    SPACAR beam numbers), `.releases` (per user element the released deformations), `.mode` (10,
    3 or 9), `.damping_ratio` (opt transfer's modal damping, for flexmb.transfer), `.write(path)`."""

    def __init__(self, dat, model, beams, releases, mode, damping_ratio, name):
        self.dat, self.model, self.beams, self.releases = dat, model, beams, releases
        self.mode, self.damping_ratio, self.name = mode, damping_ratio, name

    def __iter__(self):
        return iter((self.dat, self.model))

    def node(self, i):
        """SPACAR's (position, orientation, warping) node numbers of user node i (1-based)."""
        return 3 * i - 2, 3 * i - 1, 3 * i

    def write(self, path):
        with open(path, "w") as f:
            f.write(self.dat)
        return str(path)

    def __repr__(self):
        return f"<flexmb.light {self.name}: {len(self.beams)} elements as {sum(map(len, self.beams))} beams, mode {self.mode}>"


def build(nodes, elements, nprops=(), eprops=(), opt=None, *, digits="full"):
    """The .dat SPACAR Light writes for these inputs and its flexmb model (LightModel). nodes: N x 3
    (m); elements: M x 2 user node numbers (1-based); nprops: a list whose entry i (a dict or None)
    holds node i+1's properties, or a dict {node number: dict}; eprops: a list of dicts, each with
    `elems` (1-based element numbers); opt: a dict of SPACAR Light's options (filename, gravity,
    loadsteps, mode, transfer, rls, custom*). digits: "full" or "spacarlight"."""
    if digits not in ("full", "spacarlight"):
        raise ValueError(f"digits: 'full' or 'spacarlight', not {digits!r}")
    from . import parse  # the package's reader (a late import: this module is part of the package)

    s = _Inputs(nodes, elements, nprops, eprops, opt)
    name = (s.opt.get("filename") or "spacar_file") + ("_3" if s.mode == 3 else "") + ".dat"
    releases = s.releases
    if releases is None:
        # Searched on the file SPACAR Light runs first (mode 0, its rounding): the redundant rows span
        # several dimensions, and which singular vector comes first changes with the sixth decimal.
        first = _Writer(s, 0, None, "spacarlight").text()
        releases = _find_releases(s, _kinematic(parse(first, name)), name)
    w = _Writer(s, s.mode, releases, digits)
    dat = w.text()
    return LightModel(dat, parse(dat, name), w.beams, [list(r) for r in releases], s.mode, s.damping, name)


# ---- inputs: SPACAR Light's fields, checked -------------------------------------------------------


def _given(props, key):
    """A field counts when present and not empty (SPACAR Light's isfield && ~isempty)."""
    if props is None or key not in props:
        return False
    v = props[key]
    if v is None or isinstance(v, (bool, np.bool_)) and not v:
        return False
    if isinstance(v, str):
        return v != ""
    return not (hasattr(v, "__len__") and len(v) == 0)


def _vector(v, n, what):
    a = np.asarray(v, dtype=float).ravel()
    if a.size != n or not np.all(np.isfinite(a)):
        raise ValueError(f"{what}: expected {n} finite numbers, got {v!r}")
    return a


def _scalar(v, what):
    if isinstance(v, bool) or not isinstance(v, numbers.Real) or not math.isfinite(v):
        raise ValueError(f"{what}: expected a finite number, got {v!r}")
    return float(v)


class _Inputs:
    def __init__(self, nodes, elements, nprops, eprops, opt):
        self.nodes = np.asarray(nodes, dtype=float)
        if self.nodes.ndim != 2 or self.nodes.shape[1] != 3 or not np.all(np.isfinite(self.nodes)):
            raise ValueError(f"nodes: expected an N x 3 array of finite coordinates, got shape {self.nodes.shape}")
        el = np.asarray(elements)
        if el.ndim != 2 or el.shape[1] != 2 or el.size == 0 or np.any(el != np.round(el)):
            raise ValueError("elements: expected an M x 2 array of node numbers (1-based)")
        self.elements = el.astype(int)
        nn = len(self.nodes)
        if self.elements.min() < 1 or self.elements.max() > nn:
            raise ValueError(f"elements: node numbers must lie in 1..{nn}")
        lengths = []
        for i, (p, q) in enumerate(self.elements, 1):
            if p == q:
                raise ValueError(f"element {i}: both ends on node {p}")
            lengths.append(np.linalg.norm(self.nodes[q - 1] - self.nodes[p - 1]))
            if lengths[-1] <= 1e-5:
                raise ValueError(f"element {i}: length at most 1e-5 m")
        if max(lengths) > 1000 * min(lengths):
            raise ValueError("elements: the longest is more than 1000 times the shortest (SPACAR Light's limit)")
        loose = sorted(set(range(1, nn + 1)) - set(self.elements.ravel().tolist()))
        if loose:
            raise ValueError(f"nodes {loose} belong to no element")
        self.nprops = self._nodes(nprops, nn)
        self.opt = dict(opt or {})
        for k in self.opt:
            if k not in OPTIONS:
                raise ValueError(f"opt: unknown field {k!r} (SPACAR Light knows {', '.join(OPTIONS)})")
        self.sets, self.set_of = self._sets(eprops)
        self._options()

    def _nodes(self, nprops, nn):
        if isinstance(nprops, dict):
            items = list(nprops.items())
        else:
            items = [(i + 1, p) for i, p in enumerate(nprops)]
        out = [None] * nn
        for n, p in items:
            if not isinstance(n, numbers.Integral) or not 1 <= n <= nn:
                raise ValueError(f"nprops: node {n!r} does not exist (nodes 1..{nn})")
            if p is None:
                continue
            p = dict(p)
            for k in p:
                if k not in NODE_FIELDS:
                    raise ValueError(f"nprops of node {n}: unknown field {k!r}")
            for k in ("force", "force_initial", "moment", "moment_initial"):
                if _given(p, k):
                    p[k] = _vector(p[k], 3, f"nprops of node {n}: {k}")
            if _given(p, "mominertia"):
                p["mominertia"] = _vector(p["mominertia"], 6, f"nprops of node {n}: mominertia")
            for k in ("rot", "rot_initial"):
                if _given(p, k):
                    p[k] = _vector(p[k], 4, f"nprops of node {n}: {k} (angle, then the axis)")
            for k in ("transfer_in", "transfer_out"):
                if _given(p, k):
                    p[k] = [p[k]] if isinstance(p[k], str) else list(p[k])
                    known = TRANSFER_IN if k == "transfer_in" else TRANSFER_OUT
                    for c in p[k]:
                        if c not in known:
                            raise ValueError(f"nprops of node {n}: {k} {c!r} is not one of {', '.join(known)}")
            if _given(p, "fix") and any(_given(p, k) for k in ("fix_pos", "fix_orien", "fix_x", "fix_y", "fix_z",
                                                                "fix_warp")):
                raise ValueError(f"nprops of node {n}: fix together with fix_pos/fix_orien/fix_warp/fix_x/y/z")
            rotations = sum(_given(p, k) or _given(p, k.replace("rot", "rot_initial")) for k in
                            ("rot", "rot_x", "rot_y", "rot_z"))
            if rotations > 1:
                raise ValueError(f"nprops of node {n}: more than one rotational input (SPACAR Light allows one)")
            out[n - 1] = p
        return out

    def _sets(self, eprops):
        sets, set_of = [], {}
        for i, e in enumerate(eprops):
            e = dict(e)
            for k in e:
                if k not in ELEMENT_FIELDS:
                    raise ValueError(f"eprops[{i}]: unknown field {k!r} (SPACAR Light knows {', '.join(ELEMENT_FIELDS)})")
            if not _given(e, "elems"):
                continue  # SPACAR Light ignores a set without elements (with a warning)
            elems = [int(x) for x in np.atleast_1d(e["elems"])]
            for x in elems:
                if not 1 <= x <= len(self.elements):
                    raise ValueError(f"eprops[{i}].elems: element {x} does not exist (1..{len(self.elements)})")
                if x in set_of:
                    raise ValueError(f"eprops[{i}].elems: element {x} already has properties (eprops[{set_of[x]}])")
                set_of[x] = len(sets)
            e["elems"] = elems
            self._check_set(e, i)
            sets.append(e)
        return sets, set_of

    def _check_set(self, e, i):
        shape = e.get("cshape") if _given(e, "cshape") else None
        if shape is not None:
            if shape not in ("rect", "circ"):
                raise ValueError(f"eprops[{i}].cshape: 'rect' or 'circ', not {shape!r}")
            if not _given(e, "dim"):
                raise ValueError(f"eprops[{i}]: cshape {shape!r} needs dim")
            e["dim"] = _vector(e["dim"], 2 if shape == "rect" else 1, f"eprops[{i}].dim")
            if shape == "rect":
                if np.any(e["dim"] < 1e-4):
                    raise ValueError(f"eprops[{i}].dim: SPACAR Light wants at least 1e-4 m")
                if not _given(e, "orien"):
                    raise ValueError(f"eprops[{i}]: a rect section needs orien")
        flex = [int(d) for d in np.atleast_1d(e["flex"])] if _given(e, "flex") else []
        if any(d not in range(1, 7) for d in flex):
            raise ValueError(f"eprops[{i}].flex: deformation modes are 1..6, got {flex}")
        e["flex"] = flex
        need = ("cshape", "emod", "smod", "dens") if flex else (("cshape",) if _given(e, "dens") else ())
        for k in need:
            if not _given(e, k):
                raise ValueError(f"eprops[{i}]: {'flex' if flex else 'dens'} needs {k}")
        n = e.get("nbeams", 1) if _given(e, "nbeams") else 1
        if isinstance(n, bool) or not isinstance(n, numbers.Real) or n < 1 or n != int(n):
            raise ValueError(f"eprops[{i}].nbeams: a positive integer, got {n!r}")
        e["nbeams"] = int(n)
        e["warping"] = _given(e, "warping")  # a round section too (BEAMW without warping stiffness)
        e["color"] = _color(e.get("color"), i)
        orien = _vector(e["orien"], 3, f"eprops[{i}].orien") if _given(e, "orien") else np.array([0.0, 1.0, 0.0])
        e["orien"] = orien
        for x in e["elems"]:
            p, q = self.elements[x - 1]
            axis = self.nodes[q - 1] - self.nodes[p - 1]
            c = np.dot(axis / np.linalg.norm(axis), orien / np.linalg.norm(orien))
            if math.sqrt(max(0.0, 1 - c * c)) < 1e-5:
                raise ValueError(f"eprops[{i}].orien {list(orien)} is (almost) along element {x}")

    def _options(self):
        o = self.opt
        transfer = o.get("transfer")
        if isinstance(transfer, (list, tuple)):
            self.transfer, self.damping = bool(transfer[0]), (float(transfer[1]) if len(transfer) > 1 else None)
        else:
            self.transfer, self.damping = bool(transfer), None
        mode = o.get("mode", 10)
        if self.transfer:
            mode = 9
        elif mode not in (3, 10):
            raise ValueError(f"opt mode: 10 or 3 (9 through opt transfer), not {mode!r}")
        self.mode = mode
        if self.transfer:
            given = lambda k: any(p is not None and _given(p, k) for p in self.nprops)  # noqa: E731
            for k in ("force", "force_initial", "moment", "moment_initial", "displ_x", "displ_y", "displ_z",
                      "displ_initial_x", "displ_initial_y", "displ_initial_z"):
                if given(k):
                    raise ValueError(f"opt transfer: SPACAR Light's state-space model takes no nprops {k}")
            if not (given("transfer_in") and given("transfer_out")):
                raise ValueError("opt transfer: needs an nprops transfer_in and a transfer_out")
        self.loadsteps = int(o["loadsteps"]) if "loadsteps" in o else 10
        if self.loadsteps < 1:
            raise ValueError("opt loadsteps: at least 1")
        if "gravity" in o and o["gravity"] is not None and len(o["gravity"]):
            self.gravity = _vector(o["gravity"], 3, "opt gravity")
        else:
            self.gravity = None
        self.releases = None
        if "rls" in o:
            rls = o["rls"] or []
            self.releases = []
            for i in range(len(self.elements)):
                r = rls[i] if i < len(rls) else []
                r = r.get("def", []) if isinstance(r, dict) else r
                r = [int(d) for d in np.atleast_1d(r if r is not None else [])]
                if any(d not in range(1, 7) for d in r):
                    raise ValueError(f"opt rls of element {i + 1}: deformation modes are 1..6, got {r}")
                self.releases.append(r)
        for k in ("customkin", "customdyn", "customvis"):
            v = o.get(k) or []
            o[k] = [v] if isinstance(v, str) else list(v)

    def element(self, i):
        """(set, nbeams, orien, warping, flex) of user element i (1-based); defaults outside sets."""
        k = self.set_of.get(i)
        if k is None:
            return None, 1, np.array([0.0, 1.0, 0.0]), False, []
        e = self.sets[k]
        return e, e["nbeams"], e["orien"], e["warping"], e["flex"]


def _color(c, i):
    names = list(COLORS)
    if c is None or isinstance(c, str) and c == "":
        return np.array(COLORS[names[i % len(names)]]) / 255
    if isinstance(c, str):
        if c not in COLORS:
            raise ValueError(f"eprops[{i}].color: {c!r} is not one of {', '.join(names)}")
        return np.array(COLORS[c]) / 255
    if isinstance(c, numbers.Integral) and not isinstance(c, bool):
        if not 1 <= c <= len(names):
            raise ValueError(f"eprops[{i}].color: colour numbers are 1..{len(names)}")
        return np.array(COLORS[names[c - 1]]) / 255
    a = _vector(c, 3, f"eprops[{i}].color")
    if np.any(a < 0) or np.any(a > 255):
        raise ValueError(f"eprops[{i}].color: RGB values 0..1 or 0..255")
    return a / 255 if np.any(a > 1) else a


# ---- SPACAR Light's section constants ---------------------------------------------------------------


def _torsion_constant(t, w):
    """St Venant's torsion constant of a t x w rectangle, from its series (summed until a term adds
    less than 1e-4 of the sum, as SPACAR Light does)."""
    a, b = min(t, w) / 2, max(t, w) / 2
    total, n, term = 0.0, 1, 0.0
    while n < 3 or abs(term / total) > 1e-4:
        term = math.tanh(n * math.pi * b / (2 * a)) / n**5
        total += term
        n += 2
    return (2 * a) ** 3 * (2 * b) / 3 * (1 - 192 / math.pi**5 * (a / b) * total)


def _section(e):
    """(A, It, Iy, Iz, shear factor k as a function of nu, warping constant, warping inertia)."""
    if e["cshape"] == "rect":
        w, t = e["dim"]
        return w * t, _torsion_constant(t, w), t**3 * w / 12, t * w**3 / 12, "rect", (w * t) ** 3 / 144
    d = e["dim"][0]
    return math.pi / 4 * d**2, math.pi / 32 * d**4, math.pi / 64 * d**4, math.pi / 64 * d**4, "circ", 0.0


def stiffness(e):
    """ESTIFF of a set: EA, GIt, EIy, EIz, the two shear coefficients EI/(kGA) and (warping) E Cw."""
    A, It, Iy, Iz, shape, Cw = _section(e)
    E, G = float(e["emod"]), float(e["smod"])
    nu = E / (2 * G) - 1
    k = 10 * (1 + nu) / (12 + 11 * nu) if shape == "rect" else 6 * (1 + nu) / (7 + 6 * nu)
    return [E * A, G * It, E * Iy, E * Iz, E * Iy / (G * A * k), E * Iz / (G * A * k), E * Cw]


def inertia(e):
    """EM of a set per unit length: rho A, rho (Iy + Iz), rho Iy, rho Iz, 0 and (warping) rho Iw; a
    round section gets Iw = 1 (SPACAR Light's value: the mass matrix must not be singular)."""
    A, _, Iy, Iz, shape, Iw = _section(e)
    rho = float(e["dens"])
    return [rho * A, rho * (Iy + Iz), rho * Iy, rho * Iz, 0.0, rho * (Iw if shape == "rect" else 1.0)]


def _quaternion_of(axang):
    """Euler parameters of a rotation by axang[0] about the axis axang[1:4]."""
    axis = np.asarray(axang[1:4], dtype=float)
    s = math.sin(axang[0] / 2) / np.linalg.norm(axis)
    return [math.cos(axang[0] / 2)] + list(s * axis)


# ---- the .dat ----------------------------------------------------------------------------------------


class _Writer:
    """The .dat of SPACAR Light's inputs for one mode (0 for the release search) and releases."""

    def __init__(self, s, mode, releases, digits):
        self.s, self.mode, self.releases, self.spacarlight = s, mode, releases, digits == "spacarlight"
        self.beams = []

    def num(self, v, decimals=6):
        v = float(v)
        if self.spacarlight:
            return f"{v:.{decimals}f}"
        return repr(v + 0.0)

    def text(self):
        s = self.s
        out = ["# SPACAR .dat written by flexmb.light from SPACAR Light's inputs (nodes, elements, nprops, eprops, opt)"]
        if self.mode == 3:
            out.append("OUTLEVEL 0 1")
        out += self._geometry()
        out += self._fixes()
        out += self._inputs()
        out += list(s.opt["customkin"])
        out += ["END", "HALT"]
        out += self._sections()
        out += self._nodal_masses()
        if s.gravity is not None:
            out.append("GRAVITY " + " ".join(self.num(g) for g in s.gravity))
        out.append(self._iterstep())
        out += list(s.opt["customdyn"])
        if self.mode != 9:
            out += self._loads()
        else:
            out += ["END", "HALT"] + self._transfer()
        out += ["END", "END", ""]
        out += self._visualization()
        return "\n".join(out) + "\n"

    def _geometry(self):
        s = self.s
        nn = len(s.nodes)
        nodes = [f"X {3 * i + 1:4d} " + " ".join(self.num(c) for c in s.nodes[i]) + f"   # node {i + 1}"
                 for i in range(nn)]
        beams, deformations = [], []
        self.warping_fixes = []
        label, beam = 3 * nn + 1, 1
        for i, (p, q) in enumerate(s.elements, 1):
            e, n, orien, warping, flex = s.element(i)
            if warping and not flex:
                # A rigid BEAMW still computes its warping deformations: fix its warping nodes.
                self.warping_fixes += [3 * p, 3 * q]
            ends = [3 * p - 2]
            start, step = s.nodes[p - 1], (s.nodes[q - 1] - s.nodes[p - 1]) / n
            for k in range(1, n):
                nodes.append(f"X {label:4d} " + " ".join(self.num(c) for c in start + k * step) +
                             f"   # element {i}, inside")
                ends.append(label)
                if warping and not flex:
                    self.warping_fixes.append(label + 2)
                label += 3
            ends.append(3 * q - 2)
            mine = []
            for k in range(n):
                a, b = ends[k], ends[k + 1]
                conn = f"{a} {a + 1} {a + 2} {b} {b + 1} {b + 2}" if warping else f"{a} {a + 1} {b} {b + 1}"
                where = f"element {i}" + (f" beam {k + 1}" if n > 1 else "")
                beams.append(f"{'BEAMW' if warping else 'BEAM'} {beam:4d} {conn} " +
                             " ".join(self.num(c) for c in orien) + f"   # {where}")
                last = k == n - 1
                rel = self.releases[i - 1] if last and self.releases is not None else []
                dyne = [d for d in flex if d not in rel]
                if dyne:
                    deformations.append(f"DYNE {beam:4d} " + " ".join(map(str, dyne)))
                if rel:
                    deformations.append(f"RLSE {beam:4d} " + " ".join(map(str, rel)))
                mine.append(beam)
                beam += 1
            self.beams.append(mine)
        return nodes + beams + deformations

    def _fixes(self):
        out = []
        for i, p in enumerate(self.s.nprops, 1):
            if p is None:
                continue
            x, r = 3 * i - 2, 3 * i - 1
            if _given(p, "fix"):
                out += [f"FIX {x:4d}", f"FIX {r:4d}"]
                self.warping_fixes.append(3 * i)
            if _given(p, "fix_pos"):
                out.append(f"FIX {x:4d}")
            for c, k in enumerate(("fix_x", "fix_y", "fix_z"), 1):
                if _given(p, k):
                    out.append(f"FIX {x:4d} {c}")
            if _given(p, "fix_orien"):
                out.append(f"FIX {r:4d}")
            if _given(p, "fix_warp"):
                self.warping_fixes.append(3 * i)
        # Warping nodes last (unused ones too, as SPACAR Light writes them).
        return out + [f"FIX {w:4d}   # warping" for w in sorted(set(self.warping_fixes))]

    def _inputs(self):
        if self.mode == 9:
            return []
        kw = "DYNX" if self.mode == 3 else "INPUTX"
        out = []
        for i, p in enumerate(self.s.nprops, 1):
            if p is None:
                continue
            x, r = 3 * i - 2, 3 * i - 1
            for c, a in enumerate("xyz", 1):
                if _given(p, "displ_" + a) or _given(p, "displ_initial_" + a):
                    out.append(f"{kw} {x:4d} {c}")
            if _given(p, "rot") or _given(p, "rot_initial"):
                out.append(f"{kw} {r:4d} 2 3 4")
            for c, a in enumerate("xyz", 2):
                if _given(p, "rot_" + a) or _given(p, "rot_initial_" + a):
                    out.append(f"{kw} {r:4d} {c}")
        return out

    def _sections(self):
        stiff, mass = [], []
        for e in self.s.sets:
            if not (_given(e, "dens") and float(e["dens"]) > 0):
                continue
            n = 6 if e["warping"] else 5
            values = " ".join(self.num(v, 15) for v in inertia(e)[:n])
            beams = [b for x in e["elems"] for b in self.beams[x - 1]]
            mass += [f"EM {b:4d} {values}" for b in beams]
            if e["flex"]:
                n = 7 if e["warping"] else 6
                values = " ".join(self.num(v, 15) for v in stiffness(e)[:n])
                stiff += [f"ESTIFF {b:4d} {values}" for b in beams]
        return stiff + mass

    def _nodal_masses(self):
        out = []
        for i, p in enumerate(self.s.nprops, 1):
            if p is None:
                continue
            if _given(p, "mass"):
                out.append(f"XM {3 * i - 2:4d} {self.num(_scalar(p['mass'], f'nprops of node {i}: mass'))}")
            if _given(p, "mominertia"):
                out.append(f"XM {3 * i - 1:4d} " + " ".join(self.num(v) for v in p["mominertia"]))
        return out

    def _has(self, keys):
        return self.mode != 9 and any(p is not None and any(_given(p, k) for k in keys) for p in self.s.nprops)

    def _iterstep(self):
        # Initial loads (XF, INPUTX values) are ramped over the load steps when there are also
        # increments (DELXF, DELINPX): SPACAR's ITERSTEP maxit nsteps tol c4 c5 ninit.
        motions = self.mode != 3
        initial = self._has(("force_initial", "moment_initial") + (("displ_initial_x", "displ_initial_y",
                            "displ_initial_z", "rot_initial", "rot_initial_x", "rot_initial_y", "rot_initial_z")
                            if motions else ()))
        added = self._has(("force", "moment") + (("displ_x", "displ_y", "displ_z", "rot", "rot_x", "rot_y", "rot_z")
                                                 if motions else ()))
        steps = self.s.loadsteps - 1
        nsteps, c5, ninit = (steps, 3, steps) if initial and added else (1, 1, steps) if initial else \
            (steps, 3, 0) if added else (1, 1, 0)
        return f"ITERSTEP 10 {nsteps} {self.num(5e-7, 7)} 1 {c5} {ninit}"

    def _loads(self):
        forces, moments, rotations, displacements = [], [], [], []
        nodes = self.s.nodes
        for i, p in enumerate(self.s.nprops, 1):
            if p is None:
                continue
            x, r = 3 * i - 2, 3 * i - 1
            for key, kw, lst, label in (("force", "DELXF", forces, x), ("force_initial", "XF", forces, x),
                                        ("moment", "DELXF", moments, r), ("moment_initial", "XF", moments, r)):
                if _given(p, key):
                    lst.append(f"{kw} {label:4d} " + " ".join(self.num(v) for v in p[key]))
            if self.mode == 3:
                continue
            for c, a in enumerate("xyz", 1):
                if _given(p, "displ_" + a):
                    v = _scalar(p["displ_" + a], f"nprops of node {i}: displ_{a}")
                    displacements.append(f"DELINPX {x:4d} {c} {self.num(v)}")
            for c, a in enumerate("xyz", 1):
                if _given(p, "displ_initial_" + a):
                    v = nodes[i - 1][c - 1] + _scalar(p["displ_initial_" + a], f"nprops of node {i}: displ_initial_{a}")
                    displacements.append(f"INPUTX {x:4d} {c} {self.num(v)}")
            for key, kw in (("rot", "DELINPX"), ("rot_initial", "INPUTX")):
                if _given(p, key):
                    q = _quaternion_of(p[key])
                    rotations += [f"{kw} {r:4d} {c} {self.num(q[c - 1])}" for c in (2, 3, 4)]
            # A rotation about one axis: its Euler parameter sin(angle / 2) on that axis.
            for prefix, kw in (("rot_", "DELINPX"), ("rot_initial_", "INPUTX")):
                for c, a in enumerate("xyz", 2):
                    if _given(p, prefix + a):
                        v = _scalar(p[prefix + a], f"nprops of node {i}: {prefix}{a}")
                        rotations.append(f"{kw} {r:4d} {c} {self.num(math.sin(v / 2))}")
        return forces + moments + rotations + displacements

    def _transfer(self):
        ins, outs = [], []
        for i, p in enumerate(self.s.nprops, 1):
            if p is None:
                continue
            for c in p.get("transfer_in") or []:
                ins.append(f"INPUTF {len(ins) + 1:3d} {3 * i - 2:4d} {TRANSFER_IN[c]}")
            for c in p.get("transfer_out") or []:
                kw, d = TRANSFER_OUT[c]
                outs.append(f"{kw} {len(outs) + 1:3d} {3 * i - 2:4d} {d}")
        return ins + outs

    def _visualization(self):
        s = self.s
        out = ["VISUALIZATION", "INITIAL", "COLOR " + " ".join(self.num(0.0, 2) for _ in range(3))]
        for e in s.sets:
            beams = " ".join(str(b) for x in e["elems"] for b in self.beams[x - 1])
            if _given(e, "cshape"):
                out += [f"BEAMPROPS {beams}", "CROSSTYPE " + e["cshape"].upper(),
                        "CROSSDIM " + " ".join(self.num(d) for d in e["dim"])]
            out += [f"GRAPHICS {beams}", "FACECOLOR " + " ".join(self.num(c) for c in e["color"])]
            if _given(e, "opacity"):
                out.append(f"OPACITY {self.num(_scalar(e['opacity'], 'opacity'), 2)}")
            if _given(e, "hide"):
                out.append(f"DONOTDRAW {beams}")
        loose = [self.beams[i - 1][0] for i in range(1, len(s.elements) + 1) if i not in s.set_of]
        if loose:
            out += ["GRAPHICS " + " ".join(map(str, loose)),
                    "FACECOLOR " + " ".join(self.num(c / 255) for c in NO_SET_COLOR)]
        return out + list(s.opt["customvis"])


# ---- releases: SPACAR Light's closing of loops -----------------------------------------------------


def _kinematic(model):
    from . import _core

    return _core.kinematic(model)


def _find_releases(s, k, name):
    """Per user element the deformations to release so that D's calculable block (the rows of the
    fixed, input and dynamic deformations; the columns of the calculable coordinates) is square and
    regular: SPACAR Light's search. While rows are redundant, take the first left singular vector of
    the redundancy, and among the deformations that make up 1 - 1e-6 of its length (largest first)
    release the first that belongs to the last beam of an element whose set makes it flexible."""
    from scipy.linalg import svd

    nep, nxp, le = k["nep"], k["nxp"], np.asarray(k["le"])
    D = np.asarray(k["bigd"])[: nep[0] + nep[2] + nep[3], nxp[0]: nxp[0] + nxp[1]]
    releases = [[] for _ in s.elements]
    if D.size == 0:
        raise ValueError(f"{name}: no calculable coordinates or no deformations: nothing to solve for")
    sv = svd(D, compute_uv=False, lapack_driver="gesvd")
    m, n = D.shape
    nsing = int(np.sum(sv < math.sqrt(np.finfo(float).eps) * sv[0]))
    over, under = (m - n + nsing, nsing) if m > n else (nsing, n - m + nsing) if m < n else (nsing, nsing)
    if under > 0:
        raise ValueError(f"{name}: the model is underconstrained ({under} coordinates not determined): "
                         "check the connectivity, the boundary conditions (fix) and opt rls")
    ids = list(range(1, m + 1))  # the places in e of D's remaining rows
    last = {bs[-1]: i for i, bs in enumerate(_beam_numbers(s))}
    for _ in range(over):
        U = svd(D, full_matrices=True, lapack_driver="gesvd")[0]
        oc = U[:, U.shape[1] - over] ** 2
        order = np.argsort(-oc, kind="stable")
        count = int(np.argmax(np.cumsum(oc[order]) > math.sqrt(1 - 1e-6))) + 1
        for row in order[:count]:
            beam, mode = [int(v) + 1 for v in np.argwhere(le == ids[row])[0]]
            user = last.get(beam)
            if user is None:
                continue
            flex = s.element(user + 1)[4]
            if mode in flex and mode not in releases[user]:
                releases[user].append(mode)
                del ids[row]
                D = np.delete(D, row, axis=0)
                over -= 1
                break
        else:
            done = "; ".join(f"element {i + 1}: {r}" for i, r in enumerate(releases) if r) or "none"
            raise ValueError(f"{name}: {over} overconstraint(s) could not be released in a flexible element "
                             f"(releases so far: {done}); a rigid loop? Give opt rls by hand")
    return [sorted(r) for r in releases]


def _beam_numbers(s):
    """SPACAR beam numbers per user element (the numbering of _Writer._geometry)."""
    beams, b = [], 1
    for i in range(1, len(s.elements) + 1):
        n = s.element(i)[1]
        beams.append(list(range(b, b + n)))
        b += n
    return beams
