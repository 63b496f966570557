"""Static kernels of the dynamic model: MoorDyn's stationary solver and its legacy dynamic
relaxation (spec section 6), and Newton statics (pseudo-transient Newton with the implicit
scheme's Jacobian). The strategies that use them are in :mod:`moorline.system.initial`; the
quasi-static line model is :mod:`moorline.quasistatic`.
"""

from __future__ import annotations

import copy
import logging
import math

import numpy as np

from .integrate import FINAL_END, advance
from .jacobian import S_NJAC, S_NRHS, assemble, clear, copy2, displace, factor, fd_steps, shift_colour, solve_increment
from .jit import compile_for, fast_typeof, kernel
from .linestates import xs_offset
from .rhs import rhs_call

log = logging.getLogger(__name__)

#: Newton statics stops as converged after this many iterations in a row with every residual
#: acceleration at or below its tolerance, although its position updates stay above theirs: a node
#: at the kink of MoorDyn's seabed contact law (full stiffness from zero penetration, none above)
#: is stepped across it and back by a full Newton step on each side, 1e-8 to 1e-6 m, and never
#: settles (the lazy-wave benchmark cable: 398 iterations in a row below the residual tolerance,
#: then the 400-iteration budget ran out and a dynamic relaxation followed). The iterate of the
#: run with the smallest residual is kept.
STALL_ITERS = 10
#: finite-difference step of Newton statics' Jacobian, relative to each coordinate (at least 1 m).
#: It must be small against the smallest feature of the residual near the equilibrium: the stretch
#: of a segment near a free hanging end, where the tension falls to the end node's weight, sits
#: that close to the slack kink (no tension when compressed): 4.4e-8 m on MoorDyn's
#: test_dynamic_currents.txt with its segments doubled (0.25 m of 1.1 kg/m chain, EA 7.5 MN). A
#: step of 1e-7 x 40 m straddled it, so shortening a segment by the step made it slack and the
#: Jacobian held it a hundred times too soft: Newton stayed at 12 m/s^2 for hundreds of
#: iterations and the start failed. 1e-10 of the coordinate is still 4.5e5 times the round-off of
#: the perturbed coordinate (and of the segment lengths it changes): the differences keep five to
#: six digits, which Newton does not notice.
STATIC_FD_REL = 1e-10

# -1 (evaluate the coupled trajectory on the piece that holds t), passed as np.int64(-1) in the
# kernels: the literal -1 would make numba compile rhs once more for the type Literal[int](-1)


@kernel
def _accel_norm_sum(dy, n3, n6):
    """Sum of the acceleration norms of the 3-DOF rows, plus |a| + |alpha| of each 6-DOF block."""
    uoff = 3 * n3 + 7 * n6
    s = 0.0
    for r in range(n3):
        o = uoff + 3 * r
        s += math.sqrt(dy[o] ** 2 + dy[o + 1] ** 2 + dy[o + 2] ** 2)
    for j in range(n6):
        o = uoff + 3 * n3 + 6 * j
        s += math.sqrt(dy[o] ** 2 + dy[o + 1] ** 2 + dy[o + 2] ** 2)
        s += math.sqrt(dy[o + 3] ** 2 + dy[o + 4] ** 2 + dy[o + 5] ** 2)
    return s


@kernel
def _move_along(y, dy, n3, n6, h):
    """Pseudo-time move of the positions along the accelerations: q += h a for 3-DOF rows and
    block positions; block orientations turn by h alpha (quaternion renormalised)."""
    uoff = 3 * n3 + 7 * n6
    for i in range(3 * n3):
        y[i] += h * dy[uoff + i]
    for j in range(n6):
        oq = 3 * n3 + 7 * j
        ou = uoff + 3 * n3 + 6 * j
        for c in range(3):
            y[oq + c] += h * dy[ou + c]
        wx = h * dy[ou + 3]
        wy = h * dy[ou + 4]
        wz = h * dy[ou + 5]
        w = y[oq + 3]
        x = y[oq + 4]
        yy = y[oq + 5]
        z = y[oq + 6]
        nw = w - 0.5 * (wx * x + wy * yy + wz * z)
        nx = x + 0.5 * (wx * w + wy * z - wz * yy)
        ny = yy + 0.5 * (wy * w + wz * x - wx * z)
        nz = z + 0.5 * (wz * w + wx * yy - wy * x)
        n = math.sqrt(nw * nw + nx * nx + ny * ny + nz * nz)
        y[oq + 3] = nw / n
        y[oq + 4] = nx / n
        y[oq + 5] = ny / n
        y[oq + 6] = nz / n


