"""MoorDyn's other explicit and fixed-point time schemes (spec 5.2), step by step as MoorDyn-C
v2.7 takes them, so a deck that names one runs the same algorithm here:

- ``Heun``: the predictor is the last step's derivative, ``y* = y + h f_old``; the corrector
  ``y = y* + h/2 (f(t, y*) - f_old)``, and ``f(t, y*)`` (evaluated at the step's start time, as
  MoorDyn does) is kept for the next step;
- ``AB2``..``AB4`` (also ``LAB2``..``LAB4``, which are the same in MoorDyn-C): Adams-Bashforth with
  the textbook weights, lower orders during start-up;
- ``LEuler``: Euler in which each line is evaluated only when the time since its last update
  reaches 0.999 x CFL x its segment period (points, rods and bodies every step); in between the
  line's whole derivative (velocities and accelerations) is reused, and so are the end forces and
  masses it hands to its points and rods (``LineArrays.calc``). It runs as the time loop's Euler
  step between :func:`leuler_begin` and :func:`leuler_end`;
- ``ACA<M>``: Newmark's average constant acceleration (gamma 1/2, beta 1/4) by M relaxed
  fixed-point iterations on the end-of-step derivative;
- ``Wilson<M>``: Wilson-theta (theta 1.37) the same way, evaluated at t + theta h and brought back.

The scheme parameters ``sp`` (see :func:`moorline.core.integrate.parse_scheme`):
[c, M, c0, c1, AB order, steps taken, gamma or theta, beta, then for LEuler the update interval
of every line followed by the time since its last update]. ``S`` is (5, n) scratch; ``S[3]``
holds the derivative the scheme carries between steps (zero at the start), ``S[0]`` for LEuler.
"""

from __future__ import annotations

import math

from .jit import kernel
from .rhs import rhs_call

SP_ORDER = 4
SP_STEPS = 5
SP_GAMMA = 6  # Newmark gamma, Wilson theta
SP_BETA = 7
SP_LINES = 8  # LEuler: line update intervals, then times since the last update


@kernel
def relax_factor(m, M, c0, c1):
    """MoorDyn's relaxation of iteration ``m`` of ``M``."""
    return c0 * (1.0 - 1.0 / M) + c1 * (1.0 - 0.5 * (math.tanh(4.0 * ((m + 1.0) / M - 0.5)) + 1.0))


