"""The tree kernel specialised to one linkage shape: generated straight-line source, compiled and cached by numba.

Why: the general tree kernel (kernel.rhs_tree) walks its tables (paths, parents, contact bodies) with loops of
data-dependent length and keeps every intermediate in memory; the mass matrix is factorised densely. For a given
shape (which body hangs from which, which bodies each clearance joint connects) all of that is known before the
integration, so the generated right-hand side has every index as a literal and every intermediate in a local variable,
skips the structural zeros of the Jacobian and of the mass matrix, and factorises the mass matrix from the leaves to
the root without fill-in (Featherstone, Rigid Body Dynamics Algorithms, 2008, Section 6.5, the L^T D L factorisation
of a branch-induced sparse matrix): one division per coordinate, independent across branches. Only the shape is
compiled in; dimensions, masses, contact parameters and laws stay in the arrays, so a study's model calls (uncertain
dimensions and materials) share one compiled kernel.

The generated module holds the right-hand side (``rhs_spec``, the contract of kernel.rhs_tree) and a copy of the
Dormand-Prince loop (kernel.integrate_tree's source, its tree call redirected to ``rhs_spec``). It is written to a
cache directory under a name hashed from the generated source and the sources of the kernel and the contact laws (a
change to either gives a new file, so numba's per-file cache never serves stale machine code), and imported from there
(numba caches per file, next to it).
"""

from __future__ import annotations

import hashlib
import importlib.util
import inspect
import os
import sys
import tempfile
import textwrap
import threading
from pathlib import Path

import numba
import numpy as np

from jointwear.contact import laws as _laws_module
from jointwear.mechanism import kernel as K
from jointwear.mechanism.tree import TreeLayout

_LOCK = threading.Lock()
_LOADED: dict[str, object] = {}  # module name -> module
_BY_KEY: dict[tuple, object] = {}  # shape_key -> module (simulate builds a runner per call: skip the hashing)


def shape_key(lay: TreeLayout, nd: int, cint: np.ndarray) -> tuple:
    """What the generated code depends on: the tree's rows (kind, body, parent, first coordinate, path), the number of
    driven bodies and the bodies of each clearance joint."""
    rows = tuple(tuple(int(v) for v in row[: K.T_PATH + int(row[K.T_LEN])]) for row in lay.jint)
    joints = tuple((int(c[K.CI_BB]), int(c[K.CI_BJ])) for c in cint)
    return rows, int(nd), joints


class _Emitter:
    """Source lines of the specialised right-hand side; J components are names, "1" or None (zero)."""

    def __init__(self):
        self.lines: list[str] = []

    def __call__(self, line: str) -> None:
        self.lines.append("    " + line)


def _mul(a, b):
    if a is None or b is None:
        return None
    if a == "1":
        return b
    if b == "1":
        return a
    return f"{a} * {b}"


def _num(v):
    return "1.0" if v == "1" else v


def _carried(e, p, pj: dict, rx: str, ry: str) -> dict:
    """The Jacobian columns of a point rigidly carried by a body (its columns pj) at (rx, ry) from the body's centre
    of mass: jx - jw ry, jy + jw rx, jw; named locals where a column turns the body."""
    out = {}
    for i, (jx, jy, jw) in pj.items():
        if jw is None:
            out[i] = (jx, jy, jw)
            continue
        ex, ey = f"{p}jx{i}", f"{p}jy{i}"
        e(f"{ex} = " + (f"-{_mul(jw, ry)}" if jx is None else f"{_num(jx)} - {_mul(jw, ry)}"))
        e(f"{ey} = " + (_mul(jw, rx) if jy is None else f"{_num(jy)} + {_mul(jw, rx)}"))
        out[i] = (ex, ey, jw)
    return out


