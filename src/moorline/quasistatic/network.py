"""Compiled core of the quasi-static network: lines between points, points on bodies, the Newton
solve of the free degrees of freedom and the condensed stiffness of the coupled ones.

Degrees of freedom
------------------
Every point has a position; a point is fixed, owns 3 degrees of freedom (a free or coupled point) or
rides on a body. Every body has 6 degrees of freedom (x, y, z and three rotations) or none (fixed).
A degree of freedom is *free* (solved for equilibrium) or *coupled* (given). They are numbered in one
vector ``z``: the ``nu`` free ones first, then the coupled ones in the order of the coupled input
vector. Rotations are small rotations about the **global** axes at the current pose: a body's
orientation is kept as a rotation matrix ``R`` and a rotation increment ``w`` updates it to
``exp(S(w)) R``; a point on a body moves by ``dr = dx + w x (R r_rel) = [I, -S(R r_rel)] [dx; w]``.

Loads and stiffness
-------------------
``Q`` [N, N m] is the generalised load on ``z`` (the forces on point DOFs; force and moment about the
reference point, global axes, on body DOFs) and ``K = -dQ/dz``. A point on a body with total force
``f`` at arm ``rho`` adds ``[f; rho x f]`` to its body and the load-stiffness term
``(f . rho) I - rho f^T`` (``-S(f) S(rho)``) to the rotation block, which makes the rotation block
unsymmetric by ``S(M)/2`` where ``M`` is the moment of those loads (MoorPy's convention too). A body's
own loads (only when it has free degrees of freedom): its weight at its centre of gravity and a
buoyancy force at its centre of buoyancy, both rotating with it, the linear hydrostatic restoring
``-C (q - q0)`` with ``q`` its pose (Euler angles roll, pitch, yaw, ``R = Rx Ry Rz``) and a constant
external load.

The equilibrium ``Q_u = 0`` is solved by Newton's method with a step limit and a backtracking line
search; the coupled stiffness follows from the implicit-function theorem:
``K_c = K_cc - K_cu K_uu^-1 K_uc``, and any quantity ``g`` (end tensions) changes with the coupled
DOFs as ``dg/dc = G_c - G_u K_uu^-1 K_uc``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from ..core.numerics import euler_R
from .line2d import LINE2D_SIZE, O_D, O_H, O_HL, O_KTL, O_KTU, O_LB, O_V, O_VL, QS_BELOW_SEABED, upright_line

# line float table columns
LF_L, LF_EA, LF_W, LF_CB, LF_GX, LF_GY, LF_H, LF_V = range(8)
LF_SIZE = 8
# line int table columns: end A point, end B point, seabed end (0 none, 1 end A, 2 end B)
LI_A, LI_B, LI_BED = range(3)
# line work columns: forces on A, B (6), dF/d(rB - rA) of A, B (18), tensions (2), their gradients (6), ...
LW_F = 0
LW_D = 6
LW_T = 24
LW_DT = 26
LW_LB = 32
LW_LOA = 33  # 1 when end A is the lower end
LW_CONTACT = 34
LW_SLOPE = 35
LW_SIZE = 36
# point tables: float (position or body-frame offset, constant force); int (kind, body, 3 DOF indices)
PT_FIXED, PT_DOF, PT_BODY = 0, 1, 2
# body float table: r (3), R (9), weight, rCG (3), buoyancy, rCB (3), C (36), q0 (6), external load (6)
BF_R = 0
BF_ROT = 3
BF_WT = 12
BF_CG = 13
BF_BUOY = 16
BF_CB = 17
BF_C = 20
BF_Q0 = 56
BF_FEXT = 62
BF_SIZE = 68
# body int table: own loads flag, 6 DOF indices
# options: force tolerance [N], length scale [m], max iterations, max step [m], max rotation [rad]
OPT_FTOL, OPT_LSCALE, OPT_MAXIT, OPT_MAXSTEP, OPT_MAXROT = range(5)
# kernel status
NET_OK = 0
NET_NOT_CONVERGED = 1
NET_SINGULAR = 2
NET_LINE_FAILED = 3
_NWATCH = 3  # extra Newton steps tried from a full step that raised the merit
_FLOOR = 100.0  # a residual below this times the tolerance that no step lowers is round-off: converged


@njit(cache=True, error_model="numpy")
def angles_of(R):
    """Roll, pitch, yaw [rad] of ``R = Rx Ry Rz`` (pitch in [-pi/2, pi/2])."""
    pitch = math.asin(max(-1.0, min(1.0, R[0, 2])))
    if abs(R[0, 2]) < 1.0 - 1e-12:
        return math.atan2(-R[1, 2], R[2, 2]), pitch, math.atan2(-R[0, 1], R[0, 0])
    return math.atan2(R[2, 1], R[1, 1]), pitch, 0.0


@njit(cache=True, error_model="numpy")
def _rotate_by(w0, w1, w2, R):
    """``R <- exp(S(w)) R`` (Rodrigues)."""
    th = math.sqrt(w0 * w0 + w1 * w1 + w2 * w2)
    if th == 0.0:
        return
    k0, k1, k2 = w0 / th, w1 / th, w2 / th
    c = math.cos(th)
    s = math.sin(th)
    v = 1.0 - c
    E = np.empty((3, 3))
    E[0, 0] = c + k0 * k0 * v
    E[0, 1] = k0 * k1 * v - k2 * s
    E[0, 2] = k0 * k2 * v + k1 * s
    E[1, 0] = k1 * k0 * v + k2 * s
    E[1, 1] = c + k1 * k1 * v
    E[1, 2] = k1 * k2 * v - k0 * s
    E[2, 0] = k2 * k0 * v - k1 * s
    E[2, 1] = k2 * k1 * v + k0 * s
    E[2, 2] = c + k2 * k2 * v
    Rn = np.empty((3, 3))
    for i in range(3):
        for j in range(3):
            Rn[i, j] = E[i, 0] * R[0, j] + E[i, 1] * R[1, j] + E[i, 2] * R[2, j]
    R[:, :] = Rn


@njit(cache=True, error_model="numpy")
def euler_rate_matrix(roll, pitch, T):
    """Fill ``T`` (3, 3): the global angular increment of Euler-angle increments, ``w = T d(roll,
    pitch, yaw)`` for ``R = Rx Ry Rz``."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    T[0, 0], T[0, 1], T[0, 2] = 1.0, 0.0, sp
    T[1, 0], T[1, 1], T[1, 2] = 0.0, cr, -sr * cp
    T[2, 0], T[2, 1], T[2, 2] = 0.0, sr, cr * cp


