"""Rods and bodies: kinematics, loads, 6x6 mass assembly and equations of motion (spec 3.13-3.15).

Orientation is a unit quaternion (w, x, y, z) integrated as four plain numbers and normalised when
it is turned into a rotation matrix, so there is no gimbal lock; angular velocities are in global
axes and the quaternion rate is 0.5 (0, omega) (x) Q.

6x6 quantities are [force; moment] about a reference point (end A of a rod, the reference point of
a body) in global axes, and mass matrices act on [acceleration of that point; angular
acceleration]. A child (node, point, rod) whose own 6x6 mass M_c acts about a point offset by r
from its parent's reference point adds T^T M_c T to the parent, T = [[I, -S(r)], [0, I]] with
S(r) a = r x a (the rigid offset of MoorDyn's ``translateMass``).
"""

from __future__ import annotations

import math

from .jit import derivative_kernel
from .layout import (
    ATT_POINT,
    ATT_ROD_A,
    BODY_COUPLED,
    BODY_COUPLED_PINNED,
    BODY_FIXED,
    BODY_FREE,
    INERTIA_MOORDYN,
    P_BODY,
    ROD_BODY,
    ROD_BODY_PINNED,
    ROD_COUPLED,
    ROD_COUPLED_PINNED,
    ROD_FREE,
)
from .numerics import (
    add_translated3,
    add_translated6,
    cross3,
    euler_R,
    mattvec3,
    matvec3,
    quat_rate,
    quat_to_R,
    solve_dense,
)
from .seabed import _ramp, seabed_at


@derivative_kernel
def _pinned_rotation(M6, F6, acc, M3, rhs3, x3, dense):
    """Angular acceleration of an object whose reference point moves with the imposed
    acceleration ``acc[:3]``: alpha = M_rr^-1 (F_rot - M_rt a), written into ``acc[3:]``.
    M3, rhs3, x3, dense are scratch."""
    for a in range(3):
        s = F6[3 + a]
        for c in range(3):
            s -= M6[3 + a, c] * acc[c]
            M3[a, c] = M6[3 + a, 3 + c]
        rhs3[a] = s
    solve_dense(M3, rhs3, x3, 3, dense)
    for a in range(3):
        acc[3 + a] = x3[a]


# ---------------------------------------------------------------------------------- kinematics


@derivative_kernel
def body_kinematics(y, R, W):
    """Pose and velocity of every body from its kind: fixed (deck pose), coupled (the coupling
    input, Euler-angle rates taken as the angular velocity as MoorDyn does), coupled-pinned
    (translation from the input, rotation from the state) and free (state)."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    xc = W.xc
    vc = W.vc
    for i in range(R.body_kind.size):
        k = R.body_kind[i]
        Rm = W.bR[i]
        if k == BODY_FIXED:
            quat_to_R(R.body_Q0[i], 0, Rm)
            for c in range(3):
                W.br[i, c] = R.body_r0[i, c]
                W.bv[i, c] = 0.0
                W.bw[i, c] = 0.0
        elif k == BODY_COUPLED:
            o = R.body_cpl[i]
            euler_R(xc[o + 3], xc[o + 4], xc[o + 5], Rm)
            for c in range(3):
                W.br[i, c] = xc[o + c]
                W.bv[i, c] = vc[o + c]
                W.bw[i, c] = vc[o + 3 + c]
        else:
            j = R.body_blk[i]
            oq = 3 * n3 + 7 * j
            ou = uoff + 3 * n3 + 6 * j
            quat_to_R(y, oq + 3, Rm)
            if k == BODY_COUPLED_PINNED:
                o = R.body_cpl[i]
                for c in range(3):
                    W.br[i, c] = xc[o + c]
                    W.bv[i, c] = vc[o + c]
            else:
                for c in range(3):
                    W.br[i, c] = y[oq + c]
                    W.bv[i, c] = y[ou + c]
            for c in range(3):
                W.bw[i, c] = y[ou + 3 + c]


@derivative_kernel
def _on_body(b, rel_x, rel_y, rel_z, bR, br, bv, bw):
    """Global position and velocity of a point given in body ``b``'s axes."""
    gx, gy, gz = matvec3(bR[b], rel_x, rel_y, rel_z)
    cx, cy, cz = cross3(bw[b, 0], bw[b, 1], bw[b, 2], gx, gy, gz)
    return br[b, 0] + gx, br[b, 1] + gy, br[b, 2] + gz, bv[b, 0] + cx, bv[b, 1] + cy, bv[b, 2] + cz


