"""Line kernels: segment tension and damping, node loads (weight, buoyancy, Morison drag and fluid
inertia, seabed contact and friction), node mass and acceleration.

Equations of the spec (shared/spec, sections 3.1-3.9 and 3.12). Kernels read node kinematics
from ``W.r``, ``W.v`` (end nodes already copied from their attachments) and write every result
into the :class:`~moorline.core.layout.Work` arrays.
"""

from __future__ import annotations

import math

import numpy as np

from .features import BENDING, LINE_STATES, STICKSLIP, either, when
from .jit import derivative_kernel, kernel, vector_kernel
from .layout import ATT_ROD_A, ATT_ROD_B
from .linestates import VIS_ELASTIC, segment_axial
from .numerics import bracket, unit3
from .seabed import FRIC_STICKSLIP, seabed_at, seabed_force, seabed_force_stickslip

_EPS = 1e-12


@derivative_kernel
def table_interp(x, y, start, n, v):
    """Piecewise-linear interpolation in ``x[start:start+n]``, clamped at both ends."""
    if v <= x[start]:
        return y[start]
    last = start + n - 1
    if v >= x[last]:
        return y[last]
    lo = bracket(x, start, last, v)
    f = (v - x[lo]) / (x[lo + 1] - x[lo])
    return y[lo] + f * (y[lo + 1] - y[lo])


@derivative_kernel
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


@kernel
def _no_states(ls):
    """Stand-in for :func:`segment_axial` in kernels compiled without line states (unreachable)."""
    return 0.0 * ls, 0.0 * ls