@njit(cache=True, error_model="numpy")
def line3d(rA, rB, lf, li, o2, lw):
    """Solve one line between end positions ``rA``, ``rB`` [m] and fill its work row ``lw``.

    ``lf``/``li`` are the line's rows of the float/int tables (the warm start ``LF_H, LF_V`` is
    updated), ``o2`` a scratch array of size ``LINE2D_SIZE``. Returns the status of
    :func:`moorline.quasistatic.line2d.upright_line`.
    """
    d0 = rB[0] - rA[0]
    d1 = rB[1] - rA[1]
    d2 = rB[2] - rA[2]
    bed = li[LI_BED]
    if bed == 2:
        lo_a = d2 > 0.0
    else:
        lo_a = d2 >= 0.0
    contact = (bed == 1 and lo_a) or (bed == 2 and not lo_a)
    if bed != 0 and not contact:
        # the end on the seabed is the upper one: the other end must not lie below the seabed plane
        sb = 1.0 if bed == 1 else -1.0  # from the seabed end to the other end
        Xo = math.hypot(d0, d1)
        slope_o = (lf[LF_GX] * d0 + lf[LF_GY] * d1) * sb / Xo if Xo > 0.0 else 0.0
        if sb * d2 - Xo * slope_o < -1e-9 * (lf[LF_L] + Xo + abs(d2)):
            return QS_BELOW_SEABED
        # the seabed then descends from the seabed end towards the other end, and the line may lie down the
        # slope before it lifts off: solve it in the seabed end's frame (the other end below it, above the plane)
        lo_a = bed == 1
        contact = True
    sg = 1.0 if lo_a else -1.0
    u0 = sg * d0
    u1 = sg * d1
    X = math.hypot(u0, u1)
    Z = sg * d2
    if X > 0.0:
        ux, uy = u0 / X, u1 / X
    else:
        ux, uy = 1.0, 0.0
    gx = lf[LF_GX]
    gy = lf[LF_GY]
    t = gx * ux + gy * uy if contact else 0.0
    status, _ = upright_line(X, Z, lf[LF_L], lf[LF_EA], lf[LF_W], contact, t, lf[LF_CB], lf[LF_H], lf[LF_V], o2)
    if status != 0:
        return status
    H, V, HL, VL = o2[O_H], o2[O_V], o2[O_HL], o2[O_VL]
    lf[LF_H] = H
    lf[LF_V] = V
    tg0 = tg1 = 0.0
    if contact and X > 0.0:
        tg0 = (gx - t * ux) / X
        tg1 = (gy - t * uy) / X
    # gradients of H, V, HL, VL with respect to the upright chord (lower -> upper)
    G = np.empty((4, 3))
    for i in range(4):
        fX = o2[O_D + 3 * i]
        fZ = o2[O_D + 3 * i + 1]
        ft = o2[O_D + 3 * i + 2]
        G[i, 0] = fX * ux + ft * tg0
        G[i, 1] = fX * uy + ft * tg1
        G[i, 2] = fZ
    kU = o2[O_KTU]
    kL = o2[O_KTL]
    # forces on the upper and lower ends and their derivatives with respect to the upright chord
    Fu = np.array([-H * ux, -H * uy, -V])
    Fl = np.array([HL * ux, HL * uy, VL])
    Du = np.empty((3, 3))
    Dl = np.empty((3, 3))
    uh = (ux, uy)
    for i in range(2):
        for j in range(3):
            ph = 0.0
            if j < 2:
                ph = (1.0 if i == j else 0.0) - uh[i] * uh[j]
            Du[i, j] = -(uh[i] * G[0, j] + kU * ph)
            Dl[i, j] = uh[i] * G[2, j] + kL * ph
    for j in range(3):
        Du[2, j] = -G[1, j]
        Dl[2, j] = G[3, j]
    Tu = math.hypot(H, V)
    Tl = math.hypot(HL, VL)
    dTu = np.zeros(3)
    dTl = np.zeros(3)
    if Tu > 0.0:
        for j in range(3):
            dTu[j] = (H * G[0, j] + V * G[1, j]) / Tu
    if Tl > 0.0:
        for j in range(3):
            dTl[j] = (HL * G[2, j] + VL * G[3, j]) / Tl
    # to ends A and B, derivatives with respect to rB - rA
    for j in range(3):
        if lo_a:
            lw[LW_F + j] = Fl[j]
            lw[LW_F + 3 + j] = Fu[j]
            lw[LW_DT + j] = dTl[j]
            lw[LW_DT + 3 + j] = dTu[j]
        else:
            lw[LW_F + j] = Fu[j]
            lw[LW_F + 3 + j] = Fl[j]
            lw[LW_DT + j] = -dTu[j]
            lw[LW_DT + 3 + j] = -dTl[j]
        for i in range(3):
            if lo_a:
                lw[LW_D + 3 * i + j] = Dl[i, j]
                lw[LW_D + 9 + 3 * i + j] = Du[i, j]
            else:
                lw[LW_D + 3 * i + j] = -Du[i, j]
                lw[LW_D + 9 + 3 * i + j] = -Dl[i, j]
    lw[LW_T] = Tl if lo_a else Tu
    lw[LW_T + 1] = Tu if lo_a else Tl
    lw[LW_LB] = o2[O_LB]
    lw[LW_LOA] = 1.0 if lo_a else 0.0
    lw[LW_CONTACT] = 1.0 if contact else 0.0
    lw[LW_SLOPE] = t
    return 0