@derivative_kernel
def rod_kinematics(y, R, W):
    """End-A position and velocity, axis and angular velocity of every rod (spec 3.14.4); the
    axis of a zero-length rod that takes it from its cables is set later by
    :func:`zero_length_axes`."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    xc = W.xc
    vc = W.vc
    Rm = W.m33[2]
    for k in range(R.rod_kind.size):
        kind = R.rod_kind[k]
        b = R.rod_body[k]
        j = R.rod_blk[k]
        ax = R.rod_qrel[k, 0]
        ay = R.rod_qrel[k, 1]
        az = R.rod_qrel[k, 2]
        wx = 0.0
        wy = 0.0
        wz = 0.0
        # end A
        if kind == ROD_BODY or kind == ROD_BODY_PINNED:
            px, py, pz, vx, vy, vz = _on_body(b, R.rod_rA0[k, 0], R.rod_rA0[k, 1], R.rod_rA0[k, 2], W.bR, W.br, W.bv,
                                                  W.bw)
        elif kind == ROD_COUPLED or kind == ROD_COUPLED_PINNED:
            o = R.rod_cpl[k]
            px, py, pz = xc[o], xc[o + 1], xc[o + 2]
            vx, vy, vz = vc[o], vc[o + 1], vc[o + 2]
        elif kind == ROD_FREE:
            if j >= 0:
                oq = 3 * n3 + 7 * j
                ou = uoff + 3 * n3 + 6 * j
                px, py, pz = y[oq], y[oq + 1], y[oq + 2]
                vx, vy, vz = y[ou], y[ou + 1], y[ou + 2]
            else:
                o = 3 * R.rod_row[k]
                px, py, pz = y[o], y[o + 1], y[o + 2]
                vx, vy, vz = y[3 * n3 + 7 * n6 + o], y[3 * n3 + 7 * n6 + o + 1], y[3 * n3 + 7 * n6 + o + 2]
        else:  # fixed or pinned to the ground
            px, py, pz = R.rod_rA0[k, 0], R.rod_rA0[k, 1], R.rod_rA0[k, 2]
            vx, vy, vz = 0.0, 0.0, 0.0
        # axis and angular velocity
        if j >= 0:
            oq = 3 * n3 + 7 * j
            ou = uoff + 3 * n3 + 6 * j
            quat_to_R(y, oq + 3, Rm)
            ax, ay, az = matvec3(Rm, R.rod_qref[k, 0], R.rod_qref[k, 1], R.rod_qref[k, 2])
            wx, wy, wz = y[ou + 3], y[ou + 4], y[ou + 5]
        elif kind == ROD_BODY or kind == ROD_BODY_PINNED:
            ax, ay, az = matvec3(W.bR[b], ax, ay, az)
            wx, wy, wz = W.bw[b, 0], W.bw[b, 1], W.bw[b, 2]
        elif kind == ROD_COUPLED:
            o = R.rod_cpl[k]
            euler_R(xc[o + 3], xc[o + 4], xc[o + 5], Rm)
            ax, ay, az = matvec3(Rm, R.rod_qref[k, 0], R.rod_qref[k, 1], R.rod_qref[k, 2])
            wx, wy, wz = vc[o + 3], vc[o + 4], vc[o + 5]
        W.rodr[k, 0, 0] = px
        W.rodr[k, 0, 1] = py
        W.rodr[k, 0, 2] = pz
        W.rodv[k, 0, 0] = vx
        W.rodv[k, 0, 1] = vy
        W.rodv[k, 0, 2] = vz
        W.rodq[k, 0] = ax
        W.rodq[k, 1] = ay
        W.rodq[k, 2] = az
        W.rodw[k, 0] = wx
        W.rodw[k, 1] = wy
        W.rodw[k, 2] = wz


@derivative_kernel
def zero_length_axes(R, L, W):
    """Axis of every zero-length rod from its cables (spec 3.14.4, MoorDyn's semantics): the
    normalised sum over attached lines of sigma EI e_end / l_end, sigma = +1 for a line end B on rod
    end A or a line end A on rod end B, -1 otherwise. Whatever the rod is attached to (fixed, on a
    body, coupled, free), so a single cable on it is in effect pinned there."""
    for k in range(R.rod_kind.size):
        if R.rod_N[k] != 0:
            continue
        sx = 0.0
        sy = 0.0
        sz = 0.0
        for li in range(L.node_ptr.size - 1):
            for j in range(2):
                if L.end_kind[li, j] == ATT_POINT or L.end_idx[li, j] != k:
                    continue
                n0 = L.node_ptr[li]
                n1 = L.node_ptr[li + 1] - 1
                if j == 0:
                    ex = W.r[n0 + 1, 0] - W.rodr[k, 0, 0]
                    ey = W.r[n0 + 1, 1] - W.rodr[k, 0, 1]
                    ez = W.r[n0 + 1, 2] - W.rodr[k, 0, 2]
                else:
                    ex = W.rodr[k, 0, 0] - W.r[n1 - 1, 0]
                    ey = W.rodr[k, 0, 1] - W.r[n1 - 1, 1]
                    ez = W.rodr[k, 0, 2] - W.r[n1 - 1, 2]
                le2 = ex * ex + ey * ey + ez * ez
                if le2 <= 0.0:
                    continue
                at_a = L.end_kind[li, j] == ATT_ROD_A
                sig = 1.0 if (j == 1 and at_a) or (j == 0 and not at_a) else -1.0
                ei = L.EI[li]
                if L.ei_tab[li, 1] > 0:  # a moment-curvature table: its first slope
                    s0 = L.ei_tab[li, 0]
                    ei = (L.tab_y[s0 + 1] - L.tab_y[s0]) / (L.tab_x[s0 + 1] - L.tab_x[s0])
                if ei <= 0.0:
                    ei = 1e-12  # lines without EI still orient the rod when nothing else does
                # e / l = (vector / l) / l = vector / l^2
                f = sig * ei / le2
                sx += f * ex
                sy += f * ey
                sz += f * ez
        n = math.sqrt(sx * sx + sy * sy + sz * sz)
        if n > 0.0:
            W.rodq[k, 0] = sx / n
            W.rodq[k, 1] = sy / n
            W.rodq[k, 2] = sz / n


@derivative_kernel
def rod_nodes(R, W):
    """End B and the node positions and velocities of every rod from end A, axis and omega."""
    rodq = W.rodq
    rodw = W.rodw
    rodr = W.rodr
    rodv = W.rodv
    rn_r = W.rn_r
    rn_v = W.rn_v
    rod_N = R.rod_N
    rod_L = R.rod_L
    rod_node_ptr = R.rod_node_ptr
    for k in range(R.rod_kind.size):
        N = rod_N[k]
        Lr = rod_L[k]
        n0 = rod_node_ptr[k]
        qx = rodq[k, 0]
        qy = rodq[k, 1]
        qz = rodq[k, 2]
        wx = rodw[k, 0]
        wy = rodw[k, 1]
        wz = rodw[k, 2]
        for i in range(N + 1):
            s = Lr * i / N if N > 0 else 0.0
            ox, oy, oz = cross3(wx, wy, wz, s * qx, s * qy, s * qz)
            n = n0 + i
            rn_r[n, 0] = rodr[k, 0, 0] + s * qx
            rn_r[n, 1] = rodr[k, 0, 1] + s * qy
            rn_r[n, 2] = rodr[k, 0, 2] + s * qz
            rn_v[n, 0] = rodv[k, 0, 0] + ox
            rn_v[n, 1] = rodv[k, 0, 1] + oy
            rn_v[n, 2] = rodv[k, 0, 2] + oz
        nb = n0 + N
        for c in range(3):
            rodr[k, 1, c] = rn_r[nb, c]
            rodv[k, 1, c] = rn_v[nb, c]


@derivative_kernel
def body_point_kinematics(P, W):
    """Position and velocity of the points fixed to bodies."""
    for p in range(P.kind.size):
        if P.kind[p] != P_BODY:
            continue
        px, py, pz, vx, vy, vz = _on_body(P.body[p], P.r0[p, 0], P.r0[p, 1], P.r0[p, 2], W.bR, W.br, W.bv,
                                                  W.bw)
        W.pr[p, 0] = px
        W.pr[p, 1] = py
        W.pr[p, 2] = pz
        W.pv[p, 0] = vx
        W.pv[p, 1] = vy
        W.pv[p, 2] = vz
        W.pa[p, 0] = 0.0
        W.pa[p, 1] = 0.0
        W.pa[p, 2] = 0.0


# ---------------------------------------------------------------------------------- loads


@derivative_kernel
def _wet_section(zi, zeta, d, A, sinphi):
    """Wet area of a rod's cross-section at a node at height ``zi`` (a circle of diameter ``d``
    and area ``A``, tilted by phi from vertical), the height of its centroid, and the lowest
    height of the section. Returns (Aw, zc, zlo)."""
    hs = 0.5 * d * sinphi
    zhi = zi + hs
    zlo = zi - hs
    if zlo > zeta:
        Aw = 0.0
        zc = 0.0
    elif zhi < zeta:
        Aw = A
        zc = zi
    elif sinphi < 0.001:
        Aw = 0.5 * A  # MoorDyn-C writes 0.5 (m^2) here; half the section is what it means
        zc = 0.0
    else:
        G = (zi - zeta) / sinphi
        al = math.acos(min(1.0, max(-1.0, 2.0 * G / d)))
        den = 2.0 * al - math.sin(2.0 * al)
        Aw = d * d / 8.0 * den
        zc = zi - 2.0 / 3.0 * d * math.sin(al) ** 3 / den if den > 1e-12 else zi
    return Aw, zc, zlo


@derivative_kernel
def _axis_dyad(Mq, qx, qy, qz):
    """Mq = q q^T."""
    Mq[0, 0] = qx * qx
    Mq[0, 1] = qx * qy
    Mq[0, 2] = qx * qz
    Mq[1, 0] = qy * qx
    Mq[1, 1] = qy * qy
    Mq[1, 2] = qy * qz
    Mq[2, 0] = qz * qx
    Mq[2, 1] = qz * qy
    Mq[2, 2] = qz * qz


@derivative_kernel
def _rod_end_effects(F, Mi, Mq, i, N, vof, A, rho, g, zc, d, sinphi, sb, cb, uq, aq, CdEnd, CaEnd, Vh, pdn, qx, qy,
                     qz, mx, my):
    """End effects of a rod at its node ``i`` of 0..N (end A, s = +1, at node 0; end B, s = -1, at
    node N; both at the one node of a zero-length rod), for a submerged section: the buoyancy of
    the end face and its moment, axial drag and added mass of the end, the wave's dynamic pressure
    on it. Added into the node's load rows ``F`` and mass ``Mi``; returns the moment (mx, my)."""
    for e in range(2):
        if (e == 0 and i != 0) or (e == 1 and i != N):
            continue
        s = 1.0 if e == 0 else -1.0
        fb = -s * vof * A * rho * g * zc
        F[1, 0] += fb * qx
        F[1, 1] += fb * qy
        F[1, 2] += fb * qz
        mb = -s * vof * (math.pi * d ** 4 / 64.0) * rho * g * sinphi
        mx += mb * sb
        my -= mb * cb
        uqm = abs(uq)
        cdq = 0.5 * vof * A * rho * CdEnd * uqm * uq
        F[3, 0] += cdq * qx
        F[3, 1] += cdq * qy
        F[3, 2] += cdq * qz
        caq = vof * rho * CaEnd * Vh * aq
        F[5, 0] += caq * qx
        F[5, 1] += caq * qy
        F[5, 2] += caq * qz
        pd = s * vof * A * pdn
        F[6, 0] += pd * qx
        F[6, 1] += pd * qy
        F[6, 2] += pd * qz
        mae = vof * rho * CaEnd * Vh
        for a in range(3):
            for c in range(3):
                Mi[a, c] += mae * Mq[a, c]
    return mx, my


