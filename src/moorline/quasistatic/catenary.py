"""Quasi-static elastic catenary: the "catenary start" of every line (spec section 6.2).

A line of unstretched length ``L`` [m], axial stiffness ``EA`` [N] and wet weight per unit length
``W`` [N/m] (``W < 0`` is buoyant) hangs in the vertical plane through its two ends.  In that plane
end A is the origin, end B lies at horizontal distance ``XF >= 0`` [m] and height ``ZF`` [m], the
unstretched arc length ``s`` [m] runs from A (``s = 0``) to B (``s = L``).

Sign conventions
----------------
``HF`` [N] is the horizontal component of the tension, constant along the line and ``>= 0``.
Vertical components are taken along the line in the direction of increasing ``s`` (from A to B):
on the suspended part ``V(s) = V_A + W s`` and the tension is ``T(s) = sqrt(HF^2 + V(s)^2)``; on
the part lying on the seabed ``V = 0`` and ``T = HF`` (the seabed carries that weight).  The line
pulls end A with the force ``(+HF, V(0))`` and end B with ``(-HF, -V(L))`` (local X from A towards
B, Z up).

* :func:`catenary_solve` returns, as in FAST/MoorDyn, ``VF`` = the vertical tension at the
  **upper** end (end B if ``ZF >= 0``, end A if ``ZF < 0``), positive when the line pulls that end
  down; for a hanging (``W > 0``) line ``VF > 0``, for a buoyant one it can be negative.  The
  problem is solved in the "upright" frame whose origin is the lower end (mirrored when
  ``ZF < 0``), where ``V_A = VF - W L`` is the vertical tension at the lower end, or minus the
  seabed reaction ``W L_B`` when the line touches down.  :func:`catenary_profile` takes this pair.
* :func:`catenary_nodes` returns ``VF`` = ``V(L)``, the physical vertical tension at end B of the
  problem as given, positive when the line pulls end B down (0 when B lies on the seabed).
* :func:`catenary` returns both ends: ``VA = V(0)`` and ``VB = V(L)``.

Seabed model
------------
With ``seabed`` true and ``W > 0`` a frictionless seabed is the horizontal line through the lower
end.  Where the solution would dip below it, the part of length ``L_B`` next to the lower end lies
on the seabed with tension ``HF``.  A buoyant line (``W < 0``) never touches it.  The solve is
refused (:data:`STATUS_TOO_LONG`) when the line is too long to lie as an "L" (flat along the seabed
to below the upper end, then hanging straight up).

Solver
------
Newton-Raphson on ``(HF, VF)`` with the analytic Jacobian, the initial guess of the spec (for
``W < 0`` mirrored vertically, ``VF0 = W L/2 + |W| ZF / (2 tanh lambda0)``, and with the floor of
``HF0`` scaled by ``min(1, |W| L)`` for lines lighter than 1 N), the
increments scaled by ``(1 - tol * iteration)`` and ``HF`` kept above ``tol * HF``; convergence when
``|dHF| <= tol |HF|`` and ``|dVF| <= tol |VF|`` (spec), or when the end conditions hold to round-off
(residual below 1e-12 of the size of the terms), which also covers solutions with ``VF`` at or near
zero where the relative step test can never be met.  Two extra undamped Newton steps then polish
the answer to round-off, and a solution is accepted only if its end-condition residual is below
``tol`` times the size of the problem.  If the first attempt fails, a second one starts from
the same guess with a backtracking line search on the residual (the spec's "one restart"), and a
third one from the straight elastic line (tension ``EA (chord/L - 1)^+ + |W| L / 2``).
Every attempt stops after ``min(max_iter, 1/tol)`` iterations, so a solve never hangs.

Special cases solved in closed form instead of by Newton:

* ``W == 0``: a straight elastic line, tension ``EA (chord/L - 1)`` if ``L <= chord``, otherwise
  :data:`STATUS_SLACK_WEIGHTLESS` (a slack weightless line has no defined shape).
* ``XF == 0`` (vertical line): ``HF = 0`` and ``VF`` from the vertical balance; a slack vertical line
  hangs folded (``V_A`` and ``VF`` of opposite signs).
* ``seabed``, ``W > 0`` and ``ZF == 0`` with ``L < XF``: a taut line flat on the seabed, ``VF = 0``.

Status codes
------------
====  =========================  ============================================================
code  name                       meaning
====  =========================  ============================================================
0     STATUS_OK                  converged (or solved in closed form)
1     STATUS_NOT_CONVERGED       Newton failed in all three attempts (cap, singular, ...)
2     STATUS_TOO_LONG            refused: seabed, ``W > 0`` and ``L >= L_max`` (spec 6.2)
3     STATUS_SLACK_WEIGHTLESS    ``W == 0`` and ``L > chord``: shape undetermined
4     STATUS_INVALID             ``L <= 0``, ``EA <= 0``, ``XF < 0``, ``tol`` outside (0, 0.1],
                                 ``max_iter < 1``, ``N < 1`` or a non-finite input
5     STATUS_SHORT_SPAN          :func:`catenary_nodes` only: horizontal span < 1e-4 m, the
                                 straight (vertical) chord is kept on purpose, as MoorDyn does
====  =========================  ============================================================

On any nonzero status ``HF`` and ``VF`` are NaN.  ``HF == 0`` only for a vertical line (``XF == 0``)
or a weightless line exactly as long as its chord.
"""