def _emit_slider(e, body: dict, r: int, b: int, par: int, d: int, n: int, nb: int) -> None:
    """A body hung by a prismatic joint (kernel.tree_kinematics): it turns with its parent (the ground or a free
    body) and its point slides along the parent's line at s = y[d]."""
    p = f"b{b}_"
    q = body[par] if par >= 0 else {"x": None, "y": None, "phi": None, "c": None, "s": None, "vx": None, "vy": None,
                                    "w": None, "ax": None, "ay": None, "J": {}}

    def rot(sx, sy, c, s):
        if c is None:
            return sx, sy
        return f"{c} * {sx} - {s} * {sy}", f"{s} * {sx} + {c} * {sy}"

    c, s_ = rot(f"jpar[{r}, 7]", f"jpar[{r}, 8]", q["c"], q["s"])
    e(f"{p}c = {c}")
    e(f"{p}s = {s_}")
    e(f"{p}phi = " + (f"jpar[{r}, 6]" if q["phi"] is None else f"{q['phi']} + jpar[{r}, 6]"))
    e(f"{p}sv = y[{d}]")
    e(f"{p}sd = y[{n + d}]")
    ux, uy = rot(f"jpar[{r}, 4]", f"jpar[{r}, 5]", q["c"], q["s"])
    e(f"{p}ux = {ux}")
    e(f"{p}uy = {uy}")
    lx, ly = rot(f"jpar[{r}, 0]", f"jpar[{r}, 1]", q["c"], q["s"])
    bx, by = rot(f"jpar[{r}, 2]", f"jpar[{r}, 3]", f"{p}c", f"{p}s")
    e(f"{p}dx = {lx} + {p}sv * {p}ux - ({bx})")  # parent's centre of mass -> the body's
    e(f"{p}dy = {ly} + {p}sv * {p}uy - ({by})")
    w = q["w"]
    e(f"{p}w = {w or '0.0'}")
    for k, a, cross, slide, coriolis in (("x", "dx", f"- {w} * {p}dy", f"{p}ux", f"- 2.0 * {w} * {p}sd * {p}uy"),
                                         ("y", "dy", f"+ {w} * {p}dx", f"{p}uy", f"+ 2.0 * {w} * {p}sd * {p}ux")):
        e(f"{p}{k} = " + (f"{p}{a}" if q[k] is None else f"{q[k]} + {p}{a}"))
        rate = f"{q['v' + k] or '0.0'}" + ("" if w is None else f" {cross}") + f" + {p}sd * {slide}"
        e(f"{p}v{k} = {rate}")
        acc = f"{q['a' + k] or '0.0'}" + ("" if w is None else f" - {w} * {w} * {p}{a} {coriolis}")
        e(f"{p}a{k} = {acc}")
    J = _carried(e, p, q["J"], f"{p}dx", f"{p}dy") if 0 <= par < nb else {}
    J[d] = (f"{p}ux", f"{p}uy", None)
    body[b] = {k: p + k for k in ("x", "y", "phi", "c", "s", "vx", "vy", "w", "ax", "ay")}
    body[b].update(free=True, J=J)