@kernel(inline="always")
def heun_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    f_old = S[3]
    f = S[0]
    for i in range(y.size):
        y[i] += h * f_old[i]
    B.ctl[1] = 1
    rhs_call(t, y, f, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
    B.ctl[1] = 0
    for i in range(y.size):
        y[i] += 0.5 * h * (f[i] - f_old[i])
        f_old[i] = f[i]


@kernel(inline="always")
def ab_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    # the past derivatives live in S[1..3] (newest first), the new one in S[4] (scratch between
    # steps, where the time loop's final evaluation also goes)
    order = int(sp[SP_ORDER])
    n = int(sp[SP_STEPS])
    f0 = S[4]
    f1 = S[1]
    f2 = S[2]
    f3 = S[3]
    B.ctl[1] = 1
    rhs_call(t, y, f0, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
    B.ctl[1] = 0
    if n == 0:
        for i in range(y.size):
            y[i] += h * f0[i]
    elif n == 1:
        for i in range(y.size):
            y[i] += h * (1.5 * f0[i] - 0.5 * f1[i])
    elif n == 2:
        for i in range(y.size):
            y[i] += h * (23.0 * f0[i] - 16.0 * f1[i] + 5.0 * f2[i]) / 12.0
    else:
        for i in range(y.size):
            y[i] += h * (55.0 * f0[i] - 59.0 * f1[i] + 37.0 * f2[i] - 9.0 * f3[i]) / 24.0
    for i in range(y.size):
        f3[i] = f2[i]
        f2[i] = f1[i]
        f1[i] = f0[i]
    sp[SP_STEPS] = min(n + 1, order - 1)


@kernel
def leuler_begin(h, sp, node_ptr, calc):
    """Local-time-step Euler, before its derivative: flag (``calc``) the lines whose update
    interval has elapsed since their last update (all of them at the first step)."""
    nl = node_ptr.size - 1
    first = sp[SP_STEPS] == 0.0
    for li in range(nl):
        dt0 = sp[SP_LINES + li]
        acc = sp[SP_LINES + nl + li] + h
        if first or acc >= dt0:
            sp[SP_LINES + nl + li] = h
            calc[li] = 1
        else:
            sp[SP_LINES + nl + li] = acc
            calc[li] = 0


@kernel
def leuler_end(sp, calc):
    """Local-time-step Euler, after its derivative: every line is flagged for evaluation again
    (what every other caller of the derivative expects). The derivative was written into the
    row the scheme carries (``S[0]``), and the derivative leaves a line not evaluated now its
    rows there from its last update (velocities and accelerations alike, as MoorDyn-C does), so
    nothing is copied; the Euler update ``y += h f`` follows in the caller."""
    for li in range(calc.size):
        calc[li] = 1
    sp[SP_STEPS] = 1.0


@kernel
def _newmark_state(y0, d0, d1, out, R, mult, P, pa, pb, qa, qb):
    """out = y0 + mult * (v', a'): positions move by mult (v0 + P (pa a0 + pb a1)), velocities by
    mult (qa a0 + qb a1), first-order states by mult (qa x0' + qb x1'). ``d0``, ``d1``: the
    derivatives at the start and at the iterate; v0 is d0's position rate. 6-DOF blocks turn their
    quaternion with the angular velocity w0 + P (pa alpha0 + pb alpha1), w0 from d0's quaternion rate."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    for i in range(3 * n3):
        out[i] = y0[i] + mult * (d0[i] + P * (pa * d0[uoff + i] + pb * d1[uoff + i]))
        out[uoff + i] = y0[uoff + i] + mult * (qa * d0[uoff + i] + qb * d1[uoff + i])
    for j in range(n6):
        oq = 3 * n3 + 7 * j
        ou = uoff + 3 * n3 + 6 * j
        for c in range(3):
            out[oq + c] = y0[oq + c] + mult * (d0[oq + c] + P * (pa * d0[ou + c] + pb * d1[ou + c]))
        # w0 = 2 Im(qdot conj(Q)) from the quaternion rate of d0 at the quaternion of y0
        qw = y0[oq + 3]
        qx = y0[oq + 4]
        qy = y0[oq + 5]
        qz = y0[oq + 6]
        dw = d0[oq + 3]
        dx = d0[oq + 4]
        dyy = d0[oq + 5]
        dz = d0[oq + 6]
        nq = qw * qw + qx * qx + qy * qy + qz * qz
        wx = 2.0 * (-dw * qx + dx * qw - dyy * qz + dz * qy) / nq
        wy = 2.0 * (-dw * qy + dx * qz + dyy * qw - dz * qx) / nq
        wz = 2.0 * (-dw * qz - dx * qy + dyy * qx + dz * qw) / nq
        wx += P * (pa * d0[ou + 3] + pb * d1[ou + 3])
        wy += P * (pa * d0[ou + 4] + pb * d1[ou + 4])
        wz += P * (pa * d0[ou + 5] + pb * d1[ou + 5])
        out[oq + 3] = qw + mult * (-0.5 * (wx * qx + wy * qy + wz * qz))
        out[oq + 4] = qx + mult * 0.5 * (wx * qw + wy * qz - wz * qy)
        out[oq + 5] = qy + mult * 0.5 * (wy * qw + wz * qx - wx * qz)
        out[oq + 6] = qz + mult * 0.5 * (wz * qw + wx * qy - wy * qx)
        for c in range(6):
            out[ou + c] = y0[ou + c] + mult * (qa * d0[ou + c] + qb * d1[ou + c])
    for i in range(uoff + 3 * n3 + 6 * n6, y0.size):
        out[i] = y0[i] + mult * (qa * d0[i] + qb * d1[i])


@kernel(inline="always")
def newmark_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    """MoorDyn's ACA<M>: Newmark (gamma, beta) with M relaxed fixed-point iterations on the
    derivative at the end of the step; the last iterate's derivative is kept for the next step."""
    M = int(sp[1])
    c0 = sp[2]
    c1 = sp[3]
    gamma = sp[SP_GAMMA]
    beta = sp[SP_BETA]
    d0 = S[3]
    d1 = S[0]
    d2 = S[1]
    y1 = S[4]
    for i in range(y.size):
        d1[i] = d0[i]
        d2[i] = d0[i]
    for m in range(M):
        _newmark_state(y, d0, d1, y1, R, h, h, 0.5 - beta, beta, 1.0 - gamma, gamma)
        B.ctl[1] = 1 if m == 0 else 0
        rhs_call(t + h, y1, d1, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
        if m < M - 1:
            rel = relax_factor(m, M, c0, c1)
            for i in range(y.size):
                d1[i] = (1.0 - rel) * d1[i] + rel * d2[i]
                d2[i] = d1[i]
    B.ctl[1] = 0
    _newmark_state(y, d0, d1, y1, R, h, h, 0.5 - beta, beta, 1.0 - gamma, gamma)
    for i in range(y.size):
        y[i] = y1[i]
        d0[i] = d1[i]


@kernel(inline="always")
def wilson_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    """MoorDyn's Wilson<M> (theta = sp[6]): M relaxed fixed-point iterations at t + theta h (which,
    as in MoorDyn, relax the start derivative itself), then the state brought back to t + h."""
    M = int(sp[1])
    c0 = sp[2]
    c1 = sp[3]
    theta = sp[SP_GAMMA]
    tdt = theta * h
    d0 = S[3]
    d1 = S[0]
    y1 = S[4]
    for i in range(y.size):
        d1[i] = d0[i]
    for m in range(M):
        _newmark_state(y, d0, d1, y1, R, tdt, 0.5 * tdt, 2.0 / 3.0, 1.0 / 3.0, 0.5, 0.5)
        B.ctl[1] = 1 if m == 0 else 0
        rhs_call(t + tdt, y1, d1, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
        if m < M - 1:
            rel = relax_factor(m, M, c0, c1)
            for i in range(y.size):
                d0[i] = (1.0 - rel) * d0[i] + rel * d1[i]
                d1[i] = d0[i]
    B.ctl[1] = 0
    f = 1.0 / theta
    _newmark_state(y, d0, d1, y1, R, h, 0.5 * tdt, 1.0 - f / 3.0, f / 3.0, 1.0 - 0.5 * f, 0.5 * f)
    for i in range(y.size):
        y[i] = y1[i]
        d0[i] = d1[i]
