"""Compiled kernels: constraint equations, contact forces, equations of motion, Dormand-Prince 5(4).

Formulation (paper Section 2.1): Cartesian coordinates q = (x, y, phi) of every *free* body (origin
at the centre of mass), Newton-Euler equations with Lagrange multipliers and Baumgarte stabilisation

    M qdd + J^T lam = f(t, q, qd)           (f: gravity, applied loads, clearance contact forces)
    J qdd = gamma - 2 alpha Phidot - beta^2 Phi

solved by the Schur complement (M is diagonal):  (J M^-1 J^T) lam = J M^-1 f - gamma_stab,
qdd = M^-1 (f - J^T lam).  Bodies driven at constant speed about a ground pivot are *prescribed*:
their pose, velocity and acceleration are closed-form functions of t (equivalent to keeping them
in q with a driver constraint, but 3 coordinates and 3 constraint rows fewer).

Body codes in the joint tables: -1 ground, 0..nb-1 free bodies, nb..nb+nd-1 driven bodies.

All arrays are preallocated by the caller; nothing is allocated in the step loop.
Kernels compile with numba's error_model="numpy": a division by zero gives inf/NaN, which the step
control rejects, instead of a zero test and a Python exception path on every division. `integrate` releases
the GIL, so independent simulations run in threads (the wear history's lanes, jointwear.wear.history).
"""

from __future__ import annotations

import math
import types

import numpy as np
from numba import njit

from jointwear.contact.laws import contact_stiffness, friction_coefficient, normal_force

# LLVM fast-math flags of the step loop and the four-bar right-hand side: reassociation, contraction (FMA),
# reciprocals, no signed zeros; NOT no-NaN/no-inf, which the step control relies on (a NaN stage rejects the
# step). Results change only at rounding level.
FASTMATH = {"nsz", "arcp", "contract", "reassoc"}

# The step loops compile without numba's reference counting (NRT): they allocate nothing, and with NRT every
# inlined right-hand side increfs and decrefs each of its ~12 array arguments (an atomic operation through a
# function pointer, ~24 per evaluation) that LLVM's refcount pruning does not remove: most of an evaluation's
# time, the same instructions otherwise (bit-identical results). `_nrt` is numba's flag for this
# (numba.core.options); such a kernel may not create or return arrays.
STEP_LOOP_NRT = False

# joint types
REVOLUTE = 0
PRISMATIC = 1

# columns of the kinematics work table kin (one row per body code, ground last)
K_X, K_Y, K_PHI, K_C, K_S, K_VX, K_VY, K_W, K_AX, K_AY, K_AL = range(11)
NKIN = 11

# columns of cpar (clearance joint parameters)
(C_SBX, C_SBY, C_SJX, C_SJY, C_RB, C_RJ, C_GROW, C_HSUM, C_K0, C_NEXP, C_CR, C_V0MIN,
 C_MUD, C_MUS, C_VS, C_VD) = range(16)