from __future__ import annotations

import math
from enum import IntEnum
from typing import NamedTuple

import numpy as np
from numba import njit

__all__ = [
    "DEFAULT_MAX_ITER",
    "DEFAULT_TOL",
    "SHORT_SPAN",
    "STATUS_INVALID",
    "STATUS_NOT_CONVERGED",
    "STATUS_OK",
    "STATUS_SHORT_SPAN",
    "STATUS_SLACK_WEIGHTLESS",
    "STATUS_TOO_LONG",
    "CatenaryResult",
    "CatenaryStatus",
    "catenary",
    "catenary_nodes",
    "catenary_profile",
    "catenary_solve",
    "grounded_catenary_nodes",
]

STATUS_OK = 0
STATUS_NOT_CONVERGED = 1
STATUS_TOO_LONG = 2
STATUS_SLACK_WEIGHTLESS = 3
STATUS_INVALID = 4
STATUS_SHORT_SPAN = 5


class CatenaryStatus(IntEnum):
    """Status codes of the catenary kernels (mirrored by the ``STATUS_*`` constants)."""

    OK = STATUS_OK
    NOT_CONVERGED = STATUS_NOT_CONVERGED
    TOO_LONG = STATUS_TOO_LONG
    SLACK_WEIGHTLESS = STATUS_SLACK_WEIGHTLESS
    INVALID = STATUS_INVALID
    SHORT_SPAN = STATUS_SHORT_SPAN


DEFAULT_TOL = 1e-5
"""Relative convergence tolerance of MoorDyn's catenary start [-]."""
DEFAULT_MAX_ITER = 1000
"""Newton iteration cap per attempt (the spec's 1/tol is also applied) [-]."""
SHORT_SPAN = 1e-4
"""Horizontal span [m] below which :func:`catenary_nodes` keeps the straight chord (spec 6.1)."""

_LAMBDA_MAX = 1e6  # cap of the initial-guess shape parameter (near-vertical lines)
_N_POLISH = 2  # undamped Newton steps after convergence
_N_HALVE = 40  # step halvings of the line search of the second attempt
_RES_ROUNDOFF = 1e-12  # end-condition residual / size of the terms that counts as converged


# ------------------------------------------------------------------------------------------------
# small robust helpers
# ------------------------------------------------------------------------------------------------
@njit(cache=True)
def _asinhc(x):
    """asinh(x)/x, equal to 1 at x = 0, accurate for small |x|."""
    if abs(x) < 1e-3:
        x2 = x * x
        return 1.0 - x2 / 6.0 + 0.075 * x2 * x2 - (5.0 / 112.0) * x2 * x2 * x2
    return math.asinh(x) / x


