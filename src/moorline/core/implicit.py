"""Implicit time integration: generalized-alpha with Newton iterations.

The Newton iterations solve with the sparse, coloured finite-difference Jacobian of
:mod:`.jacobian` (the accelerations of the step are the unknowns).

Generalized-alpha (Chung & Hulbert 1993) on ``a = f(t, x, v)`` (``f``: the system's accelerations,
the node mass matrices already inverted by ``rhs``), in the form that weights the derivatives at
the two ends of the step rather than evaluating one derivative at a weighted state (Arnold & Bruls
2007; the HHT form of Abaqus)::

    x1 = x0 + h v0 + h^2 ((1/2 - beta) a0 + beta a1)        v1 = v0 + h ((1 - gamma) a0 + gamma a1)
    (1 - alpha_m) a1 + alpha_m a0 = (1 - alpha_f) f(t0 + h, x1, v1) + alpha_f f0

with f0 = f(t0, x0, v0) (carried over from the previous step as the value its equation implies),
alpha_m = (2 rho - 1)/(rho + 1), alpha_f = rho/(rho + 1), gamma = 1/2 - alpha_m + alpha_f,
beta = (1 - alpha_m + alpha_f)^2 / 4: second-order accurate and unconditionally stable for linear
systems, with spectral radius ``rho`` (``rho_inf``) at infinite frequency (1: no numerical
damping; 0: the highest modes are annihilated in one step); ``a`` is an algorithmic acceleration
(second-order close to the true one at t + (alpha_m - alpha_f) h). Orientations of 6-DOF blocks
advance through the rotation vector: q1 = exp(theta) q0 with theta the Newmark increment of the
global angular velocity.

Why the derivatives and not the state are weighted: lines are axially stiff (a 5 m segment of a
cable with EA 2e7 N stretches 1 mm per 4 kN), so the tension is set by millimetre differences
between node positions. Evaluated at the weighted state (1 - alpha_f) x1 + alpha_f x0 and the
time t0 + (1 - alpha_f) h, the coupled end sits at X(t0 + (1 - alpha_f) h) while the line nodes
sit on the chord between their end-of-step positions, which is off the trajectory by
alpha_f (1 - alpha_f) h^2 X''/2; a segment turning at a rate w is shortened the same way by
alpha_f (1 - alpha_f) (w h)^2 l/2. The stiff segments follow these spurious stretches, and at the
end of the step the tension is off by about EA/l alpha_f h^2 X''/(2 (1 + rho)) (a lazy-wave cable in
2 m, 8 s heave: 50 % of the fairlead tension at h = 0.1 s). With both derivatives evaluated at
states the scheme actually reaches, the stiff (quasi-static) response is exact at every step end.

Newton iterations reuse the factored Jacobian across steps (modified Newton), with the seabed
contact terms of the internal line nodes followed analytically at every iteration
(:func:`~.jacobian.contact_terms`, :func:`~.jacobian.refactor`). The Jacobian is rebuilt only
when the step size changed, the contraction of the increments (theta) predicts too many further
iterations, or a step backtracked twice; convergence is tested
on the estimated error theta / (1 - theta) |da| (Hairer & Wanner). A step that does not converge is
retried with half the step (down to ``dtM / 2**12``), and the step grows back by doubling after a
run of easy steps. Tolerances: ``atol_x`` [m or rad] on positions, ``atol_v`` [m/s or rad/s] on
velocities.
"""

from __future__ import annotations

import math

import numpy as np

from .features import FLOATING, LINE_STATES, when
from .floating import floating_after_step
from .integrate import RHO_INF, check_state, knot_step, step_end
from .jacobian import (
    N_STAT,
    S_AVALID,
    S_EASY,
    S_H,
    S_HJ,
    S_HPREV,
    S_NBACK,
    S_NIT,
    S_NREJ,
    S_NRHS,
    S_NSLOW,
    S_NSTEP,
    S_WORST,
    ImplicitArrays,
    ImplicitWork,
    colour_units,
    contact_moved,
    contact_terms,
    dependency_graph,
    newmark_radiation,
    refactor,
    solve_increment,
    step_jacobian,
)
from .jit import kernel
from .layout import Layout
from .linestates import MODE_RATE, XC_MODE, end_line_states, keep_rates, start_line_states, store_line_states
from .rhs import motion_eval, motion_piece, rhs_call