@njit(cache=True, error_model="numpy")
def _emap(p, pi, bi, rho, E, idx):
    """Map of point ``p``'s displacement to its DOFs: fills ``E`` (3, 6) and ``idx`` (6,); returns
    the number of DOFs (0 fixed, 3 point, 6 body)."""
    kind = pi[p, 0]
    if kind == PT_DOF:
        for i in range(3):
            for j in range(3):
                E[i, j] = 1.0 if i == j else 0.0
            idx[i] = pi[p, 2 + i]
        return 3
    if kind == PT_BODY:
        b = pi[p, 1]
        r0, r1, r2 = rho[p, 0], rho[p, 1], rho[p, 2]
        for i in range(3):
            for j in range(3):
                E[i, j] = 1.0 if i == j else 0.0
        # -S(rho)
        E[0, 3], E[0, 4], E[0, 5] = 0.0, r2, -r1
        E[1, 3], E[1, 4], E[1, 5] = -r2, 0.0, r0
        E[2, 3], E[2, 4], E[2, 5] = r1, -r0, 0.0
        for i in range(6):
            idx[i] = bi[b, 1 + i]
        return 6
    return 0


@njit(cache=True, error_model="numpy")
def _add_rot_load_stiffness(K, i0, f, rho):
    """``K[i0:i0+3, i0:i0+3] += (f . rho) I - rho f^T`` (a load f at arm rho rotating with its body)."""
    fr = f[0] * rho[0] + f[1] * rho[1] + f[2] * rho[2]
    for i in range(3):
        for j in range(3):
            K[i0 + i, i0 + j] += (fr if i == j else 0.0) - rho[i] * f[j]