@njit(cache=True)
def _suspended(HF, VA, W, s, EA):
    """Fully suspended elastic catenary from end A to arc length ``s``.

    Returns ``(X, Z, P, Q, R)`` with ``X``, ``Z`` [m] the position at ``s`` relative to end A and
    the Jacobian pieces ``P = (asinh a - asinh b)/W``, ``Q = (a/sqrt(1+a^2) - b/sqrt(1+b^2))/W``,
    ``R = (1/sqrt(1+b^2) - 1/sqrt(1+a^2))/W`` [m/N], ``a = (VA + W s)/HF``, ``b = VA/HF``.  All
    differences are written without cancellation and without dividing by ``W`` where ``a`` and
    ``b`` have the same sign, so ``W -> 0`` is smooth.  Requires ``HF > 0``.
    """
    a = (VA + W * s) / HF
    b = VA / HF
    e = W * s / HF  # = a - b, computed without cancellation
    sa = math.hypot(1.0, a)
    sb = math.hypot(1.0, b)
    if a == b:  # W s == 0: straight
        Xc = s / sa
        P = s / (HF * sa)
        Q = s / (HF * sa * sa * sa)
    elif a * b > 0.0:
        # asinh a - asinh b = asinh(d), d = a sb - b sa = (a - b)(a + b)/(a sb + b sa)
        g = (a + b) / (a * sb + b * sa)
        d = e * g
        Xc = s * g * _asinhc(d)
        P = Xc / HF
        Q = (s / HF) * g / (sa * sb)
    else:
        P = (math.asinh(a) - math.asinh(b)) / W
        Xc = HF * P
        Q = (a / sa - b / sb) / W
    c = (a + b) / (sa + sb)
    Zc = s * c  # (HF/W)(sa - sb)
    R = (s / HF) * c / (sa * sb)
    X = Xc + HF * s / EA
    Z = Zc + (s / EA) * (VA + 0.5 * W * s)
    return X, Z, P, Q, R


@njit(cache=True)
def _vertical_suspended(VA, W, s, EA):
    """The ``HF -> 0`` limit of the suspended catenary: ``(Z, T)`` at ``s`` of a vertical line."""
    V = VA + W * s
    if W != 0.0:
        Zc = (abs(V) - abs(VA)) / W
    else:
        Zc = s if VA >= 0.0 else -s
    return Zc + (s / EA) * (VA + 0.5 * W * s), abs(V)


@njit(cache=True)
def _residual(HF, VF, XF, ZF, L, EA, W, contact):
    """End-condition residual and Jacobian in the upright frame (``ZF >= 0``, end B on top).

    ``contact`` is true when a seabed exists at the lower end and ``W > 0``.  Returns
    ``(rX, rZ, J11, J12, J21, J22)`` with ``rX = X(L) - XF``, ``rZ = Z(L) - ZF`` [m] and
    ``J = d(X(L), Z(L))/d(HF, VF)`` [m/N].
    """
    VA = VF - W * L
    if contact and VA <= 0.0:
        # part of the line lies on the seabed: touchdown at L_B = L - VF/W
        a = VF / HF
        sa = math.hypot(1.0, a)
        LB = L - VF / W
        X = LB + (VF / W) * _asinhc(a) + HF * L / EA
        Z = (VF / W) * a / (sa + 1.0) + VF * VF / (2.0 * EA * W)
        J11 = (math.asinh(a) - a / sa) / W + L / EA
        J12 = -(a * a) / ((1.0 + sa) * sa * W)
        J22 = a / (sa * W) + VF / (EA * W)
        return X - XF, Z - ZF, J11, J12, J12, J22
    X, Z, P, Q, R = _suspended(HF, VA, W, L, EA)
    J11 = P - Q + L / EA
    J22 = Q + L / EA
    return X - XF, Z - ZF, J11, -R, -R, J22


