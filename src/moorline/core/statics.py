"""Initial conditions: the catenary start of every line, then MoorDyn's stationary solver or its
legacy dynamic relaxation (spec section 6).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .catenary import STATUS_OK, STATUS_SHORT_SPAN, catenary_nodes
from .integrate import advance
from .layout import ATT_POINT, ATT_ROD_A, P_BODY, P_COUPLED, P_FREE, Layout
from .rhs import rhs
from .rigid import body_kinematics, body_point_kinematics, rod_kinematics, rod_nodes
from .seabed import seabed_at


def end_points(layout: Layout, li: int, W) -> tuple[np.ndarray, np.ndarray]:
    """Initial positions of the two ends of line ``li`` from the point and rod-end positions
    that :func:`rigid_start` put in ``W``."""
    out = []
    for j in range(2):
        kind = layout.lines.end_kind[li, j]
        k = int(layout.lines.end_idx[li, j])
        if kind != ATT_POINT:
            out.append(W.rodr[k, 0 if kind == ATT_ROD_A else 1].copy())
        else:
            out.append(W.pr[k].copy())
    return out[0], out[1]


def rigid_start(layout: Layout, x_coupled: np.ndarray, y: np.ndarray, W) -> None:
    """Put free points, rods and bodies at their deck pose in the state ``y`` (coupled objects
    at ``x_coupled``, velocities zero) and evaluate the kinematics of bodies, rods and points
    into the Work arrays ``W`` (rod ends ``W.rodr``, points ``W.pr``)."""
    R = layout.rigid
    P = layout.points
    y[:] = 0.0
    for p in range(len(P.kind)):
        if P.kind[p] == P_FREE:
            row = int(P.row[p])
            y[3 * row:3 * row + 3] = P.r0[p]
    for k in range(len(R.rod_kind)):
        if R.rod_row[k] >= 0:
            row = int(R.rod_row[k])
            y[3 * row:3 * row + 3] = R.rod_rA0[k]
        j = int(R.rod_blk[k])
        if j >= 0:
            q, _ = layout.block_slices(j)
            y[q.start:q.start + 3] = R.rod_rA0[k] if R.rod_body[k] < 0 else 0.0
            y[q.start + 3] = 1.0  # the quaternion rotates the deck axis: identity at the start
    for i in range(len(R.body_kind)):
        j = int(R.body_blk[i])
        if j >= 0:
            q, _ = layout.block_slices(j)
            y[q.start:q.start + 3] = R.body_r0[i]
            y[q.start + 3:q.start + 7] = R.body_Q0[i]
    W.xc[:] = x_coupled
    W.vc[:] = 0.0
    W.ac[:] = 0.0
    if len(R.body_kind):
        body_kinematics(y, R, W)
    if len(R.rod_kind):
        rod_kinematics(y, R, W)
        rod_nodes(R, W)
    for p in range(len(P.kind)):
        if P.kind[p] == P_COUPLED:
            o = int(P.cpl[p])
            W.pr[p] = x_coupled[o:o + 3]
        elif P.kind[p] != P_BODY:
            W.pr[p] = P.r0[p]
    if len(R.body_kind):
        body_point_kinematics(P, W)


def catenary_start(layout: Layout, x_coupled: np.ndarray, y: np.ndarray, W, cat_tol: float = 1e-5) -> list[int]:
    """Place rigid objects at their deck pose (:func:`rigid_start`), then every line on its
    quasi-static catenary (spec 6.2); velocities zero. Returns ``(line index, status)`` of the
    lines whose catenary solve failed and were left on the straight chord (a vertical line is
    placed on its chord by design and is not a failure)."""
    rigid_start(layout, x_coupled, y, W)
    L = layout.lines
    E = layout.env
    B = layout.seabed
    failed = []
    for li in range(len(layout.line_N)):
        rA, rB = end_points(layout, li, W)
        N = int(layout.line_N[li])
        out = np.zeros((N + 1, 3))
        Wl = (L.w[li] - E.rho * L.A[li]) * E.g
        # a seabed at the lower end's level, if an end lies on (or below) the local seabed
        seabed = any(r[2] <= seabed_at(B.gx, B.gy, B.gz, E.depth, r[0], r[1])[0] * (1.0 - 1e-5) for r in (rA, rB))
        EA = float(L.seg_EA[L.seg_ptr[li]])
        status, _, _ = catenary_nodes(rA, rB, float(layout.line_L[li]), N, EA, Wl, seabed, cat_tol, out)
        if status not in (STATUS_OK, STATUS_SHORT_SPAN):
            failed.append((li, int(status)))
        # the catenary knows only a flat seabed: nothing starts below the real one (a line laid
        # on a slope starts on it, not through it)
        for j in range(1, N):
            zb = seabed_at(B.gx, B.gy, B.gz, E.depth, out[j, 0], out[j, 1])[0]
            if out[j, 2] < zb:
                out[j, 2] = zb
        for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
            row = int(L.node_row[n])
            y[3 * row:3 * row + 3] = out[n - int(L.node_ptr[li])]
    return failed


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
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


@njit(cache=True, error_model="numpy")
def stationary_solve(y, dtM, dtIC, TmaxIC, threshIC, cfl_ic, seg_min, L, R, P, E, B, Mo, W, S):
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
    for i in range(uoff, y.size):
        y[i] = 0.0
    b = 1.0
    t = 0.0
    e0 = -1.0
    e_last = np.inf
    e_check = -1.0
    next_check = dtIC
    it = 0
    while True:
        rhs(0.0, y, dy, L, R, P, E, B, Mo, W, 1.0, -1)
        e = _accel_norm_sum(dy, n3, n6)
        if e0 < 0.0:
            e0 = e
        if e > e_last:
            b /= 1.01
            for i in range(uoff):
                y[i] = 0.5 * (y[i] + qprev[i])
            rhs(0.0, y, dy, L, R, P, E, B, Mo, W, 1.0, -1)
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


@njit(cache=True, error_model="numpy")
def _fairlead_tensions(L, W, out):
    for li in range(L.seg_ptr.size - 1):
        s = L.seg_ptr[li + 1] - 1
        fx = W.T[s, 0] + W.Td[s, 0]
        fy = W.T[s, 1] + W.Td[s, 1]
        fz = W.T[s, 2] + W.Td[s, 2]
        out[li] = math.sqrt(fx * fx + fy * fy + fz * fz)


@njit(cache=True, error_model="numpy")
def dynamic_relaxation(y, dtM, scheme, sp, dtIC, TmaxIC, threshIC, cd_scale, L, R, P, E, B, Mo, W, S, vmax):
    """MoorDyn's legacy initial-condition solver (spec 6.4): integrate with drag scaled by
    ``cd_scale`` until the end-B tension of every line changes by less than ``threshIC``
    (relative) over ten samples ``dtIC/10`` apart.

    Returns (converged, t, bad_row)."""
    nl = L.seg_ptr.size - 1
    nwin = 10
    hist = np.zeros((nwin, nl))
    ten = np.zeros(nl)
    dtc = dtIC / 10.0
    t = 0.0
    ns = 0
    while t < TmaxIC - 1e-12:
        t1 = min(t + dtc, TmaxIC)
        # final_eval: the Work arrays then hold the loads of the state at t1
        t, bad, _, _ = advance(y, t, t1, dtM, scheme, sp, L, R, P, E, B, Mo, W, cd_scale, S, vmax, True)
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