NCPAR = 16
# columns of cint
CI_BB, CI_BJ, CI_LAW, CI_FRIC, CI_PROF = range(5)
# bits of cint[k, CI_PROF]: which sides carry a worn profile (a side without one is round and costs no lookup)
PROF_BEARING, PROF_JOURNAL = 1, 2
# columns of cout (contact outputs of the latest evaluation)
(O_FN, O_FT, O_VT, O_DELTA, O_VN, O_NX, O_NY, O_EX, O_EY, O_CLOC, O_VREL, O_PHIB, O_PHIJ, O_K, O_TAN_TILT) = range(15)
NCOUT = 15
# columns of cstate
S_V0, S_INC = 0, 1


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def _row(b, nb, nd):
    return b if b >= 0 else nb + nd


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def fill_kinematics(t, y, nb, dpar, kin):
    """Fill the kinematics table for free bodies (from y), driven bodies (closed form) and ground."""
    nd = dpar.shape[0]
    for b in range(nb):
        phi = y[3 * b + 2]
        kin[b, K_X] = y[3 * b]
        kin[b, K_Y] = y[3 * b + 1]
        kin[b, K_PHI] = phi
        kin[b, K_C] = math.cos(phi)
        kin[b, K_S] = math.sin(phi)
        kin[b, K_VX] = y[3 * nb + 3 * b]
        kin[b, K_VY] = y[3 * nb + 3 * b + 1]
        kin[b, K_W] = y[3 * nb + 3 * b + 2]
        kin[b, K_AX] = 0.0
        kin[b, K_AY] = 0.0
        kin[b, K_AL] = 0.0
    for d in range(nd):
        r = nb + d
        px, py, sx, sy, phi0, w = dpar[d, 0], dpar[d, 1], dpar[d, 2], dpar[d, 3], dpar[d, 4], dpar[d, 5]
        phi = phi0 + w * t
        c = math.cos(phi)
        s = math.sin(phi)
        # r_body = P - A s ; rel = r_body - P = -A s
        relx = -(c * sx - s * sy)
        rely = -(s * sx + c * sy)
        kin[r, K_X] = px + relx
        kin[r, K_Y] = py + rely
        kin[r, K_PHI] = phi
        kin[r, K_C] = c
        kin[r, K_S] = s
        kin[r, K_VX] = -w * rely
        kin[r, K_VY] = w * relx
        kin[r, K_W] = w
        kin[r, K_AX] = -w * w * relx
        kin[r, K_AY] = -w * w * rely
        kin[r, K_AL] = 0.0
    g = nb + nd
    for k in range(NKIN):
        kin[g, k] = 0.0
    kin[g, K_C] = 1.0


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def eval_constraints(nb, nd, jint, jpar, kin, phi_, phid, rest, jac):
    """Constraint values Phi, their rates Phidot, the acceleration remainder `rest` (Phi'' evaluated
    with free-body accelerations set to zero, so gamma = -rest) and the Jacobian J wrt free coordinates."""
    nj = jint.shape[0]
    nq = 3 * nb
    for r in range(2 * nj):
        for c in range(nq):
            jac[r, c] = 0.0
    for k in range(nj):
        r = 2 * k
        bi = jint[k, 1]
        bj = jint[k, 2]
        ri = _row(bi, nb, nd)
        rj = _row(bj, nb, nd)
        ci, si_ = kin[ri, K_C], kin[ri, K_S]
        cj, sj_ = kin[rj, K_C], kin[rj, K_S]
        wi, wj = kin[ri, K_W], kin[rj, K_W]
        # body-fixed vectors to the joint points, in the global frame
        aix = ci * jpar[k, 0] - si_ * jpar[k, 1]
        aiy = si_ * jpar[k, 0] + ci * jpar[k, 1]
        ajx = cj * jpar[k, 2] - sj_ * jpar[k, 3]
        ajy = sj_ * jpar[k, 2] + cj * jpar[k, 3]
        pix = kin[ri, K_X] + aix
        piy = kin[ri, K_Y] + aiy
        pjx = kin[rj, K_X] + ajx
        pjy = kin[rj, K_Y] + ajy
        vpix = kin[ri, K_VX] - wi * aiy
        vpiy = kin[ri, K_VY] + wi * aix
        vpjx = kin[rj, K_VX] - wj * ajy
        vpjy = kin[rj, K_VY] + wj * ajx
        apix = kin[ri, K_AX] - kin[ri, K_AL] * aiy - wi * wi * aix
        apiy = kin[ri, K_AY] + kin[ri, K_AL] * aix - wi * wi * aiy
        apjx = kin[rj, K_AX] - kin[rj, K_AL] * ajy - wj * wj * ajx
        apjy = kin[rj, K_AY] + kin[rj, K_AL] * ajx - wj * wj * ajy
        if jint[k, 0] == REVOLUTE:
            phi_[r] = pix - pjx
            phi_[r + 1] = piy - pjy
            phid[r] = vpix - vpjx
            phid[r + 1] = vpiy - vpjy
            rest[r] = apix - apjx
            rest[r + 1] = apiy - apjy
            if 0 <= bi < nb:
                jac[r, 3 * bi] += 1.0
                jac[r, 3 * bi + 2] += -aiy
                jac[r + 1, 3 * bi + 1] += 1.0
                jac[r + 1, 3 * bi + 2] += aix
            if 0 <= bj < nb:
                jac[r, 3 * bj] -= 1.0
                jac[r, 3 * bj + 2] -= -ajy
                jac[r + 1, 3 * bj + 1] -= 1.0
                jac[r + 1, 3 * bj + 2] -= ajx
        else:
            # prismatic: relative angle fixed, and j's point stays on i's axis (normal n fixed in i)
            phi_[r] = kin[ri, K_PHI] - kin[rj, K_PHI] - jpar[k, 6]
            phid[r] = wi - wj
            rest[r] = kin[ri, K_AL] - kin[rj, K_AL]
            nx = ci * jpar[k, 4] - si_ * jpar[k, 5]
            ny = si_ * jpar[k, 4] + ci * jpar[k, 5]
            knx, kny = -ny, nx
            dx, dy = pjx - pix, pjy - piy
            ddx, ddy = vpjx - vpix, vpjy - vpiy
            phi_[r + 1] = nx * dx + ny * dy
            phid[r + 1] = wi * (knx * dx + kny * dy) + nx * ddx + ny * ddy
            rest[r + 1] = (kin[ri, K_AL] * (knx * dx + kny * dy) - wi * wi * (nx * dx + ny * dy)
                           + 2.0 * wi * (knx * ddx + kny * ddy) + nx * (apjx - apix) + ny * (apjy - apiy))
            if 0 <= bi < nb:
                jac[r, 3 * bi + 2] += 1.0
                jac[r + 1, 3 * bi] += -nx
                jac[r + 1, 3 * bi + 1] += -ny
                jac[r + 1, 3 * bi + 2] += knx * (pjx - kin[ri, K_X]) + kny * (pjy - kin[ri, K_Y])
            if 0 <= bj < nb:
                jac[r, 3 * bj + 2] -= 1.0
                jac[r + 1, 3 * bj] += nx
                jac[r + 1, 3 * bj + 1] += ny
                jac[r + 1, 3 * bj + 2] += nx * (-ajy) + ny * ajx


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def profile_at(prof, k, side, n, ang):
    """Value and slope d/d(angle) (per radian) of the periodic Catmull-Rom (C1 cubic Hermite) interpolation of
    prof[k, side, 0:n] given at angles 2 pi k / n, from one stencil lookup.

    C1 so that the contact normal, which follows the profile's slope, does not jump at the grid points (with linear
    interpolation it did, and a journal resting where the slope changes sign chattered with ever smaller steps).
    Exact for a constant profile (a round bore)."""
    u = ang / (2.0 * math.pi)
    u = u - math.floor(u)
    x = u * n
    i1 = int(x)
    if i1 >= n:
        i1 = n - 1
    t = x - i1
    i0 = i1 - 1 if i1 > 0 else n - 1
    i2 = i1 + 1 if i1 + 1 < n else 0
    i3 = i2 + 1 if i2 + 1 < n else 0
    p0 = prof[k, side, i0]
    p1 = prof[k, side, i1]
    p2 = prof[k, side, i2]
    p3 = prof[k, side, i3]
    a1 = p2 - p0
    a2 = 2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3
    a3 = 3.0 * (p1 - p2) + p3 - p0
    value = p1 + 0.5 * t * (a1 + t * (a2 + t * a3))
    slope = 0.5 * (a1 + t * (2.0 * a2 + 3.0 * t * a3)) * (n / (2.0 * math.pi))
    return value, slope


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def contact_gradient(profiled, emag, hbp, hjp, nx, ny):
    """grad_e(delta) = n + gt t of delta = |e| - c_loc(theta), gt = -(h_b' + h_j') / |e| (worn profiles; 0 for
    round surfaces): its norm gn, direction (gx, gy), the unit tangent (tx, ty) = k x grad / gn and gt, the tangent
    of the contact normal's tilt from the centre line (the angle itself is taken when the trace is recorded: an atan
    per evaluation was a tenth of a profiled contact's cost)."""
    if profiled and emag > 1e-15:
        gt = -(hbp + hjp) / emag
        gn = math.sqrt(1.0 + gt * gt)
        gx = nx - gt * ny
        gy = ny + gt * nx
        return gn, gx, gy, -gy / gn, gx / gn, gt
    return 1.0, nx, ny, -ny, nx, 0.0  # round surfaces: the gradient is n


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def clearance_contact(k, cint, cpar, prof, ngrid, cstate, ex, ey, emag, nx, ny, rvx, rvy, wb, wj, ang_b, ang_j, cout):
    """The contact of clearance joint k, shared by the general and the four-bar kernel (inlined into each, so it
    compiles with the caller's flags). Inputs: the eccentricity e = (ex, ey) (bearing centre -> journal centre),
    its length emag and direction n; the relative velocity rv of the journal centre; the angular velocities wb,
    wj of bearing and journal; the angles ang_b, ang_j of n in the bearing and journal frames (read only for
    worn profiles). Writes cout[k] (all but O_PHIB, O_PHIJ) and returns (delta, fs, ft, fx, fy, hbp, hjp, rbl,
    rjl): fx, fy is the force on the journal centre; the caller adds the torques -fs h_j' + R_j ft on the
    journal and -fs h_b' - R_b ft (plus the moment of -f) on the bearing.

    delta(e, phi_b, phi_j) = |e| - c_loc(theta): the normal force derives from the potential
    V = K delta^(n+1)/(n+1) (damping along the same direction): -fs grad_e(delta) on the journal centre, the
    opposite on the bearing centre, torques -fs h' on bodies with worn profiles (zero for circular surfaces);
    grad_e(delta) = n + gt t, gt = -(h_b' + h_j') / |e| (contact_gradient). Friction acts at the surface points
    (torques R ft about the centres)."""
    grow = cpar[k, C_GROW]
    rbl = cpar[k, C_RB] + 0.5 * grow
    rjl = cpar[k, C_RJ] - 0.5 * grow
    kstiff = cpar[k, C_K0]
    sides = cint[k, CI_PROF]
    if sides != 0:
        hbp = 0.0
        hjp = 0.0
        if sides & PROF_BEARING:
            hb, hbp = profile_at(prof, k, 0, ngrid[k, 0], ang_b)
            rbl += hb
        if sides & PROF_JOURNAL:
            hj, hjp = profile_at(prof, k, 1, ngrid[k, 1], ang_j)
            rjl -= hj
        kstiff = contact_stiffness(cpar[k, C_HSUM], rbl, rjl)
    else:
        hbp = 0.0
        hjp = 0.0
        if grow != 0.0:
            kstiff = contact_stiffness(cpar[k, C_HSUM], rbl, rjl)
    cloc = rbl - rjl
    delta = emag - cloc
    gn, gx, gy, tx, ty, tan_tilt = contact_gradient(sides != 0, emag, hbp, hjp, nx, ny)
    vn = rvx * gx + rvy * gy + hbp * wb + hjp * wj  # d(delta)/dt
    vt = rvx * tx + rvy * ty + wj * rjl - wb * rbl
    fs = 0.0
    fn = 0.0
    ft = 0.0
    fx = 0.0
    fy = 0.0
    if delta > 0.0:
        if cstate[k, S_INC] > 0.5:
            v0 = cstate[k, S_V0]
        else:
            v0 = vn if vn > cpar[k, C_V0MIN] else cpar[k, C_V0MIN]
        fs = normal_force(cint[k, CI_LAW], kstiff, cpar[k, C_NEXP], delta, vn, cpar[k, C_CR], v0)
        fn = fs * gn  # magnitude of the normal force
        if cint[k, CI_FRIC] != 0 and fn > 0.0:
            ft = -friction_coefficient(vt, cpar[k, C_MUD], cpar[k, C_MUS], cpar[k, C_VS], cpar[k, C_VD]) * fn
        fx = -fs * gx + ft * tx
        fy = -fs * gy + ft * ty
    cout[k, O_FN] = fn
    cout[k, O_FT] = ft
    cout[k, O_VT] = vt
    cout[k, O_DELTA] = delta
    cout[k, O_VN] = vn
    cout[k, O_NX] = nx
    cout[k, O_NY] = ny
    cout[k, O_EX] = ex
    cout[k, O_EY] = ey
    cout[k, O_CLOC] = cloc
    cout[k, O_VREL] = math.sqrt(rvx * rvx + rvy * rvy)
    cout[k, O_K] = kstiff
    cout[k, O_TAN_TILT] = tan_tilt
    return delta, fs, ft, fx, fy, hbp, hjp, rbl, rjl


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def eval_contacts(nb, nd, cint, cpar, prof, ngrid, cstate, kin, f, cout):
    """Clearance-joint contact forces, added to the generalized forces f of free bodies."""
    ncj = cint.shape[0]
    for k in range(ncj):
        bb = cint[k, CI_BB]
        bj = cint[k, CI_BJ]
        rb = _row(bb, nb, nd)
        rj = _row(bj, nb, nd)
        cb, sb = kin[rb, K_C], kin[rb, K_S]
        cj, sj = kin[rj, K_C], kin[rj, K_S]
        wb, wj = kin[rb, K_W], kin[rj, K_W]
        abx = cb * cpar[k, C_SBX] - sb * cpar[k, C_SBY]
        aby = sb * cpar[k, C_SBX] + cb * cpar[k, C_SBY]
        ajx = cj * cpar[k, C_SJX] - sj * cpar[k, C_SJY]
        ajy = sj * cpar[k, C_SJX] + cj * cpar[k, C_SJY]
        obx = kin[rb, K_X] + abx
        oby = kin[rb, K_Y] + aby
        ojx = kin[rj, K_X] + ajx
        ojy = kin[rj, K_Y] + ajy
        vbx = kin[rb, K_VX] - wb * aby
        vby = kin[rb, K_VY] + wb * abx
        vjx = kin[rj, K_VX] - wj * ajy
        vjy = kin[rj, K_VY] + wj * ajx
        ex = ojx - obx
        ey = ojy - oby
        emag = math.sqrt(ex * ex + ey * ey)
        rvx = vjx - vbx
        rvy = vjy - vby
        if emag > 1e-300:
            nx = ex / emag
            ny = ey / emag
        else:
            nx = 1.0
            ny = 0.0
        if cint[k, CI_PROF] != 0:
            ang = math.atan2(ey, ex)  # not (ny, nx): the lookup need not wait for the division
            ang_b = ang - kin[rb, K_PHI]
            ang_j = ang - kin[rj, K_PHI]
        else:
            ang_b = ang_j = 0.0
        delta, fs, ft, fx, fy, hbp, hjp, rbl, rjl = clearance_contact(
            k, cint, cpar, prof, ngrid, cstate, ex, ey, emag, nx, ny, rvx, rvy, wb, wj, ang_b, ang_j, cout)
        if delta > 0.0:
            if 0 <= bj < nb:
                f[3 * bj] += fx
                f[3 * bj + 1] += fy
                f[3 * bj + 2] += ajx * fy - ajy * fx - fs * hjp + rjl * ft
            if 0 <= bb < nb:
                f[3 * bb] -= fx
                f[3 * bb + 1] -= fy
                f[3 * bb + 2] += -(abx * fy - aby * fx) - fs * hbp - rbl * ft
        cout[k, O_PHIB] = kin[rb, K_PHI]
        cout[k, O_PHIJ] = kin[rj, K_PHI]


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def schur_blocks(nb, jint, jac, winv, f, rest, phid, phi_, alpha2, beta2, smat, lam):
    """The Schur complement S = J W J^T (lower triangle, into smat) and the right-hand side
    lam = J W f + rest + 2 alpha Phidot + beta^2 Phi (W = M^-1, diagonal), by 2x2 blocks of joint pairs: the rows of a
    joint are nonzero only in the columns of its (at most two) free bodies, so a block sums over the bodies the two
    joints share (the sums over all columns without their zero terms), and joints that share no free body give a
    zero block."""
    nj = jint.shape[0]
    for ka in range(nj):
        a = 2 * ka
        b0 = jint[ka, 1]
        b1 = jint[ka, 2]
        lo = b0 if b0 < b1 else b1
        hi = b1 if b0 < b1 else b0
        clo = 3 * lo if 0 <= lo < nb else -1
        chi = 3 * hi if 0 <= hi < nb and hi != lo else -1
        acc0 = 0.0
        acc1 = 0.0
        for blk in range(2):
            c0 = clo if blk == 0 else chi
            if c0 >= 0:
                for c in range(c0, c0 + 3):
                    fw = f[c]
                    w = winv[c]
                    acc0 += jac[a, c] * fw * w
                    acc1 += jac[a + 1, c] * fw * w
        lam[a] = acc0 + rest[a] + alpha2 * phid[a] + beta2 * phi_[a]
        lam[a + 1] = acc1 + rest[a + 1] + alpha2 * phid[a + 1] + beta2 * phi_[a + 1]
        for kb in range(ka + 1):
            b = 2 * kb
            cb0 = 3 * jint[kb, 1]
            cb1 = 3 * jint[kb, 2]
            s00 = 0.0
            s01 = 0.0
            s10 = 0.0
            s11 = 0.0
            for blk in range(2):
                c0 = clo if blk == 0 else chi
                if c0 >= 0 and (c0 == cb0 or c0 == cb1):
                    for c in range(c0, c0 + 3):
                        w = winv[c]
                        ja0 = jac[a, c]
                        ja1 = jac[a + 1, c]
                        jb0 = jac[b, c]
                        jb1 = jac[b + 1, c]
                        s00 += ja0 * jb0 * w
                        s01 += ja0 * jb1 * w
                        s10 += ja1 * jb0 * w
                        s11 += ja1 * jb1 * w
            smat[a, b] = s00
            smat[a + 1, b] = s10
            smat[a + 1, b + 1] = s11
            if kb < ka:
                smat[a, b + 1] = s01


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def block_ldlt(nj, smat):
    """S = L D L^T by 2x2 blocks (one per joint) in place, from the lower triangle of smat: L_IJ (unit block-lower)
    below the diagonal blocks, D_J^-1 on them, W_IJ = L_IJ D_J mirrored above them (smat[2J + q, 2I + p] =
    W_IJ[p, q]). The stages of a step wait for each evaluation, and a factorisation is a chain of pivots: one
    division per joint (the determinant of D_J) instead of a square root and a division per row halves it, and the
    solves only multiply. A singular block (det <= 0: a
    joint without free bodies, redundant constraints) gets det = 1e-300, as the Cholesky's pivot did."""
    for jb in range(nj):
        j = 2 * jb
        d00 = smat[j, j]
        d10 = smat[j + 1, j]
        d11 = smat[j + 1, j + 1]
        for kb in range(jb):
            k = 2 * kb
            # D_J -= L_JK W_JK^T
            l00 = smat[j, k]
            l01 = smat[j, k + 1]
            l10 = smat[j + 1, k]
            l11 = smat[j + 1, k + 1]
            w00 = smat[k, j]
            w01 = smat[k + 1, j]
            w10 = smat[k, j + 1]
            w11 = smat[k + 1, j + 1]
            d00 -= l00 * w00 + l01 * w01
            d10 -= l10 * w00 + l11 * w01
            d11 -= l10 * w10 + l11 * w11
        det = d00 * d11 - d10 * d10
        if not det > 0.0:
            det = 1e-300
        rdet = 1.0 / det
        i00 = d11 * rdet
        i10 = -d10 * rdet
        i11 = d00 * rdet
        smat[j, j] = i00
        smat[j + 1, j] = i10
        smat[j, j + 1] = i10
        smat[j + 1, j + 1] = i11
        for ib in range(jb + 1, nj):
            i = 2 * ib
            # W_IJ = S_IJ - sum_K L_IK W_JK^T
            s00 = smat[i, j]
            s01 = smat[i, j + 1]
            s10 = smat[i + 1, j]
            s11 = smat[i + 1, j + 1]
            for kb in range(jb):
                k = 2 * kb
                l00 = smat[i, k]
                l01 = smat[i, k + 1]
                l10 = smat[i + 1, k]
                l11 = smat[i + 1, k + 1]
                w00 = smat[k, j]
                w01 = smat[k + 1, j]
                w10 = smat[k, j + 1]
                w11 = smat[k + 1, j + 1]
                s00 -= l00 * w00 + l01 * w01
                s01 -= l00 * w10 + l01 * w11
                s10 -= l10 * w00 + l11 * w01
                s11 -= l10 * w10 + l11 * w11
            smat[j, i] = s00
            smat[j + 1, i] = s01
            smat[j, i + 1] = s10
            smat[j + 1, i + 1] = s11
            # L_IJ = W_IJ D_J^-1
            smat[i, j] = s00 * i00 + s01 * i10
            smat[i, j + 1] = s00 * i10 + s01 * i11
            smat[i + 1, j] = s10 * i00 + s11 * i10
            smat[i + 1, j + 1] = s10 * i10 + s11 * i11


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def block_solve_and_apply(nb, jint, jac, smat, lam, f):
    """lam = S^-1 lam from the factors of block_ldlt (L z = b, x = D^-1 z - L^T x, by blocks), then f -= J^T lam
    over each joint's free-body columns."""
    nj = jint.shape[0]
    for ib in range(nj):
        i = 2 * ib
        z0 = lam[i]
        z1 = lam[i + 1]
        for kb in range(ib):
            k = 2 * kb
            z0 -= smat[i, k] * lam[k] + smat[i, k + 1] * lam[k + 1]
            z1 -= smat[i + 1, k] * lam[k] + smat[i + 1, k + 1] * lam[k + 1]
        lam[i] = z0
        lam[i + 1] = z1
    for ib in range(nj - 1, -1, -1):
        i = 2 * ib
        z0 = lam[i]
        z1 = lam[i + 1]
        x0 = smat[i, i] * z0 + smat[i + 1, i] * z1
        x1 = smat[i + 1, i] * z0 + smat[i + 1, i + 1] * z1
        for kb in range(ib + 1, nj):
            k = 2 * kb
            x0 -= smat[k, i] * lam[k] + smat[k + 1, i] * lam[k + 1]
            x1 -= smat[k, i + 1] * lam[k] + smat[k + 1, i + 1] * lam[k + 1]
        lam[i] = x0
        lam[i + 1] = x1
    # f -= J^T lam over each joint's free-body columns
    for ka in range(nj):
        a = 2 * ka
        l0 = lam[a]
        l1 = lam[a + 1]
        b0 = jint[ka, 1]
        b1 = jint[ka, 2]
        for blk in range(2):
            bb = b0 if blk == 0 else b1
            if 0 <= bb < nb and (blk == 0 or b1 != b0):
                for c in range(3 * bb, 3 * bb + 3):
                    f[c] = f[c] - jac[a, c] * l0 - jac[a + 1, c] * l1