@njit(cache=True)
def _newton(XF, ZF, L, EA, W, contact, tol, max_iter, HF0, VF0, line_search):
    """One Newton attempt in the upright frame. Returns ``(HF, VF, ok, iterations)``."""
    cap = max_iter
    cap_tol = int(1.0 / tol)
    if cap_tol < cap:
        cap = cap_tol
    HF = HF0
    VF = VF0
    rX, rZ, J11, J12, J21, J22 = _residual(HF, VF, XF, ZF, L, EA, W, contact)
    rn = math.hypot(rX, rZ)
    it = 0
    converged = False
    while it < cap:
        it += 1
        det = J11 * J22 - J12 * J21
        if not (math.isfinite(det) and det != 0.0 and math.isfinite(rn)):
            return HF, VF, False, it
        damp = 1.0 - tol * it
        dHF = -(J22 * rX - J12 * rZ) / det * damp
        dVF = -(J11 * rZ - J21 * rX) / det * damp
        full = True
        converged = False
        k = 0
        while True:
            HFn = HF + dHF
            if HFn < tol * HF:
                HFn = tol * HF
            VFn = VF + dVF
            if contact and VFn < 0.0 and VF > 0.0:
                VFn = 0.5 * VF  # the lower end cannot be below the seabed
            rXn, rZn, J11n, J12n, J21n, J22n = _residual(HFn, VFn, XF, ZF, L, EA, W, contact)
            rnn = math.hypot(rXn, rZn)
            if not line_search or (math.isfinite(rnn) and rnn <= rn) or k >= _N_HALVE:
                break
            dHF *= 0.5
            dVF *= 0.5
            full = False
            k += 1
        if full:
            small_step = abs(HFn - HF) <= tol * abs(HFn) and abs(VFn - VF) <= tol * abs(VFn)
            size = L + XF + ZF + (abs(HFn) + abs(VFn)) * L / EA  # scale of the terms summed [m]
            converged = small_step or rnn <= _RES_ROUNDOFF * size
        HF = HFn
        VF = VFn
        rX, rZ, J11, J12, J21, J22 = rXn, rZn, J11n, J12n, J21n, J22n
        rn = rnn
        if converged:
            break
    if not converged:
        return HF, VF, False, it
    # polish: undamped Newton steps, kept only while they reduce the residual
    for _ in range(_N_POLISH):
        det = J11 * J22 - J12 * J21
        if not (math.isfinite(det) and det != 0.0) or rn == 0.0:
            break
        HFn = HF - (J22 * rX - J12 * rZ) / det
        VFn = VF - (J11 * rZ - J21 * rX) / det
        if not HFn > 0.0:
            break
        rXn, rZn, J11n, J12n, J21n, J22n = _residual(HFn, VFn, XF, ZF, L, EA, W, contact)
        rnn = math.hypot(rXn, rZn)
        if not rnn < rn:
            break
        HF = HFn
        VF = VFn
        rX, rZ, J11, J12, J21, J22 = rXn, rZn, J11n, J12n, J21n, J22n
        rn = rnn
    # sanity: the end conditions must actually hold
    size = L + XF + ZF + (abs(HF) + abs(VF)) * L / EA
    ok = math.isfinite(rn) and HF > 0.0 and rn <= tol * size
    return HF, VF, ok, it


@njit(cache=True)
def _vertical_VF(ZF, L, EA, W):
    """``VF`` of a vertical line (``XF = 0``, ``HF = 0``, ``W != 0``) reaching height ``ZF``.

    Z(L) = (|VF| - |VF - W L|)/W + (L/EA)(VF - W L/2) is piecewise linear and increasing in VF.
    """
    WL = W * L
    k1 = min(0.0, WL)
    k2 = max(0.0, WL)

    def f(v):
        return (abs(v) - abs(v - WL)) / W + (L / EA) * (v - 0.5 * WL) - ZF

    f1 = f(k1)
    f2 = f(k2)
    if f1 >= 0.0:  # below the first kink, slope L/EA
        return k1 - f1 * EA / L
    if f2 <= 0.0:  # above the second kink, slope L/EA
        return k2 - f2 * EA / L
    return k1 - f1 * (k2 - k1) / (f2 - f1)  # linear in between


@njit(cache=True)
def _solve(XF, ZF, L, EA, W, seabed, tol, max_iter):
    """Catenary solve. Returns ``(HF, VF, status, iterations)``; see :func:`catenary_solve`."""
    nan = np.nan
    if not (math.isfinite(XF) and math.isfinite(ZF) and math.isfinite(L) and math.isfinite(W)):
        return nan, nan, STATUS_INVALID, 0
    if not (L > 0.0 and EA > 0.0 and XF >= 0.0 and tol > 0.0 and tol <= 0.1 and max_iter >= 1):
        return nan, nan, STATUS_INVALID, 0
    chord = math.hypot(XF, ZF)
    if W == 0.0:
        if L > chord:  # includes chord == 0
            return nan, nan, STATUS_SLACK_WEIGHTLESS, 0
        T = EA * (chord / L - 1.0)
        return T * XF / chord, T * abs(ZF) / chord, STATUS_OK, 0
    contact = seabed and W > 0.0
    Zu = abs(ZF)  # upright frame: lower end at the origin
    if contact:
        # refusal: too long to lie flat to below the upper end and hang straight up from there
        Lv = 2.0 * Zu / (1.0 + math.sqrt(1.0 + 2.0 * Zu * W / EA))
        if L >= XF + Lv:
            return nan, nan, STATUS_TOO_LONG, 0
    if XF == 0.0:
        return 0.0, _vertical_VF(Zu, L, EA, W), STATUS_OK, 0
    if contact and Zu == 0.0:
        # both ends on the seabed and L < XF (else refused): taut and flat
        return EA * (XF / L - 1.0), 0.0, STATUS_OK, 0
    # initial guess (spec 6.2)
    if L <= chord:
        lam = 0.2
    else:
        q = 3.0 * ((L * L - Zu * Zu) / (XF * XF) - 1.0)
        lam = math.sqrt(q) if q < _LAMBDA_MAX * _LAMBDA_MAX else _LAMBDA_MAX
    # spec: HF0 = max(|W XF / (2 lam)|, tol); the floor is scaled down for lines lighter than 1 N
    HF0 = max(abs(W * XF / (2.0 * lam)), tol * min(1.0, abs(W) * L))
    VF0 = 0.5 * (W * L + abs(W) * Zu / math.tanh(lam))  # spec's guess, mirrored vertically if W < 0
    HF, VF, ok, it = _newton(XF, Zu, L, EA, W, contact, tol, max_iter, HF0, VF0, False)
    if not ok:
        HF, VF, ok, it2 = _newton(XF, Zu, L, EA, W, contact, tol, max_iter, HF0, VF0, True)
        it += it2
    if not ok:
        # last resort: start from the straight elastic line carrying the weight
        T0 = EA * max(chord / L - 1.0, 0.0) + 0.5 * abs(W) * L
        HF1 = T0 * XF / chord
        VF1 = T0 * Zu / chord + 0.5 * W * L
        HF, VF, ok, it2 = _newton(XF, Zu, L, EA, W, contact, tol, max_iter, HF1, VF1, True)
        it += it2
    if not ok:
        return nan, nan, STATUS_NOT_CONVERGED, it
    return HF, VF, STATUS_OK, it