@kernel
def at_rest(y, R):
    """The statics' state: velocities (of nodes, points, rods and bodies) and radiation states
    zero; the line states after them (Syrope slow strain: history) are kept."""
    uoff = 3 * R.dims[0] + 7 * R.dims[1]
    for i in range(uoff, xs_offset(R)):
        y[i] = 0.0


@kernel
def stationary_solve(y, dtM, dtIC, TmaxIC, threshIC, cfl_ic, seg_min, L, R, P, E, B, Mo, W, F, FW, S):
    """MoorDyn's stationary initial-condition solver (spec 6.3): pseudo-time steps along the
    accelerations with all velocities held at zero (6-DOF objects also turn along their angular
    accelerations).

    Returns
    -------
    status : int
        1: converged (error below threshIC of its first value, or zero); 2: the error stalled
        (relative change over dtIC below threshIC; MoorDyn stops there too); 0: TmaxIC reached;
        -1: non-finite state.
    t : float
        Pseudo time used [s].
    E_mean : float
        Final sum of acceleration norms divided by the number of state rows and blocks [m/s^2].
    iterations : int
    """
    n3 = R.dims[0]
    n6 = R.dims[1]
    nrow = n3 + n6
    uoff = 3 * n3 + 7 * n6
    if nrow == 0:
        return 1, 0.0, 0.0, 0
    dy = S[0]
    qprev = S[1]
    at_rest(y, R)
    b = 1.0
    t = 0.0
    e0 = -1.0
    e_last = np.inf
    e_check = -1.0
    next_check = dtIC
    it = 0
    while True:
        rhs_call(0.0, y, dy, L, R, P, E, B, Mo, W, F, FW, 1.0, np.int64(-1))
        e = _accel_norm_sum(dy, n3, n6)
        if e0 < 0.0:
            e0 = e
        if e > e_last:
            b /= 1.01
            for i in range(uoff):
                y[i] = 0.5 * (y[i] + qprev[i])
            rhs_call(0.0, y, dy, L, R, P, E, B, Mo, W, F, FW, 1.0, np.int64(-1))
            e = _accel_norm_sum(dy, n3, n6)
        else:
            b *= 1.01
        b = min(max(b, 0.1), 50.0)
        e_last = e
        if not np.isfinite(e):
            return -1, t, e / nrow, it
        dte = b * dtM
        if e > 0.0:
            lim = cfl_ic * seg_min / (0.5 * dtM * e)
            if lim < dte:
                dte = lim
        for i in range(uoff):
            qprev[i] = y[i]
        _move_along(y, dy, n3, n6, dte * 0.5 * dtM)
        t += dtM
        it += 1
        if t >= next_check - 1e-12:
            next_check += dtIC
            if e == 0.0 or e / e0 < threshIC:
                return 1, t, e / nrow, it
            if e_check > 0.0 and abs(e_check - e) / e_check < threshIC:
                return 2, t, e / nrow, it
            e_check = e
        if t >= TmaxIC:
            return 0, t, e / nrow, it


@kernel(inline="always")
def _fairlead_tensions(L, W, out):
    for li in range(L.seg_ptr.size - 1):
        s = L.seg_ptr[li + 1] - 1
        fx = W.T[s, 0] + W.Td[s, 0]
        fy = W.T[s, 1] + W.Td[s, 1]
        fz = W.T[s, 2] + W.Td[s, 2]
        out[li] = math.sqrt(fx * fx + fy * fy + fz * fz)