@kernel(inline="always")
def line_forces(L, E, B, W, cd_scale):
    """Evaluate every load of every line and the accelerations of the internal line nodes.

    Parameters
    ----------
    L, E, B, W : LineArrays, EnvArrays, Seabed, Work
    cd_scale : float
        Drag multiplier (1, or CdScaleIC during dynamic relaxation).

    All lines are done in one call, in three passes (segments, bending, nodes), so the arrays
    are bound to locals once per evaluation: every binding of an array from a NamedTuple costs a
    pair of atomic reference-count updates, which per line and per evaluation was a third of the
    cost of a small system.
    """
    rho = E.rho
    g = E.g
    seg_l0 = L.seg_l0
    seg_EA = L.seg_EA
    seg_BA = L.seg_BA
    tab_x = L.tab_x
    tab_y = L.tab_y
    node_ptr = L.node_ptr
    seg_ptr = L.seg_ptr
    Ld = L.d
    LA = L.A
    Lw = L.w
    LCd = L.Cd
    LCdAx = L.CdAx
    LCa = L.Ca
    LCaAx = L.CaAx
    ea_tab = L.ea_tab
    ba_tab = L.ba_tab
    clamped = L.clamped
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
    seg_e = W.seg_e
    Fbend = W.Fbend
    gx = B.gx
    gy = B.gy
    gz = B.gz
    anchor = B.anchor
    slip = B.slip
    ctl = B.ctl
    flat = gx.size == 0
    stickslip = E.fric == FRIC_STICKSLIP
    stick_commit = stickslip and ctl[0] != 0 and ctl[1] != 0
    nl = node_ptr.size - 1

    # ---- segments: length, direction, strain, tension, damping, submergence
    vis = L.vis
    calc = L.calc
    vec = L.vec
    for li in range(nl):
        if calc[li] == 0:
            continue  # local-time-step Euler keeps this line's loads of its last update
        n0 = node_ptr[li]
        N = node_ptr[li + 1] - n0 - 1
        s0 = seg_ptr[li]
        d = Ld[li]
        ea0 = ea_tab[li, 0]
        ean = ea_tab[li, 1]
        ba0 = ba_tab[li, 0]
        ban = ba_tab[li, 1]
        visco = vis[li] != VIS_ELASTIC
        if vec[li] != 0:
            # a long line with linear EA and BA: the vectorised segment loop
            _segments_v(n0, N, s0, r, v, seg_l0, seg_EA, seg_BA, w_T, w_Td, seg_e, w_seg_len, w_seg_ldot)
            for k in range(N):
                a = n0 + k
                w_seg_F[s0 + k] = segment_wet_fraction(r, a, a + 1, w_zeta[a], w_zeta[a + 1], d)
            continue
        for k in range(N):
            s = s0 + k
            a = n0 + k
            b = a + 1
            ex, ey, ez, ls = unit3(r[b, 0] - r[a, 0], r[b, 1] - r[a, 1], r[b, 2] - r[a, 2])
            ldot = ex * (v[b, 0] - v[a, 0]) + ey * (v[b, 1] - v[a, 1]) + ez * (v[b, 2] - v[a, 2])
            l0 = seg_l0[s]
            strain = ls / l0 - 1.0
            if visco:
                # viscoelastic and Syrope ropes: the static branch's stretch state (core.linestates);
                # compiled only for systems with line states (such a line always has them)
                Tm, Dm = either(W, LINE_STATES, segment_axial, (L, W, li, s, ls, ldot, l0), _no_states, (ls,))
            elif strain > 0.0:
                if ean > 0:
                    Tm = table_interp(tab_x, tab_y, ea0, ean, strain)
                else:
                    Tm = seg_EA[s] * strain
            else:
                Tm = 0.0
            rate = ldot / l0
            if visco:
                pass
            elif ban > 0:
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
            seg_e[s, 0] = ex
            seg_e[s, 1] = ey
            seg_e[s, 2] = ez
            w_seg_F[s] = segment_wet_fraction(r, a, b, w_zeta[a], w_zeta[b], d)

    # ---- curvature and bending forces (spec 3.10)
    when(W, BENDING, line_bending, (L, W))

    # ---- nodes
    for li in range(nl):
        if calc[li] == 0:
            continue
        n0 = node_ptr[li]
        N = node_ptr[li + 1] - n0 - 1
        s0 = seg_ptr[li]
        d = Ld[li]
        A = LA[li]
        w = Lw[li]
        Cd = LCd[li] * cd_scale
        CdAx = LCdAx[li] * cd_scale
        Ca = LCa[li]
        CaAx = LCaAx[li]
        clamped_a = clamped[li, 0] != 0
        clamped_b = clamped[li, 1] != 0
        if vec[li] != 0:
            _long_line_nodes(L, E, B, W, li, n0, N, s0, d, A, w, Cd, CdAx, Ca, CaAx, clamped_a, clamped_b)
            continue
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
            qx, qy, qz, _ = unit3(r[ib, 0] - r[ia, 0], r[ib, 1] - r[ia, 1], r[ib, 2] - r[ia, 2])
            if (i == 0 and clamped_a) or (i == N and clamped_b):
                qx, qy, qz = end_tangent(L, W, li, 0 if i == 0 else 1)
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
            if flat:
                zb = -E.depth
                bnx = 0.0
                bny = 0.0
                bnz = 1.0
            else:
                zb, bnx, bny, bnz, outside = seabed_at(gx, gy, gz, E.depth, r[n, 0], r[n, 1])
                if outside:
                    ctl[2] += 1
            if r[n, 2] < zb:
                if stickslip:  # (compiled only for systems with stick-slip friction: core.features)
                    bx, by, bz = either(W, STICKSLIP, seabed_force_stickslip,
                                        (E, zb, bnx, bny, bnz, anchor, slip, ctl, n, r[n, 0], r[n, 1], r[n, 2],
                                         v[n, 0], v[n, 1], v[n, 2], qx, qy, qz, d, lam), seabed_force,
                                        (E, zb, bnx, bny, bnz, r[n, 0], r[n, 1], r[n, 2], v[n, 0], v[n, 1], v[n, 2],
                                         qx, qy, qz, d, lam))
                else:
                    bx, by, bz = seabed_force(E, zb, bnx, bny, bnz, r[n, 0], r[n, 1], r[n, 2], v[n, 0], v[n, 1],
                                              v[n, 2], qx, qy, qz, d, lam)
            else:
                bx = 0.0
                by = 0.0
                bz = 0.0
                if stick_commit:
                    # off the seabed: the friction spring of the node is relaxed at its position
                    anchor[n, 0] = r[n, 0]
                    anchor[n, 1] = r[n, 1]
                    anchor[n, 2] = r[n, 2]
                    slip[n, 0] = 0.0
                    slip[n, 1] = 0.0
            w_Fbed[n, 0] = bx
            w_Fbed[n, 1] = by
            w_Fbed[n, 2] = bz

            fx += hx + bx + Fbend[n, 0]
            fy += hy + by + Fbend[n, 1]
            fz += wz + hz + bz + Fbend[n, 2]
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