# ------------------------------------------------------------------------------------------------
# public kernels
# ------------------------------------------------------------------------------------------------
@njit(cache=True)
def catenary_solve(XF, ZF, L, EA, W, seabed, tol=DEFAULT_TOL, max_iter=DEFAULT_MAX_ITER):
    """Solve the 2-D elastic catenary for the end tensions.

    Parameters
    ----------
    XF : float
        Horizontal distance from end A to end B [m], ``>= 0``.
    ZF : float
        Height of end B above end A [m] (may be negative).
    L : float
        Unstretched length [m].
    EA : float
        Axial stiffness [N] (``EA_ref`` for a tabulated EA, spec 3.2).
    W : float
        Wet weight per unit length [N/m]; negative is buoyant, zero is weightless.
    seabed : bool
        A frictionless seabed through the lower end (used only when ``W > 0``).
    tol : float, optional
        Relative convergence tolerance [-] in (0, 0.1].
    max_iter : int, optional
        Newton iteration cap per attempt [-] (``1/tol`` is also applied).

    Returns
    -------
    HF : float
        Horizontal tension [N], ``>= 0``.
    VF : float
        Vertical tension at the upper end [N] (end B if ``ZF >= 0``, else end A), positive when
        the line pulls that end down; see the module docstring.
    status : int
        0 on success, otherwise a ``STATUS_*`` code (then ``HF`` and ``VF`` are NaN).
    """
    HF, VF, status, _ = _solve(XF, ZF, L, EA, W, seabed, tol, max_iter)
    return HF, VF, status


@njit(cache=True)
def _end_verticals(ZF, L, W, contact, VF):
    """``(V(0), V(L))`` [N]: vertical tensions at ends A and B along ``s`` (0 on the seabed),
    from ``VF`` at the upper end."""
    Vlow = VF - W * L  # at the lower end, along the upright frame's arc length
    if contact and Vlow <= 0.0:
        Vlow = 0.0
    if ZF >= 0.0:
        return Vlow, VF
    return -VF, 0.0 - Vlow


@njit(cache=True)
def _upright_profile(HF, VF, L, EA, W, contact, s):
    """Position and tension at ``s`` of a solution in a frame where A is the lower end."""
    VA = VF - W * L
    if contact and VA <= 0.0:
        LB = L - VF / W
        if s <= LB:
            return s * (1.0 + HF / EA), 0.0, HF
        ds = s - LB
        if HF > 0.0:
            u = W * ds / HF
            su = math.hypot(1.0, u)
            X = LB + ds * _asinhc(u) + HF * s / EA
            Z = ds * u / (su + 1.0) + W * ds * ds / (2.0 * EA)
            return X, Z, HF * su
        return LB, ds + W * ds * ds / (2.0 * EA), W * ds
    if HF > 0.0:
        X, Z, _, _, _ = _suspended(HF, VA, W, s, EA)
        return X, Z, math.hypot(HF, VA + W * s)
    Z, T = _vertical_suspended(VA, W, s, EA)
    return 0.0, Z, T


