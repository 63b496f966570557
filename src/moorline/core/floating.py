"""Floating bodies in the compiled loop: the terms of the Cummins equation and prismatic joints.

For every floating body (a free body of the deck, see :mod:`moorline.model.floating`), with ``x``
its displacement from the mean pose (translation of the reference point; roll, pitch, yaw of the
rotation relative to the mean orientation, Rx Ry Rz) and ``v`` its velocity and angular velocity
(global axes), one evaluation adds to the body's 6-DOF force about its reference point:

- hydrostatics ``F0 - C x``: the buoyancy at rest (``rho g V`` up at the centre of buoyancy) and the
  buoyancy part of the hydrostatic stiffness (the weight acts at the CG and turns with the body);
- the wave excitation: ``r(t) sum_j Re(X_j a_j exp(i w_j t))`` summed over the components, or
  interpolated (cubic Hermite) from a table over the sea's repeat period;
- the radiation memory: ``-sum_j int K_ij(tau) v_j(t - tau) dtau``, by a state-space model per DOF
  pair (states ``z`` at the end of the state vector, ``z' = A z + B v_j``, force ``-C z``) or by
  direct convolution of the sampled impulse response with the recorded velocity history;
- extra linear and quadratic damping, stiffness and a constant load; drag-only Morison strips;
- the linear PTO of each joint, ``-k (s - s0) - c s'`` along the joint axis, on the child and,
  opposite, on the parent;

and ``A_inf`` joins the body's mass matrix. Bodies coupled through ``A_inf`` (one coefficient
set) or joints form a group whose accelerations come from one solve: with joints, in reduced
coordinates ``q`` (6 per root body, 1 slide per joint), ``(T^T M T) q'' = T^T (F - M gamma)`` with
the full accelerations ``T q'' + gamma`` (``gamma``: the centripetal and Coriolis terms of the
slide). Bodies keep their full 6-DOF state; after every accepted step each child is put back on
its joint (position, orientation, velocity), so the constraint holds to round-off at step ends
without penalty springs.

The implicit scheme advances the state-space radiation states by the trapezoidal rule inside its
step map (:func:`radiation_trapezoid`): they are linear in the body velocities, so they need no
Newton unknowns of their own and the bodies' Jacobian blocks include them through the velocity.
"""

from __future__ import annotations

import math

from .features import WATER, when
from .jit import derivative_kernel, kernel
from .layout import (
    CTL_QS_MOORING,
    CTL_RADIATION,
    EXC_OFF,
    EXC_SUM,
    FC_DAMPING,
    FC_EXCITATION,
    FC_EXTRA,
    FC_HYDROSTATIC,
    FC_MOORING,
    FC_MORISON,
    FC_PTO,
    FC_RADIATION,
    N_FC,
    RAD_CONVOLUTION,
    RAD_STATE_SPACE,
)
from .numerics import lu_factor, lu_solve, quat_mul, quat_to_R, solve_dense
from .waterkin import _ramp, fluid_at


# ------------------------------------------------------------------------------------ small algebra
@derivative_kernel
def rel_angles(Rm, R0, out, o):
    """Roll, pitch, yaw of Rm R0^T (the rotation from the mean orientation, global axes,
    Rx Ry Rz) into out[o:o+3]."""
    r02 = Rm[0, 0] * R0[2, 0] + Rm[0, 1] * R0[2, 1] + Rm[0, 2] * R0[2, 2]
    r12 = Rm[1, 0] * R0[2, 0] + Rm[1, 1] * R0[2, 1] + Rm[1, 2] * R0[2, 2]
    r22 = Rm[2, 0] * R0[2, 0] + Rm[2, 1] * R0[2, 1] + Rm[2, 2] * R0[2, 2]
    r00 = Rm[0, 0] * R0[0, 0] + Rm[0, 1] * R0[0, 1] + Rm[0, 2] * R0[0, 2]
    r01 = Rm[0, 0] * R0[1, 0] + Rm[0, 1] * R0[1, 1] + Rm[0, 2] * R0[1, 2]
    out[o + 1] = math.asin(max(-1.0, min(1.0, r02)))
    out[o] = math.atan2(-r12, r22)
    out[o + 2] = math.atan2(-r01, r00)