@kernel(inline="always")
def end_tangent(L, W, li, j):
    """Direction a clamped end ``j`` (0: end A, 1: end B) of line ``li`` takes from its rod: the
    cable leaves the rod straight, so end A on rod end B and end B on rod end A follow the rod axis
    (A to B), the other two pairings its opposite (spec 3.10)."""
    r = L.end_idx[li, j]
    kind = L.end_kind[li, j]
    sgn = 1.0 if (j == 0 and kind == ATT_ROD_B) or (j == 1 and kind == ATT_ROD_A) else -1.0
    return sgn * W.rodq[r, 0], sgn * W.rodq[r, 1], sgn * W.rodq[r, 2]


@derivative_kernel
def _kappa(lam, ax, ay, az, bx, by, bz):
    """Curvature (4/lam) sin(theta/2) between unit vectors a and b over length lam, and the unit
    bending axis a x b (zero when a and b are parallel).

    sin(theta/2) is taken as half the chord |a - b|, not as MoorDyn's sqrt((1 - a.b)/2): the
    same in exact arithmetic, but 1 - a.b cancels to round-off for a nearly straight line, whose
    curvature then came out with an absolute error of about (4/lam) sqrt(eps/2) = 4e-8/lam 1/m
    and a jump to zero below theta = 2e-8 rad. On a cable lying straight on the seabed that was
    a force noise of EI 4e-8 / (lam l) at every node, which held Newton statics of the lazy-wave
    cable on 0.5 m segments at 2e-5 m/s^2 above its 1e-5 tolerance; the chord is exact to
    round-off relative to theta."""
    if lam <= 0.0:
        return 0.0, 0.0, 0.0, 0.0
    dx = ax - bx
    dy = ay - by
    dz = az - bz
    chord2 = dx * dx + dy * dy + dz * dz
    if chord2 == 0.0:
        return 0.0, 0.0, 0.0, 0.0
    kap = 2.0 / lam * math.sqrt(chord2)
    # the zero vector when a and b are anti-parallel: no defined bending plane
    px, py, pz, _ = unit3(ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx)
    return kap, px, py, pz