def rhs_source(key: tuple) -> str:
    """Source of ``rhs_spec`` for a shape_key."""
    rows, nd, joints = key
    nb = len(rows)
    n = sum(3 if r[K.T_KIND] == K.TREE_FLOATING else 1 for r in rows)
    e = _Emitter()
    body = {}  # body code -> dict of local names: x, y, phi, c, s, vx, vy, w (None: zero), free: ax, ay, J
    # driven bodies (closed form at t, rotated from the step's base point by w dt)
    for dd in range(nd):
        r = nb + dd
        p = f"d{dd}_"
        e(f"{p}w = dpar[{dd}, 5]")
        e(f"{p}c, {p}s = small_rotation(cb[{n + dd}], sb[{n + dd}], {p}w * dt)")
        e(f"{p}relx = -({p}c * dpar[{dd}, 2] - {p}s * dpar[{dd}, 3])")
        e(f"{p}rely = -({p}s * dpar[{dd}, 2] + {p}c * dpar[{dd}, 3])")
        e(f"{p}x = dpar[{dd}, 0] + {p}relx")
        e(f"{p}y = dpar[{dd}, 1] + {p}rely")
        e(f"{p}phi = dpar[{dd}, 4] + {p}w * t")
        e(f"{p}vx = -{p}w * {p}rely")
        e(f"{p}vy = {p}w * {p}relx")
        e(f"{p}ax = -{p}w * {p}w * {p}relx")
        e(f"{p}ay = -{p}w * {p}w * {p}rely")
        body[r] = {k: p + k for k in ("x", "y", "phi", "c", "s", "vx", "vy", "w", "ax", "ay")}
    # free bodies by the tree recursion (rows parents first)
    for r, row in enumerate(rows):
        kind, b, par, d = row[K.T_KIND], row[K.T_BODY], row[K.T_PARENT], row[K.T_DOF]
        p = f"b{b}_"
        if kind == K.TREE_FLOATING:
            e(f"{p}c, {p}s = small_rotation(cb[{d + 2}], sb[{d + 2}], y[{d + 2}] - yb[{d + 2}])")
            for k, idx in (("x", d), ("y", d + 1), ("phi", d + 2), ("vx", n + d), ("vy", n + d + 1), ("w", n + d + 2)):
                e(f"{p}{k} = y[{idx}]")
            body[b] = {k: p + k for k in ("x", "y", "phi", "c", "s", "vx", "vy", "w")}
            body[b].update(ax=None, ay=None, free=True,
                           J={d: ("1", None, None), d + 1: (None, "1", None), d + 2: (None, None, "1")})
            continue
        if kind == K.TREE_PRISMATIC:
            _emit_slider(e, body, r, b, par, d, n, nb)
            continue
        e(f"{p}c, {p}s = small_rotation(cb[{d}], sb[{d}], y[{d}] - yb[{d}])")
        e(f"{p}phi = y[{d}]")
        e(f"{p}w = y[{n + d}]")
        if par == -1:  # ground parent: its frame is the global one, at rest
            e(f"{p}apx = jpar[{r}, 0]")
            e(f"{p}apy = jpar[{r}, 1]")
        else:
            q = body[par]
            e(f"{p}apx = {q['c']} * jpar[{r}, 0] - {q['s']} * jpar[{r}, 1]")
            e(f"{p}apy = {q['s']} * jpar[{r}, 0] + {q['c']} * jpar[{r}, 1]")
        e(f"{p}abx = {p}c * jpar[{r}, 2] - {p}s * jpar[{r}, 3]")
        e(f"{p}aby = {p}s * jpar[{r}, 2] + {p}c * jpar[{r}, 3]")
        if par == -1:
            e(f"{p}x = {p}apx - {p}abx")
            e(f"{p}y = {p}apy - {p}aby")
            e(f"{p}vx = {p}w * {p}aby")
            e(f"{p}vy = -{p}w * {p}abx")
            e(f"{p}ax = {p}w * {p}w * {p}abx")
            e(f"{p}ay = {p}w * {p}w * {p}aby")
        else:
            q = body[par]
            e(f"{p}x = {q['x']} + {p}apx - {p}abx")
            e(f"{p}y = {q['y']} + {p}apy - {p}aby")
            e(f"{p}vx = {q['vx']} - {q['w']} * {p}apy + {p}w * {p}aby")
            e(f"{p}vy = {q['vy']} + {q['w']} * {p}apx - {p}w * {p}abx")
            # accelerations at qdd = 0 (the parent's angular one is zero: driven at constant speed, or free)
            pax = "" if q["ax"] is None else f"{q['ax']} "
            pay = "" if q["ay"] is None else f"{q['ay']} "
            e(f"{p}ax = {pax}- {q['w']} * {q['w']} * {p}apx + {p}w * {p}w * {p}abx")
            e(f"{p}ay = {pay}- {q['w']} * {q['w']} * {p}apy + {p}w * {p}w * {p}aby")
        J = {}
        if par >= 0 and par < nb:  # the parent's Jacobian, carrying the joint point (k x ap per unit of its turning)
            J = {i: (jx, jy, None) for i, (jx, jy, _) in _carried(e, p, body[par]["J"], f"{p}apx", f"{p}apy").items()}
        e(f"{p}mabx = -{p}abx")
        J[d] = (f"{p}aby", f"{p}mabx", "1")
        body[b] = {k: p + k for k in ("x", "y", "phi", "c", "s", "vx", "vy", "w", "ax", "ay")}
        body[b].update(free=True, J=J)
    ground = {"x": None, "y": None, "phi": None, "c": "1", "s": None, "vx": None, "vy": None, "w": None}

    def get(code):
        return ground if code == -1 else body[code]

    # generalized forces per free body, then the clearance contacts (as kernel.eval_contacts)
    for row in rows:
        b = row[K.T_BODY]
        for c, k in enumerate(("fx", "fy", "fm")):
            e(f"b{b}_{k} = fext[{3 * b + c}]")

    def rot(q, sx, sy):
        """Body-fixed (sx, sy) in the global frame for body locals q."""
        if q["s"] is None:
            return sx, sy
        return f"{q['c']} * {sx} - {q['s']} * {sy}", f"{q['s']} * {sx} + {q['c']} * {sy}"

    def plus(a, b):
        return b if a is None else f"{a} + {b}"

    for k, (bb, bj) in enumerate(joints):
        qb, qj = get(bb), get(bj)
        p = f"k{k}_"
        x, y_ = rot(qb, f"cpar[{k}, {K.C_SBX}]", f"cpar[{k}, {K.C_SBY}]")
        e(f"{p}abx = {x}")
        e(f"{p}aby = {y_}")
        x, y_ = rot(qj, f"cpar[{k}, {K.C_SJX}]", f"cpar[{k}, {K.C_SJY}]")
        e(f"{p}ajx = {x}")
        e(f"{p}ajy = {y_}")
        e(f"{p}ex = {plus(qj['x'], p + 'ajx')} - ({plus(qb['x'], p + 'abx')})")
        e(f"{p}ey = {plus(qj['y'], p + 'ajy')} - ({plus(qb['y'], p + 'aby')})")
        for s, q in (("b", qb), ("j", qj)):
            vx = f"- {q['w']} * {p}a{s}y" if q["w"] is not None else ""
            vy = f"+ {q['w']} * {p}a{s}x" if q["w"] is not None else ""
            e(f"{p}v{s}x = {q['vx'] or '0.0'} {vx}")
            e(f"{p}v{s}y = {q['vy'] or '0.0'} {vy}")
        e(f"{p}emag = math.sqrt({p}ex * {p}ex + {p}ey * {p}ey)")
        e(f"{p}rvx = {p}vjx - {p}vbx")
        e(f"{p}rvy = {p}vjy - {p}vby")
        e(f"if {p}emag > 1e-300:")
        e(f"    {p}nx = {p}ex / {p}emag")
        e(f"    {p}ny = {p}ey / {p}emag")
        e("else:")
        e(f"    {p}nx = 1.0")
        e(f"    {p}ny = 0.0")
        phib, phij = qb["phi"] or "0.0", qj["phi"] or "0.0"
        e(f"if cint[{k}, {K.CI_PROF}] != 0:")
        e(f"    {p}ang = math.atan2({p}ey, {p}ex)  # as kernel.eval_contacts")
        e(f"    {p}angb = {p}ang - {phib}")
        e(f"    {p}angj = {p}ang - {phij}")
        e("else:")
        e(f"    {p}angb = 0.0")
        e(f"    {p}angj = 0.0")
        e(f"{p}delta, {p}fs, {p}ft, {p}fx, {p}fy, {p}hbp, {p}hjp, {p}rbl, {p}rjl = clearance_contact(")
        e(f"    {k}, cint, cpar, prof, ngrid, cstate, {p}ex, {p}ey, {p}emag, {p}nx, {p}ny, {p}rvx, {p}rvy,")
        e(f"    {qb['w'] or '0.0'}, {qj['w'] or '0.0'}, {p}angb, {p}angj, cout)")
        if 0 <= bj < nb or 0 <= bb < nb:
            e(f"if {p}delta > 0.0:")
            if 0 <= bj < nb:
                e(f"    b{bj}_fx += {p}fx")
                e(f"    b{bj}_fy += {p}fy")
                e(f"    b{bj}_fm += {p}ajx * {p}fy - {p}ajy * {p}fx - {p}fs * {p}hjp + {p}rjl * {p}ft")
            if 0 <= bb < nb:
                e(f"    b{bb}_fx -= {p}fx")
                e(f"    b{bb}_fy -= {p}fy")
                e(f"    b{bb}_fm += -({p}abx * {p}fy - {p}aby * {p}fx) - {p}fs * {p}hbp - {p}rbl * {p}ft")
        e(f"cout[{k}, {K.O_PHIB}] = {phib}")
        e(f"cout[{k}, {K.O_PHIJ}] = {phij}")
    # M = J^T M_c J and g = J^T (f - M_c c), summed over the bodies (rows) in order, structural zeros skipped
    gterms: dict[int, list[str]] = {i: [] for i in range(n)}
    mterms: dict[tuple, list[str]] = {}
    for row in rows:
        b = row[K.T_BODY]
        p = f"b{b}_"
        J = body[b]["J"]
        e(f"{p}m0 = mass[{3 * b}]")
        e(f"{p}m2 = mass[{3 * b + 2}]")
        for c, (fk, ak) in enumerate((("fx", "ax"), ("fy", "ay"))):
            a = body[b][ak]
            e(f"{p}g{c} = {p}{fk}" + ("" if a is None else f" - {p}m0 * {a}"))
        path = [int(v) for v in row[K.T_PATH: K.T_PATH + row[K.T_LEN]]]
        for ii, di in enumerate(path):
            jx, jy, jw = J[di]
            terms = [t for t in (_mul(jx, f"{p}g0"), _mul(jy, f"{p}g1"), _mul(jw, f"{p}fm")) if t]
            if terms:
                gterms[di].append("(" + " + ".join(terms) + ")")
            for dk in path[: ii + 1]:
                kx, ky, kw = J[dk]
                terms = [t for t in (_mul(_mul(f"{p}m0", jx), kx), _mul(_mul(f"{p}m0", jy), ky),
                                     _mul(_mul(f"{p}m2", jw), kw)) if t]
                if terms:
                    mterms.setdefault((di, dk), []).append("(" + " + ".join(terms) + ")")
    # coordinate parents: the coordinate before it on any path
    lam = {}
    for row in rows:
        path = [int(v) for v in row[K.T_PATH: K.T_PATH + row[K.T_LEN]]]
        for i, d in enumerate(path):
            lam[d] = path[i - 1] if i else -1

    def anc(k):
        out = []
        i = lam[k]
        while i != -1:
            out.append(i)
            i = lam[i]
        return out

    for i in range(n):
        e(f"x{i} = " + (" + ".join(gterms[i]) if gterms[i] else "0.0"))
        for k in [i, *anc(i)]:
            e(f"M{i}_{k} = " + (" + ".join(mterms[(i, k)]) if (i, k) in mterms else "0.0"))
    # L^T D L from the leaves (highest coordinates) to the roots: no fill-in outside the ancestors' pattern
    for k in range(n - 1, -1, -1):
        e(f"r{k} = 1.0 / M{k}_{k}")
        for i in anc(k):
            e(f"L{k}_{i} = M{k}_{i} * r{k}")
            for j in [i, *anc(i)]:
                e(f"M{i}_{j} = M{i}_{j} - L{k}_{i} * M{k}_{j}")
    # M x = g: L^T z = g, z = D^-1 z, L x = z
    for k in range(n - 1, -1, -1):
        for i in anc(k):
            e(f"x{i} = x{i} - L{k}_{i} * x{k}")
    for k in range(n):
        e(f"x{k} = x{k} * r{k}")
    for k in range(n):
        for i in anc(k):
            e(f"x{k} = x{k} - L{k}_{i} * x{i}")
    for i in range(n):
        e(f"dy[row, {i}] = y[{n + i}]")
        e(f"dy[row, {n + i}] = x{i}")
    head = ("@njit(cache=True, inline=\"always\", error_model=\"numpy\", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)\n"
            "def rhs_spec(t, dt, y, yb, dy, row, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,\n"
            "             kin, cb, sb, cacc, jt, mm, gq, f, cout):\n"
            f"    \"\"\"kernel.rhs_tree for the shape {key!r} (generated by jointwear.mechanism.tree_codegen).\"\"\"\n")
    return head + "\n".join(e.lines) + "\n"