@derivative_kernel
def _excitation(t, X, f, out):
    """Excitation force and moment of floating body ``f`` at time ``t`` into out (6,)."""
    mode = X.ctl[0]
    for d in range(6):
        out[d] = 0.0
    if mode == EXC_OFF:
        return
    r, _ = _ramp(t, X.par[0])
    if r == 0.0:
        return
    o = 6 * f
    if mode == EXC_SUM:
        for j in range(X.w.size):
            c = math.cos(X.w[j] * t)
            s = math.sin(X.w[j] * t)
            for d in range(6):
                out[d] += X.Xr[j, o + d] * c - X.Xi[j, o + d] * s
    else:
        dt = X.par[1]
        period = X.par[2]
        tau = t - period * math.floor(t / period)
        u = tau / dt
        k = int(u)
        n = X.G.shape[0] - 1
        if k >= n:
            k = n - 1
        s = u - k
        h00 = (1.0 + 2.0 * s) * (1.0 - s) * (1.0 - s)
        h10 = s * (1.0 - s) * (1.0 - s) * dt
        h01 = s * s * (3.0 - 2.0 * s)
        h11 = s * s * (s - 1.0) * dt
        for d in range(6):
            out[d] = h00 * X.G[k, o + d] + h10 * X.dG[k, o + d] + h01 * X.G[k + 1, o + d] + h11 * X.dG[k + 1, o + d]
    for d in range(6):
        out[d] *= r


@derivative_kernel
def _convolution(t, F, fw, f, out):
    """Radiation memory force on floating body ``f`` by convolution of the impulse response with
    the velocity history (trapezoidal rule; the newest interval ends at the current velocity)."""
    K = F.irf
    nt = K.shape[0]
    nd = K.shape[1]
    dt = F.par[0]
    for d in range(6):
        out[d] = 0.0
    count = fw.hctl[0] - fw.hctl[1]  # samples recorded since the history (re)started
    if nt == 0 or count <= 0:
        return
    # newest sample k0 at t_k0 = k0 dt <= t; lags tau_n = gap + n dt of the samples k0 - n
    k0 = fw.hctl[0] - 1
    gap = t - k0 * dt
    frac = gap / dt
    m = int(frac)
    s = frac - m
    o = 6 * f
    # trapezoids over [0, gap] (K(0) v(t), K(gap) v_k0) and then one sample interval each
    for i in range(6):
        acc = 0.0
        for j in range(nd):
            acc += K[0, j, o + i] * fw.vel[j]
        out[i] -= 0.5 * gap * acc
    nmax = min(count, nt - 1 - m)
    for n in range(nmax):
        row = (k0 - n) % nt
        a = m + n
        w = 0.0
        if n == 0:
            w += 0.5 * gap
        if n < nmax - 1:
            w += 0.5 * dt
        if n > 0:
            w += 0.5 * dt
        for i in range(6):
            acc = 0.0
            for j in range(nd):
                acc += ((1.0 - s) * K[a, j, o + i] + s * K[a + 1, j, o + i]) * fw.hist[row, j]
            out[i] -= w * acc