@derivative_kernel
def line_bending(L, W):
    """Curvature at every node of every line and, for lines with bending stiffness, the bending
    forces: at each bent node a self-equilibrated triple of forces on the node and its two
    neighbours (spec 3.10); at an end clamped to a rod, the couple of the end segment against the
    rod axis. Needs the segment lengths and unit vectors of the current evaluation."""
    node_ptr = L.node_ptr
    seg_ptr = L.seg_ptr
    EI = L.EI
    ei_tab = L.ei_tab
    clamped = L.clamped
    tab_x = L.tab_x
    tab_y = L.tab_y
    seg_e = W.seg_e
    seg_len = W.seg_len
    kurv = W.kurv
    Fb = W.Fbend
    end_moment = W.end_moment
    for li in range(node_ptr.size - 1):
        if L.calc[li] == 0:
            continue
        n0 = node_ptr[li]
        N = node_ptr[li + 1] - n0 - 1
        s0 = seg_ptr[li]
        EIc = EI[li]
        et0 = ei_tab[li, 0]
        etn = ei_tab[li, 1]
        stiff = EIc > 0.0 or etn > 0
        for i in range(N + 1):
            Fb[n0 + i, 0] = 0.0
            Fb[n0 + i, 1] = 0.0
            Fb[n0 + i, 2] = 0.0
        for j in range(2):
            for c in range(3):
                end_moment[li, j, c] = 0.0
        if not stiff:
            # no bending forces: the curvature is only an output, computed on demand
            # (moorline.system.LineView.node_curvatures), not in every evaluation
            continue
        for i in range(N + 1):
            kurv[n0 + i] = 0.0
        for i in range(1, N):
            a = s0 + i - 1
            b = s0 + i
            la = seg_len[a]
            lb = seg_len[b]
            kap, px, py, pz = _kappa(la + lb, seg_e[a, 0], seg_e[a, 1], seg_e[a, 2], seg_e[b, 0], seg_e[b, 1],
                                     seg_e[b, 2])
            n = n0 + i
            kurv[n] = kap
            if kap == 0.0:
                continue
            m = kap * EIc if etn == 0 else table_interp(tab_x, tab_y, et0, etn, kap)
            # f_{i-1} = (M / l_a) e_a x p,  f_{i+1} = (M / l_b) e_b x p,  f_i = -(f_{i-1} + f_{i+1})
            ca = m / la
            cb = m / lb
            fax = ca * (seg_e[a, 1] * pz - seg_e[a, 2] * py)
            fay = ca * (seg_e[a, 2] * px - seg_e[a, 0] * pz)
            faz = ca * (seg_e[a, 0] * py - seg_e[a, 1] * px)
            fbx = cb * (seg_e[b, 1] * pz - seg_e[b, 2] * py)
            fby = cb * (seg_e[b, 2] * px - seg_e[b, 0] * pz)
            fbz = cb * (seg_e[b, 0] * py - seg_e[b, 1] * px)
            Fb[n - 1, 0] += fax
            Fb[n - 1, 1] += fay
            Fb[n - 1, 2] += faz
            Fb[n + 1, 0] += fbx
            Fb[n + 1, 1] += fby
            Fb[n + 1, 2] += fbz
            Fb[n, 0] -= fax + fbx
            Fb[n, 1] -= fay + fby
            Fb[n, 2] -= faz + fbz
        # clamped ends: the rod axis acts as a segment reflected about the end node
        for j in range(2):
            if clamped[li, j] == 0:
                continue
            qx, qy, qz = end_tangent(L, W, li, j)
            if j == 0:
                s = s0
                kap, px, py, pz = _kappa(seg_len[s], qx, qy, qz, seg_e[s, 0], seg_e[s, 1], seg_e[s, 2])
                nend = n0
                nin = n0 + 1
                sgn = 1.0
            else:
                s = s0 + N - 1
                kap, px, py, pz = _kappa(seg_len[s], seg_e[s, 0], seg_e[s, 1], seg_e[s, 2], qx, qy, qz)
                nend = n0 + N
                nin = n0 + N - 1
                sgn = -1.0
            kurv[nend] = kap
            if kap == 0.0:
                continue
            m = kap * EIc if etn == 0 else table_interp(tab_x, tab_y, et0, etn, kap)
            cm = m / seg_len[s]
            fx = cm * (seg_e[s, 1] * pz - seg_e[s, 2] * py)
            fy = cm * (seg_e[s, 2] * px - seg_e[s, 0] * pz)
            fz = cm * (seg_e[s, 0] * py - seg_e[s, 1] * px)
            Fb[nin, 0] += fx
            Fb[nin, 1] += fy
            Fb[nin, 2] += fz
            Fb[nend, 0] -= fx
            Fb[nend, 1] -= fy
            Fb[nend, 2] -= fz
            end_moment[li, j, 0] = sgn * m * px
            end_moment[li, j, 1] = sgn * m * py
            end_moment[li, j, 2] = sgn * m * pz


@derivative_kernel
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


@derivative_kernel
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


# ----------------------------------------------------------------------------- long lines, vectorised
# (which lines: LineArrays.vec, set by the layout from core.layout.VECTOR_MIN_NODES; four doubles
# per vector whatever the processor offers, core.jit.VECTOR_WIDTH)
# The loops below index with unsigned integers: numba then emits no wrap-around for negative
# indices, which keeps LLVM from vectorising ("unsafe indirect dependence"). Each loop starts by
# checking that its (n, 3) arrays have 3 columns: past that check LLVM knows the stride of every
# access and vectorises the (x, y, z) rows as interleaved groups; without it the loops stay scalar.
U1 = np.uint64(1)
_A2 = "float64[:, ::1]"
_A1 = "float64[::1]"