def _redirected(fn, name: str) -> str:
    """The source of kernel's tree-mode function `name` with its rhs_tree call redirected to rhs_spec."""
    src = textwrap.dedent(inspect.getsource(fn.py_func))
    src = src[src.index(f"def {name}("):]
    if src.count("rhs_tree(") != 1:
        raise RuntimeError(f"kernel's {name} no longer has exactly one rhs_tree call to redirect")
    return src.replace("rhs_tree(", "rhs_spec(")


def module_source(key: tuple) -> str:
    """The whole generated module: imports, rhs_spec and the Dormand-Prince loop calling it (`mode` is a module
    constant, which numba folds: the loop compiles the tree branch only, as kernel.integrate_tree).

    The single evaluation at a record's start stays kernel's general one (kernel.EVALUATORS): compiled once for every
    shape, where a generated copy would compile again per shape (~20 s for the six-bar with three clearances)."""
    return ("# Generated by jointwear.mechanism.tree_codegen: do not edit.\n"
            "import math\n\n"
            "from numba import njit\n\n"
            "from jointwear.mechanism.kernel import *  # noqa: F401,F403 (the loop's helpers and tables)\n"
            "from jointwear.mechanism.kernel import FASTMATH, STEP_LOOP_NRT, clearance_contact, small_rotation\n\n"
            f"mode = {K.MODES.index('tree')}\n\n\n"
            + rhs_source(key) + "\n\n"
            "@njit(cache=True, nogil=True, error_model=\"numpy\", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)\n"
            + _redirected(K.integrate_tree, "integrate"))