@njit(cache=True, error_model="numpy", fastmath=False, _nrt=STEP_LOOP_NRT)
def rhs(t, y, dy, row, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
        kin, phi_, phid, rest, jac, smat, lam, f, cout):
    """dy[row] = (qd, qdd) for the state y = (q, qd) of the free bodies; also fills lam and cout.

    winv: inverse masses/inertias per free coordinate (diagonal M^-1); fext: constant generalized
    forces per free coordinate (gravity, applied loads).

    Compiled with fastmath=False on purpose: without an explicit value numba lets a function inherit its caller's
    flags, so the copy compiled for `integrate` ran with FASTMATH and the one for `accelerations` without it, and the
    helpers (compiled once, for whichever caller came first) without. Explicit, the helpers inlined here keep the
    arithmetic they had as separate functions (the contact block's bit for bit), at no cost in speed. The helpers are
    inlined (inline="always"; without reference counting an inlined call costs nothing, and the calls' overhead
    goes)."""
    nd = dpar.shape[0]
    nq = 3 * nb
    nj = jint.shape[0]
    nc = 2 * nj
    fill_kinematics(t, y, nb, dpar, kin)
    for i in range(nq):
        f[i] = fext[i]
    eval_contacts(nb, nd, cint, cpar, prof, ngrid, cstate, kin, f, cout)
    if nc > 0:
        eval_constraints(nb, nd, jint, jpar, kin, phi_, phid, rest, jac)
        alpha2 = 2.0 * baum[0]
        beta2 = baum[1] * baum[1]
        schur_blocks(nb, jint, jac, winv, f, rest, phid, phi_, alpha2, beta2, smat, lam)
        block_ldlt(nj, smat)
        block_solve_and_apply(nb, jint, jac, smat, lam, f)
    for i in range(nq):
        dy[row, i] = y[nq + i]
        dy[row, nq + i] = f[i] * winv[i]


