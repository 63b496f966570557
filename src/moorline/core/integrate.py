"""Explicit time schemes and the compiled time loop.

The schemes only do algebra on state vectors; all physics is in :func:`moorline.core.rhs.rhs`.
``advance`` runs many internal steps of at most ``dtM`` in compiled code, never stepping across a
knot of the coupled trajectory (so a MoorDyn coupling step of length dt is covered by
floor(dt/dtM) full steps and one shorter remainder, exactly as MoorDyn does).
"""

from __future__ import annotations

import logging
from enum import IntEnum

import numpy as np
from numba import njit

from .rhs import motion_piece, rhs

log = logging.getLogger("moorline.core")


class Scheme(IntEnum):
    EULER = 0
    RK2 = 1
    RK4 = 2


#: largest stable omega*dt of the highest axial segment mode for damping ratio ~0.5-1
#: (spec 5.4, linear analysis of a taut chain); used by the time-step report
STABLE_OMEGA_DT = {Scheme.EULER: 1.0, Scheme.RK2: 2.0, Scheme.RK4: 2.6}

#: how many derivative evaluations one step costs
EVALS_PER_STEP = {Scheme.EULER: 1, Scheme.RK2: 2, Scheme.RK4: 4}

_MOORDYN_NAMES = ("LEULER", "HEUN", "AB2", "AB3", "AB4", "LAB2", "LAB3", "LAB4")
_MOORDYN_PREFIXES = ("BEULER", "MIDPOINT", "ACA", "WILSON")


def parse_scheme(name: str) -> Scheme:
    """Map a MoorDyn ``tScheme`` name to a :class:`Scheme`.

    Euler, RK2 and RK4 are implemented. MoorDyn names that moorline does not implement yet, and
    unknown names, fall back to RK2 as MoorDyn does for unknown names, with a warning.
    """
    key = str(name).strip().upper()
    if key in ("EULER", "RK1"):
        return Scheme.EULER
    if key == "RK2":
        return Scheme.RK2
    if key == "RK4":
        return Scheme.RK4
    if key in _MOORDYN_NAMES or key.startswith(_MOORDYN_PREFIXES):
        log.warning("time scheme %r is a MoorDyn scheme that moorline does not implement yet; using RK2", name)
    else:
        log.warning("unknown time scheme %r (expected Euler, RK2 or RK4); using RK2 as MoorDyn does", name)
    return Scheme.RK2


@njit(cache=True, error_model="numpy")
def _axpy(out, y, h, k):
    for i in range(y.size):
        out[i] = y[i] + h * k[i]


@njit(cache=True, error_model="numpy")
def step(y, t, h, scheme, L, R, P, E, B, Mo, W, cd_scale, S, piece):
    """One step of length ``h`` in place, on trajectory piece ``piece``. ``S``: (5, n) scratch."""
    k1 = S[0]
    k2 = S[1]
    k3 = S[2]
    k4 = S[3]
    yt = S[4]
    # the stick-slip friction anchors are committed at the first stage of every step
    B.ctl[1] = 1
    rhs(t, y, k1, L, R, P, E, B, Mo, W, cd_scale, piece)
    B.ctl[1] = 0
    if scheme == 0:
        for i in range(y.size):
            y[i] += h * k1[i]
    elif scheme == 1:
        _axpy(yt, y, 0.5 * h, k1)
        rhs(t + 0.5 * h, yt, k2, L, R, P, E, B, Mo, W, cd_scale, piece)
        for i in range(y.size):
            y[i] += h * k2[i]
    else:
        _axpy(yt, y, 0.5 * h, k1)
        rhs(t + 0.5 * h, yt, k2, L, R, P, E, B, Mo, W, cd_scale, piece)
        _axpy(yt, y, 0.5 * h, k2)
        rhs(t + 0.5 * h, yt, k3, L, R, P, E, B, Mo, W, cd_scale, piece)
        _axpy(yt, y, h, k3)
        rhs(t + h, yt, k4, L, R, P, E, B, Mo, W, cd_scale, piece)
        c = h / 6.0
        for i in range(y.size):
            y[i] += c * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@njit(cache=True, error_model="numpy")
def check_state(y, vmax):
    """Index of the first state row with a non-finite value or a speed above ``vmax``, else -1."""
    nrow = y.size // 6
    uoff = 3 * nrow
    v2 = vmax * vmax
    for r in range(nrow):
        o = 3 * r
        s = y[uoff + o] ** 2 + y[uoff + o + 1] ** 2 + y[uoff + o + 2] ** 2
        if not (s < v2) or not np.isfinite(y[o] + y[o + 1] + y[o + 2]):
            return r
    return -1


@njit(cache=True, error_model="numpy")
def advance(y, t, t_end, dtM, scheme, L, R, P, E, B, Mo, W, cd_scale, S, vmax, final_eval):
    """Integrate ``y`` in place from ``t`` to ``t_end`` in steps of at most ``dtM``; with
    ``final_eval``, evaluate all loads once more at the final state (on the last step's trajectory
    piece) so that the Work arrays describe the state at ``t_end``.

    Returns
    -------
    t : float
        Time reached (``t_end`` unless the state went bad).
    bad_row : int
        -1, or the state row that became non-finite or exceeded ``vmax`` [m/s].
    n_steps : int
    piece : int
        Trajectory piece of the last step (-1 if no step was taken).
    """
    tol = 1e-9 * dtM
    nk = Mo.t.size
    j = 0
    n_steps = 0
    piece = -1
    while t_end - t > tol:
        h = t_end - t
        if dtM < h:
            h = dtM
        while j < nk and Mo.t[j] <= t + tol:
            j += 1
        if j < nk and Mo.t[j] - t < h:
            h = Mo.t[j] - t
        piece = motion_piece(Mo, t + 0.5 * h)
        step(y, t, h, scheme, L, R, P, E, B, Mo, W, cd_scale, S, piece)
        n_steps += 1
        if t_end - (t + h) <= tol:
            t = t_end
        elif j < nk and abs(Mo.t[j] - (t + h)) <= tol:
            t = Mo.t[j]
        else:
            t = t + h
        bad = check_state(y, vmax)
        if bad >= 0:
            return t, bad, n_steps, piece
    if final_eval:
        rhs(t, y, S[0], L, R, P, E, B, Mo, W, cd_scale, piece)
    return t, -1, n_steps, piece