#: the Jacobian is rebuilt when the contraction of the Newton increments is at least THETA_MAX, or
#: predicts more further iterations than SLOW_ITER or, if more, SLOW_SHARE times the derivative
#: evaluations of a Jacobian (one per colour and component: 9 on the OC3 chain, 27 on the lazy-wave
#: cable of benchmarks/decks, whose bending and rods need more colours). A modified-Newton
#: iteration costs about one evaluation, so a system whose Jacobian costs more waits longer before
#: rebuilding it: on that cable (GenAlpha, 34 segments, 0.2 s) a threshold of 4 built 111
#: Jacobians in 300 steps and took 43.5 ms, 6-12 built 70-88 and took 37.4-37.7 ms
#: (benchmarks/RESULTS.md section 6, session 10)
THETA_MAX = 0.9
SLOW_ITER = 4.0
SLOW_SHARE = 1.0 / 3.0
#: a residual growing by more than this factor over an iteration starts a backtracking line search
GROWTH = 1.0
#: the iterations start from a1 = a0 + PREDICTOR (h / h_prev) (a0 - a_prev): half the linear
#: extrapolation of the accelerations (OC3 chain, 15 segments, dt 0.1 s: 11 % fewer derivative
#: evaluations than the constant start a1 = a0; the full extrapolation overshoots at landings)
PREDICTOR = 0.5