@kernel(inline="always")
def node_loads(fx, fy, fz, lam, lamw, qx, qy, qz, vx, vy, vz, ux, uy, uz, ax, ay, az, rho, g, w, A, d, Cd, CdAx,
               Ca, CaAx):
    """Loads on a line node but the seabed's and the bending force: the internal force (fx, fy,
    fz) of its segments, weight and buoyancy, Morison drag on the velocity relative to the water
    (u, a: water velocity and acceleration) split along the tangent q, fluid inertia (Froude-Krylov
    and the added mass of the fluid acceleration). ``lam``, ``lamw``: unstretched and submerged
    nodal length. Returns the net force, the hydrodynamic force, the weight (z) and the masses m,
    ma (transverse added), mq (tangential added). Scalars only and no branches, so that a loop
    over nodes that calls it vectorises. (The scalar pass of :func:`line_forces` writes the same
    formulas inline: routed through this function and :func:`_seabed_node` it ran 10 % slower on
    WD0050_Chain, 4.07-4.16 against 3.67-3.72 us per step.)"""
    m = w * lam
    vol = A * lamw
    wz = -g * (m - rho * vol)
    ux = ux - vx
    uy = uy - vy
    uz = uz - vz
    uq = ux * qx + uy * qy + uz * qz
    uqx = uq * qx
    uqy = uq * qy
    uqz = uq * qz
    upx = ux - uqx
    upy = uy - uqy
    upz = uz - uqz
    upm = math.sqrt(upx * upx + upy * upy + upz * upz)
    cp = 0.5 * rho * Cd * d * lamw * upm
    cq = 0.5 * rho * CdAx * math.pi * d * lamw * math.fabs(uq)
    aq = ax * qx + ay * qy + az * qz
    ip = rho * (1.0 + Ca) * vol
    iq = rho * (1.0 + CaAx) * vol
    hx = cp * upx + cq * uqx + ip * (ax - aq * qx) + iq * aq * qx
    hy = cp * upy + cq * uqy + ip * (ay - aq * qy) + iq * aq * qy
    hz = cp * upz + cq * uqz + ip * (az - aq * qz) + iq * aq * qz
    return fx + hx, fy + hy, fz + wz + hz, hx, hy, hz, wz, m, rho * vol * Ca, rho * vol * CaAx


@kernel(inline="always")
def node_acceleration(fx, fy, fz, qx, qy, qz, m, ma, mq):
    """Acceleration of a line node under net force f: the closed-form inverse of
    m I + ma (I - q q^T) + mq q q^T."""
    fq = fx * qx + fy * qy + fz * qz
    ip = 1.0 / (m + ma)
    iq = 1.0 / (m + mq)
    return (fx - fq * qx) * ip + fq * qx * iq, (fy - fq * qy) * ip + fq * qy * iq, (fz - fq * qz) * ip + fq * qz * iq


@kernel(inline="always")
def _store_node(n, fx, fy, fz, hx, hy, hz, wz, m, ma, mq, F, H, W, M):
    """Net force, hydrodynamic force, weight and masses of node n into the Work arrays."""
    F[n, 0] = fx
    F[n, 1] = fy
    F[n, 2] = fz
    H[n, 0] = hx
    H[n, 1] = hy
    H[n, 2] = hz
    W[n, 0] = 0.0
    W[n, 1] = 0.0
    W[n, 2] = wz
    M[n, 0] = m
    M[n, 1] = ma
    M[n, 2] = mq


