"""The state derivative of the whole system: one compiled function, ``rhs``.

Order of one evaluation (spec 3.16): coupled and free point kinematics; line end nodes copy their
points; internal nodes from the state; line loads and internal-node accelerations; points collect
the end forces and masses of their lines and solve their own equations; rods, then the loads the
rods and points pass to their bodies and the bodies' own; the potential-flow loads of floating
bodies (:mod:`.floating`) and the solve of bodies coupled by added mass or joints; the other bodies'
equations of motion.
"""

from __future__ import annotations

import math

from .features import FLOATING, LINE_STATES, RIGID, WATER, when
from .floating import floating_loads, floating_motion
from .jit import derivative_kernel, kernel
from .layout import ATT_POINT, ATT_ROD_A, P_COUPLED, P_FIXED, P_FREE
from .lines import add_end_mass, line_forces, solve3
from .linestates import XC_TIME, line_state_rates, load_line_states, viv_after, viv_before
from .numerics import bracket
from .rigid import (
    body_kinematics,
    body_motion,
    body_point_kinematics,
    rigid_dynamics,
    rod_kinematics,
    rod_loads,
    rod_nodes,
    zero_length_axes,
)
from .waterkin import WAVES_EXTERNAL, fluid_at, fluid_at_points


@derivative_kernel
def motion_piece(Mo, t):
    """Index of the trajectory piece holding time ``t`` (right-continuous at knots, clamped)."""
    tk = Mo.t
    if t < tk[1]:
        return 0
    if t >= tk[tk.size - 2]:
        return tk.size - 2
    return bracket(tk, 1, tk.size - 2, t)


@derivative_kernel
def motion_eval(Mo, t, piece, x, v, a):
    """Evaluate the coupled trajectory ``Mo`` at time ``t`` into x, v, a, on trajectory piece
    ``piece`` (or, when negative, on the piece that holds ``t``). A time step never straddles a knot
    and evaluates all its stages on its own piece, as MoorDyn holds x + xd (tau - t) over a step."""
    k = piece if piece >= 0 else motion_piece(Mo, t)
    s = t - Mo.t[k]
    cc = Mo.c
    for j in range(x.size):
        c0 = cc[k, j, 0]
        c1 = cc[k, j, 1]
        c2 = cc[k, j, 2]
        c3 = cc[k, j, 3]
        x[j] = c0 + s * (c1 + s * (c2 + s * c3))
        v[j] = c1 + s * (2.0 * c2 + 3.0 * s * c3)
        a[j] = 2.0 * c2 + 6.0 * s * c3


@kernel(inline="always")
def _node_state(y, uoff, node_row, r, v, n):
    """Position and velocity of interior line node n from the state ``y``."""
    o = 3 * node_row[n]
    for c in range(3):
        r[n, c] = y[o + c]
        v[n, c] = y[uoff + o + c]


@kernel(inline="always")
def set_kinematics(t, y, L, R, P, Mo, W, piece):
    """Bodies, rods, points and line nodes from the state ``y`` and the coupled trajectory at
    time ``t`` (spec 3.16, step 1)."""
    # arrays are bound to locals once: reading them from a NamedTuple inside a loop costs a
    # reference-count update per access
    pr = W.pr
    pv = W.pv
    pa = W.pa
    r = W.r
    v = W.v
    xc = W.xc
    vc = W.vc
    kind = P.kind
    r0 = P.r0
    cpl = P.cpl
    prow = P.row
    node_ptr = L.node_ptr
    node_row = L.node_row
    end_kind = L.end_kind
    end_idx = L.end_idx
    uoff = 3 * R.dims[0] + 7 * R.dims[1]
    if xc.size > 0:
        motion_eval(Mo, t, piece, xc, vc, W.ac)
    nl = node_ptr.size - 1
    calc = L.calc
    for li in range(nl):
        n1 = node_ptr[li] + 1
        n2 = node_ptr[li + 1] - 1
        if calc[li] == 0 and n2 - n1 > 2:
            # local Euler, a line not evaluated now: only its nodes next to the ends are read
            # (zero-length rods take their axis from them: rigid.zero_length_axes)
            _node_state(y, uoff, node_row, r, v, n1)
            _node_state(y, uoff, node_row, r, v, n2 - 1)
            continue
        for n in range(n1, n2):
            _node_state(y, uoff, node_row, r, v, n)
    if L.xs_s0.size > 0:
        when(W, LINE_STATES, load_line_states, (y, L, R, W))
    if R.body_kind.size > 0:
        when(W, RIGID, body_kinematics, (y, R, W))
    if R.rod_kind.size > 0:
        when(W, RIGID, rod_kinematics, (y, R, W))
        when(W, RIGID, zero_length_axes, (R, L, W))
        when(W, RIGID, rod_nodes, (R, W))
    for p in range(kind.size):
        k = kind[p]
        if k == P_FIXED:
            for c in range(3):
                pr[p, c] = r0[p, c]
                pv[p, c] = 0.0
                pa[p, c] = 0.0
        elif k == P_COUPLED:
            o = cpl[p]
            for c in range(3):
                pr[p, c] = xc[o + c]
                pv[p, c] = vc[o + c]
                pa[p, c] = W.ac[o + c]
        elif k == P_FREE:
            o = 3 * prow[p]
            for c in range(3):
                pr[p, c] = y[o + c]
                pv[p, c] = y[uoff + o + c]
    if R.body_kind.size > 0:
        when(W, RIGID, body_point_kinematics, (P, W))
    rodr = W.rodr
    rodv = W.rodv
    for li in range(nl):
        for j in range(2):
            n = node_ptr[li] if j == 0 else node_ptr[li + 1] - 1
            kd = end_kind[li, j]
            if kd == ATT_POINT:
                p = end_idx[li, j]
                for c in range(3):
                    r[n, c] = pr[p, c]
                    v[n, c] = pv[p, c]
            else:
                k = end_idx[li, j]
                e = 0 if kd == ATT_ROD_A else 1
                for c in range(3):
                    r[n, c] = rodr[k, e, c]
                    v[n, c] = rodv[k, e, c]


