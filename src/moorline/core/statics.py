"""Initial conditions: the catenary start of every line, then MoorDyn's stationary solver or its
legacy dynamic relaxation (spec section 6).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .catenary import STATUS_OK, STATUS_SHORT_SPAN, catenary_nodes
from .integrate import advance
from .layout import ATT_POINT, ATT_ROD_A, P_COUPLED, P_FREE, Layout
from .rhs import rhs
from .seabed import seabed_at


def end_points(layout: Layout, x_coupled: np.ndarray, li: int) -> tuple[np.ndarray, np.ndarray]:
    """Initial positions of the two ends of line ``li`` with coupled points at ``x_coupled``."""
    P = layout.points
    R = layout.rods
    out = []
    for j in range(2):
        kind = layout.lines.end_kind[li, j]
        k = int(layout.lines.end_idx[li, j])
        if kind != ATT_POINT:
            # fixed rods: end A, or end B unless the rod has zero length
            out.append(R.rA0[k].copy() if kind == ATT_ROD_A or R.N[k] == 0 else R.rB0[k].copy())
        elif P.kind[k] == P_COUPLED:
            o = int(P.cpl[k])
            out.append(np.asarray(x_coupled[o:o + 3], dtype=float))
        else:
            out.append(P.r0[k].copy())
    return out[0], out[1]


def catenary_start(layout: Layout, x_coupled: np.ndarray, y: np.ndarray, cat_tol: float = 1e-5) -> list[int]:
    """Place every line on its quasi-static catenary (spec 6.2) and free points at their deck
    positions; velocities zero. Returns ``(line index, status)`` of the lines whose catenary solve
    failed and were left on the straight chord (a vertical line is placed on its chord by design
    and is not a failure)."""
    L = layout.lines
    E = layout.env
    B = layout.seabed
    y[:] = 0.0
    failed = []
    for li in range(len(layout.line_N)):
        rA, rB = end_points(layout, x_coupled, li)
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
    P = layout.points
    for p in range(len(P.kind)):
        if P.kind[p] == P_FREE:
            row = int(P.row[p])
            y[3 * row:3 * row + 3] = P.r0[p]
    return failed


@njit(cache=True, error_model="numpy")
def _accel_norm_sum(dy):
    nrow = dy.size // 6
    uoff = 3 * nrow
    s = 0.0
    for r in range(nrow):
        o = uoff + 3 * r
        s += math.sqrt(dy[o] ** 2 + dy[o + 1] ** 2 + dy[o + 2] ** 2)
    return s


@njit(cache=True, error_model="numpy")
def stationary_solve(y, dtM, dtIC, TmaxIC, threshIC, cfl_ic, seg_min, L, R, P, E, B, Mo, W, S):
    """MoorDyn's stationary initial-condition solver (spec 6.3): pseudo-time steps along the
    accelerations with all velocities held at zero.

    Returns
    -------
    status : int
        1: converged (error below threshIC of its first value, or zero); 2: the error stalled
        (relative change over dtIC below threshIC; MoorDyn stops there too); 0: TmaxIC reached;
        -1: non-finite state.
    t : float
        Pseudo time used [s].
    E_mean : float
        Final sum of acceleration norms divided by the number of state rows [m/s^2].
    iterations : int
    """
    nrow = y.size // 6
    uoff = 3 * nrow
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
        e = _accel_norm_sum(dy)
        if e0 < 0.0:
            e0 = e
        if e > e_last:
            b /= 1.01
            for i in range(uoff):
                y[i] = 0.5 * (y[i] + qprev[i])
            rhs(0.0, y, dy, L, R, P, E, B, Mo, W, 1.0, -1)
            e = _accel_norm_sum(dy)
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
            y[i] += dte * 0.5 * dtM * dy[uoff + i]
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