# ---------------------------------------------------------------------------------------------
# Tree kernel (joint coordinates; docs/dynamics.md, "Tree kernel"): the ideal joints of a linkage cut at its clearance
# joints form a forest hanging from the ground or driven bodies, so they hold exactly, with no multipliers. simulate
# runs code generated per linkage shape (jointwear.mechanism.tree_codegen); rhs_tree is its general reference form.
TREE_REVOLUTE = 0
TREE_FLOATING = 1
TREE_PRISMATIC = 2
# a prismatic row's jpar: the line's point (0, 1) and unit direction (4, 5) in the parent's frame, the body's
# sliding point in its own frame (2, 3), the body's angle over the parent's beta (6) and its cos, sin (7, 8)
NTPAR = 9
(T_KIND, T_BODY, T_PARENT, T_DOF, T_LEN, T_PATH) = range(6)


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def tree_base(t, y, jint, dpar, kin, cb, sb):
    """cos and sin of every body angle at the base point (t, y) of a step: coordinates' into cb[:n], sb[:n], the
    drivers' into cb[n + d], sb[n + d] (the stages rotate them instead of calling sin/cos), and the ground's row of kin."""
    n = y.shape[0] // 2
    g = kin.shape[0] - 1  # the ground's row is constant: set here, once per step
    for k in range(NKIN):
        kin[g, k] = 0.0
    kin[g, K_C] = 1.0
    for r in range(jint.shape[0]):
        if jint[r, T_KIND] == TREE_PRISMATIC:  # its coordinate is a length; its angle is its parent's + beta
            continue
        d = jint[r, T_DOF] + (2 if jint[r, T_KIND] == TREE_FLOATING else 0)
        cb[d] = math.cos(y[d])
        sb[d] = math.sin(y[d])
    for dd in range(dpar.shape[0]):
        phi = dpar[dd, 4] + dpar[dd, 5] * t
        cb[n + dd] = math.cos(phi)
        sb[n + dd] = math.sin(phi)


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def small_rotation(c0, s0, d):
    """cos and sin of (theta0 + d) as crank_rotation, with cos d and sin d to d^4 and d^5 for |d| <= 5e-3
    (truncation < 2e-17 and 2e-20 |d|, below rounding): a body turns by ~1e-4 rad in a contact-limited step, and the
    shorter polynomials shorten the chain every stage waits for."""
    if d > 5e-3 or d < -5e-3:
        return crank_rotation(c0, s0, d)
    d2 = d * d
    cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0))
    sd = d * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0)))
    return c0 * cd - s0 * sd, s0 * cd + c0 * sd


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def tree_kinematics(t, dt, y, yb, cb, sb, nb, dpar, jint, jpar, kin, cacc, jt):
    """Poses and velocities of all bodies into kin (free bodies by the tree recursion from y; driven bodies in closed
    form at t; ground), the free bodies' accelerations at qdd = 0 into cacc (3 per body) and the Jacobian of their
    Cartesian velocities with respect to the coordinate rates into jt (3 nb, n). Angles are rotated from the base
    point's cos/sin (tree_base at yb, t - dt) by the increments y - yb and w dt."""
    n = y.shape[0] // 2
    nd = dpar.shape[0]
    for dd in range(nd):
        r = nb + dd
        px, py, sx, sy, w = dpar[dd, 0], dpar[dd, 1], dpar[dd, 2], dpar[dd, 3], dpar[dd, 5]
        c, s = small_rotation(cb[n + dd], sb[n + dd], w * dt)
        relx = -(c * sx - s * sy)
        rely = -(s * sx + c * sy)
        kin[r, K_X] = px + relx
        kin[r, K_Y] = py + rely
        kin[r, K_PHI] = dpar[dd, 4] + w * t
        kin[r, K_C] = c
        kin[r, K_S] = s
        kin[r, K_VX] = -w * rely
        kin[r, K_VY] = w * relx
        kin[r, K_W] = w
        kin[r, K_AX] = -w * w * relx
        kin[r, K_AY] = -w * w * rely
        kin[r, K_AL] = 0.0
    for r in range(jint.shape[0]):
        b = jint[r, T_BODY]
        d = jint[r, T_DOF]
        if jint[r, T_KIND] == TREE_FLOATING:
            c, s = small_rotation(cb[d + 2], sb[d + 2], y[d + 2] - yb[d + 2])
            kin[b, K_X] = y[d]
            kin[b, K_Y] = y[d + 1]
            kin[b, K_PHI] = y[d + 2]
            kin[b, K_C] = c
            kin[b, K_S] = s
            kin[b, K_VX] = y[n + d]
            kin[b, K_VY] = y[n + d + 1]
            kin[b, K_W] = y[n + d + 2]
            cacc[3 * b] = 0.0
            cacc[3 * b + 1] = 0.0
            cacc[3 * b + 2] = 0.0
            for i in range(3):
                jt[3 * b, i] = 1.0 if i == 0 else 0.0
                jt[3 * b + 1, i] = 1.0 if i == 1 else 0.0
                jt[3 * b + 2, i] = 1.0 if i == 2 else 0.0
        elif jint[r, T_KIND] == TREE_PRISMATIC:
            # the body's point slides along a line fixed in the parent, at s = y[d]; it turns with the parent
            p = jint[r, T_PARENT]
            pr = _row(p, nb, nd)
            cp, sp = kin[pr, K_C], kin[pr, K_S]
            wp = kin[pr, K_W]
            c = cp * jpar[r, 7] - sp * jpar[r, 8]
            s = sp * jpar[r, 7] + cp * jpar[r, 8]
            sv = y[d]
            sd = y[n + d]
            ux = cp * jpar[r, 4] - sp * jpar[r, 5]
            uy = sp * jpar[r, 4] + cp * jpar[r, 5]
            # parent's centre of mass -> the body's centre of mass: line point + s u - the body's point
            dx = cp * jpar[r, 0] - sp * jpar[r, 1] + sv * ux - (c * jpar[r, 2] - s * jpar[r, 3])
            dy = sp * jpar[r, 0] + cp * jpar[r, 1] + sv * uy - (s * jpar[r, 2] + c * jpar[r, 3])
            kin[b, K_X] = kin[pr, K_X] + dx
            kin[b, K_Y] = kin[pr, K_Y] + dy
            kin[b, K_PHI] = kin[pr, K_PHI] + jpar[r, 6]
            kin[b, K_C] = c
            kin[b, K_S] = s
            kin[b, K_VX] = kin[pr, K_VX] - wp * dy + sd * ux
            kin[b, K_VY] = kin[pr, K_VY] + wp * dx + sd * uy
            kin[b, K_W] = wp
            last = jint[r, T_LEN] - 1  # s closes the path; the parent's path precedes it
            if 0 <= p < nb:
                pax, pay, pal = cacc[3 * p], cacc[3 * p + 1], cacc[3 * p + 2]
                for i in range(last):  # rigidly carried by the parent
                    jw = jt[3 * p + 2, i]
                    jt[3 * b, i] = jt[3 * p, i] - jw * dy
                    jt[3 * b + 1, i] = jt[3 * p + 1, i] + jw * dx
                    jt[3 * b + 2, i] = jw
            else:
                pax, pay, pal = kin[pr, K_AX], kin[pr, K_AY], kin[pr, K_AL]
            # a = a_p + al_p k x d - w_p^2 d + 2 w_p sdot k x u (+ sddot u, through jt)
            cacc[3 * b] = pax - pal * dy - wp * wp * dx - 2.0 * wp * sd * uy
            cacc[3 * b + 1] = pay + pal * dx - wp * wp * dy + 2.0 * wp * sd * ux
            cacc[3 * b + 2] = pal
            jt[3 * b, last] = ux
            jt[3 * b + 1, last] = uy
            jt[3 * b + 2, last] = 0.0
        else:
            p = jint[r, T_PARENT]
            pr = _row(p, nb, nd)
            c, s = small_rotation(cb[d], sb[d], y[d] - yb[d])
            cp, sp = kin[pr, K_C], kin[pr, K_S]
            wp = kin[pr, K_W]
            w = y[n + d]
            # parent's centre of mass -> joint point (ap), body's centre of mass -> joint point (ab)
            apx = cp * jpar[r, 0] - sp * jpar[r, 1]
            apy = sp * jpar[r, 0] + cp * jpar[r, 1]
            abx = c * jpar[r, 2] - s * jpar[r, 3]
            aby = s * jpar[r, 2] + c * jpar[r, 3]
            kin[b, K_X] = kin[pr, K_X] + apx - abx
            kin[b, K_Y] = kin[pr, K_Y] + apy - aby
            kin[b, K_PHI] = y[d]
            kin[b, K_C] = c
            kin[b, K_S] = s
            kin[b, K_VX] = kin[pr, K_VX] - wp * apy + w * aby
            kin[b, K_VY] = kin[pr, K_VY] + wp * apx - w * abx
            kin[b, K_W] = w
            last = jint[r, T_LEN] - 1  # the body's own angle closes its path; the parent's path precedes it
            if 0 <= p < nb:
                pax, pay, pal = cacc[3 * p], cacc[3 * p + 1], cacc[3 * p + 2]
                for i in range(last):  # the joint point is carried by the parent (its angle: 1 on its own
                    jw = jt[3 * p + 2, i]  # coordinate, 0 elsewhere, unless it slides on a prismatic joint)
                    jt[3 * b, i] = jt[3 * p, i] - jw * apy
                    jt[3 * b + 1, i] = jt[3 * p + 1, i] + jw * apx
                    jt[3 * b + 2, i] = 0.0
            else:
                pax, pay, pal = kin[pr, K_AX], kin[pr, K_AY], kin[pr, K_AL]
            cacc[3 * b] = pax - pal * apy - wp * wp * apx + w * w * abx
            cacc[3 * b + 1] = pay + pal * apx - wp * wp * apy + w * w * aby
            cacc[3 * b + 2] = 0.0
            jt[3 * b, last] = aby
            jt[3 * b + 1, last] = -abx
            jt[3 * b + 2, last] = 1.0


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def rhs_tree(t, dt, y, yb, dy, row, nb, mass, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
             kin, cb, sb, cacc, jt, mm, gq, f, cout):
    """dy[row] = (qd, qdd) of the tree kernel at (t, y), the stage of a step from the base point (t - dt, yb) whose
    cos/sin are in cb, sb (tree_base). M(q) = J^T M_c J and the generalized forces J^T (f - M_c c) over the
    coordinates, then M qdd = g by a dense L D L^T (one division per coordinate). Also fills cout.

    The coordinates are one absolute angle per body (a slide for a body on a prismatic joint; x, y, phi for a body
    held by clearance joints only): those of the Cartesian state, with the same error scales. The tables
    (jointwear.mechanism.tree: one row per free body, parents first) take the Cartesian kernel's slots: a jint row
    is (kind, body, parent code, first coordinate,
    length L of the path, the path: the coordinates the body's velocity depends on, ascending, its own angle last),
    a jpar row (parent-frame point of the joint, body-frame point of the joint), and ``mass`` (the slot of winv)
    holds the masses M_c, not M^-1. The Jacobian is stored by path (jt[3 b + c, i] = d v_bc / d qdot_path[i]), so
    that M and J^T f sum over the L^2 pairs of each body's path instead of dense products (the six-bar: 8 pairs
    instead of 160)."""
    n = y.shape[0] // 2
    nd = dpar.shape[0]
    nq = 3 * nb
    tree_kinematics(t, dt, y, yb, cb, sb, nb, dpar, jint, jpar, kin, cacc, jt)
    for i in range(nq):
        f[i] = fext[i]
    eval_contacts(nb, nd, cint, cpar, prof, ngrid, cstate, kin, f, cout)
    for d1 in range(n):
        gq[d1] = 0.0
        for d2 in range(d1 + 1):
            mm[d1, d2] = 0.0
    for r in range(jint.shape[0]):
        b = jint[r, T_BODY]
        m0, m1, m2 = mass[3 * b], mass[3 * b + 1], mass[3 * b + 2]
        f0 = f[3 * b] - m0 * cacc[3 * b]
        f1 = f[3 * b + 1] - m1 * cacc[3 * b + 1]
        f2 = f[3 * b + 2] - m2 * cacc[3 * b + 2]
        for i in range(jint[r, T_LEN]):
            di = jint[r, T_PATH + i]
            jx, jy, jw = jt[3 * b, i], jt[3 * b + 1, i], jt[3 * b + 2, i]
            gq[di] += jx * f0 + jy * f1 + jw * f2
            ux, uy, uw = m0 * jx, m1 * jy, m2 * jw
            for k in range(i + 1):
                mm[di, jint[r, T_PATH + k]] += ux * jt[3 * b, k] + uy * jt[3 * b + 1, k] + uw * jt[3 * b + 2, k]
    # L D L^T in place: U_ij = L_ij D_j below the diagonal and 1 / D_j on it, so that only the pivots divide
    for j in range(n):
        dj = mm[j, j]
        for k in range(j):
            dj -= mm[j, k] * mm[j, k] * mm[k, k]
        for i in range(j + 1, n):
            acc = mm[i, j]
            for k in range(j):
                acc -= mm[i, k] * mm[j, k] * mm[k, k]
            mm[i, j] = acc
        mm[j, j] = 1.0 / dj
    # L z = g, then x = D^-1 z - L^T x (L_ik = U_ik / D_k)
    for i in range(n):
        acc = gq[i]
        for k in range(i):
            acc -= mm[i, k] * mm[k, k] * gq[k]
        gq[i] = acc
    for i in range(n - 1, -1, -1):
        acc = gq[i] * mm[i, i]
        for k in range(i + 1, n):
            acc -= mm[k, i] * mm[i, i] * gq[k]
        gq[i] = acc
    for i in range(n):
        dy[row, i] = y[n + i]
        dy[row, n + i] = gq[i]


