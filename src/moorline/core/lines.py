"""Line kernels: segment tension and damping, node loads (weight, buoyancy, Morison drag and fluid
inertia, seabed contact and friction), node mass and acceleration.

Equations of the spec (shared/spec, sections 3.1-3.9 and 3.12). Kernels read node kinematics
from ``W.r``, ``W.v`` (end nodes already copied from their attachments) and write every result
into the :class:`~moorline.core.layout.Work` arrays.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .seabed import seabed_force

_EPS = 1e-12


@njit(cache=True, error_model="numpy")
def table_interp(x, y, start, n, v):
    """Piecewise-linear interpolation in ``x[start:start+n]``, clamped at both ends."""
    if v <= x[start]:
        return y[start]
    last = start + n - 1
    if v >= x[last]:
        return y[last]
    lo = start
    hi = last
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if x[mid] <= v:
            lo = mid
        else:
            hi = mid
    f = (v - x[lo]) / (x[hi] - x[lo])
    return y[lo] + f * (y[hi] - y[lo])


@njit(cache=True, error_model="numpy")
def segment_wet_fraction(r, a, b, zeta_a, zeta_b, d):
    """Submerged fraction of the segment between nodes ``a`` and ``b`` of ``r`` (spec 3.6)."""
    zs = 0.5 * (zeta_a + zeta_b)
    za = r[a, 2] - zs
    zb = r[b, 2] - zs
    if za <= 0.0 and zb < 0.0:
        return 1.0
    if za > 0.0 and zb > 0.0:
        return 0.0
    if za == -zb:
        return 0.5
    # the segment pierces the surface: widen it by d/2 normal to its axis in the vertical plane
    sx = r[b, 0] - r[a, 0]
    sy = r[b, 1] - r[a, 1]
    sz = r[b, 2] - r[a, 2]
    # n parallel to s x (z x s) = z |s|^2 - s (s . z)
    ss = sx * sx + sy * sy + sz * sz
    nx = -sx * sz
    ny = -sy * sz
    nz = ss - sz * sz
    nn = math.sqrt(nx * nx + ny * ny + nz * nz)
    nzu = nz / nn if nn > 0.0 else 0.0
    if za < zb:
        zlow = za - 0.5 * d * nzu
        zup = zb + 0.5 * d * nzu
    else:
        zlow = zb - 0.5 * d * nzu
        zup = za + 0.5 * d * nzu
    return -zlow / (-zlow + zup)


@njit(cache=True, error_model="numpy")
def line_forces(li, L, E, B, W, cd_scale):
    """Evaluate every load of line ``li`` and the accelerations of its internal nodes.

    Parameters
    ----------
    li : int
        Line index.
    L, E, B, W : LineArrays, EnvArrays, Seabed, Work
    cd_scale : float
        Drag multiplier (1, or CdScaleIC during dynamic relaxation).
    """
    n0 = L.node_ptr[li]
    N = L.node_ptr[li + 1] - n0 - 1
    s0 = L.seg_ptr[li]
    d = L.d[li]
    A = L.A[li]
    w = L.w[li]
    rho = E.rho
    g = E.g
    Cd = L.Cd[li] * cd_scale
    CdAx = L.CdAx[li] * cd_scale
    Ca = L.Ca[li]
    CaAx = L.CaAx[li]
    ea0 = L.ea_tab[li, 0]
    ean = L.ea_tab[li, 1]
    ba0 = L.ba_tab[li, 0]
    ban = L.ba_tab[li, 1]

    # arrays bound once per call: reading them from the NamedTuple inside the loops costs a
    # reference-count update per access
    seg_l0 = L.seg_l0
    seg_EA = L.seg_EA
    seg_BA = L.seg_BA
    tab_x = L.tab_x
    tab_y = L.tab_y
    r = W.r
    v = W.v
    w_U = W.U
    w_Ud = W.Ud
    w_zeta = W.zeta
    w_T = W.T
    w_Td = W.Td
    w_seg_len = W.seg_len
    w_seg_ldot = W.seg_ldot
    w_seg_F = W.seg_F
    w_q = W.q
    w_F = W.F
    w_Fhyd = W.Fhyd
    w_Fbed = W.Fbed
    w_W = W.W
    w_mass = W.mass
    w_acc = W.acc
    w_kurv = W.kurv

    # ---- segments: length, direction, strain, tension, damping, submergence
    for k in range(N):
        s = s0 + k
        a = n0 + k
        b = a + 1
        dx = r[b, 0] - r[a, 0]
        dy = r[b, 1] - r[a, 1]
        dz = r[b, 2] - r[a, 2]
        ls = math.sqrt(dx * dx + dy * dy + dz * dz)
        if ls > 0.0:
            ex = dx / ls
            ey = dy / ls
            ez = dz / ls
        else:
            ex = 0.0
            ey = 0.0
            ez = 0.0
        ldot = ex * (v[b, 0] - v[a, 0]) + ey * (v[b, 1] - v[a, 1]) + ez * (v[b, 2] - v[a, 2])
        l0 = seg_l0[s]
        strain = ls / l0 - 1.0
        if strain > 0.0:
            if ean > 0:
                Tm = table_interp(tab_x, tab_y, ea0, ean, strain)
            else:
                Tm = seg_EA[s] * strain
        else:
            Tm = 0.0
        rate = ldot / l0
        if ban > 0:
            if tab_x[ba0] < 0.0:
                Dm = table_interp(tab_x, tab_y, ba0, ban, rate)
            else:
                Dm = table_interp(tab_x, tab_y, ba0, ban, abs(rate))
                if rate < 0.0:
                    Dm = -Dm
        else:
            Dm = seg_BA[s] * rate
        w_T[s, 0] = Tm * ex
        w_T[s, 1] = Tm * ey
        w_T[s, 2] = Tm * ez
        w_Td[s, 0] = Dm * ex
        w_Td[s, 1] = Dm * ey
        w_Td[s, 2] = Dm * ez
        w_seg_len[s] = ls
        w_seg_ldot[s] = ldot
        w_seg_F[s] = segment_wet_fraction(r, a, b, w_zeta[a], w_zeta[b], d)

    # ---- nodes
    for i in range(N + 1):
        n = n0 + i
        # tangent
        if i == 0:
            ia = n
            ib = n + 1
        elif i == N:
            ia = n - 1
            ib = n
        else:
            ia = n - 1
            ib = n + 1
        qx = r[ib, 0] - r[ia, 0]
        qy = r[ib, 1] - r[ia, 1]
        qz = r[ib, 2] - r[ia, 2]
        qn = math.sqrt(qx * qx + qy * qy + qz * qz)
        if qn > 0.0:
            qx /= qn
            qy /= qn
            qz /= qn
        w_q[n, 0] = qx
        w_q[n, 1] = qy
        w_q[n, 2] = qz

        # lengths: unstretched nodal length and submerged nodal length
        lam = 0.0
        lamw = 0.0
        if i > 0:
            lL = seg_l0[s0 + i - 1]
            lam += 0.5 * lL
            lamw += 0.5 * lL * w_seg_F[s0 + i - 1]
        if i < N:
            lR = seg_l0[s0 + i]
            lam += 0.5 * lR
            lamw += 0.5 * lR * w_seg_F[s0 + i]
        m = w * lam
        vol = A * lamw

        # internal forces
        fx = 0.0
        fy = 0.0
        fz = 0.0
        if i < N:
            s = s0 + i
            fx += w_T[s, 0] + w_Td[s, 0]
            fy += w_T[s, 1] + w_Td[s, 1]
            fz += w_T[s, 2] + w_Td[s, 2]
        if i > 0:
            s = s0 + i - 1
            fx -= w_T[s, 0] + w_Td[s, 0]
            fy -= w_T[s, 1] + w_Td[s, 1]
            fz -= w_T[s, 2] + w_Td[s, 2]

        # weight and buoyancy
        wz = -g * (m - rho * vol)
        w_W[n, 0] = 0.0
        w_W[n, 1] = 0.0
        w_W[n, 2] = wz

        # Morison drag on the relative velocity, split along the tangent
        ux = w_U[n, 0] - v[n, 0]
        uy = w_U[n, 1] - v[n, 1]
        uz = w_U[n, 2] - v[n, 2]
        uq = ux * qx + uy * qy + uz * qz
        uqx = uq * qx
        uqy = uq * qy
        uqz = uq * qz
        upx = ux - uqx
        upy = uy - uqy
        upz = uz - uqz
        upm = math.sqrt(upx * upx + upy * upy + upz * upz)
        cp = 0.5 * rho * Cd * d * lamw * upm
        cq = 0.5 * rho * CdAx * math.pi * d * lamw * abs(uq)
        # fluid inertia (Froude-Krylov + added mass of the fluid acceleration)
        aq = w_Ud[n, 0] * qx + w_Ud[n, 1] * qy + w_Ud[n, 2] * qz
        ip = rho * (1.0 + Ca) * vol
        iq = rho * (1.0 + CaAx) * vol
        hx = cp * upx + cq * uqx + ip * (w_Ud[n, 0] - aq * qx) + iq * aq * qx
        hy = cp * upy + cq * uqy + ip * (w_Ud[n, 1] - aq * qy) + iq * aq * qy
        hz = cp * upz + cq * uqz + ip * (w_Ud[n, 2] - aq * qz) + iq * aq * qz
        w_Fhyd[n, 0] = hx
        w_Fhyd[n, 1] = hy
        w_Fhyd[n, 2] = hz

        # seabed contact and friction
        bx, by, bz = seabed_force(E, B, n, r[n, 0], r[n, 1], r[n, 2], v[n, 0], v[n, 1], v[n, 2], qx, qy, qz, d,
                                  lam)
        w_Fbed[n, 0] = bx
        w_Fbed[n, 1] = by
        w_Fbed[n, 2] = bz

        fx += hx + bx
        fy += hy + by
        fz += wz + hz + bz
        w_F[n, 0] = fx
        w_F[n, 1] = fy
        w_F[n, 2] = fz

        ma = rho * vol * Ca
        mq = rho * vol * CaAx
        w_mass[n, 0] = m
        w_mass[n, 1] = ma
        w_mass[n, 2] = mq
        if 0 < i < N:
            # closed-form inverse of m I + ma (I - q q^T) + mq q q^T
            fq = fx * qx + fy * qy + fz * qz
            ip = 1.0 / (m + ma)
            iq = 1.0 / (m + mq)
            w_acc[n, 0] = (fx - fq * qx) * ip + fq * qx * iq
            w_acc[n, 1] = (fy - fq * qy) * ip + fq * qy * iq
            w_acc[n, 2] = (fz - fq * qz) * ip + fq * qz * iq
        else:
            w_acc[n, 0] = 0.0
            w_acc[n, 1] = 0.0
            w_acc[n, 2] = 0.0

    # ---- geometric curvature at internal nodes (spec 3.10); zero at pinned ends
    w_kurv[n0] = 0.0
    w_kurv[n0 + N] = 0.0
    for i in range(1, N):
        sa = s0 + i - 1
        sb = s0 + i
        la = w_seg_len[sa]
        lb = w_seg_len[sb]
        if la <= 0.0 or lb <= 0.0:
            w_kurv[n0 + i] = 0.0
            continue
        n = n0 + i
        c = ((r[n, 0] - r[n - 1, 0]) * (r[n + 1, 0] - r[n, 0]) + (r[n, 1] - r[n - 1, 1]) * (r[n + 1, 1] - r[n, 1])
             + (r[n, 2] - r[n - 1, 2]) * (r[n + 1, 2] - r[n, 2])) / (la * lb)
        if c >= 1.0 - 2.220446049250313e-16:
            w_kurv[n] = 0.0
        else:
            w_kurv[n] = 4.0 / (la + lb) * math.sqrt(0.5 * (1.0 - c))


@njit(cache=True, error_model="numpy")
def add_end_mass(M, p, m, ma, mq, q, n):
    """Add the mass matrix m I + ma (I - q q^T) + mq q q^T of a line end node (tangent ``q[n]``)
    to point ``p``."""
    for a in range(3):
        for b in range(3):
            qq = q[n, a] * q[n, b]
            val = (mq - ma) * qq
            if a == b:
                val += m + ma
            M[p, a, b] += val


@njit(cache=True, error_model="numpy")
def solve3(M, p, f, out):
    """Solve the 3x3 system M[p] x = f[p] (Cramer's rule) into ``out[p]``; False if singular."""
    a = M[p, 0, 0]
    b = M[p, 0, 1]
    c = M[p, 0, 2]
    d = M[p, 1, 0]
    e = M[p, 1, 1]
    ff = M[p, 1, 2]
    g = M[p, 2, 0]
    h = M[p, 2, 1]
    k = M[p, 2, 2]
    co0 = e * k - ff * h
    co1 = ff * g - d * k
    co2 = d * h - e * g
    det = a * co0 + b * co1 + c * co2
    if det == 0.0 or not np.isfinite(det):
        out[p, 0] = np.nan
        out[p, 1] = np.nan
        out[p, 2] = np.nan
        return False
    inv = 1.0 / det
    f0 = f[p, 0]
    f1 = f[p, 1]
    f2 = f[p, 2]
    out[p, 0] = (co0 * f0 + (c * h - b * k) * f1 + (b * ff - c * e) * f2) * inv
    out[p, 1] = (co1 * f0 + (a * k - c * g) * f1 + (c * d - a * ff) * f2) * inv
    out[p, 2] = (co2 * f0 + (b * g - a * h) * f1 + (a * e - b * d) * f2) * inv
    return True