# ------------------------------------------------------------------------------------ loads
@derivative_kernel
def floating_loads(t, y, dy, R, E, W, F, FW):
    """Potential-flow, extra and PTO loads of every floating body into W.b6F (A_inf into W.b6M),
    their components into FW.F, and the derivatives of the state-space radiation states."""
    fw = FW
    nf = F.body.size
    rho = E.rho
    comp = fw.F
    for f in range(nf):
        i = F.body[f]
        Rm = W.bR[i]
        for c in range(3):
            fw.xi[f, c] = W.br[i, c] - F.pose0[f, c]
            fw.vel[6 * f + c] = W.bv[i, c]
            fw.vel[6 * f + 3 + c] = W.bw[i, c]
        rel_angles(Rm, F.R0[f], fw.xi[f], 3)
        for k in range(N_FC):
            for d in range(6):
                comp[f, k, d] = 0.0
    for f in range(nf):
        xi = fw.xi[f]
        for a in range(6):
            s = F.F0[f, a]
            e = F.Fc[f, a]
            dmp = 0.0
            for b in range(6):
                s -= F.C[f, a, b] * xi[b]
                e -= F.Kext[f, a, b] * xi[b]
                vb = fw.vel[6 * f + b]
                dmp -= F.Blin[f, a, b] * vb + F.Bquad[f, a, b] * abs(vb) * vb
            comp[f, FC_HYDROSTATIC, a] = s
            comp[f, FC_EXTRA, a] = e
            comp[f, FC_DAMPING, a] = dmp
        _excitation(t, E.exc, f, comp[f, FC_EXCITATION])
    # radiation memory
    if F.ctl[CTL_RADIATION] == RAD_CONVOLUTION:
        for f in range(nf):
            _convolution(t, F, fw, f, comp[f, FC_RADIATION])
    else:
        zoff = 6 * R.dims[0] + 13 * R.dims[1]
        for p in range(F.ss_i.size):
            i = F.ss_i[p]
            j = F.ss_j[p]
            vj = fw.vel[j]
            p0 = F.ss_ptr[p]
            n = F.ss_ptr[p + 1] - p0
            force = 0.0
            for r in range(n):
                s = F.ss_B[p0 + r] * vj
                for c in range(n):
                    s += F.ss_A[p0 + r, c] * y[zoff + p0 + c]
                dy[zoff + p0 + r] = s
                force -= F.ss_C[p0 + r] * y[zoff + p0 + r]
            comp[i // 6, FC_RADIATION, i % 6] += force
    # drag-only Morison strips
    fk = fw.fk
    K = E.water
    still = K.wave_mode == 0 and K.current_mode == 0
    for m in range(F.ms_fb.size):
        f = F.ms_fb[m]
        i = F.body[f]
        Rm = W.bR[i]
        ax = F.ms_rB[m, 0] - F.ms_rA[m, 0]
        ay = F.ms_rB[m, 1] - F.ms_rA[m, 1]
        az = F.ms_rB[m, 2] - F.ms_rA[m, 2]
        ln = math.sqrt(ax * ax + ay * ay + az * az)
        qx = (Rm[0, 0] * ax + Rm[0, 1] * ay + Rm[0, 2] * az) / ln
        qy = (Rm[1, 0] * ax + Rm[1, 1] * ay + Rm[1, 2] * az) / ln
        qz = (Rm[2, 0] * ax + Rm[2, 1] * ay + Rm[2, 2] * az) / ln
        n = F.ms_n[m]
        c0 = 0.5 * rho * F.ms_Cd[m] * F.ms_d[m] * ln / n
        for k in range(n):
            u = (k + 0.5) / n
            lx = F.ms_rA[m, 0] + u * ax
            ly = F.ms_rA[m, 1] + u * ay
            lz = F.ms_rA[m, 2] + u * az
            gx = Rm[0, 0] * lx + Rm[0, 1] * ly + Rm[0, 2] * lz
            gy = Rm[1, 0] * lx + Rm[1, 1] * ly + Rm[1, 2] * lz
            gz = Rm[2, 0] * lx + Rm[2, 1] * ly + Rm[2, 2] * lz
            px = W.br[i, 0] + gx
            py = W.br[i, 1] + gy
            pz = W.br[i, 2] + gz
            if still:
                for c in range(8):
                    fk[c] = 0.0
            else:
                # (a system without water kinematics is always still, and its kernels take
                # core.features.NoWater, without the arrays fluid_at reads)
                when(W, WATER, fluid_at, (t, px, py, pz, K, fk))
            if pz > fk[6]:
                continue  # dry
            wx = W.bw[i, 0]
            wy = W.bw[i, 1]
            wz = W.bw[i, 2]
            ux = fk[0] - (W.bv[i, 0] + wy * gz - wz * gy)
            uy = fk[1] - (W.bv[i, 1] + wz * gx - wx * gz)
            uz = fk[2] - (W.bv[i, 2] + wx * gy - wy * gx)
            ua = ux * qx + uy * qy + uz * qz
            ux -= ua * qx
            uy -= ua * qy
            uz -= ua * qz
            um = math.sqrt(ux * ux + uy * uy + uz * uz)
            fx = c0 * um * ux
            fy = c0 * um * uy
            fz = c0 * um * uz
            cf = comp[f, FC_MORISON]
            cf[0] += fx
            cf[1] += fy
            cf[2] += fz
            cf[3] += gy * fz - gz * fy
            cf[4] += gz * fx - gx * fz
            cf[5] += gx * fy - gy * fx
    # joints: slide, rate and the PTO force pair
    for jn in range(F.jt_child.size):
        joint_state(F, FW, W, jn)
        s = fw.jt[jn, 0]
        sd = fw.jt[jn, 1]
        fp = -F.jt_k[jn] * (s - F.jt_s0[jn]) - F.jt_c[jn] * sd
        fw.jt[jn, 2] = F.jt_c[jn] * sd * sd
        c = F.jt_child[jn]
        p = F.jt_parent[jn]
        ex, ey, ez, dx, dy_, dz = _joint_axis(F, W, jn)
        cf = comp[c, FC_PTO]
        cf[0] += fp * ex
        cf[1] += fp * ey
        cf[2] += fp * ez
        if p >= 0:
            pf = comp[p, FC_PTO]
            pf[0] -= fp * ex
            pf[1] -= fp * ey
            pf[2] -= fp * ez
            # the reaction acts at the child's reference point, d from the parent's
            pf[3] -= fp * (dy_ * ez - dz * ey)
            pf[4] -= fp * (dz * ex - dx * ez)
            pf[5] -= fp * (dx * ey - dy_ * ex)
    # the quasi-static mooring, linearised about the pose of the step's start
    if F.ctl[CTL_QS_MOORING] == 1:
        pose = FW.qpose
        for f in range(nf):
            i = F.body[f]
            for c in range(3):
                pose[6 * f + c] = W.br[i, c]
            rel_angles(W.bR[i], FW.eye3, pose, 6 * f + 3)
        nd = 6 * nf
        for a in range(nd):
            s = F.ql_F[a]
            for b in range(nd):
                s -= F.ql_K[a, b] * (pose[b] - F.ql_x0[b])
            comp[a // 6, FC_MOORING, a % 6] = s
    # into the bodies' loads and mass matrices
    for f in range(nf):
        i = F.body[f]
        for a in range(6):
            s = 0.0
            for k in range(N_FC):
                s += comp[f, k, a]
            W.b6F[i, a] += s
            for b in range(6):
                W.b6M[i, a, b] += F.Ainf[6 * f + a, 6 * f + b]


@derivative_kernel
def _joint_axis(F, W, jn):
    """Global slide direction e and the vector d from the parent's reference point to the
    child's (zero for a fixed axis)."""
    c = F.jt_child[jn]
    p = F.jt_parent[jn]
    ci = F.body[c]
    if p < 0:
        return F.jt_axis[jn, 0], F.jt_axis[jn, 1], F.jt_axis[jn, 2], 0.0, 0.0, 0.0
    pi = F.body[p]
    Rm = W.bR[pi]
    a = F.jt_axis[jn]
    ex = Rm[0, 0] * a[0] + Rm[0, 1] * a[1] + Rm[0, 2] * a[2]
    ey = Rm[1, 0] * a[0] + Rm[1, 1] * a[1] + Rm[1, 2] * a[2]
    ez = Rm[2, 0] * a[0] + Rm[2, 1] * a[1] + Rm[2, 2] * a[2]
    return ex, ey, ez, W.br[ci, 0] - W.br[pi, 0], W.br[ci, 1] - W.br[pi, 1], W.br[ci, 2] - W.br[pi, 2]


@kernel(inline="always")
def _relative_velocity(W, ci, pi, dx, dy, dz):
    """Velocity of body ``ci``'s reference point relative to the point of body ``pi`` it is at,
    d = (dx, dy, dz) from ``pi``'s reference point: v_c - v_p - omega_p x d."""
    wx = W.bw[pi, 0]
    wy = W.bw[pi, 1]
    wz = W.bw[pi, 2]
    return (W.bv[ci, 0] - W.bv[pi, 0] - (wy * dz - wz * dy), W.bv[ci, 1] - W.bv[pi, 1] - (wz * dx - wx * dz),
            W.bv[ci, 2] - W.bv[pi, 2] - (wx * dy - wy * dx))


@derivative_kernel
def joint_state(F, FW, W, jn):
    """Slide s [m] and its rate [m/s] of joint ``jn`` from the body kinematics in W, into
    FW.jt[jn, 0:2]."""
    c = F.jt_child[jn]
    p = F.jt_parent[jn]
    ci = F.body[c]
    ex, ey, ez, dx, dy, dz = _joint_axis(F, W, jn)
    a = F.jt_axis[jn]
    d0 = F.jt_d0[jn]
    if p < 0:
        s = ex * (W.br[ci, 0] - d0[0]) + ey * (W.br[ci, 1] - d0[1]) + ez * (W.br[ci, 2] - d0[2])
        sd = ex * W.bv[ci, 0] + ey * W.bv[ci, 1] + ez * W.bv[ci, 2]
    else:
        pi = F.body[p]
        s = ex * dx + ey * dy + ez * dz - (a[0] * d0[0] + a[1] * d0[1] + a[2] * d0[2])
        rvx, rvy, rvz = _relative_velocity(W, ci, pi, dx, dy, dz)
        sd = ex * rvx + ey * rvy + ez * rvz
    FW.jt[jn, 0] = s
    FW.jt[jn, 1] = sd


# ------------------------------------------------------------------------------------ group motion
@derivative_kernel
def floating_motion(R, W, F, FW):
    """Accelerations of the bodies of every group with several members or a joint (one solve per
    group, in reduced coordinates when it has joints) into W.bacc; single bodies are left to the
    rigid-body solve. A joint's child that is off its joint (within an explicit step before the
    projection, or while Newton statics iterate) gets a critically damped pull back onto it at the
    rate F.par[1] (0.3 / dtM: a real eigenvalue -0.3 per step, harmless for every scheme); on the
    joint the pull is zero, so the dynamics are those of the exact constraint."""
    fw = FW
    for g in range(F.grp_ptr.size - 1):
        g0 = F.grp_ptr[g]
        nm = F.grp_ptr[g + 1] - g0
        if F.grouped[F.grp_members[g0]] == 0:
            continue
        n = 6 * nm
        M = fw.Mg
        Fv = fw.Fg
        T = fw.T
        gam = fw.gam
        for a in range(n):
            gam[a] = 0.0
        # full mass matrix and loads of the group (A_inf's diagonal blocks are already in b6M)
        for u in range(nm):
            fu = F.grp_members[g0 + u]
            iu = F.body[fu]
            for a in range(6):
                Fv[6 * u + a] = W.b6F[iu, a]
                for v in range(nm):
                    fv = F.grp_members[g0 + v]
                    for b in range(6):
                        if u == v:
                            M[6 * u + a, 6 * v + b] = W.b6M[iu, a, b]
                        else:
                            M[6 * u + a, 6 * v + b] = F.Ainf[6 * fu + a, 6 * fv + b]
        # reduced coordinates: 6 per member that is no joint's child, 1 per child
        m = 0
        for u in range(nm):
            if F.child_joint[F.grp_members[g0 + u]] < 0:
                m += 6
            else:
                m += 1
        for a in range(n):
            for b in range(m):
                T[a, b] = 0.0
        col = 0
        for u in range(nm):
            fu = F.grp_members[g0 + u]
            if F.child_joint[fu] < 0:
                for a in range(6):
                    T[6 * u + a, col + a] = 1.0
                col += 6
        # children: their rows follow the parent's columns, plus their own slide column
        for u in range(nm):
            fu = F.grp_members[g0 + u]
            jn = F.child_joint[fu]
            if jn < 0:
                continue
            ex, ey, ez, dx, dy, dz = _joint_axis(F, W, jn)
            p = F.jt_parent[jn]
            r = 6 * u
            T[r, col] = ex
            T[r + 1, col] = ey
            T[r + 2, col] = ez
            if p >= 0:
                # parent's columns: roots take the first columns, 6 each, in member order
                pc = 0
                for v in range(nm):
                    fv = F.grp_members[g0 + v]
                    if fv == p:
                        break
                    if F.child_joint[fv] < 0:
                        pc += 6
                for a in range(3):
                    T[r + a, pc + a] = 1.0
                    T[r + 3 + a, pc + 3 + a] = 1.0
                # v_c = v_p + omega_p x d: the -S(d) block
                T[r, pc + 4] = dz
                T[r, pc + 5] = -dy
                T[r + 1, pc + 3] = -dz
                T[r + 1, pc + 5] = dx
                T[r + 2, pc + 3] = dy
                T[r + 2, pc + 4] = -dx
                pi = F.body[p]
                wx = W.bw[pi, 0]
                wy = W.bw[pi, 1]
                wz = W.bw[pi, 2]
                sd = fw.jt[jn, 1]
                # omega x (omega x d) + 2 s' omega x e
                cx = wy * dz - wz * dy
                cy = wz * dx - wx * dz
                cz = wx * dy - wy * dx
                gam[r] = wy * cz - wz * cy + 2.0 * sd * (wy * ez - wz * ey)
                gam[r + 1] = wz * cx - wx * cz + 2.0 * sd * (wz * ex - wx * ez)
                gam[r + 2] = wx * cy - wy * cx + 2.0 * sd * (wx * ey - wy * ex)
            col += 1
        # F - M gamma; Mr = T^T M T; Fr = T^T (F - M gamma)
        for a in range(n):
            s = Fv[a]
            for b in range(n):
                s -= M[a, b] * gam[b]
            Fv[a] = s
        MT = fw.MT
        for a in range(n):
            for b in range(m):
                s = 0.0
                for c in range(n):
                    s += M[a, c] * T[c, b]
                MT[a, b] = s
        Mr = fw.Mr
        for a in range(m):
            s = 0.0
            for c in range(n):
                s += T[c, a] * Fv[c]
            fw.Fr[a] = s
            for b in range(m):
                s = 0.0
                for c in range(n):
                    s += T[c, a] * MT[c, b]
                Mr[a, b] = s
        solve_dense(Mr, fw.Fr, fw.qa, m, fw.dense)
        for u in range(nm):
            iu = F.body[F.grp_members[g0 + u]]
            for a in range(6):
                s = gam[6 * u + a]
                for b in range(m):
                    s += T[6 * u + a, b] * fw.qa[b]
                W.bacc[iu, a] = s
    # a child off its joint (only within a step, or while statics iterate) is pulled back
    wc = F.par[1]
    for jn in range(F.jt_child.size):
        e = fw.jerr
        _joint_violation(F, FW, W, jn, e)
        ci = F.body[F.jt_child[jn]]
        for a in range(6):
            W.bacc[ci, a] -= wc * wc * e[a] + 2.0 * wc * e[6 + a]


@derivative_kernel
def _joint_violation(F, FW, W, jn, out):
    """How far the child of joint ``jn`` is off its joint: position and rotation-vector errors
    (out[0:6]) and velocity and angular-velocity errors (out[6:12]), from the body kinematics in W."""
    c = F.jt_child[jn]
    p = F.jt_parent[jn]
    ci = F.body[c]
    a = F.jt_axis[jn]
    d0 = F.jt_d0[jn]
    Rt = FW.m33[1]
    Rq = FW.m33[0]
    quat_to_R(F.jt_q[jn], 0, Rq)
    if p < 0:
        ex = a[0]
        ey = a[1]
        ez = a[2]
        rx = W.br[ci, 0] - d0[0]
        ry = W.br[ci, 1] - d0[1]
        rz = W.br[ci, 2] - d0[2]
        vx = W.bv[ci, 0]
        vy = W.bv[ci, 1]
        vz = W.bv[ci, 2]
        for i in range(3):
            for j in range(3):
                Rt[i, j] = Rq[i, j]
        wx = 0.0
        wy = 0.0
        wz = 0.0
    else:
        pi = F.body[p]
        Rp = W.bR[pi]
        ex = Rp[0, 0] * a[0] + Rp[0, 1] * a[1] + Rp[0, 2] * a[2]
        ey = Rp[1, 0] * a[0] + Rp[1, 1] * a[1] + Rp[1, 2] * a[2]
        ez = Rp[2, 0] * a[0] + Rp[2, 1] * a[1] + Rp[2, 2] * a[2]
        # the child's offset from where d0 puts it
        gx = Rp[0, 0] * d0[0] + Rp[0, 1] * d0[1] + Rp[0, 2] * d0[2]
        gy = Rp[1, 0] * d0[0] + Rp[1, 1] * d0[1] + Rp[1, 2] * d0[2]
        gz = Rp[2, 0] * d0[0] + Rp[2, 1] * d0[1] + Rp[2, 2] * d0[2]
        dx = W.br[ci, 0] - W.br[pi, 0]
        dy = W.br[ci, 1] - W.br[pi, 1]
        dz = W.br[ci, 2] - W.br[pi, 2]
        rx = dx - gx
        ry = dy - gy
        rz = dz - gz
        wx = W.bw[pi, 0]
        wy = W.bw[pi, 1]
        wz = W.bw[pi, 2]
        vx, vy, vz = _relative_velocity(W, ci, pi, dx, dy, dz)
        for i in range(3):
            for j in range(3):
                Rt[i, j] = Rp[i, 0] * Rq[0, j] + Rp[i, 1] * Rq[1, j] + Rp[i, 2] * Rq[2, j]
    # components across the axis only (the slide is free)
    sa = rx * ex + ry * ey + rz * ez
    out[0] = rx - sa * ex
    out[1] = ry - sa * ey
    out[2] = rz - sa * ez
    va = vx * ex + vy * ey + vz * ez
    out[6] = vx - va * ex
    out[7] = vy - va * ey
    out[8] = vz - va * ez
    # rotation error: the vector part of R_c R_t^T (small-angle rotation vector)
    Rc = W.bR[ci]
    m01 = Rc[0, 0] * Rt[1, 0] + Rc[0, 1] * Rt[1, 1] + Rc[0, 2] * Rt[1, 2]
    m10 = Rc[1, 0] * Rt[0, 0] + Rc[1, 1] * Rt[0, 1] + Rc[1, 2] * Rt[0, 2]
    m02 = Rc[0, 0] * Rt[2, 0] + Rc[0, 1] * Rt[2, 1] + Rc[0, 2] * Rt[2, 2]
    m20 = Rc[2, 0] * Rt[0, 0] + Rc[2, 1] * Rt[0, 1] + Rc[2, 2] * Rt[0, 2]
    m12 = Rc[1, 0] * Rt[2, 0] + Rc[1, 1] * Rt[2, 1] + Rc[1, 2] * Rt[2, 2]
    m21 = Rc[2, 0] * Rt[1, 0] + Rc[2, 1] * Rt[1, 1] + Rc[2, 2] * Rt[1, 2]
    out[3] = 0.5 * (m21 - m12)
    out[4] = 0.5 * (m02 - m20)
    out[5] = 0.5 * (m10 - m01)
    out[9] = W.bw[ci, 0] - wx
    out[10] = W.bw[ci, 1] - wy
    out[11] = W.bw[ci, 2] - wz


# ------------------------------------------------------------------------------------ implicit scheme
@kernel
def _factor_pair(F, fw, p, h):
    """LU factors of I - h/2 A of state-space pair ``p`` into fw.lu (rows of the pair)."""
    p0 = F.ss_ptr[p]
    n = F.ss_ptr[p + 1] - p0
    for r in range(n):
        for c in range(n):
            fw.lu[p0 + r, c] = (1.0 if r == c else 0.0) - 0.5 * h * F.ss_A[p0 + r, c]
    lu_factor(fw.lu, p0, n, fw.lu_piv)
    fw.lu_h[p] = h


@kernel
def radiation_trapezoid(y0, y1, h, R, F, FW):
    """State-space radiation states at the end of an implicit step of length ``h`` by the
    trapezoidal rule, (I - h/2 A) z1 = (I + h/2 A) z0 + h/2 B (v0 + v1), from the body velocities at
    both ends (``y0``, ``y1``) into ``y1``."""
    if F.ss_i.size == 0 or F.ctl[CTL_RADIATION] != RAD_STATE_SPACE:
        return
    fw = FW
    zoff = 6 * R.dims[0] + 13 * R.dims[1]
    b = fw.zv
    for p in range(F.ss_i.size):
        if fw.lu_h[p] != h:
            _factor_pair(F, fw, p, h)
        p0 = F.ss_ptr[p]
        n = F.ss_ptr[p + 1] - p0
        jy = F.dof_y[F.ss_j[p]]
        vv = 0.5 * h * (y0[jy] + y1[jy])
        for r in range(n):
            s = y0[zoff + p0 + r] + vv * F.ss_B[p0 + r]
            for c in range(n):
                s += 0.5 * h * F.ss_A[p0 + r, c] * y0[zoff + p0 + c]
            b[r] = s
        lu_solve(fw.lu, p0, n, fw.lu_piv, b)
        for r in range(n):
            y1[zoff + p0 + r] = b[r]


# ------------------------------------------------------------------------------------ after a step
@kernel
def _project_joints(y, R, W, F, FW):
    """Put every joint's child back on its joint: position, orientation, velocity and angular
    velocity from the parent's state and the slide (projected from the child's own state)."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    Rp = FW.m33[0]
    for jn in range(F.jt_child.size):
        c = F.jt_child[jn]
        p = F.jt_parent[jn]
        jc = R.body_blk[F.body[c]]
        cq = 3 * n3 + 7 * jc
        cu = uoff + 3 * n3 + 6 * jc
        a = F.jt_axis[jn]
        d0 = F.jt_d0[jn]
        if p < 0:
            s = a[0] * (y[cq] - d0[0]) + a[1] * (y[cq + 1] - d0[1]) + a[2] * (y[cq + 2] - d0[2])
            sd = a[0] * y[cu] + a[1] * y[cu + 1] + a[2] * y[cu + 2]
            for k in range(3):
                y[cq + k] = d0[k] + s * a[k]
                y[cu + k] = sd * a[k]
                y[cu + 3 + k] = 0.0
            for k in range(4):
                y[cq + 3 + k] = F.jt_q[jn, k]
            continue
        jp = R.body_blk[F.body[p]]
        pq = 3 * n3 + 7 * jp
        pu = uoff + 3 * n3 + 6 * jp
        quat_to_R(y, pq + 3, Rp)
        ex = Rp[0, 0] * a[0] + Rp[0, 1] * a[1] + Rp[0, 2] * a[2]
        ey = Rp[1, 0] * a[0] + Rp[1, 1] * a[1] + Rp[1, 2] * a[2]
        ez = Rp[2, 0] * a[0] + Rp[2, 1] * a[1] + Rp[2, 2] * a[2]
        dx = y[cq] - y[pq]
        dy = y[cq + 1] - y[pq + 1]
        dz = y[cq + 2] - y[pq + 2]
        wx = y[pu + 3]
        wy = y[pu + 4]
        wz = y[pu + 5]
        s = ex * dx + ey * dy + ez * dz - (a[0] * d0[0] + a[1] * d0[1] + a[2] * d0[2])
        rvx = y[cu] - y[pu] - (wy * dz - wz * dy)
        rvy = y[cu + 1] - y[pu + 1] - (wz * dx - wx * dz)
        rvz = y[cu + 2] - y[pu + 2] - (wx * dy - wy * dx)
        sd = ex * rvx + ey * rvy + ez * rvz
        # child reference point at d = R_p (d0 + s a)
        lx = d0[0] + s * a[0]
        ly = d0[1] + s * a[1]
        lz = d0[2] + s * a[2]
        dx = Rp[0, 0] * lx + Rp[0, 1] * ly + Rp[0, 2] * lz
        dy = Rp[1, 0] * lx + Rp[1, 1] * ly + Rp[1, 2] * lz
        dz = Rp[2, 0] * lx + Rp[2, 1] * ly + Rp[2, 2] * lz
        y[cq] = y[pq] + dx
        y[cq + 1] = y[pq + 1] + dy
        y[cq + 2] = y[pq + 2] + dz
        quat_mul(y[pq + 3], y[pq + 4], y[pq + 5], y[pq + 6], F.jt_q[jn], 0, y, cq + 3)
        y[cu] = y[pu] + wy * dz - wz * dy + sd * ex
        y[cu + 1] = y[pu + 1] + wz * dx - wx * dz + sd * ey
        y[cu + 2] = y[pu + 2] + wx * dy - wy * dx + sd * ez
        y[cu + 3] = wx
        y[cu + 4] = wy
        y[cu + 5] = wz


@kernel
def _record_history(t, y, F, FW):
    """Velocity samples at t_k = k dt up to ``t`` (linear between the last recorded step end and
    this one) into the convolution's ring buffer."""
    fw = FW
    nt = fw.hist.shape[0]
    nd = fw.vlast.size
    dt = F.par[0]
    t0 = fw.hpar[0]
    span = t - t0
    while True:
        k = fw.hctl[0]
        tk = k * dt
        if tk > t + 1e-12 * dt:
            break
        row = k % nt
        w = (tk - t0) / span if span > 0.0 else 1.0
        w = min(max(w, 0.0), 1.0)
        for j in range(nd):
            fw.hist[row, j] = (1.0 - w) * fw.vlast[j] + w * y[F.dof_y[j]]
        fw.hctl[0] = k + 1
    for j in range(nd):
        fw.vlast[j] = y[F.dof_y[j]]
    fw.hpar[0] = t


@kernel
def floating_after_step(t, y, R, W, F, FW):
    """After an accepted step ending at ``t``: children back on their joints; the convolution's
    velocity history."""
    if F.body.size == 0:
        return
    if F.jt_child.size > 0:
        _project_joints(y, R, W, F, FW)
    if F.ctl[CTL_RADIATION] == RAD_CONVOLUTION:
        _record_history(t, y, F, FW)


@kernel
def floating_restart(t, y, R, W, F, FW):
    """Forget the radiation memory (state-space states zero, no velocity history) and restart the
    history at time ``t`` with the current velocities (after the initial conditions, or a state
    set from outside)."""
    if F.body.size == 0:
        return
    zoff = 6 * R.dims[0] + 13 * R.dims[1]
    for i in range(zoff, zoff + R.dims[2]):  # the line states after them are not radiation memory
        y[i] = 0.0
    fw = FW
    if F.jt_child.size > 0:
        _project_joints(y, R, W, F, FW)
    # the history starts at the first sample time at or after t (the velocity before counts as 0)
    k = int(math.ceil(t / F.par[0] - 1e-9))
    fw.hctl[0] = k
    fw.hctl[1] = k
    fw.hpar[0] = t
    for j in range(fw.vlast.size):
        fw.vlast[j] = y[F.dof_y[j]]