@kernel
def dynamic_relaxation(y, dtM, scheme, sp, dtIC, TmaxIC, threshIC, cd_scale, L, R, P, E, B, Mo, W, F, FW, S, vmax, H):
    """MoorDyn's legacy initial-condition solver (spec 6.4): integrate with drag scaled by
    ``cd_scale`` until the end-B tension of every line changes by less than ``threshIC``
    (relative) over ten samples ``dtIC/10`` apart. ``H``: (11, n_lines) scratch (kernels
    allocate nothing).

    Returns (converged, t, bad_row)."""
    nl = L.seg_ptr.size - 1
    nwin = 10
    hist = H[:nwin]
    ten = H[nwin]
    for k in range(nwin):
        for li in range(nl):
            hist[k, li] = 0.0
    dtc = dtIC / 10.0
    t = 0.0
    ns = 0
    while t < TmaxIC - 1e-12:
        t1 = min(t + dtc, TmaxIC)
        # FINAL_END: the Work arrays then hold the loads of the state at t1
        t, bad, _, _ = advance(y, t, t1, dtM, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, vmax,
                               np.int64(FINAL_END))
        if bad >= 0:
            return False, t, bad
        _fairlead_tensions(L, W, ten)
        for k in range(nwin - 1):
            for li in range(nl):
                hist[k, li] = hist[k + 1, li]
        for li in range(nl):
            hist[nwin - 1, li] = ten[li]
        ns += 1
        if ns >= nwin:
            ok = True
            for li in range(nl):
                for k in range(nwin - 1):
                    ref = abs(hist[k, li])
                    if abs(ten[li] - hist[k, li]) > threshIC * max(ref, 1e-12):
                        ok = False
            if ok:
                return True, t, -1
    return False, t, -1


# ---------------------------------------------------------------------------------------------- Newton statics
@kernel
def _static_residual(IW, uoff):
    """After an evaluation into IW.f0: -f's accelerations into IW.G, the evaluation counted.
    Returns (max |acc|, L2 norm); inf for a non-finite one."""
    IW.stat[S_NRHS] += 1
    big = 0.0
    s = 0.0
    for i in range(IW.G.size):
        g = IW.f0[uoff + i]
        IW.G[i] = -g
        s += g * g
        if abs(g) > big or not np.isfinite(g):
            big = abs(g) if np.isfinite(g) else np.inf
    return big, math.sqrt(s)


@kernel
def _colour_state(A, IW, y, cu, k, n3, n6):
    """The state of one finite-difference column group of Newton statics' Jacobian: ``y`` = IW.y0
    displaced along component ``k`` of the nodes of colour ``cu``. False if the colour has no
    such component (nothing to evaluate)."""
    dq = IW.da
    for i in range(IW.a1.size):
        dq[i] = 0.0
    if not shift_colour(A, cu, k, dq, IW.eps, 1.0):
        return False
    for i in range(y.size):
        y[i] = IW.y0[i]
    displace(IW.y0, dq, y, n3, n6, 1.0)
    return True


@kernel
def _colour_columns(A, IW, uoff, cu, k, diag):
    """Assemble the Jacobian's columns of one group from the evaluation at its state (IW.f1)."""
    IW.stat[S_NRHS] += 1
    assemble(A, IW, IW.f0, IW.f1, uoff, cu, k, diag, 1.0, IW.eps)


@kernel
def _static_factor(A, IW, y, rawAB, rawBB, diag, keep):
    """``y`` back to IW.y0 and the Jacobian factored with ``diag`` on its diagonal. Its
    finite-difference part, assembled with a zero diagonal, is kept in ``rawAB``/``rawBB``
    (``keep``: a new Jacobian, counted) or taken back from them (a retry with another diagonal:
    the LU overwrote the band). The border blocks LBt and BL hold no diagonal and the LU leaves
    them as they are. Adding ``diag`` to the kept -df/dx gives the numbers of an assembly with it,
    bit for bit (x + 0 + d = x + d). Returns LU's status."""
    for i in range(y.size):
        y[i] = IW.y0[i]
    if keep:
        IW.stat[S_NJAC] += 1
        copy2(IW.AB, rawAB)
        copy2(IW.BB, rawBB)
    else:
        copy2(rawAB, IW.AB)
        copy2(rawBB, IW.BB)
    kv = A.band[0] + A.band[1]
    nl = IW.a1.size - A.band[2]
    for i in range(IW.a1.size):
        p = A.pinv[i]
        if p < nl:
            IW.AB[kv, p] += diag
        else:
            IW.BB[p - nl, p - nl] += diag
    return factor(A, IW)