@njit(cache=True, error_model="numpy")
def positions(pf, pi, bf, r, rho):
    """Global positions ``r`` (nP, 3) of every point and, for points on bodies, their arms ``rho``."""
    for p in range(pi.shape[0]):
        if pi[p, 0] == PT_BODY:
            b = pi[p, 1]
            for i in range(3):
                rho[p, i] = (bf[b, BF_ROT + 3 * i] * pf[p, 0] + bf[b, BF_ROT + 3 * i + 1] * pf[p, 1]
                             + bf[b, BF_ROT + 3 * i + 2] * pf[p, 2])
                r[p, i] = bf[b, BF_R + i] + rho[p, i]
        else:
            for i in range(3):
                rho[p, i] = 0.0
                r[p, i] = pf[p, i]


@njit(cache=True, error_model="numpy")
def assemble(lf, li, pf, pi, bf, bi, lw, r, rho, fp, Q, K):
    """Solve every line at the current positions and assemble ``Q`` (nz,) and ``K = -dQ/dz``
    (nz, nz). Returns ``-1`` or the index of the first line that failed."""
    nL = li.shape[0]
    nP = pi.shape[0]
    positions(pf, pi, bf, r, rho)
    o2 = np.empty(LINE2D_SIZE)
    for ln in range(nL):
        st = line3d(r[li[ln, LI_A]], r[li[ln, LI_B]], lf[ln], li[ln], o2, lw[ln])
        if st != 0:
            return ln
    for p in range(nP):
        for i in range(3):
            fp[p, i] = pf[p, 3 + i]
    for ln in range(nL):
        for e in range(2):
            p = li[ln, e]
            for i in range(3):
                fp[p, i] += lw[ln, LW_F + 3 * e + i]
    Q[:] = 0.0
    K[:, :] = 0.0
    Ex = np.zeros((3, 6))
    Ey = np.zeros((3, 6))
    ix = np.zeros(6, dtype=np.int64)
    iy = np.zeros(6, dtype=np.int64)
    for p in range(nP):
        n = _emap(p, pi, bi, rho, Ex, ix)
        for j in range(n):
            if ix[j] < 0:
                continue
            acc = 0.0
            for i in range(3):
                acc += Ex[i, j] * fp[p, i]
            Q[ix[j]] += acc
        if n == 6 and ix[3] >= 0:
            _add_rot_load_stiffness(K, ix[3], fp[p], rho[p])
    M = np.empty((3, 3))
    T1 = np.empty((3, 6))
    for ln in range(nL):
        for x in range(2):
            nx = _emap(li[ln, x], pi, bi, rho, Ex, ix)
            if nx == 0:
                continue
            for y in range(2):
                ny = _emap(li[ln, y], pi, bi, rho, Ey, iy)
                if ny == 0:
                    continue
                sgn = 1.0 if y == 0 else -1.0  # K_xy = -dF_x/dr_y, dF_x/dr_A = -D_x, dF_x/dr_B = D_x
                for i in range(3):
                    for j in range(3):
                        M[i, j] = sgn * lw[ln, LW_D + 9 * x + 3 * i + j]
                for i in range(3):
                    for j in range(ny):
                        T1[i, j] = M[i, 0] * Ey[0, j] + M[i, 1] * Ey[1, j] + M[i, 2] * Ey[2, j]
                for a in range(nx):
                    if ix[a] < 0:
                        continue
                    for b in range(ny):
                        if iy[b] < 0:
                            continue
                        K[ix[a], iy[b]] += Ex[0, a] * T1[0, b] + Ex[1, a] * T1[1, b] + Ex[2, a] * T1[2, b]
    for b in range(bi.shape[0]):
        if bi[b, 0]:
            _body_loads(bf[b], bi[b], Q, K)
    return -1