@njit(cache=True)
def catenary_profile(XF, ZF, L, EA, W, seabed, HF, VF, s, X, Z, T):
    """Fill the shape and tension of a solved catenary at given arc lengths.

    Parameters
    ----------
    XF, ZF, L, EA, W, seabed
        The problem, as passed to :func:`catenary_solve` (units there).
    HF, VF : float
        The solution of :func:`catenary_solve` [N] (``VF`` at the upper end).
    s : ndarray, shape (n,)
        Unstretched arc lengths from end A [m], in ``[0, L]``.
    X, Z : ndarray, shape (n,)
        Output: horizontal distance from A towards B and height above A [m].
    T : ndarray, shape (n,)
        Output: tension magnitude [N].

    Notes
    -----
    ``W == 0`` gives the straight line along the chord (stretched uniformly); with ``HF == 0``
    (vertical line) ``X = 0``.  With ``ZF < 0`` the seabed part lies next to end B.
    """
    n = s.shape[0]
    if W == 0.0:
        Tm = math.hypot(HF, VF)
        for i in range(n):
            f = s[i] / L
            X[i] = XF * f
            Z[i] = ZF * f
            T[i] = Tm
        return
    contact = seabed and W > 0.0
    if ZF >= 0.0:
        for i in range(n):
            X[i], Z[i], T[i] = _upright_profile(HF, VF, L, EA, W, contact, s[i])
        return
    # mirrored: the upright frame runs from end B (origin, lower end) to end A
    for i in range(n):
        xm, zm, tm = _upright_profile(HF, VF, L, EA, W, contact, L - s[i])
        X[i] = XF - xm
        Z[i] = ZF + zm
        T[i] = tm


@njit(cache=True)
def catenary_nodes(rA, rB, L, N, EA, W, seabed, tol, out, max_iter=DEFAULT_MAX_ITER):
    """Place the N+1 nodes of a line on its catenary between two end points in 3-D.

    Parameters
    ----------
    rA, rB : ndarray, shape (3,)
        Positions of end A (node 0) and end B (node N) [m], z up.
    L : float
        Unstretched length [m].
    N : int
        Number of segments, ``>= 1``.
    EA : float
        Axial stiffness [N].
    W : float
        Wet weight per unit length [N/m].
    seabed : bool
        A frictionless seabed through the lower end (the caller decides, spec 6.2).
    tol : float
        Relative convergence tolerance [-].
    out : ndarray, shape (N+1, 3)
        Output: node positions [m]; node i at unstretched arc length ``i L / N``. Nodes 0 and N
        are exactly ``rA`` and ``rB``.
    max_iter : int, optional
        Newton iteration cap per attempt [-].

    Returns
    -------
    status : int
        0 on success; otherwise a ``STATUS_*`` code and ``out`` holds the straight chord.
        ``STATUS_SHORT_SPAN`` (5) means a horizontal span below 1e-4 m, where the straight chord
        is kept by design.
    HF : float
        Horizontal tension [N] (NaN unless status is 0).
    VF : float
        Vertical tension at end B [N] (end B as given, upper or lower), positive when the line
        pulls end B down: the line pulls end B with the force ``-HF (cos psi, sin psi, 0) - VF e_z``
        and 0 when end B lies on the seabed; NaN unless status is 0.
    """
    dx = rB[0] - rA[0]
    dy = rB[1] - rA[1]
    dz = rB[2] - rA[2]
    XF = math.hypot(dx, dy)
    HF = np.nan
    VF = np.nan
    if N < 1:
        return STATUS_INVALID, HF, VF
    status = STATUS_SHORT_SPAN
    if XF >= SHORT_SPAN:
        HF, VF, status, _ = _solve(XF, dz, L, EA, W, seabed, tol, max_iter)
    if status == STATUS_OK:
        cpsi = dx / XF
        spsi = dy / XF
        s = np.empty(N + 1)
        X = np.empty(N + 1)
        Z = np.empty(N + 1)
        T = np.empty(N + 1)
        for i in range(N + 1):
            s[i] = L * i / N
        catenary_profile(XF, dz, L, EA, W, seabed, HF, VF, s, X, Z, T)
        for i in range(1, N):
            out[i, 0] = rA[0] + X[i] * cpsi
            out[i, 1] = rA[1] + X[i] * spsi
            out[i, 2] = rA[2] + Z[i]
    else:
        for i in range(1, N):
            f = i / N
            out[i, 0] = rA[0] + f * dx
            out[i, 1] = rA[1] + f * dy
            out[i, 2] = rA[2] + f * dz
    for j in range(3):
        out[0, j] = rA[j]
        out[N, j] = rB[j]
    if status == STATUS_OK:
        _, VF = _end_verticals(dz, L, W, seabed and W > 0.0, VF)
    return status, HF, VF