# Dormand-Prince 5(4) tableau (Dormand & Prince 1980; Hairer, Norsett & Wanner I, Table II.5.2).
# Row 6 of DP_A equals the 5th-order weights (FSAL): stage 6 is evaluated at the new point.
DP_C = np.array([0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0])
DP_A = np.array([
    [0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [1.0 / 5.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [3.0 / 40.0, 9.0 / 40.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0.0, 0.0, 0.0, 0.0],
    [19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0.0, 0.0, 0.0],
    [9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0.0, 0.0],
    [35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0, 0.0],
])
# error weights: b5 - b4
DP_E = np.array([71.0 / 57600.0, 0.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
                 -1.0 / 40.0])


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def step_limit(cout, clear_frac, hmax):
    """Largest next step: hmax and, per clearance joint, clear_frac * local clearance / |relative velocity of the
    journal centre| (no impact can be stepped over); from the contact outputs of the latest accepted point."""
    hlim = hmax
    for k in range(cout.shape[0]):
        vrel = cout[k, O_VREL]
        cl = cout[k, O_CLOC]
        if vrel > 0.0 and cl > 0.0:
            hh = clear_frac * cl / vrel
            if hh < hlim:
                hlim = hh
    return hlim


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def next_step(t, h, hlim, t_end, hmin, nrec, cap, nsteps, max_steps):
    """The next attempt of a step loop (shared by the explicit and the implicit one): h clipped to hlim and to
    land exactly on t_end, the new time tn, and a stop code for counters[3] (0 = go on, 1 = record buffer full,
    2 = max_steps, 3 = step underflow below hmin)."""
    if nrec >= cap:
        return h, t, 1
    if nsteps >= max_steps:
        return h, t, 2
    if h > hlim:
        h = hlim
    tn = t + h
    if tn >= t_end - 1e-14 * abs(t_end):
        h = t_end - t
        tn = t_end
    if h < hmin:
        return h, tn, 3
    return h, tn, 0


@njit(cache=True, inline="always", error_model="numpy", _nrt=STEP_LOOP_NRT)
def accept_point(t, h, y, ks, lam, cout, cstate, cpar, t_record, nrec, rec_t, rec_h, rec_y, rec_acc, rec_lam, rec_c):
    """Bookkeeping of an accepted step, shared by the explicit and the implicit loop: the contact memory (impact
    speed v0 at the start of each contact, for the damping term of the normal force) and, from t_record on, the
    record of the new point (state, accelerations ks[0, nq:], multipliers, contact outputs). Returns the new
    record count. The loops compile without reference counting, so passing the arrays costs nothing extra."""
    for k in range(cout.shape[0]):
        if cout[k, O_DELTA] > 0.0:
            if cstate[k, S_INC] < 0.5:
                vn = cout[k, O_VN]
                cstate[k, S_V0] = vn if vn > cpar[k, C_V0MIN] else cpar[k, C_V0MIN]
                cstate[k, S_INC] = 1.0
        else:
            cstate[k, S_INC] = 0.0
    if t >= t_record:
        ny = y.shape[0]
        nq = ny // 2
        rec_t[nrec] = t
        rec_h[nrec] = h
        for i in range(ny):
            rec_y[nrec, i] = y[i]
        for i in range(nq):
            rec_acc[nrec, i] = ks[0, nq + i]
        for i in range(lam.shape[0]):
            rec_lam[nrec, i] = lam[i]
        for k in range(cout.shape[0]):
            for m in range(NCOUT):
                rec_c[k, m, nrec] = cout[k, m]
        nrec += 1
    return nrec


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def crank_rotation(c0, s0, d):
    """cos and sin of (theta0 + d) from c0 = cos theta0, s0 = sin theta0 by the addition theorem; for |d| <= 0.05
    (a step is at most period / 200, i.e. 0.031 rad, by default) cos d and sin d by their Taylor series to d^8 and
    d^9 (truncation < 3e-20 and 6e-18 |d|, below rounding). A sin/cos pair costs about as much as a third of an
    evaluation of rhs_fourbar_cs; this way a Dormand-Prince step needs one instead of six."""
    if d > 0.05 or d < -0.05:
        cd = math.cos(d)
        sd = math.sin(d)
    else:
        d2 = d * d
        cd = 1.0 - d2 * (0.5 - d2 * (1.0 / 24.0 - d2 * (1.0 / 720.0 - d2 * (1.0 / 40320.0))))
        sd = d * (1.0 - d2 * (1.0 / 6.0 - d2 * (1.0 / 120.0 - d2 * (1.0 / 5040.0 - d2 * (1.0 / 362880.0)))))
    return c0 * cd - s0 * sd, s0 * cd + c0 * sd


# The step loops are built per right-hand side (MODES): `mode` is a closure constant, which numba folds and prunes
# before it inlines the right-hand sides, so that each loop compiles only its own (one loop with all three took
# ~100 s to compile). Closure constants are part of numba's cache key.
MODES = ("cartesian", "natural_fourbar", "tree")


def compile_for_mode(fn, mode: int, **options):
    """numba's dispatcher of the builder-made function `fn` for MODES[mode], named `<name>_<mode>`: the name gives each
    mode its own cache file (a closure's qualified name is otherwise the same for every mode)."""
    fn.__name__ = fn.__qualname__ = f"{fn.__name__}_{MODES[mode]}"
    return njit(cache=True, **options)(fn)


def _dormand_prince(mode: int):
    """The Dormand-Prince step loop on the right-hand side MODES[mode] (compiled on first call, cached)."""
    def integrate(t, y, t_end, h, rtol, atolv, hmax, clear_frac, max_steps, t_record,
                  nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                  kin, phi_, phid, rest, jac, smat, lam, f, cout, ks, ytmp,
                  rec_t, rec_h, rec_y, rec_acc, rec_lam, rec_c, counters):
        """Dormand-Prince 5(4) with error control from t to t_end (in place on y).

        rec_c is (n_joints, NCOUT, capacity): each output recorded contiguously over the steps.
        ks: (7, ny) stage derivatives; ks[0] must hold f(t, y) on entry (and holds f at the final
        point on exit).  Records every accepted step with t >= t_record into the rec_* buffers
        (starting at counters[0]); stops early when the buffers are full.  counters: [n_recorded,
        n_accepted, n_rejected, status]; status 0 = reached t_end, 1 = buffer full, 2 = max_steps,
        3 = step underflow.  Step limits: h <= hmax and, per clearance joint, h <= clear_frac *
        clearance / |relative velocity of the journal centre| (no impact can be stepped over).
        Returns (t, h).
        """
        ny = y.shape[0]
        cap = rec_t.shape[0]
        nrec = counters[0]
        nsteps = 0
        counters[3] = 0
        hmin = 1e-15 * max(abs(t), abs(t_end), 1.0)
        c0 = s0 = cs = ss = 0.0  # crank angle cos/sin (four-bar kernel)
        hlim = step_limit(cout, clear_frac, hmax)
        while t < t_end:
            h, tn, stop = next_step(t, h, hlim, t_end, hmin, nrec, cap, nsteps, max_steps)
            if stop:
                counters[3] = stop
                break
            for st in range(1, 7):
                for i in range(ny):
                    acc = 0.0
                    for m in range(st):
                        acc += DP_A[st, m] * ks[m, i]
                    ytmp[st - 1, i] = y[i] + h * acc
                ts = tn if st >= 5 else t + DP_C[st] * h
                if mode == 0:
                    rhs(ts, ytmp[st - 1], ks, st, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                        baum, kin, phi_, phid, rest, jac, smat, lam, f, cout)
                elif mode == 2:  # tree kernel: the work slots phi_, phid, rest, jac, smat, lam hold cb, sb, cacc, jt,
                    # mm, gq
                    if st == 1:
                        tree_base(t, y, jint, dpar, kin, phi_, phid)
                    rhs_tree(ts, ts - t, ytmp[st - 1], y, ks, st, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof,
                             ngrid, cstate, kin, phi_, phid, rest, jac, smat, lam, f, cout)
                else:
                    if st == 1:  # crank angle at t once per attempt; the stages rotate it (crank_rotation)
                        th0 = dpar[0, 4] + dpar[0, 5] * t
                        c0 = math.cos(th0)
                        s0 = math.sin(th0)
                    if st <= 5:  # stages 5 and 6 are both at tn
                        cs, ss = crank_rotation(c0, s0, dpar[0, 5] * (ts - t))
                    rhs_fourbar_cs(cs, ss, ytmp, st - 1, ks, st, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam,
                                   cout)
            err = 0.0
            for i in range(ny):
                ei = h * (DP_E[0] * ks[0, i] + DP_E[2] * ks[2, i] + DP_E[3] * ks[3, i] + DP_E[4] * ks[4, i]
                          + DP_E[5] * ks[5, i] + DP_E[6] * ks[6, i])
                yi = abs(y[i])
                yn = abs(ytmp[5, i])
                sc = atolv[i] + rtol * (yi if yi > yn else yn)
                r = ei / sc
                err += r * r
            err = math.sqrt(err / ny)
            nsteps += 1
            if err <= 1.0:
                t = tn
                for i in range(ny):
                    y[i] = ytmp[5, i]
                    ks[0, i] = ks[6, i]
                counters[1] += 1
                nrec = accept_point(t, h, y, ks, lam, cout, cstate, cpar, t_record, nrec, rec_t, rec_h, rec_y, rec_acc,
                                    rec_lam, rec_c)
                hlim = step_limit(cout, clear_frac, hmax)
                fac = 0.9 * (err if err > 1e-10 else 1e-10) ** (-0.2)
                if fac > 5.0:
                    fac = 5.0
                if fac < 0.2:
                    fac = 0.2
                h = h * fac
            else:
                counters[2] += 1
                if err == err:  # not NaN
                    fac = 0.9 * err ** (-0.2)
                    if fac < 0.2:
                        fac = 0.2
                else:  # a stage produced NaN/inf (e.g. a huge penetration): shrink hard and retry
                    fac = 0.1
                h = h * fac
        counters[0] = nrec
        return t, h

    return compile_for_mode(integrate, mode, nogil=True, error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)


def _called(fn, **options):
    """A dispatcher of the inlined function ``fn`` compiled as a function of its own, under its own name and cache
    file. The record's single evaluation calls it: inlining the right-hand side there again cost 2-3x its own compile
    (~20 s for the tree's), for a call made once per record."""
    py = fn.py_func
    copy = types.FunctionType(py.__code__, py.__globals__, py.__name__ + "_called", py.__defaults__, py.__closure__)
    copy.__qualname__ = copy.__name__
    copy.__doc__ = py.__doc__
    return njit(cache=True, **options)(copy)


def _evaluation(mode: int):
    """One evaluation of the right-hand side MODES[mode] (the record's first point; compiled on first call)."""
    def accelerations(t, y, dy, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                      kin, phi_, phid, rest, jac, smat, lam, f, cout):
        """One evaluation of the equations of motion into dy (2-D, row 0)."""
        if mode == 0:
            rhs(t, y, dy, 0, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate, baum,
                kin, phi_, phid, rest, jac, smat, lam, f, cout)
        elif mode == 2:
            tree_base(t, y, jint, dpar, kin, phi_, phid)
            rhs_tree_called(t, 0.0, y, y, dy, 0, nb, winv, fext, dpar, jint, jpar, cint, cpar, prof, ngrid, cstate,
                            kin, phi_, phid, rest, jac, smat, lam, f, cout)
        else:
            Y = np.empty((1, y.shape[0]))
            Y[0, :] = y
            rhs_fourbar_called(t, Y, 0, dy, 0, dpar, jpar, cint, cpar, prof, ngrid, cstate, baum, lam, cout)

    return compile_for_mode(accelerations, mode, error_model="numpy")


INTEGRATORS = tuple(_dormand_prince(m) for m in range(3))
integrate_cartesian, integrate_natural_fourbar, integrate_tree = INTEGRATORS
EVALUATORS = tuple(_evaluation(m) for m in range(3))


def empty_work(nb: int, nd: int, nj: int, ncj: int) -> dict[str, np.ndarray]:
    """Preallocated work arrays of the kernels."""
    nq = 3 * nb
    nc = 2 * nj
    return {
        "kin": np.zeros((nb + nd + 1, NKIN)),
        "phi_": np.zeros(nc),
        "phid": np.zeros(nc),
        "rest": np.zeros(nc),
        "jac": np.zeros((nc, nq)),
        "smat": np.zeros((nc, nc)),
        "lam": np.zeros(nc),
        "f": np.zeros(nq),
        "cout": np.zeros((ncj, NCOUT)),
    }


# ---------------------------------------------------------------------------------------------
# Fast path: four-bar with the clearance joint between the driven crank and the rod (joint A).
# Natural coordinates (Garcia de Jalon & Bayo 1994): q = (A, B), the rod's end points (A = centre
# of the rod's eye), the rocker is the segment C-B with C fixed. The mass matrix is constant,
# the constraints are the two link lengths, no trigonometry except the crank angle. Same physics
# as the Cartesian formulation above (checked by tests/dynamics/test_fast_path.py).
# fp (1 x NFP) layout:
FP_L2, FP_L3, FP_CX, FP_CY, FP_P, FP_R, FP_S, FP_QAX, FP_QAY, FP_QBX, FP_QBY, FP_T3, FP_T2, FP_SIG, FP_PX, FP_PY = range(16)
NFP = 16


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def rhs_fourbar(t, Y, yrow, dy, row, dpar, fp, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
    """dy[row] for the state Y[yrow] = (A, B, Adot, Bdot) of the natural-coordinate four-bar (see notes)."""
    th = dpar[0, 4] + dpar[0, 5] * t
    rhs_fourbar_cs(math.cos(th), math.sin(th), Y, yrow, dy, row, dpar, fp, cint, cpar, prof, ngrid, cstate, baum,
                   lam, cout)


@njit(cache=True, inline="always", error_model="numpy", fastmath=FASTMATH, _nrt=STEP_LOOP_NRT)
def rhs_fourbar_cs(c, sn, Y, yrow, dy, row, dpar, fp, cint, cpar, prof, ngrid, cstate, baum, lam, cout):
    """rhs_fourbar given c, sn = cos, sin of the crank angle (the only place where time enters)."""
    ax, ay, bx, by = Y[yrow, 0], Y[yrow, 1], Y[yrow, 2], Y[yrow, 3]
    avx, avy, bvx, bvy = Y[yrow, 4], Y[yrow, 5], Y[yrow, 6], Y[yrow, 7]
    l2 = fp[0, FP_L2]
    l3 = fp[0, FP_L3]
    p = fp[0, FP_P]
    r = fp[0, FP_R]
    s = fp[0, FP_S]
    sig = fp[0, FP_SIG]
    # crank pin (prescribed): pin = pivot + R(theta) (s_A - s_O)
    w = dpar[0, 5]
    ux = fp[0, FP_PX]
    uy = fp[0, FP_PY]
    relx = c * ux - sn * uy
    rely = sn * ux + c * uy
    pinx = dpar[0, 0] + relx
    piny = dpar[0, 1] + rely
    pvx = -w * rely
    pvy = w * relx
    dx = bx - ax
    dyy = by - ay
    ddx = bvx - avx
    ddy = bvy - avy
    d2 = dx * dx + dyy * dyy
    id2 = 1.0 / d2
    wrod = (dx * ddy - dyy * ddx) * id2
    ex3 = bx - fp[0, FP_CX]
    ey3 = by - fp[0, FP_CY]
    qax = fp[0, FP_QAX]
    qay = fp[0, FP_QAY]
    qbx = fp[0, FP_QBX]
    qby = fp[0, FP_QBY]
    tq = fp[0, FP_T2]  # torque on the rod
    t3 = fp[0, FP_T3]
    if t3 != 0.0:
        e32 = ex3 * ex3 + ey3 * ey3
        qbx += -t3 * ey3 / e32
        qby += t3 * ex3 / e32
    # ---- contact (bearing centre -> journal centre) ----
    k = 0
    if sig > 0.0:  # bearing on the rod, journal = crank pin
        ex = pinx - ax
        ey = piny - ay
        rvx = pvx - avx
        rvy = pvy - avy
        wb = wrod
        wj = w
    else:  # bearing on the crank, journal = rod's pin
        ex = ax - pinx
        ey = ay - piny
        rvx = avx - pvx
        rvy = avy - pvy
        wb = w
        wj = wrod
    emag = math.sqrt(ex * ex + ey * ey)
    if emag > 1e-300:
        ie = 1.0 / emag
        nx = ex * ie
        ny = ey * ie
    else:
        nx = 1.0
        ny = 0.0
    sides = cint[k, CI_PROF]
    if sides != 0:
        # angles of n relative to the body x axes (rod: along A->B; crank: at angle th), of the worn sides only
        rod_side = PROF_BEARING if sig > 0.0 else PROF_JOURNAL
        ang_rod = 0.0
        ang_crk = 0.0
        if sides & rod_side:
            dl = math.sqrt(d2)
            rdx = dx / dl
            rdy = dyy / dl
            ang_rod = math.atan2(rdx * ny - rdy * nx, rdx * nx + rdy * ny)
        if sides & (PROF_BEARING + PROF_JOURNAL - rod_side):
            ang_crk = math.atan2(c * ny - sn * nx, c * nx + sn * ny)
        if sig > 0.0:
            ab = ang_rod
            aj = ang_crk
        else:
            ab = ang_crk
            aj = ang_rod
    else:
        ab = aj = 0.0
    delta, fs, ft, fjx, fjy, hbp, hjp, rbl, rjl = clearance_contact(
        k, cint, cpar, prof, ngrid, cstate, ex, ey, emag, nx, ny, rvx, rvy, wb, wj, ab, aj, cout)
    if delta > 0.0:
        if sig > 0.0:  # rod carries the bearing: -Fj at A, torque -fs h_b' - R_b ft
            qax -= fjx
            qay -= fjy
            tq += -fs * hbp - rbl * ft
        else:  # rod carries the journal: Fj at A, torque -fs h_j' + R_j ft
            qax += fjx
            qay += fjy
            tq += -fs * hjp + rjl * ft
    cout[k, O_PHIB] = 0.0
    cout[k, O_PHIJ] = 0.0
    # torque on the rod -> couple on (A, B)
    if tq != 0.0:
        cx = tq * dyy * id2
        cy = tq * dx * id2
        qbx -= cx
        qby += cy
        qax += cx
        qay -= cy
    # ---- constraints |B - A|^2 = l2^2, |B - C|^2 = l3^2 (Baumgarte) ----
    alpha2 = 2.0 * baum[0]
    beta2 = baum[1] * baum[1]
    phi1 = d2 - l2 * l2
    phi2 = ex3 * ex3 + ey3 * ey3 - l3 * l3
    phid1 = 2.0 * (dx * ddx + dyy * ddy)
    phid2 = 2.0 * (ex3 * bvx + ey3 * bvy)
    g1 = -2.0 * (ddx * ddx + ddy * ddy) - alpha2 * phid1 - beta2 * phi1
    g2 = -2.0 * (bvx * bvx + bvy * bvy) - alpha2 * phid2 - beta2 * phi2
    # free accelerations M^-1 Q
    fax = p * qax + r * qbx
    fay = p * qay + r * qby
    fbx = r * qax + s * qbx
    fby = r * qay + s * qby
    b1 = 2.0 * (dx * (fbx - fax) + dyy * (fby - fay)) - g1
    b2 = 2.0 * (ex3 * fbx + ey3 * fby) - g2
    s11 = 4.0 * d2 * (p - 2.0 * r + s)
    s12 = 4.0 * (s - r) * (dx * ex3 + dyy * ey3)
    s22 = 4.0 * s * (ex3 * ex3 + ey3 * ey3)
    idet = 1.0 / (s11 * s22 - s12 * s12)
    lam1 = (s22 * b1 - s12 * b2) * idet
    lam2 = (s11 * b2 - s12 * b1) * idet
    lam[0] = lam1
    lam[1] = lam2
    qax += 2.0 * dx * lam1
    qay += 2.0 * dyy * lam1
    qbx -= 2.0 * dx * lam1 + 2.0 * ex3 * lam2
    qby -= 2.0 * dyy * lam1 + 2.0 * ey3 * lam2
    dy[row, 0] = avx
    dy[row, 1] = avy
    dy[row, 2] = bvx
    dy[row, 3] = bvy
    dy[row, 4] = p * qax + r * qbx
    dy[row, 5] = p * qay + r * qby
    dy[row, 6] = r * qax + s * qbx
    dy[row, 7] = r * qay + s * qby


# the evaluators' flags as the inlined bodies had them there (the caller's: no fastmath): the same arithmetic
rhs_tree_called = _called(rhs_tree, error_model="numpy", fastmath=False, _nrt=STEP_LOOP_NRT)
rhs_fourbar_called = _called(rhs_fourbar, error_model="numpy", fastmath=False, _nrt=STEP_LOOP_NRT)