@derivative_kernel
def _total_load(F):
    """Row 8 of a rod node's loads: the sum of rows 0-7."""
    for c in range(3):
        tot = 0.0
        for a in range(8):
            tot += F[a, c]
        F[8, c] = tot


@derivative_kernel
def rod_loads(R, E, B, W, cd_scale):
    """Node loads of every rod (spec 3.14.2, with end effects and partial submergence), the line
    end forces and masses at its end nodes, and the 6x6 sums about end A (spec 3.14.3) into
    ``W.rod6F`` and ``W.rod6M``."""
    rho = E.rho
    g = E.g
    rn_F = W.rn_F
    rn_vof = W.rn_vof
    rn_M = W.rn_M
    rn_r = W.rn_r
    rn_v = W.rn_v
    rn_U = W.rn_U
    rn_Ud = W.rn_Ud
    rn_zeta = W.rn_zeta
    rn_pd = W.rn_pd
    rodq = W.rodq
    rodr = W.rodr
    rodMext = W.rodMext
    rodF = W.rodF
    rodEM = W.rodEM
    rod6F = W.rod6F
    rod6M = W.rod6M
    rod_N = R.rod_N
    rod_L = R.rod_L
    rod_d = R.rod_d
    rod_w = R.rod_w
    rod_Cd = R.rod_Cd
    rod_Ca = R.rod_Ca
    rod_CdEnd = R.rod_CdEnd
    rod_CaEnd = R.rod_CaEnd
    rod_node_ptr = R.rod_node_ptr
    gx = B.gx
    gy = B.gy
    gz = B.gz
    Mq = W.m33[3]
    Ssc = W.m33[4]
    for k in range(R.rod_kind.size):
        N = rod_N[k]
        Lr = rod_L[k]
        d = rod_d[k]
        A = 0.25 * math.pi * d * d
        w = rod_w[k]
        Cd = rod_Cd[k] * cd_scale
        Ca = rod_Ca[k]
        CdEnd = rod_CdEnd[k] * cd_scale
        CaEnd = rod_CaEnd[k]
        n0 = rod_node_ptr[k]
        qx = rodq[k, 0]
        qy = rodq[k, 1]
        qz = rodq[k, 2]
        sinphi = math.sqrt(qx * qx + qy * qy)
        cosphi = qz
        if sinphi >= 1e-6:
            cb = qx / sinphi
            sb = qy / sinphi
        else:
            cb = 1.0
            sb = 0.0
        zeta = rn_zeta[n0 + N]
        zA = rodr[k, 0, 2]
        zB = rodr[k, 1, 2]
        if zA < zeta and zB < zeta:
            h0 = Lr
        elif zA < zeta:
            h0 = (zeta - zA) / qz
        elif zB < zeta:
            h0 = -(zeta - zA) / qz
        else:
            h0 = 0.0
        lseg = Lr / N if N > 0 else 0.0
        Vh = 2.0 / 3.0 * math.pi * (0.5 * d) ** 3
        mx = rodMext[k, 0]
        my = rodMext[k, 1]
        mz = rodMext[k, 2]
        if N == 0:
            # a zero-length rod: one node without length, mass or volume of its own (no weight,
            # buoyancy, drag, added mass or seabed contact along it), with both ends' effects;
            # the same arithmetic as the general path less its terms that are exactly zero
            n = n0
            zi = rn_r[n, 2]
            Aw, zc, zlo = _wet_section(zi, zeta, d, A, sinphi)
            vof = (1.0 if zi < zeta else 0.0) * cosphi * cosphi + (Aw / A) * sinphi * sinphi
            rn_vof[n] = vof
            F = rn_F[n]
            Mi = rn_M[n]
            for a in range(9):
                for c in range(3):
                    F[a, c] = 0.0
            for a in range(3):
                for c in range(3):
                    Mi[a, c] = 0.0
            _axis_dyad(Mq, qx, qy, qz)
            if zlo < zeta:
                uq = ((rn_U[n, 0] - rn_v[n, 0]) * qx + (rn_U[n, 1] - rn_v[n, 1]) * qy
                      + (rn_U[n, 2] - rn_v[n, 2]) * qz)
                aq = rn_Ud[n, 0] * qx + rn_Ud[n, 1] * qy + rn_Ud[n, 2] * qz
                mx, my = _rod_end_effects(F, Mi, Mq, 0, 0, vof, A, rho, g, zc, d, sinphi, sb, cb, uq, aq, CdEnd,
                                          CaEnd, Vh, rn_pd[n], qx, qy, qz, mx, my)
            _total_load(F)
        else:
            S = 0.0
            for i in range(N + 1):
                n = n0 + i
                dL = (0.5 * lseg if (i == 0 or i == N) else lseg) if N > 0 else 0.0
                mi = w * dL
                vi = A * dL
                zi = rn_r[n, 2]
                # axial wet fraction
                if dL > 0.0:
                    if h0 >= 0.0:
                        vof0 = 1.0 if S + dL <= h0 else ((h0 - S) / dL if S < h0 else 0.0)
                    else:
                        vof0 = 1.0 if S >= -h0 else ((S + dL + h0) / dL if S + dL > -h0 else 0.0)
                else:
                    vof0 = 1.0 if zi < zeta else 0.0
                S += dL
                Aw, zc, zlo = _wet_section(zi, zeta, d, A, sinphi)
                vof = vof0 * cosphi * cosphi + (Aw / A) * sinphi * sinphi
                rn_vof[n] = vof
                # relative flow, split along and across the axis
                ux = rn_U[n, 0] - rn_v[n, 0]
                uy = rn_U[n, 1] - rn_v[n, 1]
                uz = rn_U[n, 2] - rn_v[n, 2]
                uq = ux * qx + uy * qy + uz * qz
                upx = ux - uq * qx
                upy = uy - uq * qy
                upz = uz - uq * qz
                upm = math.sqrt(upx * upx + upy * upy + upz * upz)
                adx = rn_Ud[n, 0]
                ady = rn_Ud[n, 1]
                adz = rn_Ud[n, 2]
                aq = adx * qx + ady * qy + adz * qz
                apx = adx - aq * qx
                apy = ady - aq * qy
                apz = adz - aq * qz
                F = rn_F[n]
                for a in range(9):
                    for c in range(3):
                        F[a, c] = 0.0
                # weight and the transverse part of buoyancy
                F[0, 2] = -mi * g
                bb = -vof * vi * rho * g * sinphi
                F[1, 0] = bb * cb * cosphi
                F[1, 1] = bb * sb * cosphi
                F[1, 2] = -bb * sinphi
                cdp = vof * 0.5 * rho * Cd * d * dL * upm
                F[2, 0] = cdp * upx
                F[2, 1] = cdp * upy
                F[2, 2] = cdp * upz
                cap = vof * rho * (1.0 + Ca) * vi
                F[4, 0] = cap * apx
                F[4, 1] = cap * apy
                F[4, 2] = cap * apz
                # mass: m I + vof rho v Ca (I - q q^T)
                Mi = rn_M[n]
                ma = vof * rho * vi * Ca
                _axis_dyad(Mq, qx, qy, qz)
                for a in range(3):
                    for c in range(3):
                        Mi[a, c] = -ma * Mq[a, c]
                    Mi[a, a] += mi + ma
                # seabed: vertical contact only (spec 3.14.2)
                zb = seabed_at(gx, gy, gz, E.depth, rn_r[n, 0], rn_r[n, 1])[0]
                if zi < zb and dL > 0.0:
                    F[7, 2] = ((zb - zi) * E.kBot - rn_v[n, 2] * E.cBot * _ramp(zb - zi, E.bed_ramp)) * d * dL
                # end effects: end A (s = +1) at node 0, end B (s = -1) at node N
                if zlo < zeta and (i == 0 or i == N):
                    mx, my = _rod_end_effects(F, Mi, Mq, i, N, vof, A, rho, g, zc, d, sinphi, sb, cb, uq, aq, CdEnd,
                                              CaEnd, Vh, rn_pd[n], qx, qy, qz, mx, my)
                _total_load(F)
        if zA < zeta < zB:
            mw = (math.pi * d ** 4 / 16.0) * rho * g * sinphi * cosphi
            mx += mw * sb
            my -= mw * cb
        # the lines at the end nodes
        for e in range(2):
            n = n0 if e == 0 else n0 + N
            for c in range(3):
                rn_F[n, 8, c] += rodF[k, e, c]
                for a in range(3):
                    rn_M[n, c, a] += rodEM[2 * k + e, c, a]
        # 6x6 sums about end A
        F6 = rod6F[k]
        M6 = rod6M[k]
        for a in range(6):
            F6[a] = 0.0
            for c in range(6):
                M6[a, c] = 0.0
        for i in range(N + 1):
            n = n0 + i
            rx = rn_r[n, 0] - rodr[k, 0, 0]
            ry = rn_r[n, 1] - rodr[k, 0, 1]
            rz = rn_r[n, 2] - rodr[k, 0, 2]
            fx = rn_F[n, 8, 0]
            fy = rn_F[n, 8, 1]
            fz = rn_F[n, 8, 2]
            F6[0] += fx
            F6[1] += fy
            F6[2] += fz
            cx, cy, cz = cross3(rx, ry, rz, fx, fy, fz)
            F6[3] += cx
            F6[4] += cy
            F6[5] += cz
            add_translated3(M6, rn_M[n], rx, ry, rz, Ssc)
        F6[3] += mx
        F6[4] += my
        F6[5] += mz
        if N > 0:
            # rotational inertia beyond the lumped node masses: Ic across, Iax along the axis
            m = w * Lr
            Iax = 0.5 * m * (0.5 * d) ** 2
            Ic = m * (0.25 * (0.5 * d) ** 2 - Lr * Lr / (6.0 * N * N))
            for a in range(3):
                for c in range(3):
                    M6[3 + a, 3 + c] += (Iax - Ic) * Mq[a, c]
                M6[3 + a, 3 + a] += Ic