@njit(cache=True, error_model="numpy")
def _body_loads(bfr, bir, Q, K):
    """Add a body's own loads (weight, buoyancy, linear hydrostatics, external) and their stiffness."""
    R = bfr[BF_ROT:BF_ROT + 9].reshape(3, 3)
    f = np.zeros(3)
    rho = np.empty(3)
    it = bir[1]
    ir = bir[4]
    for which in range(2):
        off = BF_CG if which == 0 else BF_CB
        f[2] = -bfr[BF_WT] if which == 0 else bfr[BF_BUOY]
        if f[2] == 0.0:
            continue
        for i in range(3):
            rho[i] = R[i, 0] * bfr[off] + R[i, 1] * bfr[off + 1] + R[i, 2] * bfr[off + 2]
        if it >= 0:
            Q[bir[3]] += f[2]
        if ir >= 0:
            Q[ir] += rho[1] * f[2]
            Q[ir + 1] += -rho[0] * f[2]
            _add_rot_load_stiffness(K, ir, f, rho)
    roll, pitch, yaw = angles_of(R)
    q = np.array([bfr[BF_R], bfr[BF_R + 1], bfr[BF_R + 2], roll, pitch, yaw])
    dq = np.empty(6)
    for i in range(6):
        dq[i] = q[i] - bfr[BF_Q0 + i]
    for i in range(3, 6):  # wrap angle differences to (-pi, pi]
        dq[i] = dq[i] - 2.0 * math.pi * math.floor((dq[i] + math.pi) / (2.0 * math.pi))
    C = bfr[BF_C:BF_C + 36].reshape(6, 6)
    # inverse of the Euler rate matrix (euler_rate_matrix), in closed form (cos(pitch) != 0)
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    Ti = np.empty((3, 3))
    Ti[0, 0], Ti[0, 1], Ti[0, 2] = 1.0, sr * sp / cp, -cr * sp / cp
    Ti[1, 0], Ti[1, 1], Ti[1, 2] = 0.0, cr, sr
    Ti[2, 0], Ti[2, 1], Ti[2, 2] = 0.0, -sr / cp, cr / cp
    for i in range(6):
        k = bir[1 + i]
        if k < 0:
            continue
        acc = bfr[BF_FEXT + i]
        for j in range(6):
            acc -= C[i, j] * dq[j]
        Q[k] += acc
        for j in range(3):
            if bir[1 + j] >= 0:
                K[k, bir[1 + j]] += C[i, j]
        if ir >= 0:
            for j in range(3):
                acc = 0.0
                for m in range(3):
                    acc += C[i, 3 + m] * Ti[m, j]
                K[k, ir + j] += acc


@njit(cache=True, error_model="numpy")
def lu_factor(A, piv):
    """In-place LU factorisation with partial pivoting; returns False when a pivot is zero or tiny
    (below 1e-14 of the largest diagonal entry)."""
    n = A.shape[0]
    big = 0.0
    for i in range(n):
        big = max(big, abs(A[i, i]))
    small = 1e-14 * big if big > 0.0 else 1e-300
    for k in range(n):
        p = k
        for i in range(k + 1, n):
            if abs(A[i, k]) > abs(A[p, k]):
                p = i
        piv[k] = p
        if not abs(A[p, k]) > small:
            return False
        if p != k:
            for j in range(n):
                A[k, j], A[p, j] = A[p, j], A[k, j]
        inv = 1.0 / A[k, k]
        for i in range(k + 1, n):
            A[i, k] *= inv
            a = A[i, k]
            if a != 0.0:
                for j in range(k + 1, n):
                    A[i, j] -= a * A[k, j]
    return True