@derivative_kernel
def set_water(t, K, W):
    """Water velocity and acceleration, surface elevation (and dynamic pressure at rod nodes) at
    every line node, rod node, point and body reference point at time ``t`` (spec 4). External
    kinematics (MoorDyn's WaveKin 1) come from ``K.U_ext``/``K.Ud_ext`` in MoorDyn's node order:
    line nodes, rod nodes, points, the ground body, bodies."""
    fk = W.fk
    nn = W.r.shape[0]
    ext = K.wave_mode == WAVES_EXTERNAL
    fluid_at_points(t, W.r, K, fk)
    for n in range(nn):
        for c in range(3):
            W.U[n, c] = fk[n, c]
            W.Ud[n, c] = fk[n, 3 + c]
        W.zeta[n] = fk[n, 6]
    off = nn
    for group in range(3):
        r = W.rn_r if group == 0 else (W.pr if group == 1 else W.br)
        m = r.shape[0]
        if group == 2:
            off += 1  # MoorDyn's ground body
        if m == 0:
            continue
        if ext:
            for i in range(m):
                fluid_at(t, r[i, 0], r[i, 1], r[i, 2], K, fk[i])
                for c in range(3):
                    fk[i, c] += K.U_ext[off + i, c]
                    fk[i, 3 + c] += K.Ud_ext[off + i, c]
        else:
            fluid_at_points(t, r, K, fk)
        for i in range(m):
            for c in range(3):
                if group == 0:
                    W.rn_U[i, c] = fk[i, c]
                    W.rn_Ud[i, c] = fk[i, 3 + c]
                elif group == 1:
                    W.pU[i, c] = fk[i, c]
                else:
                    W.bU[i, c] = fk[i, c]
            if group == 0:
                W.rn_zeta[i] = fk[i, 6]
                W.rn_pd[i] = fk[i, 7]
        off += m


@kernel(inline="always")
def point_loads(P, E, W, cd_scale):
    """Net force and mass matrix of every point (spec 3.13); accelerations of free points."""
    pU = W.pU
    pv = W.pv
    pF = W.pF
    pM = W.pM
    kind = P.kind
    CdA = P.CdA
    F_ext = P.F_ext
    V = P.V
    m = P.m
    Ca = P.Ca
    for p in range(kind.size):
        ux = pU[p, 0] - pv[p, 0]
        uy = pU[p, 1] - pv[p, 1]
        uz = pU[p, 2] - pv[p, 2]
        um = math.sqrt(ux * ux + uy * uy + uz * uz)
        cd = 0.5 * E.rho * CdA[p] * cd_scale * um
        pF[p, 0] += F_ext[p, 0] + cd * ux
        pF[p, 1] += F_ext[p, 1] + cd * uy
        pF[p, 2] += F_ext[p, 2] + cd * uz + E.g * (E.rho * V[p] - m[p])
        madd = m[p] + E.rho * Ca[p] * V[p]
        for c in range(3):
            pM[p, c, c] += madd
        if kind[p] == P_FREE:
            solve3(pM, p, pF, W.pa)


@derivative_kernel
def _any_viv(L):
    for li in range(L.viv.shape[0]):
        if L.viv[li, 0] > 0.0:
            return True
    return False