@derivative_kernel
def _centripetal_on_body(br, bw, b6F, b, Mc, cx_, cy_, cz_, moment):
    """Centripetal load on body b of a mass ``Mc`` (3x3) centred at c (global): force
    -Mc (omega x (omega x (c - r_b))) and, if ``moment``, its moment about the reference point
    (MoorDyn-C 2.7 applies the force alone: ``InertialLoads moordyn``)."""
    rx = cx_ - br[b, 0]
    ry = cy_ - br[b, 1]
    rz = cz_ - br[b, 2]
    wx = bw[b, 0]
    wy = bw[b, 1]
    wz = bw[b, 2]
    if wx == 0.0 and wy == 0.0 and wz == 0.0:
        return
    ox, oy, oz = cross3(wx, wy, wz, rx, ry, rz)
    ax, ay, az = cross3(wx, wy, wz, ox, oy, oz)
    fx = -(Mc[0, 0] * ax + Mc[0, 1] * ay + Mc[0, 2] * az)
    fy = -(Mc[1, 0] * ax + Mc[1, 1] * ay + Mc[1, 2] * az)
    fz = -(Mc[2, 0] * ax + Mc[2, 1] * ay + Mc[2, 2] * az)
    b6F[b, 0] += fx
    b6F[b, 1] += fy
    b6F[b, 2] += fz
    if moment:
        mx, my, mz = cross3(rx, ry, rz, fx, fy, fz)
        b6F[b, 3] += mx
        b6F[b, 4] += my
        b6F[b, 5] += mz