class StaticEval:
    """Newton statics' evaluations: the residual, and J = diag I - df/dx at IW.y0 (zero
    velocities) by coloured finite differences, factored.

    The loops over the colours run in Python around compiled pieces that call the derivative
    from Python (its kept entry point, :func:`moorline.core.jit.compile_for`), not in one compiled
    kernel: a kernel that calls ``rhs_call`` is compiled with the derivative's whole closure
    linked in and optimised once more for it, some 9 s of CPU time of a first run for the README
    example (benchmarks/RESULTS.md, first-run section); here the Python costs a few
    microseconds per evaluation of a derivative that is evaluated a few hundred times.
    """

    def __init__(self, y, A, IW, L, R, P, E, B, Mo, W, F, FW):
        self.y, self.A, self.IW = y, A, IW
        self.n3 = int(R.dims[0])
        self.n6 = int(R.dims[1])
        self.uoff = 3 * self.n3 + 7 * self.n6
        self.R = R
        self.nt = (L, R, P, E, B, Mo, W, F, FW)
        # the compiled entry points, called directly: a dispatcher's call types its NamedTuple
        # arguments in Python first, some microseconds per call
        self.rhs = compile_for(rhs_call, (0.0, y, IW.f0, *self.nt, 1.0, np.int64(-1)))
        n3, n6 = self.n3, self.n6
        self.velocities = compile_for(at_rest, (y, R))
        self.res = compile_for(_static_residual, (IW, self.uoff))
        self.fd_steps = compile_for(fd_steps, (IW, n3, n6, STATIC_FD_REL, 1.0))
        self.clear = compile_for(clear, (IW,))
        self.state = compile_for(_colour_state, (A, IW, y, 0, 0, n3, n6))
        self.columns = compile_for(_colour_columns, (A, IW, self.uoff, 0, 0, 1.0))
        # -df/dx of the last Jacobian, kept for a retry with another diagonal
        self.rawAB = np.empty_like(IW.AB)
        self.rawBB = np.empty_like(IW.BB)
        self.factor = compile_for(_static_factor, (A, IW, y, self.rawAB, self.rawBB, 1.0, True))

    def with_env(self, E) -> StaticEval:
        """The same evaluations in the environment ``E`` instead, with the compiled entry points
        kept: looking them up types every NamedTuple of arrays again, 3-4 ms a time, which a
        continuation of several Newton solves (:func:`moorline.system.initial.newton_ic`) paid
        on every one. ``E`` must have the type of the environment given (a ``_replace`` of it
        with values of the same types, such as a softened seabed), which is checked."""
        L, R, P, E0, B, Mo, W, F, FW = self.nt
        if E is E0:
            return self
        if fast_typeof(E) != fast_typeof(E0):
            raise TypeError("StaticEval.with_env: the environment's numba type differs from the one the entry "
                            "points were compiled for")
        other = copy.copy(self)
        other.nt = (L, R, P, E, B, Mo, W, F, FW)
        return other

    def residual(self) -> tuple[float, float]:
        """f at the positions of ``y`` with zero velocities (line states kept) into IW.f0 and -f's
        accelerations into IW.G. Returns (max |acc|, L2 norm)."""
        y, IW = self.y, self.IW
        self.velocities(y, self.R)
        self.rhs(0.0, y, IW.f0, *self.nt, 1.0, np.int64(-1))
        return self.res(IW, self.uoff)

    def jacobian(self, diag: float) -> int:
        """J = diag I - df/dx at IW.y0, factored (IW.f0 must hold f at IW.y0; ``y`` is left at
        IW.y0). Returns LU's status (0 factored)."""
        y, A, IW, n3, n6, uoff = self.y, self.A, self.IW, self.n3, self.n6, self.uoff
        self.fd_steps(IW, n3, n6, STATIC_FD_REL, 1.0)
        self.clear(IW)
        kmax = 6 if n6 > 0 else 3
        rhs, nt, f1, state, columns = self.rhs, self.nt, IW.f1, self.state, self.columns
        piece = np.int64(-1)
        for cu in range(A.col_ptr.size - 1):
            for k in range(kmax):
                if state(A, IW, y, cu, k, n3, n6):
                    rhs(0.0, y, f1, *nt, 1.0, piece)
                    columns(A, IW, uoff, cu, k, 0.0)
        return int(self.factor(A, IW, y, self.rawAB, self.rawBB, float(diag), True))

    def refactor(self, diag: float) -> int:
        """The last :meth:`jacobian`'s -df/dx (still at IW.y0) with ``diag`` on the diagonal
        instead, factored, without evaluating the derivative again. ``y`` is left at IW.y0.
        Returns LU's status."""
        return int(self.factor(self.A, self.IW, self.y, self.rawAB, self.rawBB, float(diag), False))