@njit(cache=True, error_model="numpy")
def lu_solve(A, piv, b):
    """Solve ``A x = b`` in place with the factors of :func:`lu_factor`."""
    n = A.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            b[k], b[p] = b[p], b[k]
    for i in range(n):
        acc = b[i]
        for j in range(i):
            acc -= A[i, j] * b[j]
        b[i] = acc
    for i in range(n - 1, -1, -1):
        acc = b[i]
        for j in range(i + 1, n):
            acc -= A[i, j] * b[j]
        b[i] = acc / A[i, i]


@njit(cache=True, error_model="numpy")
def set_coupled(xc, nu, pf, pi, bf, bi):
    """Put the coupled DOF values ``xc`` [m, rad] on their points and bodies (a body whose three
    rotations are coupled takes them as Euler angles roll, pitch, yaw)."""
    for p in range(pi.shape[0]):
        if pi[p, 0] == PT_DOF:
            for i in range(3):
                k = pi[p, 2 + i]
                if k >= nu:
                    pf[p, i] = xc[k - nu]
    R = np.empty((3, 3))
    for b in range(bi.shape[0]):
        for i in range(3):
            k = bi[b, 1 + i]
            if k >= nu:
                bf[b, BF_R + i] = xc[k - nu]
        k = bi[b, 4]
        if k >= nu:
            euler_R(xc[k - nu], xc[bi[b, 5] - nu], xc[bi[b, 6] - nu], R)
            for i in range(3):
                for j in range(3):
                    bf[b, BF_ROT + 3 * i + j] = R[i, j]


@njit(cache=True, error_model="numpy")
def apply_step(dz, lam, nu, pf, pi, bf, bi):
    """Move the free DOFs by ``lam * dz[:nu]``."""
    for p in range(pi.shape[0]):
        if pi[p, 0] == PT_DOF:
            for i in range(3):
                k = pi[p, 2 + i]
                if 0 <= k < nu:
                    pf[p, i] += lam * dz[k]
    R = np.empty((3, 3))
    for b in range(bi.shape[0]):
        for i in range(3):
            k = bi[b, 1 + i]
            if 0 <= k < nu:
                bf[b, BF_R + i] += lam * dz[k]
        k = bi[b, 4]
        if 0 <= k < nu:
            for i in range(3):
                for j in range(3):
                    R[i, j] = bf[b, BF_ROT + 3 * i + j]
            _rotate_by(lam * dz[k], lam * dz[bi[b, 5]], lam * dz[bi[b, 6]], R)
            for i in range(3):
                for j in range(3):
                    bf[b, BF_ROT + 3 * i + j] = R[i, j]


@njit(cache=True, error_model="numpy")
def _merit(Q, nu, rotdof, lscale):
    """Scaled residuals: the largest free force [N] or moment / length scale [N], and the root sum
    of squares of the same (the line-search merit)."""
    m = 0.0
    s = 0.0
    for k in range(nu):
        v = abs(Q[k]) / lscale if rotdof[k] else abs(Q[k])
        s += v * v
        if v > m:
            m = v
    return m, math.sqrt(s)


@njit(cache=True, error_model="numpy")
def _watchdog(dz, res, res2, nu, lf, li, pf, pi, bf, bi, rotdof, opt, lw, r, rho, fp, Q, K, A, piv):
    """Take the full Newton step ``dz`` and, if it does not lower the merit, up to ``_NWATCH`` more
    Newton steps from there (each limited like the first); accept when the merit falls below the
    start. A straight Newton step cannot follow a junction swinging on nearly taut legs (the legs
    overstretch along the step); the next Newton step from the overstretched state pulls it back onto
    the arc. Returns ``(accepted, residual, merit)``; on refusal the state is left where it stopped."""
    apply_step(dz, 1.0, nu, pf, pi, bf, bi)
    d2 = np.empty(nu)
    for w in range(_NWATCH + 1):
        if assemble(lf, li, pf, pi, bf, bi, lw, r, rho, fp, Q, K) >= 0:
            return False, res, res2
        rn, rn2 = _merit(Q, nu, rotdof, opt[OPT_LSCALE])
        if rn2 < res2 or rn <= opt[OPT_FTOL]:
            return True, rn, rn2
        if w == _NWATCH:
            break
        A[:, :] = K[:nu, :nu]
        if not lu_factor(A, piv):
            break
        d2[:] = Q[:nu]
        lu_solve(A, piv, d2)
        mt = 0.0
        mr = 0.0
        for k in range(nu):
            if rotdof[k]:
                mr = max(mr, abs(d2[k]))
            else:
                mt = max(mt, abs(d2[k]))
        lam = 1.0
        if mt > opt[OPT_MAXSTEP]:
            lam = opt[OPT_MAXSTEP] / mt
        if mr * lam > opt[OPT_MAXROT]:
            lam = opt[OPT_MAXROT] / mr
        apply_step(d2, lam, nu, pf, pi, bf, bi)
    return False, res, res2