@derivative_kernel
def _add_child_to_body(br, b6F, b6M, b, F6, M6, point_only, ax, ay, az, S):
    """Add a child's force/moment ``F6`` and mass about its point a (global) to body b. With
    ``point_only`` F6[3:] is ignored and only the 3x3 block M6[:3, :3] is used (a point mass)."""
    rx = ax - br[b, 0]
    ry = ay - br[b, 1]
    rz = az - br[b, 2]
    mx, my, mz = cross3(rx, ry, rz, F6[0], F6[1], F6[2])
    b6F[b, 0] += F6[0]
    b6F[b, 1] += F6[1]
    b6F[b, 2] += F6[2]
    b6F[b, 3] += mx
    b6F[b, 4] += my
    b6F[b, 5] += mz
    if point_only == 0:
        b6F[b, 3] += F6[3]
        b6F[b, 4] += F6[4]
        b6F[b, 5] += F6[5]
    add_translated6(b6M[b], M6[:3, :3], M6[:3, 3:], M6[3:, :3], M6[3:, 3:], point_only, rx, ry, rz, S)


@derivative_kernel
def _rod_inertial(k, R, W, Fe):
    """Fe = rod k's F6 plus its velocity-dependent inertial loads about end A: the centripetal
    force -M_i omega x (omega x r_i) of every node (and its moment), and the gyroscopic moment
    -omega x (I_c omega) of the rotational inertia added beyond the lumped nodes (none with
    ``InertialLoads moordyn``: MoorDyn-C 2.7 leaves them out)."""
    for a in range(6):
        Fe[a] = W.rod6F[k, a]
    wx = W.rodw[k, 0]
    wy = W.rodw[k, 1]
    wz = W.rodw[k, 2]
    if (wx == 0.0 and wy == 0.0 and wz == 0.0) or R.inertia[0] == INERTIA_MOORDYN:
        return
    n0 = R.rod_node_ptr[k]
    N = R.rod_N[k]
    for i in range(N + 1):
        n = n0 + i
        rx = W.rn_r[n, 0] - W.rodr[k, 0, 0]
        ry = W.rn_r[n, 1] - W.rodr[k, 0, 1]
        rz = W.rn_r[n, 2] - W.rodr[k, 0, 2]
        ox, oy, oz = cross3(wx, wy, wz, rx, ry, rz)
        cx, cy, cz = cross3(wx, wy, wz, ox, oy, oz)
        Mi = W.rn_M[n]
        fx = -(Mi[0, 0] * cx + Mi[0, 1] * cy + Mi[0, 2] * cz)
        fy = -(Mi[1, 0] * cx + Mi[1, 1] * cy + Mi[1, 2] * cz)
        fz = -(Mi[2, 0] * cx + Mi[2, 1] * cy + Mi[2, 2] * cz)
        mx, my, mz = cross3(rx, ry, rz, fx, fy, fz)
        Fe[0] += fx
        Fe[1] += fy
        Fe[2] += fz
        Fe[3] += mx
        Fe[4] += my
        Fe[5] += mz
    if N > 0:
        Lr = R.rod_L[k]
        m = R.rod_w[k] * Lr
        d = R.rod_d[k]
        Iax = 0.5 * m * (0.5 * d) ** 2
        Ic = m * (0.25 * (0.5 * d) ** 2 - Lr * Lr / (6.0 * N * N))
        qx = W.rodq[k, 0]
        qy = W.rodq[k, 1]
        qz = W.rodq[k, 2]
        wq = wx * qx + wy * qy + wz * qz
        # I omega = Ic omega + (Iax - Ic) (q . omega) q
        ix = Ic * wx + (Iax - Ic) * wq * qx
        iy = Ic * wy + (Iax - Ic) * wq * qy
        iz = Ic * wz + (Iax - Ic) * wq * qz
        gx, gy, gz = cross3(wx, wy, wz, ix, iy, iz)
        Fe[3] -= gx
        Fe[4] -= gy
        Fe[5] -= gz


