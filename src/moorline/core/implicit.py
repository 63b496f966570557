"""Implicit time integration (generalized-alpha with Newton iterations) and the Newton static solve.

Both solve for one vector of per-DOF unknowns in velocity space (``U``: 3 per 3-DOF row, 6 per
6-DOF block): the accelerations of the step for the time scheme, the position increments for
statics. Their Jacobian is sparse and structured: a line node only sees its neighbours (two on
each side with bending stiffness), a point, rod or body only the line nodes near its ends. It is
built by coloured finite differences of the one ``rhs`` (every physical model, friction, contact,
bending and waves included, without hand-derived derivatives): DOFs that share no equation are
perturbed together, so a Jacobian costs one derivative evaluation per colour, 9 for a chain and
15 for a cable with bending stiffness, whatever the number of nodes. The unknowns are ordered by
reverse Cuthill-McKee so the Jacobian is banded; it is factored by banded LU with partial pivoting
in O(n kl (kl + ku)). Everything is O(nodes) per iteration.

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

Newton iterations reuse the factored Jacobian across steps (modified Newton). Seabed contact is
what changes it fastest: a landing node's contact stiffness and damping are 10-30 times its inertia
term at dt 0.1 s. Those terms of the internal line nodes are followed analytically at every
iteration (:func:`_contact_terms`, :func:`_refactor`: the finite-difference Jacobian plus the change
of each node's diagonal contact block since it was built, refactored, no derivative evaluations).
The Jacobian is rebuilt only when the step size changed, the contraction of the increments
(theta) predicts too many further iterations, or a step backtracked twice; convergence is tested
on the estimated error theta / (1 - theta) |da| (Hairer & Wanner). A step that does not converge is
retried with half the step (down to ``dtM / 2**12``), and the step grows back by doubling after a
run of easy steps. Tolerances: ``atol_x`` [m or rad] on positions, ``atol_v`` [m/s or rad/s] on
velocities.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numba import njit

from .integrate import check_state, knot_step, step_end
from .layout import ATT_POINT, P_BODY, P_FREE, Layout
from .rhs import motion_eval, motion_piece, rhs
from .seabed import contact_slope, seabed_at

# indices into ImplicitWork.stat
S_H = 0  # current step size [s]
S_HJ = 1  # step size the factored Jacobian belongs to (0: none)
S_AVALID = 2  # 1 once a0 and fs hold the algorithmic acceleration and the derivative of the current state
S_NRHS = 3  # derivative evaluations (counter)
S_NJAC = 4  # Jacobians built (counter)
S_NIT = 5  # Newton iterations (counter)
S_NREJ = 6  # rejected (halved) steps (counter)
S_NSTEP = 7  # accepted steps (counter)
S_EASY = 8  # accepted steps in a row that converged in at most two iterations
S_WORST = 9  # DOF of the largest residual at the last failure
S_NFAC = 10  # refactorizations of a Jacobian updated for seabed contact (counter)
S_NBACK = 11  # backtracking line searches (counter)
S_NSLOW = 12  # Jacobians rebuilt for slow or diverging iterations (counter)
S_HPREV = 13  # length of the last accepted step (0: IW.ap not valid)
N_STAT = 14

#: the Jacobian is rebuilt when the contraction of the Newton increments is at least THETA_MAX, or
#: predicts more than SLOW_ITER further iterations (a Jacobian costs 9-15 derivative evaluations)
THETA_MAX = 0.9
SLOW_ITER = 4.0
#: a residual growing by more than this factor over an iteration starts a backtracking line search
GROWTH = 1.0
#: the iterations start from a1 = a0 + PREDICTOR (h / h_prev) (a0 - a_prev): half the linear
#: extrapolation of the accelerations (OC3 chain, 15 segments, dt 0.1 s: 11 % fewer derivative
#: evaluations than the constant start a1 = a0; the full extrapolation overshoots at landings)
PREDICTOR = 0.5

# slots of the per-node seabed contact terms (ImplicitWork.cst[which, node, slot])
C_NOW = 0  # at the last residual evaluation
C_FD = 1  # at the iterate the finite-difference Jacobian was built at
C_APP = 2  # in the factored Jacobian

#: default spectral radius at infinite frequency: 0 (asymptotic annihilation) damps the
#: lumped-mass model's axial and seabed-contact modes, which a large step cannot resolve, within a
#: step; on the OC3 chain catenary in surge (15 segments, 100 s) it is also the most accurate:
#: fairlead tension RMS error against RK4 0.62 % at dt 0.1 s and 0.65 % at 0.25 s, against 0.80 %
#: and 1.7 % with rho_inf 0.7 (the lumped-mass mesh error alone is 0.62 %)
RHO_INF = 0.0


class ImplicitArrays(NamedTuple):
    """Structure of the unknowns (fixed for a layout)."""

    udof: np.ndarray  # int64 (n_units,): first DOF (in U space) of each unit (3-DOF row or 6-DOF block)
    ncomp: np.ndarray  # int64 (n_units,): 3 or 6
    adj_ptr: np.ndarray  # int64 (n_units+1,): CSR of the units whose accelerations depend on each unit
    adj_idx: np.ndarray  # int64: (self included)
    col_ptr: np.ndarray  # int64 (n_colours+1,): CSR of the units of each colour
    col_units: np.ndarray  # int64
    pinv: np.ndarray  # int64 (n_dof,): position of each DOF in the banded order
    perm: np.ndarray  # int64 (n_dof,): DOF at each banded position
    band: np.ndarray  # int64 (2,): kl, ku
    par: np.ndarray  # (14,) alpha_m, alpha_f, beta, gamma, atol_x, atol_v, max_iter, rho_inf, drag scale,
    #                 contact update tolerance (0: off), THETA_MAX, SLOW_ITER, GROWTH, PREDICTOR
    cn_node: np.ndarray  # int64 (n_cn,): internal line nodes (seabed contact tracked in the Jacobian)
    cn_dof: np.ndarray  # int64 (n_cn,): their first DOF
    cn_area: np.ndarray  # (n_cn,): their contact area d lam [m^2]


class ImplicitWork(NamedTuple):
    a0: np.ndarray  # (n_dof,) algorithmic acceleration at the start of the step
    a1: np.ndarray  # (n_dof,) unknown: acceleration at the end of the step
    G: np.ndarray  # (n_dof,) residual
    da: np.ndarray  # (n_dof,) Newton increment (banded order while solving)
    eps: np.ndarray  # (n_dof,) finite-difference perturbations
    y0: np.ndarray  # (n_state,) state at the start of the step
    fs: np.ndarray  # (n_dof,) derivative (accelerations) at the start of the step
    ck: np.ndarray  # (3, n_coupled_dof) coupled positions, velocities, accelerations fs was evaluated with
    f0: np.ndarray  # (n_state,) derivative at the iterate
    f1: np.ndarray  # (n_state,) derivative at a perturbed iterate
    AB: np.ndarray  # (2 kl + ku + 1, n_dof) banded LU factors
    piv: np.ndarray  # int64 (n_dof,)
    stat: np.ndarray  # (N_STAT,)
    Jraw: np.ndarray  # like AB: the finite-difference Jacobian before factorization
    ap: np.ndarray  # (n_dof,) algorithmic acceleration at the start of the last accepted step
    cst: np.ndarray  # (3, n_cn, 8): contact terms of the nodes (C_NOW, C_FD, C_APP):
    #                  s [N/(m/s^2)], M^-1 n [1/kg] (3), n (3), s |M^-1 n|


def parse_rho(text: str) -> float:
    """Spectral radius from the tScheme suffix of ``GenAlpha[rho]`` (empty: the default)."""
    if not text:
        return RHO_INF
    try:
        rho = float(text)
    except ValueError:
        rho = -1.0
    if not 0.0 <= rho <= 1.0:
        raise ValueError(f"time scheme GenAlpha{text}: expected GenAlpha<rho_inf> with 0 <= rho_inf <= 1, "
                         f"e.g. GenAlpha0.7")
    return rho


def gen_alpha_parameters(rho: float) -> tuple[float, float, float, float]:
    """(alpha_m, alpha_f, beta, gamma) of Chung & Hulbert for spectral radius ``rho``."""
    am = (2.0 * rho - 1.0) / (rho + 1.0)
    af = rho / (rho + 1.0)
    gamma = 0.5 - am + af
    beta = 0.25 * (1.0 - am + af) ** 2
    return am, af, beta, gamma


# ---------------------------------------------------------------------------------------------- structure
def _line_reach(layout: Layout, li: int) -> int:
    L = layout.lines
    return 2 if (L.EI[li] > 0.0 or L.ei_tab[li, 1] > 0) else 1


def _end_units(layout: Layout, li: int, side: int) -> list[int]:
    """State units that set the position of end ``side`` of line ``li``."""
    L, P, R = layout.lines, layout.points, layout.rigid
    n3 = layout.n_rows
    k = int(L.end_idx[li, side])
    out = []
    if L.end_kind[li, side] == ATT_POINT:
        if P.kind[k] == P_FREE:
            out.append(int(P.row[k]))
        elif P.kind[k] == P_BODY and R.body_blk[P.body[k]] >= 0:
            out.append(n3 + int(R.body_blk[P.body[k]]))
    else:
        if R.rod_row[k] >= 0:
            out.append(int(R.rod_row[k]))
        if R.rod_blk[k] >= 0:
            out.append(n3 + int(R.rod_blk[k]))
        b = int(R.rod_body[k])
        if b >= 0 and R.body_blk[b] >= 0:
            out.append(n3 + int(R.body_blk[b]))
    return out


def dependency_graph(layout: Layout) -> list[set]:
    """For each state unit (3-DOF rows, then 6-DOF blocks), the units its accelerations depend on
    (a safe over-estimate, symmetric, self included)."""
    n3, n6 = layout.n_rows, layout.n_blocks
    nu = n3 + n6
    L, R = layout.lines, layout.rigid
    adj = [{u} for u in range(nu)]

    def link(group):
        group = list(group)
        for a in group:
            adj[a].update(group)

    junction: dict[int, set] = {}
    for li in range(len(layout.line_N)):
        n0, n1 = int(L.node_ptr[li]), int(L.node_ptr[li + 1])
        w = _line_reach(layout, li)
        units = [_end_units(layout, li, 0)] + [[int(L.node_row[n])] for n in range(n0 + 1, n1 - 1)] + \
                [_end_units(layout, li, 1)]
        nn = len(units)
        for k in range(nn):
            for kk in range(k, min(nn, k + w + 1)):
                link(units[k] + units[kk])
        for side, ends in ((0, range(0, min(nn, w + 2))), (1, range(max(0, nn - w - 2), nn))):
            near = set()
            for k in ends:
                near.update(units[k])
            for u in units[0 if side == 0 else nn - 1]:
                junction.setdefault(u, set()).update(near)
    # a body sees everything near the rods it carries; a rod on a body moves with it
    for k in range(len(R.rod_kind)):
        b = int(R.rod_body[k])
        if b < 0 or R.body_blk[b] < 0:
            continue
        bu = n3 + int(R.body_blk[b])
        for ru in ([int(R.rod_row[k])] if R.rod_row[k] >= 0 else []) + \
                  ([n3 + int(R.rod_blk[k])] if R.rod_blk[k] >= 0 else []):
            junction.setdefault(bu, set()).update(junction.get(ru, set()) | {ru})
    for u, near in junction.items():
        link(near | {u})
    return adj


def colour_units(adj: list[set]) -> np.ndarray:
    """Greedy distance-2 colouring: units that share no dependent unit get the same colour."""
    nu = len(adj)
    colour = -np.ones(nu, dtype=np.int64)
    order = sorted(range(nu), key=lambda u: -len(adj[u]))
    for u in order:
        taken = set()
        for v in adj[u]:
            for w in adj[v]:
                if colour[w] >= 0:
                    taken.add(int(colour[w]))
        c = 0
        while c in taken:
            c += 1
        colour[u] = c
    return colour


#: default tolerance of the seabed contact update of the Jacobian (see :func:`gen_alpha_step`)
CONTACT_TOL = 0.1


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
    # banded order of the DOFs: reverse Cuthill-McKee, unless the natural order is narrower
    rows, cols = [], []
    for u in range(nu):
        for v in adj[u]:
            for a in range(ncomp[u]):
                for b in range(ncomp[v]):
                    rows.append(udof[u] + a)
                    cols.append(udof[v] + b)
    rows = np.array(rows, dtype=np.int64)
    cols = np.array(cols, dtype=np.int64)

    def width(pinv):
        d = pinv[rows] - pinv[cols] if rows.size else np.zeros(1, dtype=np.int64)
        return int(max(d.max(), 0)), int(max(-d.min(), 0))

    natural = np.arange(ndof, dtype=np.int64)
    best = (natural, natural)
    kl, ku = width(natural)
    if ndof:
        g = coo_matrix((np.ones(rows.size), (rows, cols)), shape=(ndof, ndof)).tocsr()
        perm = np.asarray(reverse_cuthill_mckee(g, symmetric_mode=True), dtype=np.int64)
        pinv = np.empty(ndof, dtype=np.int64)
        pinv[perm] = np.arange(ndof)
        kl2, ku2 = width(pinv)
        if kl2 + ku2 < kl + ku:
            best, kl, ku = (perm, pinv), kl2, ku2
    am, af, beta, gamma = gen_alpha_parameters(rho)
    par = np.array([am, af, beta, gamma, atol_x, atol_v, float(max_iter), rho, 1.0, contact_tol, THETA_MAX,
                    SLOW_ITER, GROWTH, PREDICTOR])
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
                          np.array([kl, ku], dtype=np.int64), par, np.array(cn_node, dtype=np.int64),
                          np.array(cn_dof, dtype=np.int64), np.array(cn_area, dtype=float))


def new_implicit_work(layout: Layout, A: ImplicitArrays, dtM: float) -> ImplicitWork:
    ndof = A.udof.size and int(A.udof[-1] + A.ncomp[-1])
    n = layout.n_state
    kl, ku = int(A.band[0]), int(A.band[1])
    z = np.zeros
    stat = z(N_STAT)
    stat[S_H] = dtM
    return ImplicitWork(z(ndof), z(ndof), z(ndof), z(ndof), z(ndof), z(n), z(ndof), z((3, layout.n_coupled_dof)),
                        z(n), z(n), z((2 * kl + ku + 1, max(ndof, 1))), np.zeros(max(ndof, 1), dtype=np.int64),
                        stat, z((2 * kl + ku + 1, max(ndof, 1))), z(ndof), z((3, A.cn_node.size, 8)))


# ---------------------------------------------------------------------------------------------- banded LU
@njit(cache=True, error_model="numpy", _nrt=False)
def _copy2(src, dst):
    """dst[:, :] = src (an array assignment would need numba's runtime, which these kernels run
    without)."""
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


@njit(cache=True, error_model="numpy", _nrt=False)
def band_lu(AB, n, kl, ku, piv):
    """LU factorization with partial pivoting of the banded matrix A (LAPACK dgbtrf storage:
    A[i, j] in AB[kl + ku + i - j, j], the first kl rows free for fill-in). Returns 0, or
    1 + the column of a zero pivot."""
    kv = kl + ku
    ju = 0
    for j in range(n):
        km = min(kl, n - 1 - j)
        jp = 0
        big = abs(AB[kv, j])
        for p in range(1, km + 1):
            a = abs(AB[kv + p, j])
            if a > big:
                big = a
                jp = p
        piv[j] = j + jp
        if big == 0.0:
            return j + 1
        ju = max(ju, min(j + ku + jp, n - 1))
        if jp != 0:
            for c in range(j, ju + 1):
                i1 = kv + j - c
                i2 = i1 + jp
                tmp = AB[i1, c]
                AB[i1, c] = AB[i2, c]
                AB[i2, c] = tmp
        inv = 1.0 / AB[kv, j]
        for p in range(1, km + 1):
            AB[kv + p, j] *= inv
        for c in range(j + 1, ju + 1):
            t = AB[kv + j - c, c]
            if t != 0.0:
                base = kv + j - c
                for p in range(1, km + 1):
                    AB[base + p, c] -= AB[kv + p, j] * t
    return 0


@njit(cache=True, error_model="numpy", _nrt=False)
def band_solve(AB, n, kl, ku, piv, b):
    """Solve A x = b in place with the factors of :func:`band_lu`."""
    kv = kl + ku
    if kl > 0:
        for j in range(n - 1):
            lm = min(kl, n - 1 - j)
            p = piv[j]
            if p != j:
                tmp = b[p]
                b[p] = b[j]
                b[j] = tmp
            bj = b[j]
            if bj != 0.0:
                for i in range(1, lm + 1):
                    b[j + i] -= AB[kv + i, j] * bj
    for j in range(n - 1, -1, -1):
        b[j] /= AB[kv, j]
        bj = b[j]
        if bj != 0.0:
            for i in range(max(0, j - kv), j):
                b[i] -= AB[kv + i - j, j] * bj


# ---------------------------------------------------------------------------------------------- state algebra
@njit(cache=True, error_model="numpy", _nrt=False)
def _rotate_quat(q0, o0, tx, ty, tz, out, o):
    """out[o:o+4] = exp(theta) (x) q0[o0:o0+4], theta a rotation vector in global axes."""
    ang = math.sqrt(tx * tx + ty * ty + tz * tz)
    if ang > 1e-12:
        s = math.sin(0.5 * ang) / ang
    else:
        s = 0.5 - ang * ang / 48.0
    rw = math.cos(0.5 * ang)
    rx = s * tx
    ry = s * ty
    rz = s * tz
    w = q0[o0]
    x = q0[o0 + 1]
    y = q0[o0 + 2]
    z = q0[o0 + 3]
    out[o] = rw * w - rx * x - ry * y - rz * z
    out[o + 1] = rw * x + rx * w + ry * z - rz * y
    out[o + 2] = rw * y - rx * z + ry * w + rz * x
    out[o + 3] = rw * z + rx * y - ry * x + rz * w


@njit(cache=True, error_model="numpy", _nrt=False)
def displace(y0, dq, y, n3, n6, cq):
    """Positions of ``y`` = those of ``y0`` moved by ``cq * dq`` (U-space increments: metres,
    and rotation vectors in global axes for the orientations)."""
    for i in range(3 * n3):
        y[i] = y0[i] + cq * dq[i]
    for j in range(n6):
        o = 3 * n3 + 7 * j
        d = 3 * n3 + 6 * j
        for c in range(3):
            y[o + c] = y0[o + c] + cq * dq[d + c]
        _rotate_quat(y0, o + 3, cq * dq[d + 3], cq * dq[d + 4], cq * dq[d + 5], y, o + 3)


@njit(cache=True, error_model="numpy", _nrt=False)
def _newmark(y0, a0, a1, h, par, y1, n3, n6, G):
    """End-of-step state ``y1`` from (y0, a0, a1); ``G`` is scratch for the position increments."""
    beta = par[2]
    gamma = par[3]
    uoff = 3 * n3 + 7 * n6
    nd = a0.size
    for i in range(nd):
        G[i] = h * y0[uoff + i] + h * h * ((0.5 - beta) * a0[i] + beta * a1[i])
        y1[uoff + i] = y0[uoff + i] + h * ((1.0 - gamma) * a0[i] + gamma * a1[i])
    displace(y0, G, y1, n3, n6, 1.0)


@njit(cache=True, error_model="numpy", _nrt=False)
def _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, piece):
    """G = (1 - alpha_m) a1 + alpha_m a0 - (1 - alpha_f) f(t + h, x1, v1) - alpha_f fs; leaves y
    at the end-of-step state and its derivative in IW.f0."""
    par = A.par
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    _newmark(IW.y0, IW.a0, IW.a1, h, par, y, n3, n6, IW.G)
    rhs(t + h, y, IW.f0, L, R, P, E, B, Mo, W, par[8], piece)
    IW.stat[S_NRHS] += 1
    am = par[0]
    af = par[1]
    G = IW.G
    for i in range(G.size):
        G[i] = (1.0 - am) * IW.a1[i] + am * IW.a0[i] - (1.0 - af) * IW.f0[uoff + i] - af * IW.fs[i]
    if par[9] > 0.0:
        cf = 1.0 - par[1]
        _contact_terms(A, IW, E, B, W, par[2] * h * h * cf, par[3] * h * cf)


@njit(cache=True, error_model="numpy", _nrt=False)
def _contact_terms(A, IW, E, B, W, cx, cv):
    """Seabed contact terms of the Jacobian at the state of the last derivative evaluation (W), into
    IW.cst[C_NOW]: each internal line node below the seabed adds s M^-1 n n^T to its diagonal block,
    with s = k cx + c cv (:func:`~moorline.core.seabed.contact_slope`; ``cx``, ``cv``: the
    derivatives of the midpoint position and velocity with respect to the acceleration unknown)."""
    cst = IW.cst
    flat = B.gx.size == 0
    for m in range(A.cn_node.size):
        n = A.cn_node[m]
        if flat:
            zb = -E.depth
            nx = 0.0
            ny = 0.0
            nz = 1.0
        else:
            zb, nx, ny, nz, _ = seabed_at(B.gx, B.gy, B.gz, E.depth, W.r[n, 0], W.r[n, 1])
        s = 0.0
        if W.r[n, 2] < zb:
            k, c, nx, ny, nz = contact_slope(E, zb, nx, ny, nz, W.r[n, 2], W.v[n, 0], W.v[n, 1], W.v[n, 2],
                                             A.cn_area[m])
            s = k * cx + c * cv
        cst[C_NOW, m, 0] = s
        if s == 0.0:
            cst[C_NOW, m, 7] = 0.0
            continue
        # M^-1 n with the node mass matrix m I + ma (I - q q^T) + mq q q^T
        ia = 1.0 / (W.mass[n, 0] + W.mass[n, 1])
        iq = 1.0 / (W.mass[n, 0] + W.mass[n, 2])
        qn = (W.q[n, 0] * nx + W.q[n, 1] * ny + W.q[n, 2] * nz) * (iq - ia)
        mx = ia * nx + qn * W.q[n, 0]
        my = ia * ny + qn * W.q[n, 1]
        mz = ia * nz + qn * W.q[n, 2]
        cst[C_NOW, m, 1] = mx
        cst[C_NOW, m, 2] = my
        cst[C_NOW, m, 3] = mz
        cst[C_NOW, m, 4] = nx
        cst[C_NOW, m, 5] = ny
        cst[C_NOW, m, 6] = nz
        cst[C_NOW, m, 7] = s * math.sqrt(mx * mx + my * my + mz * mz)


@njit(cache=True, error_model="numpy", _nrt=False)
def _contact_moved(A, IW, tol, diag):
    """True when the contact term of a node changed since the factorization by more than ``tol``
    times its diagonal (``diag``: the inertia term 1 - alpha_m, plus the larger contact term)."""
    cst = IW.cst
    for m in range(A.cn_node.size):
        a = cst[C_NOW, m, 7]
        b = cst[C_APP, m, 7]
        if abs(a - b) > tol * (diag + max(a, b)):
            return True
    return False


@njit(cache=True, error_model="numpy", _nrt=False)
def _refactor(A, IW):
    """Factor the finite-difference Jacobian with its contact terms moved from the iterate it was
    built at (C_FD) to the last evaluation (C_NOW). Returns the LU status."""
    kv = A.band[0] + A.band[1]
    AB = IW.AB
    _copy2(IW.Jraw, AB)
    cst = IW.cst
    pinv = A.pinv
    for m in range(A.cn_node.size):
        d0 = A.cn_dof[m]
        for which in (C_NOW, C_FD):
            s = cst[which, m, 0]
            if s == 0.0:
                continue
            if which == C_FD:
                s = -s
            for b in range(3):
                pc = pinv[d0 + b]
                snb = s * cst[which, m, 4 + b]
                for a in range(3):
                    AB[kv + pinv[d0 + a] - pc, pc] += snb * cst[which, m, 1 + a]
        for k in range(8):
            cst[C_APP, m, k] = cst[C_NOW, m, k]
    IW.stat[S_NFAC] += 1
    return band_lu(AB, IW.a1.size, A.band[0], A.band[1], IW.piv)


@njit(cache=True, error_model="numpy", _nrt=False)
def _assemble(A, IW, f0, f1, uoff, cu, k, diag, scale, eps):
    """Columns of colour (cu, component k) from the derivative difference f1 - f0:
    J[i, j] = diag [i == j] - scale (f1_i - f0_i) / eps_j, into the band storage."""
    kl = A.band[0]
    ku = A.band[1]
    kv = kl + ku
    AB = IW.AB
    pinv = A.pinv
    for m in range(A.col_ptr[cu], A.col_ptr[cu + 1]):
        uj = A.col_units[m]
        if k >= A.ncomp[uj]:
            continue
        col = A.udof[uj] + k
        pc = pinv[col]
        inv = scale / eps[col]
        for p in range(A.adj_ptr[uj], A.adj_ptr[uj + 1]):
            ui = A.adj_idx[p]
            d0 = A.udof[ui]
            for a in range(A.ncomp[ui]):
                row = d0 + a
                val = -(f1[uoff + row] - f0[uoff + row]) * inv
                if row == col:
                    val += diag
                AB[kv + pinv[row] - pc, pc] = val


@njit(cache=True, error_model="numpy", _nrt=False)
def _fd_steps(IW, n3, n6, rel, div):
    """Finite-difference perturbation of each unknown into IW.eps: ``rel`` times the size of its
    coordinate at the start (at least 1; rotations 1), divided by ``div`` (the factor from the
    unknown to the position it moves)."""
    for i in range(IW.eps.size):
        q = IW.y0[i] if i < 3 * n3 else 0.0
        IW.eps[i] = rel * max(1.0, abs(q)) / div
    for j in range(n6):
        d = 3 * n3 + 6 * j
        o = 3 * n3 + 7 * j
        for c in range(3):
            IW.eps[d + c] = rel * max(1.0, abs(IW.y0[o + c])) / div


@njit(cache=True, error_model="numpy", _nrt=False)
def _shift_colour(A, cu, k, v, eps, sign):
    """v += sign * eps on the columns of colour (cu, component k); False if there are none."""
    any_col = False
    for m in range(A.col_ptr[cu], A.col_ptr[cu + 1]):
        uj = A.col_units[m]
        if k < A.ncomp[uj]:
            col = A.udof[uj] + k
            v[col] += sign * eps[col]
            any_col = True
    return any_col


@njit(cache=True, error_model="numpy", _nrt=False)
def _step_jacobian(t, h, y, A, IW, L, R, P, E, B, Mo, W, piece):
    """Jacobian of the generalized-alpha residual with respect to a1 at the current iterate
    (IW.f0 must hold the derivative at the iterate), factored in place. Returns the LU status."""
    par = A.par
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    af = par[1]
    beta = par[2]
    nd = IW.a1.size
    # position perturbation ~ 1e-8 of the coordinate (at least 1e-8 m or rad)
    _fd_steps(IW, n3, n6, 1e-8, beta * h * h)
    IW.AB[:, :] = 0.0
    f1 = IW.f1
    nc = A.col_ptr.size - 1
    kmax = 6 if n6 > 0 else 3
    scratch = IW.da  # G and f0 (the residual at the iterate) stay valid
    for cu in range(nc):
        for k in range(kmax):
            if not _shift_colour(A, cu, k, IW.a1, IW.eps, 1.0):
                continue
            _newmark(IW.y0, IW.a0, IW.a1, h, par, y, n3, n6, scratch)
            rhs(t + h, y, f1, L, R, P, E, B, Mo, W, par[8], piece)
            IW.stat[S_NRHS] += 1
            _shift_colour(A, cu, k, IW.a1, IW.eps, -1.0)
            _assemble(A, IW, IW.f0, f1, uoff, cu, k, 1.0 - par[0], 1.0 - af, IW.eps)
    IW.stat[S_NJAC] += 1
    IW.stat[S_HJ] = h
    if par[9] > 0.0:
        _copy2(IW.AB, IW.Jraw)
        for m in range(A.cn_node.size):
            for k in range(8):
                IW.cst[C_FD, m, k] = IW.cst[C_NOW, m, k]
                IW.cst[C_APP, m, k] = IW.cst[C_NOW, m, k]
    return band_lu(IW.AB, nd, A.band[0], A.band[1], IW.piv)


@njit(cache=True, error_model="numpy", _nrt=False)
def _solve_increment(A, IW):
    """da = -J^{-1} G (through the banded order)."""
    nd = IW.G.size
    b = IW.da
    for p in range(nd):
        b[p] = -IW.G[A.perm[p]]
    band_solve(IW.AB, nd, A.band[0], A.band[1], IW.piv, b)
    # back to DOF order, through f1 as scratch
    tmp = IW.f1
    for p in range(nd):
        tmp[A.perm[p]] = b[p]
    for i in range(nd):
        b[i] = tmp[i]


@njit(cache=True, error_model="numpy", _nrt=False)
def _norm2(v):
    s = 0.0
    for i in range(v.size):
        s += v[i] * v[i]
    return s


@njit(cache=True, error_model="numpy", _nrt=False)
def _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, piece, commit):
    """fs = f(t, y) (the U part), with the stick-slip anchors committed when ``commit``; remembers
    the coupled kinematics it was evaluated with."""
    uoff = 3 * R.dims[0] + 7 * R.dims[1]
    if commit:
        B.ctl[1] = 1
    rhs(t, y, IW.f1, L, R, P, E, B, Mo, W, A.par[8], piece)
    B.ctl[1] = 0
    IW.stat[S_NRHS] += 1
    for i in range(IW.fs.size):
        IW.fs[i] = IW.f1[uoff + i]
    for j in range(W.xc.size):
        IW.ck[0, j] = W.xc[j]
        IW.ck[1, j] = W.vc[j]
        IW.ck[2, j] = W.ac[j]


@njit(cache=True, error_model="numpy", _nrt=False)
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


@njit(cache=True, error_model="numpy", _nrt=False)
def gen_alpha_step(y, t, h, A, IW, L, R, P, E, B, Mo, W, piece):
    """One generalized-alpha step of length ``h`` in place. Returns 0 on convergence, 1 when the
    Newton iterations did not converge (``y`` then restored to the start of the step).

    Modified Newton: the factored Jacobian is kept across iterations and steps. Its seabed contact
    terms follow the iterate (:func:`_refactor`, no derivative evaluations); it is rebuilt by
    finite differences only when the step size changed, the residual grew, or the observed
    contraction of the increments (theta = |da_k| / |da_k-1|) predicts more than ``SLOW_ITER``
    further iterations. Convergence: the error estimate theta / (1 - theta) |da_k| (Hairer and
    Wanner's test for Newton's method with a frozen Jacobian; |da_1| itself at the first
    iteration) below ``atol_x`` in position and ``atol_v`` in velocity."""
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
    if B.ctl[0] == 1:
        # stick-slip friction anchors are committed at the state at the start of the step (which
        # moves the friction forces: the derivative there is evaluated again)
        _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, piece, True)
    elif _coupled_moved(IW, Mo, W, t, piece):
        _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, piece, False)
    hp = IW.stat[S_HPREV]
    w = par[13] * h / hp if hp > 0.0 else 0.0
    for i in range(nd):
        IW.a1[i] = IW.a0[i] + w * (IW.a0[i] - IW.ap[i])
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
        _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, piece)
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
                _residual(t, h, y, A, IW, L, R, P, E, B, Mo, W, piece)
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
            if _step_jacobian(t, h, y, A, IW, L, R, P, E, B, Mo, W, piece) != 0:
                break
            n_built += 1
            fresh = True
            rebuild = False
            prev = 0.0
        elif par[9] > 0.0 and _contact_moved(A, IW, par[9], 1.0 - par[0]):
            # a node landed, lifted off or moved through the contact ramps: update its diagonal
            # block of the Jacobian analytically (no derivative evaluations) and refactor
            if _refactor(A, IW) != 0:
                break
        _solve_increment(A, IW)
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
            _newmark(IW.y0, IW.a0, IW.a1, h, par, y, R.dims[0], R.dims[1], IW.G)
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
    return 1


@njit(cache=True, error_model="numpy", _nrt=False)
def advance_implicit(y, t, t_end, dtM, A, IW, L, R, P, E, B, Mo, W, vmax, final_eval):
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
        _start_derivative(y, t, A, IW, L, R, P, E, B, Mo, W, -1, False)
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
        if gen_alpha_step(y, t, h, A, IW, L, R, P, E, B, Mo, W, piece) != 0:
            stat[S_NREJ] += 1
            h_cur = 0.5 * h
            if h_cur < hmin:
                stat[S_H] = h_cur
                return t, 2, int(stat[S_WORST]), piece
            continue
        stat[S_NSTEP] += 1
        t = step_end(Mo, j, t, h, t_end, tol)
        bad = check_state(y, vmax, R.dims[0], R.dims[1])
        if bad >= 0:
            stat[S_H] = h_cur
            return t, 1, bad, piece
        if h_cur < dtM and stat[S_EASY] >= 4:
            h_cur = min(2.0 * h_cur, dtM)
            stat[S_EASY] = 0
    stat[S_H] = h_cur
    if final_eval:
        rhs(t, y, IW.f0, L, R, P, E, B, Mo, W, 1.0, piece)
    return t, 0, -1, piece


# ---------------------------------------------------------------------------------------------- statics
@njit(cache=True, error_model="numpy", _nrt=False)
def _static_jacobian(y, A, IW, L, R, P, E, B, Mo, W, diag):
    """J = diag I - df/dx at the positions IW.y0 (zero velocities), factored. IW.f0 must hold the
    derivative at IW.y0. Returns the LU status."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    nd = IW.a1.size
    _fd_steps(IW, n3, n6, 1e-7, 1.0)
    IW.AB[:, :] = 0.0
    nc = A.col_ptr.size - 1
    kmax = 6 if n6 > 0 else 3
    dq = IW.da
    for cu in range(nc):
        for k in range(kmax):
            for i in range(nd):
                dq[i] = 0.0
            if not _shift_colour(A, cu, k, dq, IW.eps, 1.0):
                continue
            for i in range(y.size):
                y[i] = IW.y0[i]
            displace(IW.y0, dq, y, n3, n6, 1.0)
            rhs(0.0, y, IW.f1, L, R, P, E, B, Mo, W, 1.0, -1)
            IW.stat[S_NRHS] += 1
            _assemble(A, IW, IW.f0, IW.f1, uoff, cu, k, diag, 1.0, IW.eps)
    IW.stat[S_NJAC] += 1
    for i in range(y.size):
        y[i] = IW.y0[i]
    return band_lu(IW.AB, nd, A.band[0], A.band[1], IW.piv)