# ------------------------------------------------------------------------------------------------
# plain-Python convenience
# ------------------------------------------------------------------------------------------------
class CatenaryResult(NamedTuple):
    """Result of :func:`catenary` (sign conventions in the module docstring).

    Attributes
    ----------
    HF : float
        Horizontal tension [N].
    VF : float
        Vertical tension at the upper end [N], as returned by :func:`catenary_solve`.
    VA, VB : float
        Vertical tension at end A and end B along the line from A to B [N]: the line pulls end A
        up with ``VA`` and end B down with ``VB``; 0 at an end lying on the seabed.
    s : ndarray, shape (n+1,)
        Unstretched arc length from end A [m].
    X, Z : ndarray, shape (n+1,)
        Horizontal distance from A towards B and height above A [m].
    T : ndarray, shape (n+1,)
        Tension magnitude [N].
    touchdown_length : float
        Unstretched length lying on the seabed [m], next to the lower end (0 if none).
    status : CatenaryStatus
        Solver status.
    iterations : int
        Newton iterations used (all attempts).
    """

    HF: float
    VF: float
    VA: float
    VB: float
    s: np.ndarray
    X: np.ndarray
    Z: np.ndarray
    T: np.ndarray
    touchdown_length: float
    status: CatenaryStatus
    iterations: int


def catenary(XF, ZF, L, EA, W, seabed=False, n=50, *, tol=DEFAULT_TOL, max_iter=DEFAULT_MAX_ITER):
    """Solve a 2-D elastic catenary and sample its profile.

    Parameters
    ----------
    XF : float
        Horizontal distance from end A to end B [m], ``>= 0``.
    ZF : float
        Height of end B above end A [m].
    L : float
        Unstretched length [m].
    EA : float
        Axial stiffness [N].
    W : float
        Wet weight per unit length [N/m] (negative: buoyant).
    seabed : bool, optional
        A frictionless seabed through the lower end.
    n : int, optional
        Number of intervals of the profile (``n + 1`` samples, equally spaced in ``s``).
    tol : float, optional
        Relative convergence tolerance [-].
    max_iter : int, optional
        Newton iteration cap per attempt [-].

    Returns
    -------
    CatenaryResult
        On failure the forces and the profile arrays are NaN; check ``status``.
    """
    XF = float(XF)
    ZF = float(ZF)
    L = float(L)
    EA = float(EA)
    W = float(W)
    seabed = bool(seabed)
    HF, VF, status, iterations = _solve(XF, ZF, L, EA, W, seabed, float(tol), int(max_iter))
    s = np.linspace(0.0, L, int(n) + 1)
    X = np.full_like(s, np.nan)
    Z = np.full_like(s, np.nan)
    T = np.full_like(s, np.nan)
    VA = VB = np.nan
    touchdown = 0.0
    if status == STATUS_OK:
        catenary_profile(XF, ZF, L, EA, W, seabed, HF, VF, s, X, Z, T)
        contact = seabed and W > 0.0
        VA, VB = _end_verticals(ZF, L, W, contact, VF)
        if contact:
            touchdown = min(max(L - VF / W, 0.0), L)
    return CatenaryResult(
        float(HF),
        float(VF),
        float(VA),
        float(VB),
        s,
        X,
        Z,
        T,
        float(touchdown),
        CatenaryStatus(int(status)),
        int(iterations),
    )


# ------------------------------------------------------------------------------------------------
# a line hanging from two ends above the seabed and lying on it between them
# ------------------------------------------------------------------------------------------------
def _hang(h, a):
    """Horizontal extent and arc length of a catenary of parameter ``a`` = H / W [m] from a point
    where it is horizontal up to a height ``h`` >= 0 [m] above it: a acosh(1 + h/a) and
    sqrt(h^2 + 2 a h) (acosh through log1p: accurate for h << a)."""
    t = h / a
    return a * math.log1p(t + math.sqrt(t * (t + 2.0))), math.sqrt(h * h + 2.0 * a * h)