def _cache_dir() -> Path:
    base = os.environ.get("JOINTWEAR_KERNEL_CACHE") or os.path.join(
        os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"), "jointwear", "kernels")
    return Path(base)


def specialised_module(lay: TreeLayout, nd: int, cint: np.ndarray):
    """The generated module for this shape (``rhs_spec``, ``integrate``), written and imported once per process."""
    key = shape_key(lay, nd, cint)
    mod = _BY_KEY.get(key)
    if mod is not None:
        return mod
    src = module_source(key)
    h = hashlib.sha256()
    for part in (src, inspect.getsource(K), inspect.getsource(_laws_module), numba.__version__, sys.version):
        h.update(part.encode())
    name = "jointwear_tree_" + h.hexdigest()[:20]
    with _LOCK:
        mod = _LOADED.get(name)
        if mod is not None:
            _BY_KEY[key] = mod
            return mod
        path = _write(name, src)
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        sys.modules[name] = mod
        spec.loader.exec_module(mod)
        _LOADED[name] = mod
        _BY_KEY[key] = mod
        return mod


def _write(name: str, src: str) -> Path:
    """Write the module once (atomically: other processes may be writing the same file); a temporary directory if the
    cache directory is not writable."""
    for d in (_cache_dir(), Path(tempfile.gettempdir()) / "jointwear-kernels"):
        path = d / f"{name}.py"
        try:
            if path.exists() and path.read_text() == src:
                return path
            d.mkdir(parents=True, exist_ok=True)
            fd, tmp = tempfile.mkstemp(dir=d, suffix=".tmp")
            with os.fdopen(fd, "w") as fh:
                fh.write(src)
            os.replace(tmp, path)
            return path
        except OSError:
            continue
    raise OSError("no writable directory for the generated tree kernel (set JOINTWEAR_KERNEL_CACHE)")
