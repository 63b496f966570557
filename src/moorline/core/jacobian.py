"""The Jacobian of the implicit solves (generalized-alpha steps in :mod:`.implicit`, Newton
statics in :mod:`.statics`): its structure, finite-difference assembly and banded LU.

Both solves are for one vector of per-DOF unknowns in velocity space (``U``: 3 per 3-DOF row, 6 per
6-DOF block): the accelerations of the step for the time scheme, the position increments for
statics. Their Jacobian is sparse and structured: a line node only sees its neighbours (two on
each side with bending stiffness), a point, rod or body only the line nodes near its ends. It is
built by coloured finite differences of the one ``rhs`` (every physical model, friction, contact,
bending and waves included, without hand-derived derivatives): DOFs that share no equation are
perturbed together, so a Jacobian costs one derivative evaluation per colour, 9 for a chain and
15 for a cable with bending stiffness, whatever the number of nodes. The unknowns are ordered by
reverse Cuthill-McKee so the Jacobian is banded; it is factored by banded LU with partial pivoting
in O(n kl (kl + ku)). Everything is O(nodes) per iteration.

Seabed contact is what changes the Jacobian fastest between rebuilds: a landing node's contact
stiffness and damping are 10-30 times its inertia term at dt 0.1 s. Those terms of the internal
line nodes are followed analytically at every iteration (:func:`contact_terms`, :func:`refactor`:
the finite-difference Jacobian plus the change of each node's diagonal contact block since it was
built, refactored, no derivative evaluations).
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np

from .features import FLOATING, when
from .floating import radiation_trapezoid
from .jit import kernel
from .layout import ATT_POINT, P_BODY, P_FREE, Layout
from .numerics import lu_factor, lu_solve, quat_mul
from .rhs import rhs_call
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


# slots of the per-node seabed contact terms (ImplicitWork.cst[which, node, slot])
C_NOW = 0  # at the last residual evaluation


C_FD = 1  # at the iterate the finite-difference Jacobian was built at


C_APP = 2  # in the factored Jacobian


class ImplicitArrays(NamedTuple):
    """Structure of the unknowns (fixed for a layout)."""

    udof: np.ndarray  # int64 (n_units,): first DOF (in U space) of each unit (3-DOF row or 6-DOF block)
    ncomp: np.ndarray  # int64 (n_units,): 3 or 6
    adj_ptr: np.ndarray  # int64 (n_units+1,): CSR of the units whose accelerations depend on each unit
    adj_idx: np.ndarray  # int64: (self included)
    col_ptr: np.ndarray  # int64 (n_colours+1,): CSR of the units of each colour
    col_units: np.ndarray  # int64
    pinv: np.ndarray  # int64 (n_dof,): position of each DOF in the solver's order
    perm: np.ndarray  # int64 (n_dof,): DOF at each position
    band: np.ndarray  # int64 (3,): kl, ku of the leading (banded) block, nb border DOFs (the last nb
    #                  positions: floating-body blocks, which couple every line they carry)
    par: np.ndarray  # (14,) alpha_m, alpha_f, beta, gamma, atol_x, atol_v, max_iter, rho_inf, drag scale,
    #                 contact update tolerance (0: off), THETA_MAX, rebuild threshold (implicit.SLOW_ITER,
    #                 SLOW_SHARE), GROWTH, PREDICTOR
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
    LBt: np.ndarray  # (nb, nl): the border columns of the leading rows, transposed
    BL: np.ndarray  # (nb, nl): the border rows, leading columns
    BB: np.ndarray  # (nb, nb): the border block
    Yt: np.ndarray  # (nb, nl): (A_LL^-1 A_LB)^T
    S: np.ndarray  # (nb, nb): LU factors of the Schur complement A_BB - A_BL A_LL^-1 A_LB
    spiv: np.ndarray  # int64 (nb,)


# ---------------------------------------------------------------------------------------------- structure
def _line_reach(layout: Layout, li: int) -> int:
    L = layout.lines
    return 2 if (L.EI[li] > 0.0 or L.ei_tab[li, 1] > 0) else 1


def _rod_units(layout: Layout, k: int) -> list[int]:
    """State units of rod ``k`` itself: its 3-DOF row (pinned) or 6-DOF block (free), if any."""
    R = layout.rigid
    out = [int(R.rod_row[k])] if R.rod_row[k] >= 0 else []
    if R.rod_blk[k] >= 0:
        out.append(layout.n_rows + int(R.rod_blk[k]))
    return out


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
        out += _rod_units(layout, k)
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
    # per rod, the line ends on it: the units from the end outward, one list per line end
    at_rod: dict[int, list] = {}
    for li in range(len(layout.line_N)):
        n0, n1 = int(L.node_ptr[li]), int(L.node_ptr[li + 1])
        w = _line_reach(layout, li)
        units = [_end_units(layout, li, 0)] + [[int(L.node_row[n])] for n in range(n0 + 1, n1 - 1)] + \
                [_end_units(layout, li, 1)]
        nn = len(units)
        for k in range(nn):
            for kk in range(k, min(nn, k + w + 1)):
                link(units[k] + units[kk])
        # the junction at an end feels the units within the line's reach of it (its segment, and
        # with bending stiffness the curvature at the next node): w + 1 units, its own included
        for side, ends in ((0, range(0, min(nn, w + 1))), (1, range(max(0, nn - w - 1), nn))):
            near = set()
            for k in ends:
                near.update(units[k])
            for u in units[0 if side == 0 else nn - 1]:
                junction.setdefault(u, set()).update(near)
            if L.end_kind[li, side] != ATT_POINT:
                outward = units[:w + 1] if side == 0 else units[::-1][:w + 1]
                at_rod.setdefault(int(L.end_idx[li, side]), []).append((w, outward[1:]))
    # a body sees everything near the rods it carries; a rod on a body moves with it
    for k in range(len(R.rod_kind)):
        b = int(R.rod_body[k])
        if b < 0 or R.body_blk[b] < 0:
            continue
        bu = n3 + int(R.body_blk[b])
        for ru in _rod_units(layout, k):
            junction.setdefault(bu, set()).update(junction.get(ru, set()) | {ru})
    # floating bodies solved together (coupling added mass, radiation, joints): each sees what
    # every member of its group sees, and the members see each other
    fl = layout.fl
    for g in range(len(fl.grp_ptr) - 1):
        units = [n3 + int(R.body_blk[fl.body[f]]) for f in fl.grp_members[fl.grp_ptr[g]:fl.grp_ptr[g + 1]]]
        if len(units) > 1:
            shared = set(units)
            for u in units:
                shared |= junction.get(u, set())
            for u in units:
                junction[u] = shared
            link(units)
    # the lines on one rod see each other: a zero-length rod takes its axis from the cables on both
    # of its ends, and a clamped end's bending couples the first nodes across the rod. Two lines on
    # a rod are linked as one line through it (the rod's units one node), within the larger of
    # their reaches: the nodes near the rod on either side, not all of them with each other
    for k, ends in at_rod.items():
        rod_units = _rod_units(layout, k)
        for a in range(len(ends)):
            for b in range(a + 1, len(ends)):
                w = max(ends[a][0], ends[b][0])
                path = ends[a][1][::-1] + [rod_units] + ends[b][1]
                for i in range(len(path)):
                    for j in range(i + 1, min(len(path), i + w + 1)):
                        link(path[i] + path[j])
    # a junction (free point, rod, body) and the line units near it depend on each other; units of
    # different lines at a point or a body do not (only through it), so they are linked to it, not
    # to each other: that keeps a hub's lines apart in the banded order
    for u, near in junction.items():
        for v in near:
            adj[u].add(v)
            adj[v].add(u)
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


# ---------------------------------------------------------------------------------------------- banded LU
@kernel
def copy2(src, dst):
    """dst[:, :] = src (an array assignment would need numba's runtime, which these kernels run
    without)."""
    for i in range(src.shape[0]):
        for j in range(src.shape[1]):
            dst[i, j] = src[i, j]


@kernel
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


@kernel
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
@kernel
def _rotate_quat(q0, o0, tx, ty, tz, out, o):
    """out[o:o+4] = exp(theta) (x) q0[o0:o0+4], theta a rotation vector in global axes."""
    ang = math.sqrt(tx * tx + ty * ty + tz * tz)
    if ang > 1e-12:
        s = math.sin(0.5 * ang) / ang
    else:
        s = 0.5 - ang * ang / 48.0
    quat_mul(math.cos(0.5 * ang), s * tx, s * ty, s * tz, q0, o0, out, o)


@kernel
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


@kernel
def newmark(y0, a0, a1, h, par, y1, R, F, FW, G):
    """End-of-step state ``y1`` from (y0, a0, a1); ``G`` is scratch for the position increments.
    The radiation states of floating bodies are advanced over the step by the caller
    (:func:`newmark_radiation`)."""
    n3 = R.dims[0]
    n6 = R.dims[1]
    beta = par[2]
    gamma = par[3]
    uoff = 3 * n3 + 7 * n6
    nd = a0.size
    for i in range(nd):
        G[i] = h * y0[uoff + i] + h * h * ((0.5 - beta) * a0[i] + beta * a1[i])
        y1[uoff + i] = y0[uoff + i] + h * ((1.0 - gamma) * a0[i] + gamma * a1[i])
    displace(y0, G, y1, n3, n6, 1.0)


@kernel(inline="always")
def newmark_radiation(y0, a0, a1, h, par, y1, R, W, F, FW, G):
    """:func:`newmark`, then the radiation states of floating bodies advanced over the step
    (:func:`~moorline.core.floating.radiation_trapezoid`, compiled only for systems with floating
    bodies: the others pass their kernels none of its arrays, core.features.NoFloating)."""
    newmark(y0, a0, a1, h, par, y1, R, F, FW, G)
    if R.dims[2] > 0:
        when(W, FLOATING, radiation_trapezoid, (y0, y1, h, R, F, FW))


@kernel(inline="always")
def contact_terms(A, IW, E, B, W, cx, cv):
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


@kernel
def contact_moved(A, IW, tol, diag):
    """True when the contact term of a node changed since the factorization by more than ``tol``
    times its diagonal (``diag``: the inertia term 1 - alpha_m, plus the larger contact term)."""
    cst = IW.cst
    for m in range(A.cn_node.size):
        a = cst[C_NOW, m, 7]
        b = cst[C_APP, m, 7]
        if abs(a - b) > tol * (diag + max(a, b)):
            return True
    return False


@kernel
def clear(IW):
    """Zero the Jacobian storage (band and border) before an assembly."""
    IW.AB[:, :] = 0.0
    IW.LBt[:, :] = 0.0
    IW.BL[:, :] = 0.0
    IW.BB[:, :] = 0.0


@kernel
def factor(A, IW):
    """Factor the assembled Jacobian: banded LU of the leading block and, with border DOFs, the LU
    of the Schur complement A_BB - A_BL A_LL^-1 A_LB. Returns 0, or nonzero for a zero pivot."""
    kl = A.band[0]
    ku = A.band[1]
    nb = A.band[2]
    nl = IW.a1.size - nb
    st = band_lu(IW.AB, nl, kl, ku, IW.piv) if nl > 0 else 0
    if st != 0 or nb == 0:
        return st
    for c in range(nb):
        y = IW.Yt[c]
        for i in range(nl):
            y[i] = IW.LBt[c, i]
        if nl > 0:
            band_solve(IW.AB, nl, kl, ku, IW.piv, y)
    for r in range(nb):
        for c in range(nb):
            s = IW.BB[r, c]
            for i in range(nl):
                s -= IW.BL[r, i] * IW.Yt[c, i]
            IW.S[r, c] = s
    return 0 if lu_factor(IW.S, 0, nb, IW.spiv) else nl + 1


@kernel
def refactor(A, IW):
    """Factor the finite-difference Jacobian with its contact terms moved from the iterate it was
    built at (C_FD) to the last evaluation (C_NOW). Returns the LU status."""
    kv = A.band[0] + A.band[1]
    AB = IW.AB
    copy2(IW.Jraw, AB)
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
    return factor(A, IW)


@kernel
def assemble(A, IW, f0, f1, uoff, cu, k, diag, scale, eps):
    """Columns of colour (cu, component k) from the derivative difference f1 - f0:
    J[i, j] = diag [i == j] - scale (f1_i - f0_i) / eps_j, into the band and border storage."""
    kl = A.band[0]
    ku = A.band[1]
    kv = kl + ku
    nl = IW.a1.size - A.band[2]
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
                pr = pinv[row]
                if pr < nl and pc < nl:
                    AB[kv + pr - pc, pc] = val
                elif pr < nl:
                    IW.LBt[pc - nl, pr] = val
                elif pc < nl:
                    IW.BL[pr - nl, pc] = val
                else:
                    IW.BB[pr - nl, pc - nl] = val


@kernel
def fd_steps(IW, n3, n6, rel, div):
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


@kernel
def shift_colour(A, cu, k, v, eps, sign):
    """v += sign * eps on the columns of colour (cu, component k); False if there are none."""
    any_col = False
    for m in range(A.col_ptr[cu], A.col_ptr[cu + 1]):
        uj = A.col_units[m]
        if k < A.ncomp[uj]:
            col = A.udof[uj] + k
            v[col] += sign * eps[col]
            any_col = True
    return any_col


@kernel(inline="always")
def step_jacobian(t, h, y, A, IW, L, R, P, E, B, Mo, W, F, FW, piece):
    """Jacobian of the generalized-alpha residual with respect to a1 at the current iterate
    (IW.f0 must hold the derivative at the iterate), factored in place. Returns the LU status."""
    par = A.par
    n3 = R.dims[0]
    n6 = R.dims[1]
    uoff = 3 * n3 + 7 * n6
    af = par[1]
    beta = par[2]
    # position perturbation ~ 1e-8 of the coordinate (at least 1e-8 m or rad)
    fd_steps(IW, n3, n6, 1e-8, beta * h * h)
    clear(IW)
    f1 = IW.f1
    nc = A.col_ptr.size - 1
    kmax = 6 if n6 > 0 else 3
    scratch = IW.da  # G and f0 (the residual at the iterate) stay valid
    for cu in range(nc):
        for k in range(kmax):
            if not shift_colour(A, cu, k, IW.a1, IW.eps, 1.0):
                continue
            newmark_radiation(IW.y0, IW.a0, IW.a1, h, par, y, R, W, F, FW, scratch)
            rhs_call(t + h, y, f1, L, R, P, E, B, Mo, W, F, FW, par[8], piece)
            IW.stat[S_NRHS] += 1
            shift_colour(A, cu, k, IW.a1, IW.eps, -1.0)
            assemble(A, IW, IW.f0, f1, uoff, cu, k, 1.0 - par[0], 1.0 - af, IW.eps)
    IW.stat[S_NJAC] += 1
    IW.stat[S_HJ] = h
    if par[9] > 0.0:
        copy2(IW.AB, IW.Jraw)
        for m in range(A.cn_node.size):
            for k in range(8):
                IW.cst[C_FD, m, k] = IW.cst[C_NOW, m, k]
                IW.cst[C_APP, m, k] = IW.cst[C_NOW, m, k]
    return factor(A, IW)


@kernel
def solve_increment(A, IW):
    """da = -J^{-1} G (through the solver's order: the banded leading block, then the border by its
    Schur complement)."""
    nd = IW.G.size
    nb = A.band[2]
    nl = nd - nb
    b = IW.da
    for p in range(nd):
        b[p] = -IW.G[A.perm[p]]
    if nl > 0:
        band_solve(IW.AB, nl, A.band[0], A.band[1], IW.piv, b)
    if nb > 0:
        xb = IW.f1  # scratch (restored below from b)
        for r in range(nb):
            s = b[nl + r]
            for i in range(nl):
                s -= IW.BL[r, i] * b[i]
            xb[r] = s
        lu_solve(IW.S, 0, nb, IW.spiv, xb)
        for r in range(nb):
            b[nl + r] = xb[r]
            x = xb[r]
            for i in range(nl):
                b[i] -= IW.Yt[r, i] * x
    # back to DOF order, through f1 as scratch
    tmp = IW.f1
    for p in range(nd):
        tmp[A.perm[p]] = b[p]
    for i in range(nd):
        b[i] = tmp[i]