@kernel(inline="always")
def _seabed_node(E, W, gx, gy, gz, anchor, slip, ctl, flat, stickslip, stick_commit, n, rx, ry, rz, vx, vy, vz, qx,
                 qy, qz, d, lam):
    """Seabed contact and friction force on line node n (position r, velocity v, tangent q,
    nodal length lam); off the seabed, with stick-slip friction, its friction spring relaxed."""
    if flat:
        zb = -E.depth
        bnx = 0.0
        bny = 0.0
        bnz = 1.0
    else:
        zb, bnx, bny, bnz, outside = seabed_at(gx, gy, gz, E.depth, rx, ry)
        if outside:
            ctl[2] += 1
    if rz < zb:
        if stickslip:  # (compiled only for systems with stick-slip friction: core.features)
            return either(W, STICKSLIP, seabed_force_stickslip,
                          (E, zb, bnx, bny, bnz, anchor, slip, ctl, n, rx, ry, rz, vx, vy, vz, qx, qy, qz, d, lam),
                          seabed_force, (E, zb, bnx, bny, bnz, rx, ry, rz, vx, vy, vz, qx, qy, qz, d, lam))
        return seabed_force(E, zb, bnx, bny, bnz, rx, ry, rz, vx, vy, vz, qx, qy, qz, d, lam)
    if stick_commit:
        # off the seabed: the friction spring of the node is relaxed at its position
        anchor[n, 0] = rx
        anchor[n, 1] = ry
        anchor[n, 2] = rz
        slip[n, 0] = 0.0
        slip[n, 1] = 0.0
    return 0.0, 0.0, 0.0


@vector_kernel(f"void(int64, int64, int64, {_A2}, {_A2}, {_A1}, {_A1}, {_A1}, {_A2}, {_A2}, {_A2}, {_A1}, {_A1})")
def _segments_v(n0, N, s0, r, v, seg_l0, seg_EA, seg_BA, T, Td, e, seg_len, seg_ldot):
    """Length, direction, stretch rate, tension (zero when slack) and damping force of the N
    segments of a line with linear EA and BA (first node n0, first segment s0)."""
    if r.shape[1] != 3 or v.shape[1] != 3 or T.shape[1] != 3 or Td.shape[1] != 3 or e.shape[1] != 3:
        raise ValueError("line kernel: node and segment arrays must be (n, 3)")
    a0 = np.uint64(n0)
    j0 = np.uint64(s0)
    for k in range(np.uint64(N)):
        a = a0 + k
        b = a + U1
        j = j0 + k
        dx = r[b, 0] - r[a, 0]
        dy = r[b, 1] - r[a, 1]
        dz = r[b, 2] - r[a, 2]
        ls = math.sqrt(dx * dx + dy * dy + dz * dz)
        # (as unit3: a segment of zero length has the zero direction)
        inv = 1.0 / ls if ls > 0.0 else 0.0
        cx = dx * inv
        cy = dy * inv
        cz = dz * inv
        ldot = cx * (v[b, 0] - v[a, 0]) + cy * (v[b, 1] - v[a, 1]) + cz * (v[b, 2] - v[a, 2])
        l0 = seg_l0[j]
        strain = ls / l0 - 1.0
        Tm = seg_EA[j] * strain if strain > 0.0 else 0.0
        Dm = seg_BA[j] * (ldot / l0)
        T[j, 0] = Tm * cx
        T[j, 1] = Tm * cy
        T[j, 2] = Tm * cz
        Td[j, 0] = Dm * cx
        Td[j, 1] = Dm * cy
        Td[j, 2] = Dm * cz
        seg_len[j] = ls
        seg_ldot[j] = ldot
        e[j, 0] = cx
        e[j, 1] = cy
        e[j, 2] = cz


@vector_kernel(f"void(int64, int64, {_A2}, {_A2})")
def _tangents_v(n0, nN, r, q):
    """Tangents of the interior nodes n0 < n < nN of a line: along the chord of their neighbours."""
    if r.shape[1] != 3 or q.shape[1] != 3:
        raise ValueError("line kernel: node arrays must be (n, 3)")
    i0 = np.uint64(n0) + U1
    for k in range(np.uint64(nN - n0 - 1)):
        n = i0 + k
        a = n - U1
        b = n + U1
        dx = r[b, 0] - r[a, 0]
        dy = r[b, 1] - r[a, 1]
        dz = r[b, 2] - r[a, 2]
        ln = math.sqrt(dx * dx + dy * dy + dz * dz)
        inv = 1.0 / ln if ln > 0.0 else 0.0
        q[n, 0] = dx * inv
        q[n, 1] = dy * inv
        q[n, 2] = dz * inv