@njit(cache=True, error_model="numpy", _nrt=False)
def _static_residual(y, IW, L, R, P, E, B, Mo, W, n3, n6):
    """f at the positions of ``y`` with zero velocities into IW.f0; returns (max |acc|, L2 norm)."""
    uoff = 3 * n3 + 7 * n6
    for i in range(uoff, y.size):
        y[i] = 0.0
    rhs(0.0, y, IW.f0, L, R, P, E, B, Mo, W, 1.0, -1)
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


@njit(cache=True, error_model="numpy", _nrt=False)
def newton_statics(y, A, IW, L, R, P, E, B, Mo, W, tau0, acc_tol, dx_tol, max_iter):
    """Static equilibrium by pseudo-transient continuation of Newton's method: each iteration
    solves (I / tau^2 - df/dx) dx = f(x) at zero velocities, with tau^2 grown by the ratio of
    successive residual norms (switched evolution relaxation) so the iterations start as heavily
    damped dynamics from a poor guess and end as plain Newton. An iteration that more than doubles
    the residual is rejected and retried with tau^2 / 4.

    Returns
    -------
    status : int
        1 converged (max residual acceleration <= ``acc_tol`` [m/s^2] and the last position
        update <= ``dx_tol`` [m]), 0 not within ``max_iter`` iterations, -1 singular or non-finite.
    iterations : int
    residual : float
        Max residual acceleration at the end [m/s^2].
    """
    n3 = R.dims[0]
    n6 = R.dims[1]
    nd = IW.a1.size
    tau2 = tau0 * tau0
    big, nrm = _static_residual(y, IW, L, R, P, E, B, Mo, W, n3, n6)
    if not np.isfinite(nrm):
        return -1, 0, big
    dxmax = np.inf
    it = 0
    while it < max_iter:
        if big <= acc_tol and dxmax <= dx_tol:
            return 1, it, big
        for i in range(y.size):
            IW.y0[i] = y[i]
        # IW.f0 holds f at y0
        if _static_jacobian(y, A, IW, L, R, P, E, B, Mo, W, 1.0 / tau2) != 0:
            return -1, it, big
        while True:
            _solve_increment(A, IW)
            it += 1
            dxmax = 0.0
            for i in range(nd):
                d = abs(IW.da[i])
                if d > dxmax:
                    dxmax = d
            displace(IW.y0, IW.da, y, n3, n6, 1.0)
            big1, nrm1 = _static_residual(y, IW, L, R, P, E, B, Mo, W, n3, n6)
            if np.isfinite(nrm1) and (nrm1 <= 2.0 * nrm or tau2 < 1e-12):
                break
            # reject: back to y0 with a smaller pseudo step
            for i in range(y.size):
                y[i] = IW.y0[i]
            tau2 *= 0.25
            if it >= max_iter:
                return 0, it, big
            _static_residual(y, IW, L, R, P, E, B, Mo, W, n3, n6)
            if _static_jacobian(y, A, IW, L, R, P, E, B, Mo, W, 1.0 / tau2) != 0:
                return -1, it, big
        if not np.isfinite(nrm1):
            return -1, it, big1
        ratio = nrm / nrm1 if nrm1 > 0.0 else 1e6
        tau2 *= min(max(ratio, 0.1), 1e3)
        if tau2 > 1e30:
            tau2 = 1e30
        big = big1
        nrm = nrm1
    if big <= acc_tol and dxmax <= dx_tol:
        return 1, it, big
    return 0, it, big