def _grounded_parameter(X, hA, hB, L):
    """a = H / W of the inextensible grounded shape (see :func:`grounded_catenary_nodes`), or NaN
    when it has none. g(a) = xA + xB + (L - sA - sB) - X rises with a from L - X - hA - hB
    (a -> 0: straight up and down) to L - X (a -> inf): a root needs L < X + hA + hB and L > X."""
    def g(a):
        xa, sa = _hang(hA, a)
        xb, sb = _hang(hB, a)
        return xa + xb + L - sa - sb - X

    if not (L < X + hA + hB and L > X):
        return math.nan
    lo = 1e-12 * max(X, 1.0)
    hi = max(X, 1.0)
    for _ in range(200):
        if g(hi) > 0.0:
            break
        lo, hi = hi, 4.0 * hi
    else:
        return math.nan
    if g(lo) >= 0.0:
        return math.nan
    from scipy.optimize import brentq

    return brentq(g, lo, hi, xtol=1e-14 * hi, rtol=4.0 * np.finfo(float).eps, maxiter=500)


def grounded_catenary_nodes(rA, rB, L, N, EA, W, zb, out):
    """Place the N+1 nodes of a sinking line (``W`` > 0) whose two ends hang above a flat,
    frictionless seabed at height ``zb`` [m] but which is long enough to lie on it between them:
    a catenary hanging from each end down to a touchdown where it meets the seabed level with zero
    slope, and a straight run along the seabed in between, all at the same horizontal tension H.

    :func:`catenary_nodes` knows a seabed only through the lower end (spec 6.2, as MoorDyn's start):
    for ends above the seabed it gives the free catenary, whose sag may run through the seabed.
    This is the shape a line then takes at rest. It is solved inextensible (one equation in
    H / W, by Brent's method), then stretched once by the seabed tension: the unstretched length
    becomes L (1 + H / EA) with H from the inextensible shape (the hanging parts carry more
    tension; a start guess needs no more).

    Parameters
    ----------
    rA, rB : ndarray, shape (3,)
        End positions [m], z up, both at or above ``zb`` (an end below is taken at ``zb``).
    L : float
        Unstretched length [m].
    N : int
        Number of segments.
    EA : float
        Axial stiffness [N].
    W : float
        Wet weight per unit length [N/m].
    zb : float
        Seabed height [m].
    out : ndarray, shape (N+1, 3)
        Output, written only on success: node i at unstretched arc length ``i L / N`` from end A;
        nodes 0 and N are ``rA`` and ``rB``.

    Returns
    -------
    H : float
        Horizontal tension [N] of the placed shape, or NaN (``out`` untouched) when the line has
        no such shape: ``W`` <= 0, a horizontal span under :data:`SHORT_SPAN`, a line too short
        to reach the seabed (its free catenary is the shape) or too long to lie as a double "L"
        (straight down from each end and along the seabed between them).
    """
    rA = np.asarray(rA, dtype=float)
    rB = np.asarray(rB, dtype=float)
    d = rB[:2] - rA[:2]
    X = float(np.hypot(d[0], d[1]))
    if not (W > 0.0 and L > 0.0 and EA > 0.0 and N >= 1 and X >= SHORT_SPAN):
        return math.nan
    u = d / X
    hA = max(float(rA[2]) - zb, 0.0)
    hB = max(float(rB[2]) - zb, 0.0)
    a = _grounded_parameter(X, hA, hB, L)
    if not math.isfinite(a):
        return math.nan
    Ls = L * (1.0 + a * W / EA)
    a = _grounded_parameter(X, hA, hB, Ls)
    if not math.isfinite(a):
        return math.nan
    xA, sA = _hang(hA, a)
    _, sB = _hang(hB, a)
    sG = Ls - sA - sB
    if sG < 0.0:  # (the line does not reach the seabed)
        return math.nan
    for i in range(1, N):
        s = Ls * i / N
        if s <= sA:  # hanging from end A: sigma along the line from the touchdown
            sig = sA - s
            x = xA - a * math.asinh(sig / a)
            z = zb + math.sqrt(a * a + sig * sig) - a
        elif s <= sA + sG:
            x = xA + (s - sA)
            z = zb
        else:
            sig = s - sA - sG
            x = xA + sG + a * math.asinh(sig / a)
            z = zb + math.sqrt(a * a + sig * sig) - a
        out[i, 0] = rA[0] + x * u[0]
        out[i, 1] = rA[1] + x * u[1]
        out[i, 2] = z
    out[0] = rA
    out[N] = rB
    return a * W