def gen_alpha_parameters(rho: float) -> tuple[float, float, float, float]:
    """(alpha_m, alpha_f, beta, gamma) of Chung & Hulbert for spectral radius ``rho``."""
    am = (2.0 * rho - 1.0) / (rho + 1.0)
    af = rho / (rho + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, beta, gamma


#: default tolerance of the seabed contact update of the Jacobian (see :func:`gen_alpha_step`)
CONTACT_TOL = 0.1


def jacobian_evaluations(ncomp, col_ptr, col_units) -> int:
    """Derivative evaluations of one coloured Jacobian: per colour, one per component of its widest
    unit (``ImplicitArrays`` ``ncomp``, ``col_ptr``, ``col_units``)."""
    return sum(int(ncomp[col_units[col_ptr[c]:col_ptr[c + 1]]].max()) for c in range(col_ptr.size - 1))


def build_implicit(layout: Layout, rho: float = RHO_INF, atol_x: float = 1e-6, atol_v: float = 1e-5,
                   max_iter: int = 20, contact_tol: float = CONTACT_TOL) -> ImplicitArrays:
    """Structure of the implicit solve for ``layout``: colouring, banded order, and the internal line
    nodes whose seabed contact terms the Jacobian follows between rebuilds (``contact_tol`` 0: none)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    n3, n6 = layout.n_rows, layout.n_blocks
    nu = n3 + n6
    udof = np.array([3 * u for u in range(n3)] + [3 * n3 + 6 * j for j in range(n6)], dtype=np.int64)
    ncomp = np.array([3] * n3 + [6] * n6, dtype=np.int64)
    ndof = 3 * n3 + 6 * n6
    adj = dependency_graph(layout)
    adj_ptr = np.zeros(nu + 1, dtype=np.int64)
    adj_ptr[1:] = np.cumsum([len(a) for a in adj])
    adj_idx = np.array([v for a in adj for v in sorted(a)], dtype=np.int64)
    colour = colour_units(adj)
    nc = int(colour.max()) + 1 if nu else 0
    col_units = np.argsort(colour, kind="stable").astype(np.int64)
    col_ptr = np.zeros(nc + 1, dtype=np.int64)
    col_ptr[1:] = np.cumsum(np.bincount(colour, minlength=nc))
    # the solver's order: bodies (hubs that couple every line they carry) form a border of the last
    # DOFs, solved by their Schur complement; the rest is banded, in reverse Cuthill-McKee order unless
    # the natural order is narrower
    border_units = sorted(n3 + int(j) for j in layout.rigid.body_blk if j >= 0)
    is_border = np.zeros(nu, dtype=bool)
    is_border[border_units] = True
    lead_dofs = np.array([udof[u] + a for u in range(nu) if not is_border[u] for a in range(ncomp[u])],
                         dtype=np.int64)
    border_dofs = np.array([udof[u] + a for u in border_units for a in range(ncomp[u])], dtype=np.int64)
    nl = lead_dofs.size
    local = -np.ones(ndof, dtype=np.int64)
    local[lead_dofs] = np.arange(nl)
    rows, cols = [], []
    for u in range(nu):
        if is_border[u]:
            continue
        for v in adj[u]:
            if is_border[v]:
                continue
            for a in range(ncomp[u]):
                for b in range(ncomp[v]):
                    rows.append(local[udof[u] + a])
                    cols.append(local[udof[v] + b])
    rows = np.array(rows, dtype=np.int64)
    cols = np.array(cols, dtype=np.int64)

    def width(pos):
        d = pos[rows] - pos[cols] if rows.size else np.zeros(1, dtype=np.int64)
        return int(max(d.max(), 0)), int(max(-d.min(), 0))

    order = np.arange(nl, dtype=np.int64)  # leading DOFs (local numbers) in solver order
    kl, ku = width(order)
    if nl:
        g = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(nl, nl)).tocsr()
        rcm = np.asarray(reverse_cuthill_mckee(g, symmetric_mode=True), dtype=np.int64)
        pos = np.empty(nl, dtype=np.int64)
        pos[rcm] = np.arange(nl)
        kl2, ku2 = width(pos)
        if kl2 + ku2 < kl + ku:
            order, kl, ku = rcm, kl2, ku2
    perm = np.concatenate([lead_dofs[order], border_dofs]).astype(np.int64)
    pinv = np.empty(ndof, dtype=np.int64)
    pinv[perm] = np.arange(ndof)
    best = (perm, pinv)
    am, af, beta, gamma = gen_alpha_parameters(rho)
    slow = max(SLOW_ITER, SLOW_SHARE * jacobian_evaluations(ncomp, col_ptr, col_units))
    par = np.array([am, af, beta, gamma, atol_x, atol_v, float(max_iter), rho, 1.0, contact_tol, THETA_MAX,
                    slow, GROWTH, PREDICTOR])
    L = layout.lines
    cn_node, cn_dof, cn_area = [], [], []
    for li in range(len(layout.line_N)):
        n0, n1, s0 = int(L.node_ptr[li]), int(L.node_ptr[li + 1]), int(L.seg_ptr[li])
        for n in range(n0 + 1, n1 - 1):
            if L.node_row[n] >= 0:
                i = n - n0
                cn_node.append(n)
                cn_dof.append(3 * int(L.node_row[n]))
                cn_area.append(float(L.d[li]) * 0.5 * float(L.seg_l0[s0 + i - 1] + L.seg_l0[s0 + i]))
    return ImplicitArrays(udof, ncomp, adj_ptr, adj_idx, col_ptr, col_units, best[1], best[0],
                          np.array([kl, ku, border_dofs.size], dtype=np.int64), par, np.array(cn_node, dtype=np.int64),
                          np.array(cn_dof, dtype=np.int64), np.array(cn_area, dtype=float))


def new_implicit_work(layout: Layout, A: ImplicitArrays, dtM: float) -> ImplicitWork:
    ndof = A.udof.size and int(A.udof[-1] + A.ncomp[-1])
    n = layout.n_state
    kl, ku, nb = int(A.band[0]), int(A.band[1]), int(A.band[2])
    nl = ndof - nb
    z = np.zeros
    stat = z(N_STAT)
    stat[S_H] = dtM
    return ImplicitWork(z(ndof), z(ndof), z(ndof), z(ndof), z(ndof), z(n), z(ndof), z((3, layout.n_coupled_dof)),
                        z(n), z(n), z((2 * kl + ku + 1, max(nl, 1))), np.zeros(max(nl, 1), dtype=np.int64),
                        stat, z((2 * kl + ku + 1, max(nl, 1))), z(ndof), z((3, A.cn_node.size, 8)), z((nb, nl)),
                        z((nb, nl)), z((nb, nb)), z((nb, nl)), z((nb, nb)), np.zeros(nb, dtype=np.int64))


@kernel(inline="always")
def _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, F, FW, piece):
    """G = (1 - alpha_m) a1 + alpha_m a0 - (1 - alpha_f) f(t + h, x1, v1) - alpha_f fs; leaves y
    at the end-of-step state and its derivative in IW.f0."""
    par = A.par
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    newmark_radiation(IW.y0, IW.a0, IW.a1, h, par, y, R, W, F, FW, IW.G)
    rhs_call(t + h, y, IW.f0, L, R, P, E, B, Mo, W, F, FW, par[8], piece)
    IW.stat[S_NRHS] += 1
    am = par[0]
    af = par[1]
    G = IW.G
    for i in range(G.size):
        G[i] = (1.0 - am) * IW.a1[i] + am * IW.a0[i] - (1.0 - af) * IW.f0[uoff + i] - af * IW.fs[i]
    if par[9] > 0.0:
        cf = 1.0 - par[1]
        contact_terms(A, IW, E, B, W, par[2] * h * h * cf, par[3] * h * cf)


@kernel
def _norm2(v):
    s = 0.0
    for i in range(v.size):
        s += v[i] * v[i]
    return s


@kernel(inline="always")
def _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, F, FW, piece, commit):
    """fs = f(t, y) (the U part), with the stick-slip anchors committed when ``commit``; remembers
    the coupled kinematics it was evaluated with."""
    uoff = 3 * R.dims[0] + 7 * R.dims[1]
    if commit:
        B.ctl[1] = 1
    rhs_call(t, y, IW.f1, L, R, P, E, B, Mo, W, F, FW, A.par[8], piece)
    B.ctl[1] = 0
    IW.stat[S_NRHS] += 1
    for i in range(IW.fs.size):
        IW.fs[i] = IW.f1[uoff + i]
    if L.xs_f0.size > 0:
        when(W, LINE_STATES, keep_rates, (IW.f1, L, R))
    for j in range(W.xc.size):
        IW.ck[0, j] = W.xc[j]
        IW.ck[1, j] = W.vc[j]
        IW.ck[2, j] = W.ac[j]


@kernel(inline="always")
def _coupled_moved(IW, Mo, W, t, piece):
    """True when the coupled trajectory at ``t`` on ``piece`` is not where fs was evaluated (a
    knot with a velocity or acceleration jump, a new trajectory from the coupling). Evaluates the
    trajectory into W.xc, W.vc, W.ac, which the next derivative evaluation overwrites anyway."""
    ck = IW.ck
    if ck.shape[1] == 0:
        return False
    motion_eval(Mo, t, piece, W.xc, W.vc, W.ac)
    for j in range(ck.shape[1]):
        x = W.xc[j]
        v = W.vc[j]
        a = W.ac[j]
        if abs(x - ck[0, j]) > 1e-12 * (1.0 + abs(x)) or abs(v - ck[1, j]) > 1e-9 * (1.0 + abs(v)) or \
                abs(a - ck[2, j]) > 1e-9 * (1.0 + abs(a)):
            return True
    return False


@kernel(inline="always")
def gen_alpha_step(y, t, h, A, IW, L, R, P, E, B, Mo, W, F, FW, piece):
    """One generalized-alpha step of length ``h`` in place. Returns 0 on convergence, 1 when the
    Newton iterations did not converge (``y`` then restored to the start of the step).

    Modified Newton: the factored Jacobian is kept across iterations and steps. Its seabed contact
    terms follow the iterate (:func:`refactor`, no derivative evaluations); it is rebuilt by
    finite differences only when the step size changed, the residual grew, or the observed
    contraction of the increments (theta = |da_k| / |da_k-1|) predicts more than ``A.par[11]``
    further iterations (:data:`SLOW_ITER`, :data:`SLOW_SHARE`). Convergence: the error estimate
    theta / (1 - theta) |da_k| (Hairer and Wanner's test for Newton's method with a frozen
    Jacobian; |da_1| itself at the first iteration) below ``atol_x`` in position and ``atol_v`` in
    velocity."""
    par = A.par
    beta = par[2]
    gamma = par[3]
    atol_x = par[4]
    atol_v = par[5]
    max_iter = int(par[6])
    n = y.size
    nd = IW.a1.size
    for i in range(n):
        IW.y0[i] = y[i]
    # stick-slip friction anchors are committed at the state at the start of the step (which
    # moves the friction forces: the derivative there is evaluated again); otherwise the derivative
    # is evaluated again only when the coupled trajectory moved (one call site of rhs for both)
    commit = B.ctl[0] == 1
    if commit or _coupled_moved(IW, Mo, W, t, piece):
        _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, F, FW, piece, commit)
    hp = IW.stat[S_HPREV]
    w = par[13] * h / hp if hp > 0.0 else 0.0
    for i in range(nd):
        IW.a1[i] = IW.a0[i] + w * (IW.a0[i] - IW.ap[i])
    # viscoelastic stretch states are condensed by the trapezoidal rule inside the step map (when
    # a static solve has them condensed at rest, as during implicit relaxation, they stay so)
    nx = L.xs_s0.size if L.xs_ctl[XC_MODE] == MODE_RATE else 0
    if nx > 0:
        when(W, LINE_STATES, start_line_states, (y, L, R, h))
    hj = IW.stat[S_HJ]
    rebuild = hj <= 0.0 or abs(h - hj) > 1e-9 * h
    # increment size (in acceleration) that meets both tolerances
    tol = min(atol_x / (beta * h * h), atol_v / (gamma * h))
    n_built = 0
    n_back = 0
    fresh = False  # the factored Jacobian was built at an iterate of this step
    prev = 0.0
    gprev = np.inf
    it = 0
    while it < max_iter:
        _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, F, FW, piece)
        gnorm = _norm2(IW.G)
        if not np.isfinite(gnorm) and it == 0:
            break
        if gnorm > par[12] * gprev or not np.isfinite(gnorm):
            # the residual grew (a node crossed the contact kink, a segment went slack, the
            # Jacobian is far off): backtrack along the last increment until it falls
            bt = 0
            while (gnorm > gprev or not np.isfinite(gnorm)) and bt < 12:
                for i in range(nd):
                    IW.da[i] *= 0.5
                    IW.a1[i] -= IW.da[i]
                _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, F, FW, piece)
                gnorm = _norm2(IW.G)
                bt += 1
            IW.stat[S_NBACK] += 1
            n_back += 1
            if gnorm > gprev or not np.isfinite(gnorm):
                break
            # a node crossing the contact kink is the usual cause, which the contact terms follow;
            # a second backtrack in the step with an old Jacobian rebuilds it
            if n_back >= 2 and not fresh:
                rebuild = True
            prev = 0.0
        gprev = gnorm
        if rebuild and n_built < 10:
            if step_jacobian(t, h, y, A, IW, L, R, P, E, B, Mo, W, F, FW, piece) != 0:
                break
            n_built += 1
            fresh = True
            rebuild = False
            prev = 0.0
        elif par[9] > 0.0 and contact_moved(A, IW, par[9], 1.0 - par[0]):
            # a node landed, lifted off or moved through the contact ramps: update its diagonal
            # block of the Jacobian analytically (no derivative evaluations) and refactor
            if refactor(A, IW) != 0:
                break
        solve_increment(A, IW)
        IW.stat[S_NIT] += 1
        it += 1
        big = 0.0
        for i in range(nd):
            IW.a1[i] += IW.da[i]
            d = abs(IW.da[i])
            if d > big:
                big = d
        if not np.isfinite(big):
            break
        theta = big / prev if prev > 0.0 else -1.0
        prev = big
        if theta < 0.0:
            conv = big <= tol
        else:
            conv = theta < 1.0 and theta * big <= (1.0 - theta) * tol
        if conv or big <= 1e-3 * tol:
            newmark_radiation(IW.y0, IW.a0, IW.a1, h, par, y, R, W, F, FW, IW.G)
            if nx > 0:
                # the line states at the end of the step: one evaluation there (condensed stretch,
                # VIV phase rates), then the Syrope history
                rhs_call(t + h, y, IW.f1, L, R, P, E, B, Mo, W, F, FW, par[8], piece)
                IW.stat[S_NRHS] += 1
                when(W, LINE_STATES, store_line_states, (y, L, R, W, h, True))
                when(W, LINE_STATES, end_line_states, (L,))
            # the derivative at the end of the step as the scheme's equation gives it (the last
            # evaluation was one increment earlier); af <= 1/2
            am = par[0]
            af = par[1]
            for i in range(nd):
                IW.fs[i] = ((1.0 - am) * IW.a1[i] + am * IW.a0[i] - af * IW.fs[i]) / (1.0 - af)
                IW.ap[i] = IW.a0[i]
                IW.a0[i] = IW.a1[i]
            for j in range(W.xc.size):
                IW.ck[0, j] = W.xc[j]
                IW.ck[1, j] = W.vc[j]
                IW.ck[2, j] = W.ac[j]
            IW.stat[S_HPREV] = h
            if it <= 4:
                IW.stat[S_EASY] += 1
            else:
                IW.stat[S_EASY] = 0
            return 0
        if theta >= par[10]:
            rebuild = True
        elif theta > 0.0 and not fresh:
            # iterations still needed at this contraction: theta^k big / (1 - theta) <= tol
            rebuild = math.log((1.0 - theta) * tol / big) / math.log(theta) > par[11]
        if rebuild:
            IW.stat[S_NSLOW] += 1
    # failed: remember the worst DOF, restore the state, drop the Jacobian
    worst = 0
    big = -1.0
    for i in range(nd):
        g = abs(IW.G[i])
        if not np.isfinite(g):
            worst = i
            break
        if g > big:
            big = g
            worst = i
    IW.stat[S_WORST] = worst
    IW.stat[S_HJ] = 0.0
    IW.stat[S_EASY] = 0
    for i in range(n):
        y[i] = IW.y0[i]
    if nx > 0:
        end_line_states(L)
    return 1


@kernel
def advance_implicit(y, t, t_end, dtM, A, IW, L, R, P, E, B, Mo, W, F, FW, vmax, final_eval):
    """Integrate ``y`` in place from ``t`` to ``t_end`` with generalized-alpha steps of at most
    ``dtM``, never across a knot of the coupled trajectory.

    Returns
    -------
    t : float
        Time reached.
    status : int
        0 done; 1 a state row went non-finite or above ``vmax`` (row in ``row``); 2 Newton did not
        converge even with the step cut to ``dtM / 4096`` (worst DOF in ``row``).
    row : int
    piece : int
        Trajectory piece of the last step (-1 if none).
    """
    nd = IW.a0.size
    stat = IW.stat
    if stat[S_AVALID] == 0.0:
        stat[S_HPREV] = 0.0
        # typed constants: literal ones would make numba compile _start_derivative (and rhs) once
        # more for their Literal types (about 4 s each)
        _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, F, FW, np.int64(-1), np.bool_(False))
        for i in range(nd):
            IW.a0[i] = IW.fs[i]
        stat[S_AVALID] = 1.0
    tol = 1e-9 * dtM
    hmin = dtM / 4096.0
    j = 0
    piece = -1
    h_cur = min(stat[S_H], dtM) if stat[S_H] > 0.0 else dtM
    while t_end - t > tol:
        h, j = knot_step(Mo, j, t, min(h_cur, t_end - t), tol)
        piece = motion_piece(Mo, t + 0.5 * h)
        if gen_alpha_step(y, t, h, A, IW, L, R, P, E, B, Mo, W, F, FW, piece) != 0:
            stat[S_NREJ] += 1
            h_cur = 0.5 * h
            if h_cur < hmin:
                stat[S_H] = h_cur
                return t, 2, int(stat[S_WORST]), piece
            continue
        stat[S_NSTEP] += 1
        t = step_end(Mo, j, t, h, t_end, tol)
        when(W, FLOATING, floating_after_step, (t, y, R, W, F, FW))
        bad = check_state(y, vmax, R.dims[0], R.dims[1])
        if bad >= 0:
            stat[S_H] = h_cur
            return t, 1, bad, piece
        if h_cur < dtM and stat[S_EASY] >= 4:
            h_cur = min(2.0 * h_cur, dtM)
            stat[S_EASY] = 0
    stat[S_H] = h_cur
    if final_eval:
        rhs_call(t, y, IW.f0, L, R, P, E, B, Mo, W, F, FW, 1.0, piece)
    return t, 0, -1, piece