@vector_kernel(f"void(int64, int64, int64, {_A1}, {_A1}, {_A2}, {_A2}, {_A2}, {_A2}, {_A2}, {_A2}, {_A2}, {_A2}, "
               f"{_A2}, {_A2}, {_A2}, float64, float64, float64, float64, float64, float64, float64, float64, float64)")
def _loads_v(n0, nN, s0, seg_l0, seg_F, T, Td, q, v, U, Ud, Fb, F, H, W, M, rho, g, w, A, d, Cd, CdAx, Ca, CaAx):
    """Every load but the seabed's on the interior nodes n0 < n < nN of a line whose first segment
    is s0 (:func:`node_loads`), the bending force Fb included, and their masses."""
    if (T.shape[1] != 3 or Td.shape[1] != 3 or q.shape[1] != 3 or v.shape[1] != 3 or U.shape[1] != 3
            or Ud.shape[1] != 3 or Fb.shape[1] != 3 or F.shape[1] != 3 or H.shape[1] != 3 or W.shape[1] != 3
            or M.shape[1] != 3):
        raise ValueError("line kernel: node and segment arrays must be (n, 3)")
    i0 = np.uint64(n0) + U1
    a0 = np.uint64(s0)
    for k in range(np.uint64(nN - n0 - 1)):
        n = i0 + k
        a = a0 + k  # the segment before node n
        b = a + U1  # and after it
        lL = seg_l0[a]
        lR = seg_l0[b]
        fx, fy, fz, hx, hy, hz, wz, m, ma, mq = node_loads(
            (T[b, 0] + Td[b, 0]) - (T[a, 0] + Td[a, 0]), (T[b, 1] + Td[b, 1]) - (T[a, 1] + Td[a, 1]),
            (T[b, 2] + Td[b, 2]) - (T[a, 2] + Td[a, 2]), 0.5 * lL + 0.5 * lR, 0.5 * lL * seg_F[a] + 0.5 * lR * seg_F[b],
            q[n, 0], q[n, 1], q[n, 2], v[n, 0], v[n, 1], v[n, 2], U[n, 0], U[n, 1], U[n, 2], Ud[n, 0], Ud[n, 1],
            Ud[n, 2], rho, g, w, A, d, Cd, CdAx, Ca, CaAx)
        F[n, 0] = fx + Fb[n, 0]
        F[n, 1] = fy + Fb[n, 1]
        F[n, 2] = fz + Fb[n, 2]
        H[n, 0] = hx
        H[n, 1] = hy
        H[n, 2] = hz
        # (the weight's x and y stay the zeros the Work arrays are made with: two zero stores
        # per node here become a memset call, and a loop with a call is not vectorised)
        W[n, 2] = wz
        M[n, 0] = m
        M[n, 1] = ma
        M[n, 2] = mq


@vector_kernel(f"void(int64, int64, {_A2}, {_A2}, {_A2}, {_A2})")
def _accelerations_v(n0, nN, q, F, M, A):
    """Accelerations of the interior nodes n0 < n < nN of a line (:func:`node_acceleration`)."""
    if q.shape[1] != 3 or F.shape[1] != 3 or M.shape[1] != 3 or A.shape[1] != 3:
        raise ValueError("line kernel: node arrays must be (n, 3)")
    i0 = np.uint64(n0) + U1
    for k in range(np.uint64(nN - n0 - 1)):
        n = i0 + k
        A[n, 0], A[n, 1], A[n, 2] = node_acceleration(F[n, 0], F[n, 1], F[n, 2], q[n, 0], q[n, 1], q[n, 2], M[n, 0],
                                                      M[n, 1], M[n, 2])