@derivative_kernel
def rhs(t, y, dy, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece):
    """Write dy/dt of the state ``y`` at time ``t`` into ``dy`` (and fill the Work arrays).

    Parameters
    ----------
    t : float
        Time [s].
    y, dy : ndarray (n_state,)
        State ``[q | u]`` and its derivative ``[u | a]``.
    L, R, P, E, B, Mo, W : LineArrays, RigidArrays, PointArrays, EnvArrays, Seabed, Motion, Work
    F, FW : FloatArrays, FloatWork (the floating bodies; empty arrays when nothing floats)
    cd_scale : float
        Drag multiplier (CdScaleIC during dynamic relaxation, else 1).
    piece : int
        Piece of the coupled trajectory to evaluate (-1: the piece holding ``t``).
    """
    set_kinematics(t, y, L, R, P, Mo, W, piece)
    K = E.water
    if K.wave_mode != 0 or K.current_mode != 0:
        when(W, WATER, set_water, (t, K, W))
    rodF = W.rodF
    rodEM = W.rodEM
    rodMext = W.rodMext
    nrod = R.rod_kind.size
    for k in range(nrod):
        for e in range(2):
            for c in range(3):
                rodF[k, e, c] = 0.0
                rodMext[k, c] = 0.0
                for b in range(3):
                    rodEM[2 * k + e, c, b] = 0.0
    pF = W.pF
    pM = W.pM
    pa = W.pa
    Fn = W.F
    mass = W.mass
    q = W.q
    acc = W.acc
    kind = P.kind
    prow = P.row
    node_ptr = L.node_ptr
    node_row = L.node_row
    end_kind = L.end_kind
    end_idx = L.end_idx
    npnt = kind.size
    for p in range(npnt):
        for a in range(3):
            pF[p, a] = 0.0
            for b in range(3):
                pM[p, a, b] = 0.0
    nl = node_ptr.size - 1
    viv = L.node_xs.size > 0 and L.xs_s0.size > 0 and L.viv.size > 0 and _any_viv(L)
    if viv:
        L.xs_ctl[XC_TIME] = t
        when(W, LINE_STATES, viv_before, (L, W))
    line_forces(L, E, B, W, cd_scale)
    if viv:
        when(W, LINE_STATES, viv_after, (L, E, W))
    end_moment = W.end_moment
    for li in range(nl):
        for j in range(2):
            n = node_ptr[li] if j == 0 else node_ptr[li + 1] - 1
            if end_kind[li, j] == ATT_POINT:
                p = end_idx[li, j]
                for c in range(3):
                    pF[p, c] += Fn[n, c]
                add_end_mass(pM, p, mass[n, 0], mass[n, 1], mass[n, 2], q, n)
            else:
                k = end_idx[li, j]
                e = 0 if end_kind[li, j] == ATT_ROD_A else 1
                # the bending moment of a clamped cable end acts on the rod (zero when pinned; not
                # passed on with ClampMoment 0, as in MoorDyn-C)
                cm = 1.0 if L.clamped[li, j] == 1 else 0.0
                for c in range(3):
                    rodF[k, e, c] += Fn[n, c]
                    rodMext[k, c] += cm * end_moment[li, j, c]
                add_end_mass(rodEM, 2 * k + e, mass[n, 0], mass[n, 1], mass[n, 2], q, n)
    point_loads(P, E, W, cd_scale)

    n3 = R.dims[0]
    uoff = 3 * n3 + 7 * R.dims[1]
    # velocity rows. A line not evaluated now (local Euler) keeps its rows of dy from its last
    # update: then they are written line by line (the lines' interior nodes come first in the
    # state, line after line), else in one loop
    calc = L.calc
    n_line = 0
    for li in range(nl):
        if calc[li] == 0:
            n_line = -1
    if n_line < 0:
        n_line = 0
        for li in range(nl):
            n1 = node_ptr[li] + 1
            n2 = node_ptr[li + 1] - 1
            if n2 > n1:
                o1 = 3 * node_row[n1]
                o2 = 3 * node_row[n2 - 1] + 3
                n_line = o2
                if calc[li] != 0:
                    for i in range(o1, o2):
                        dy[i] = y[uoff + i]
    for i in range(n_line, 3 * n3):
        dy[i] = y[uoff + i]
    for li in range(nl):
        if calc[li] == 0:
            continue
        for n in range(node_ptr[li] + 1, node_ptr[li + 1] - 1):
            o = uoff + 3 * node_row[n]
            dy[o] = acc[n, 0]
            dy[o + 1] = acc[n, 1]
            dy[o + 2] = acc[n, 2]
    for p in range(npnt):
        if kind[p] == P_FREE:
            o = uoff + 3 * prow[p]
            dy[o] = pa[p, 0]
            dy[o + 1] = pa[p, 1]
            dy[o + 2] = pa[p, 2]
    if L.xs_s0.size > 0:
        when(W, LINE_STATES, line_state_rates, (L, R, W, dy))
    if nrod > 0 or R.body_kind.size > 0:
        if nrod > 0:
            when(W, RIGID, rod_loads, (R, E, B, W, cd_scale))
        when(W, RIGID, rigid_dynamics, (y, dy, R, P, E, W))
        if F.body.size > 0:
            when(W, FLOATING, floating_loads, (t, y, dy, R, E, W, F, FW))
            when(W, FLOATING, floating_motion, (R, W, F, FW))
        when(W, RIGID, body_motion, (y, dy, R, W, F))


@kernel(fastmath=True)
def rhs_call(t, y, dy, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece):
    """:func:`rhs` as a function of its own, for the kernels that evaluate it outside the explicit
    schemes' stages (initial conditions, implicit solvers and their Jacobians, MoorDyn's other
    schemes, the end of a time loop): ``rhs`` is inlined into every kernel that calls it
    (``forceinline``, which the stage loop needs), and each copy costs compile time (some 4-10 s of
    CPU for a first run); here it is one."""
    rhs(t, y, dy, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