@derivative_kernel
def rigid_dynamics(y, dy, R, P, E, W):
    """After the line, point and rod loads: rod equations of motion (free, pinned) and what rods
    and points pass to their bodies, then each body's own loads and mass matrix (W.b6F, W.b6M);
    writes the derivatives of the rows and blocks of rods into ``dy``. The bodies move in
    :func:`body_motion` (after the floating-body loads are added)."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    nb = R.body_kind.size
    for i in range(nb):
        for a in range(6):
            W.b6F[i, a] = 0.0
            W.bacc[i, a] = 0.0
            for c in range(6):
                W.b6M[i, a, c] = 0.0
    M3 = W.m33[0]
    S = W.m33[1]
    rhs3 = W.v6[0]
    x3 = W.v6[1]
    Fe = W.v6[2]
    dense = W.dense
    # points on bodies
    for p in range(P.kind.size):
        if P.kind[p] != P_BODY:
            continue
        b = P.body[p]
        _centripetal_on_body(W.br, W.bw, W.b6F, b, W.pM[p], W.pr[p, 0], W.pr[p, 1], W.pr[p, 2],
                             R.inertia[0] != INERTIA_MOORDYN)
        _add_child_to_body(W.br, W.b6F, W.b6M, b, W.pF[p], W.pM[p], 1, W.pr[p, 0], W.pr[p, 1], W.pr[p, 2], S)
    # rods
    for k in range(R.rod_kind.size):
        kind = R.rod_kind[k]
        F6 = W.rod6F[k]
        M6 = W.rod6M[k]
        acc = W.rodacc[k]
        j = R.rod_blk[k]
        for a in range(6):
            acc[a] = 0.0
        if j >= 0:
            # a rod turning on its own: the velocity-dependent inertial loads join the forces
            # (MoorDyn-C leaves them out, spec 3.14.4; a spinning rod then drifts off its
            # centre-of-mass path, tests/verification/test_rods_bodies.py)
            _rod_inertial(k, R, W, Fe)
        if kind == ROD_FREE and j >= 0:
            solve_dense(M6, Fe, acc, 6, dense)
        elif kind == ROD_FREE:
            # zero-length free rod: 3 translational DOF
            for a in range(3):
                rhs3[a] = F6[a]
                for c in range(3):
                    M3[a, c] = M6[a, c]
            solve_dense(M3, rhs3, x3, 3, dense)
            for a in range(3):
                acc[a] = x3[a]
        elif j >= 0:
            # pinned: end A imposed (acceleration zero, or the coupling input for coupled-pinned)
            if kind == ROD_COUPLED_PINNED:
                o = R.rod_cpl[k]
                for a in range(3):
                    acc[a] = W.ac[o + a]
            _pinned_rotation(M6, Fe, acc, M3, rhs3, x3, dense)
        if kind == ROD_BODY or kind == ROD_BODY_PINNED:
            b = R.rod_body[k]
            n0 = R.rod_node_ptr[k]
            N = R.rod_N[k]
            # centripetal force of each node mass about the body
            for i in range(N + 1):
                n = n0 + i
                _centripetal_on_body(W.br, W.bw, W.b6F, b, W.rn_M[n], W.rn_r[n, 0], W.rn_r[n, 1], W.rn_r[n, 2],
                                     R.inertia[0] != INERTIA_MOORDYN)
            # the rod's loads and mass, about end A (MoorDyn passes a pinned rod's moment and
            # rotational mass as well, spec 3.14.5; kept for agreement)
            _add_child_to_body(W.br, W.b6F, W.b6M, b, F6, M6, 0, W.rodr[k, 0, 0], W.rodr[k, 0, 1], W.rodr[k, 0, 2], S)
        if kind == ROD_FREE and j < 0:
            o = uoff + 3 * R.rod_row[k]
            for a in range(3):
                dy[o + a] = acc[a]
        elif j >= 0:
            oq = 3 * n3 + 7 * j
            ou = uoff + 3 * n3 + 6 * j
            wx = y[ou + 3]
            wy = y[ou + 4]
            wz = y[ou + 5]
            free = kind == ROD_FREE
            for a in range(3):
                dy[oq + a] = y[ou + a] if free else 0.0
                dy[ou + a] = acc[a] if free else 0.0
                dy[ou + 3 + a] = acc[3 + a]
            quat_rate(y, oq + 3, wx, wy, wz, dy, oq + 3)
        if kind == ROD_COUPLED:
            o = R.rod_cpl[k]
            for a in range(6):
                s = 0.0
                for c in range(6):
                    s += M6[a, c] * W.ac[o + c]
                F6[a] -= s
        elif kind == ROD_COUPLED_PINNED:
            for a in range(3):
                s = 0.0
                for c in range(6):
                    s += M6[a, c] * acc[c]
                F6[a] -= s
                F6[3 + a] = 0.0
    # bodies: own loads, then their equations of motion
    for i in range(nb):
        kind = R.body_kind[i]
        Rm = W.bR[i]
        F6 = W.b6F[i]
        M6 = W.b6M[i]
        # own mass, rotated to global axes: every 3x3 block B -> R B R^T
        M0 = R.body_M0[i]
        for bi in range(2):
            for bj in range(2):
                for a in range(3):
                    for c in range(3):
                        s = 0.0
                        for e in range(3):
                            for f in range(3):
                                s += Rm[a, e] * M0[3 * bi + e, 3 * bj + f] * Rm[c, f]
                        M6[3 * bi + a, 3 * bj + c] += s
        m = R.body_m[i]
        cgx, cgy, cgz = matvec3(Rm, R.body_rCG[i, 0], R.body_rCG[i, 1], R.body_rCG[i, 2])
        fg = E.g * (E.rho * R.body_V[i] - m)
        wx = W.bw[i, 0]
        wy = W.bw[i, 1]
        wz = W.bw[i, 2]
        ox, oy, oz = cross3(wx, wy, wz, cgx, cgy, cgz)
        cx, cy, cz = cross3(wx, wy, wz, ox, oy, oz)
        if R.inertia[0] == INERTIA_MOORDYN:
            # MoorDyn-C 2.7: the centrifugal force of the CG offset with the body's own translational
            # mass in global axes, added mass included (R M0_tt R^T c)
            tx, ty, tz = mattvec3(Rm, cx, cy, cz)
            bx, by, bz = matvec3(M0, tx, ty, tz)  # M0's translational block (its top-left 3x3)
            cx, cy, cz = matvec3(Rm, bx, by, bz)
        else:
            # the rigid mass turns with the CG; the added mass acts at the reference point
            cx, cy, cz = m * cx, m * cy, m * cz
        F6[0] -= cx
        F6[1] -= cy
        F6[2] += fg - cz
        gx, gy, gz = cross3(cgx, cgy, cgz, 0.0, 0.0, fg)
        F6[3] += gx
        F6[4] += gy
        F6[5] += gz
        # drag on the body's translation and rotation, coefficients in body axes
        ux = W.bU[i, 0] - W.bv[i, 0]
        uy = W.bU[i, 1] - W.bv[i, 1]
        uz = W.bU[i, 2] - W.bv[i, 2]
        for part in range(2):
            if part == 1:
                ux = -wx
                uy = -wy
                uz = -wz
            um = math.sqrt(ux * ux + uy * uy + uz * uz)
            if um == 0.0:
                continue
            # body-axis components, scaled by CdA, back to global
            bx, by, bz = mattvec3(Rm, ux, uy, uz)
            c0 = 0.5 * E.rho * um
            bx *= c0 * R.body_CdA[i, 3 * part]
            by *= c0 * R.body_CdA[i, 3 * part + 1]
            bz *= c0 * R.body_CdA[i, 3 * part + 2]
            for a in range(3):
                F6[3 * part + a] += Rm[a, 0] * bx + Rm[a, 1] * by + Rm[a, 2] * bz


@derivative_kernel
def body_motion(y, dy, R, W, F):
    """Body equations of motion from W.b6F and W.b6M: accelerations of free and coupled-pinned
    bodies (floating bodies solved with their group are already in W.bacc), their state
    derivatives, and the load returned for coupled bodies (F6 - M a_in)."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    M3 = W.m33[0]
    rhs3 = W.v6[0]
    x3 = W.v6[1]
    dense = W.dense
    fl = F
    for i in range(R.body_kind.size):
        kind = R.body_kind[i]
        F6 = W.b6F[i]
        M6 = W.b6M[i]
        acc = W.bacc[i]
        j = R.body_blk[i]
        f = fl.of_body[i]
        if kind == BODY_FREE and f >= 0 and fl.grouped[f] == 1:
            pass  # solved with its group (core.floating.floating_motion)
        elif kind == BODY_FREE:
            solve_dense(M6, F6, acc, 6, dense)
        elif kind == BODY_COUPLED_PINNED:
            o = R.body_cpl[i]
            for a in range(3):
                acc[a] = W.ac[o + a]
            _pinned_rotation(M6, F6, acc, M3, rhs3, x3, dense)
        elif kind == BODY_COUPLED:
            o = R.body_cpl[i]
            for a in range(6):
                acc[a] = W.ac[o + a]
        if j >= 0:
            oq = 3 * n3 + 7 * j
            ou = uoff + 3 * n3 + 6 * j
            free = kind == BODY_FREE
            for a in range(3):
                dy[oq + a] = y[ou + a] if free else 0.0
                dy[ou + a] = acc[a] if free else 0.0
                dy[ou + 3 + a] = acc[3 + a]
            quat_rate(y, oq + 3, y[ou + 3], y[ou + 4], y[ou + 5], dy, oq + 3)
        if kind == BODY_COUPLED or kind == BODY_COUPLED_PINNED:
            # the load returned to the caller: F6 - M a_in (translation only when pinned)
            na = 6 if kind == BODY_COUPLED else 3
            for a in range(na):
                s = 0.0
                for c in range(6):
                    s += M6[a, c] * acc[c]
                F6[a] -= s
            if kind == BODY_COUPLED_PINNED:
                for a in range(3):
                    F6[3 + a] = 0.0