def newton_statics(y, A, IW, L, R, P, E, B, Mo, W, F, FW, tau0, acc_tol, dx_tol, max_iter, min_growth=1.0,
                   ev: StaticEval | None = None):
    """Static equilibrium by pseudo-transient continuation of Newton's method: each iteration
    solves (I / tau^2 - df/dx) dx = f(x) at zero velocities, with tau^2 grown by the ratio of
    successive residual norms (switched evolution relaxation) so the iterations start as heavily
    damped dynamics from a poor guess and end as plain Newton. An iteration that more than doubles
    the residual is rejected and retried with tau^2 / 4. With ``min_growth`` > 1, an iteration that
    lowers the residual grows tau^2 by at least that factor, so that a system whose residual falls
    slowly (a touchdown creeping along a chain, one node per few iterations) is not held at small
    steps (:func:`moorline.system.initial.newton_ic` uses 2).

    The loop is Python around compiled kernels (:class:`StaticEval`, ``solve_increment``,
    ``displace``): it runs a few tens of iterations of milliseconds each, so the Python costs
    nothing that counts, while a compiled loop cost a first run some 13 s of compile time (the
    derivative's closure optimised once more for it).

    ``ev``: the :class:`StaticEval` of these arrays, when the caller keeps one over several solves
    (made here otherwise).

    Returns
    -------
    status : int
        1 converged (max residual acceleration <= ``acc_tol`` [m/s^2] and the last position
        update <= ``dx_tol`` [m], or the residual within ``acc_tol`` for :data:`STALL_ITERS`
        iterations in a row: then the iterate with the smallest residual), 0 not within
        ``max_iter`` iterations, -1 singular or non-finite.
    iterations : int
    residual : float
        Max residual acceleration at the end [m/s^2].
    """
    n3 = int(R.dims[0])
    n6 = int(R.dims[1])
    if ev is None:
        ev = StaticEval(y, A, IW, L, R, P, E, B, Mo, W, F, FW)
    residual = ev.residual
    jacobian = ev.jacobian

    tau2 = tau0 * tau0
    big, nrm = residual()
    if not np.isfinite(nrm):
        return -1, 0, big
    dxmax = np.inf
    it = 0
    small = 0  # iterations in a row with the residual within tolerance
    best = np.inf
    y_best = np.empty_like(y)
    while it < max_iter:
        if big <= acc_tol and dxmax <= dx_tol:
            return 1, it, big
        if big <= acc_tol:
            small += 1
            if big < best:
                best = big
                y_best[:] = y
            if small > STALL_ITERS:
                y[:] = y_best
                big, nrm = residual()
                log.info("Newton statics: residual within %.3g m/s^2 for %d iterations, position updates "
                         "still %.2g m (above %.2g: a node cycling across the seabed contact's kink); "
                         "the iterate with the smallest residual, %.3g m/s^2, is taken", acc_tol, STALL_ITERS,
                         dxmax, dx_tol, big)
                return 1, it, big
        else:
            small = 0
        IW.y0[:y.size] = y
        # IW.f0 holds f at y0
        if jacobian(1.0 / tau2) != 0:
            return -1, it, big
        while True:
            solve_increment(A, IW)
            it += 1
            dxmax = float(np.max(np.abs(IW.da), initial=0.0, where=~np.isnan(IW.da)))
            displace(IW.y0, IW.da, y, n3, n6, 1.0)
            big1, nrm1 = residual()
            if np.isfinite(nrm1) and (nrm1 <= 2.0 * nrm or tau2 < 1e-12):
                break
            # reject: back to y0 with a smaller pseudo step, on the same -df/dx (a Jacobian costs
            # one evaluation per colour and component: 9-27 here, against the one of residual())
            y[:] = IW.y0[:y.size]
            tau2 *= 0.25
            if it >= max_iter:
                return 0, it, big
            residual()
            if ev.refactor(1.0 / tau2) != 0:
                return -1, it, big
        if not np.isfinite(nrm1):
            return -1, it, big1
        ratio = nrm / nrm1 if nrm1 > 0.0 else 1e6
        if nrm1 < nrm:
            ratio = max(ratio, min_growth)
        tau2 *= min(max(ratio, 0.1), 1e3)
        if tau2 > 1e30:
            tau2 = 1e30
        big = big1
        nrm = nrm1
    if big <= acc_tol and dxmax <= dx_tol:
        return 1, it, big
    return 0, it, big