@njit(cache=True, error_model="numpy")
def network_solve(lf, li, pf, pi, bf, bi, rotdof, nu, xc, opt, lw, r, rho, fp, Q, K, A, piv, Kc, Y, want):
    """Equilibrium of the free DOFs at the coupled values ``xc`` and the condensed stiffness.

    Parameters
    ----------
    lf, li, pf, pi, bf, bi : ndarray
        Line, point and body tables (module constants); the free point positions, body poses and line
        warm starts in them are the start and are updated in place.
    rotdof : ndarray of bool, shape (nz,)
        Which DOFs are rotations.
    nu : int
        Number of free DOFs.
    xc : ndarray, shape (nz - nu,)
        Coupled DOF values [m, rad].
    opt : ndarray
        Options (``OPT_*``).
    lw, r, rho, fp, Q, K, A, piv
        Work arrays: line work (nL, LW_SIZE), point positions, arms and forces (nP, 3), loads (nz,),
        stiffness (nz, nz), LU factors (nu, nu) and pivots (nu,).
    Kc : ndarray, shape (nc, nc)
        Output (when ``want``): condensed stiffness of the coupled DOFs [N/m, N/rad, N m/rad].
    Y : ndarray, shape (nu, nc)
        Output (when ``want``): ``K_uu^-1 K_uc``; the free DOFs move by ``-Y dc``.
    want : bool
        Compute ``Kc`` and ``Y``.

    Returns
    -------
    status : int
        ``NET_OK``, ``NET_NOT_CONVERGED``, ``NET_SINGULAR`` (the free DOFs have no stiffness in some
        direction at the solution) or ``NET_LINE_FAILED``.
    iterations : int
    info : int
        The failed line's index (``NET_LINE_FAILED``), else -1.
    residual : float
        Final scaled residual [N].
    """
    nz = Q.shape[0]
    nc = nz - nu
    set_coupled(xc, nu, pf, pi, bf, bi)
    ftol = opt[OPT_FTOL]
    lscale = opt[OPT_LSCALE]
    maxit = int(opt[OPT_MAXIT])
    bad = assemble(lf, li, pf, pi, bf, bi, lw, r, rho, fp, Q, K)
    if bad >= 0:
        return NET_LINE_FAILED, 0, bad, np.inf
    it = 0
    res, res2 = _merit(Q, nu, rotdof, lscale)
    status = NET_OK
    if nu > 0:
        dz = np.empty(nu)
        pf0 = pf.copy()
        bf0 = bf.copy()
        lf0 = lf.copy()
        status = NET_NOT_CONVERGED
        while it < maxit:
            if res <= ftol:
                status = NET_OK
                break
            it += 1
            A[:, :] = K[:nu, :nu]
            ok = lu_factor(A, piv)
            mu = 0.0
            big = 0.0
            for i in range(nu):
                big = max(big, abs(K[i, i]))
            while not ok and mu < big:  # Levenberg-Marquardt regularisation of a singular Jacobian
                mu = 1e-8 * big if mu == 0.0 else 10.0 * mu
                A[:, :] = K[:nu, :nu]
                for i in range(nu):
                    A[i, i] += mu
                ok = lu_factor(A, piv)
            if not ok:
                status = NET_SINGULAR
                break
            dz[:] = Q[:nu]
            lu_solve(A, piv, dz)
            lam = 1.0
            mt = 0.0
            mr = 0.0
            for k in range(nu):
                if rotdof[k]:
                    mr = max(mr, abs(dz[k]))
                else:
                    mt = max(mt, abs(dz[k]))
            if mt > opt[OPT_MAXSTEP]:
                lam = opt[OPT_MAXSTEP] / mt
            if mr * lam > opt[OPT_MAXROT]:
                lam = opt[OPT_MAXROT] / mr
            small = mt * lam <= 1e-13 * lscale and mr * lam <= 1e-13
            pf0[:, :] = pf
            bf0[:, :] = bf
            lf0[:, :] = lf
            for k in range(nu):
                dz[k] *= lam
            accepted, res, res2 = _watchdog(dz, res, res2, nu, lf, li, pf, pi, bf, bi, rotdof, opt, lw, r, rho, fp,
                                            Q, K, A, piv)
            if not accepted:
                pf[:, :] = pf0
                bf[:, :] = bf0
                lf[:, :] = lf0
            lam = 0.5
            for _ in range(0 if accepted else 30):
                apply_step(dz, lam, nu, pf, pi, bf, bi)
                bad = assemble(lf, li, pf, pi, bf, bi, lw, r, rho, fp, Q, K)
                if bad < 0:
                    rn, rn2 = _merit(Q, nu, rotdof, lscale)
                    if rn2 < res2 or rn <= ftol:
                        res = rn
                        res2 = rn2
                        accepted = True
                        break
                pf[:, :] = pf0
                bf[:, :] = bf0
                lf[:, :] = lf0
                lam *= 0.5
            if not accepted:
                bad = assemble(lf, li, pf, pi, bf, bi, lw, r, rho, fp, Q, K)
                if bad >= 0:
                    return NET_LINE_FAILED, it, bad, res
                # no descent left: converged if the step or the residual is at round-off level
                status = NET_OK if small or res <= _FLOOR * ftol else NET_NOT_CONVERGED
                break
        if status == NET_NOT_CONVERGED and res <= ftol:
            status = NET_OK
    if not want or status != NET_OK:
        return status, it, -1, res
    # condensed stiffness: Kc = K_cc - K_cu K_uu^-1 K_uc
    for i in range(nc):
        for j in range(nc):
            Kc[i, j] = K[nu + i, nu + j]
    if nu > 0:
        A[:, :] = K[:nu, :nu]
        if not lu_factor(A, piv):
            return NET_SINGULAR, it, -1, res
        col = np.empty(nu)
        for j in range(nc):
            for i in range(nu):
                col[i] = K[i, nu + j]
            lu_solve(A, piv, col)
            for i in range(nu):
                Y[i, j] = col[i]
        for i in range(nc):
            for j in range(nc):
                acc = 0.0
                for k in range(nu):
                    acc += K[nu + i, k] * Y[k, j]
                Kc[i, j] -= acc
    return status, it, -1, res