@kernel(inline="always")
def _long_line_nodes(L, E, B, W, li, n0, N, s0, d, A, w, Cd, CdAx, Ca, CaAx, clamped_a, clamped_b):
    """The node pass of :func:`line_forces` for a long line with linear EA and BA: the interior
    nodes in vectorised loops (tangents; every load but the seabed's; accelerations), the two ends
    and the seabed contact, which branch, in scalar loops."""
    rho = E.rho
    g = E.g
    seg_l0 = L.seg_l0
    r = W.r
    v = W.v
    w_U = W.U
    w_Ud = W.Ud
    w_T = W.T
    w_Td = W.Td
    w_seg_F = W.seg_F
    w_q = W.q
    w_F = W.F
    w_Fhyd = W.Fhyd
    w_Fbed = W.Fbed
    w_W = W.W
    w_mass = W.mass
    w_acc = W.acc
    Fbend = W.Fbend
    gx = B.gx
    gy = B.gy
    gz = B.gz
    anchor = B.anchor
    slip = B.slip
    ctl = B.ctl
    flat = gx.size == 0
    stickslip = E.fric == FRIC_STICKSLIP
    stick_commit = stickslip and ctl[0] != 0 and ctl[1] != 0
    nN = n0 + N
    for j in range(2):
        n = n0 if j == 0 else nN
        if (j == 0 and clamped_a) or (j == 1 and clamped_b):
            qx, qy, qz = end_tangent(L, W, li, j)
        elif j == 0:
            qx, qy, qz, _ = unit3(r[n + 1, 0] - r[n, 0], r[n + 1, 1] - r[n, 1], r[n + 1, 2] - r[n, 2])
        else:
            qx, qy, qz, _ = unit3(r[n, 0] - r[n - 1, 0], r[n, 1] - r[n - 1, 1], r[n, 2] - r[n - 1, 2])
        w_q[n, 0] = qx
        w_q[n, 1] = qy
        w_q[n, 2] = qz
        s = s0 if j == 0 else s0 + N - 1
        sg = 1.0 if j == 0 else -1.0
        l0 = seg_l0[s]
        fx, fy, fz, hx, hy, hz, wz, m, ma, mq = node_loads(
            sg * (w_T[s, 0] + w_Td[s, 0]), sg * (w_T[s, 1] + w_Td[s, 1]), sg * (w_T[s, 2] + w_Td[s, 2]),
            0.5 * l0, 0.5 * l0 * w_seg_F[s], qx, qy, qz, v[n, 0], v[n, 1], v[n, 2], w_U[n, 0], w_U[n, 1],
            w_U[n, 2], w_Ud[n, 0], w_Ud[n, 1], w_Ud[n, 2], rho, g, w, A, d, Cd, CdAx, Ca, CaAx)
        _store_node(n, fx + Fbend[n, 0], fy + Fbend[n, 1], fz + Fbend[n, 2], hx, hy, hz, wz, m, ma, mq, w_F,
                    w_Fhyd, w_W, w_mass)
        w_acc[n, 0] = 0.0
        w_acc[n, 1] = 0.0
        w_acc[n, 2] = 0.0
    _tangents_v(n0, nN, r, w_q)
    _loads_v(n0, nN, s0, seg_l0, w_seg_F, w_T, w_Td, w_q, v, w_U, w_Ud, Fbend, w_F, w_Fhyd, w_W, w_mass, rho, g,
             w, A, d, Cd, CdAx, Ca, CaAx)
    for i in range(N + 1):
        n = n0 + i
        lam = 0.0
        if i > 0:
            lam += 0.5 * seg_l0[s0 + i - 1]
        if i < N:
            lam += 0.5 * seg_l0[s0 + i]
        bx, by, bz = _seabed_node(E, W, gx, gy, gz, anchor, slip, ctl, flat, stickslip, stick_commit, n,
                                  r[n, 0], r[n, 1], r[n, 2], v[n, 0], v[n, 1], v[n, 2], w_q[n, 0], w_q[n, 1],
                                  w_q[n, 2], d, lam)
        w_Fbed[n, 0] = bx
        w_Fbed[n, 1] = by
        w_Fbed[n, 2] = bz
        w_F[n, 0] += bx
        w_F[n, 1] += by
        w_F[n, 2] += bz
    _accelerations_v(n0, nN, w_q, w_F, w_mass, w_acc)