@njit(cache=True, error_model="numpy")
def tension_gradients(li, pi, bi, lw, rho, nu, Y, G):
    """Gradients of the end tensions with respect to the coupled DOFs, through the free ones.

    ``G`` (nL, 2, nc) [N/m, N/rad] is filled with ``dT/dc = G_c - G_u Y`` (``Y`` from
    :func:`network_solve`).
    """
    nL = li.shape[0]
    nc = G.shape[2]
    nz = nu + nc
    g = np.zeros(nz)
    E = np.zeros((3, 6))
    idx = np.zeros(6, dtype=np.int64)
    for ln in range(nL):
        for e in range(2):
            g[:] = 0.0
            for end in range(2):  # dT/dr_A = -dT/dd, dT/dr_B = +dT/dd
                sgn = -1.0 if end == 0 else 1.0
                n = _emap(li[ln, end], pi, bi, rho, E, idx)
                for j in range(n):
                    if idx[j] < 0:
                        continue
                    acc = 0.0
                    for i in range(3):
                        acc += E[i, j] * lw[ln, LW_DT + 3 * e + i]
                    g[idx[j]] += sgn * acc
            for j in range(nc):
                acc = g[nu + j]
                for k in range(nu):
                    acc -= g[k] * Y[k, j]
                G[ln, e, j] = acc
