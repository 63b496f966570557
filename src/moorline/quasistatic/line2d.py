"""The line of the quasi-static model: an elastic catenary in its vertical plane, with seabed contact
(flat or sloped) and seabed friction at its lower end, and the derivatives of its end forces.

It extends :mod:`moorline.quasistatic.catenary` (the dynamic model's start guess, frictionless and
flat, kept unchanged) with what the quasi-static solver needs: friction, a sloped seabed, lines longer
than their "L" shape, warm starts and the analytic derivatives of both end forces.

Upright frame
-------------
The line is solved in the frame whose origin is its **lower** end; the upper end lies at horizontal
distance ``X >= 0`` [m] and height ``Z >= 0`` [m]. One exception: a line whose seabed end is the higher
one, on a seabed descending from it, is solved with the origin at its seabed end and ``Z < 0`` (the other
end lower, but above the seabed plane, ``Z >= X t``), so that it can lie down the slope before lifting off;
"lower end" below then means the origin end. ``H`` [N] is the horizontal tension at the upper
end, ``V`` [N] its vertical tension: the line pulls the upper end with ``(-H, -V)`` (towards the lower
end horizontally, downwards when ``V > 0``) and the lower end with ``(+HL, +VL)``. Without friction
``HL = H``; on a suspended line ``VL = V - W L``.

Seabed (``contact``)
--------------------
With ``contact`` and ``W > 0`` the seabed is the plane through the lower end with slope
``t = tan(alpha)`` along ``+X`` (``alpha > 0``: rising towards the upper end). A length ``LB`` next to
the lower end lies on it; at touchdown the line is tangent to it (vertical tension ``H t``), and the
suspended length is ``Ls = (V - H t)/W``. On the seabed the tension falls towards the lower end at the
rate ``k = W (sin alpha + CB cos alpha)`` per unit length (the weight component down the slope plus
Coulomb friction ``CB`` times the normal load ``W cos alpha``), and never below zero: this is
MAP++'s seabed friction model (Masciola et al. 2013, the ``CB`` term of its touchdown equation), with
friction fully mobilised towards the lower end, as when the line was pulled out from the upper end.
Its flat form (``t = 0``) is MAP++'s published equation::

    X = LB + (H/W) asinh(V/H) + H L/EA + (CB W/2EA) [-LB^2 + (LB - H/(CB W)) max(LB - H/(CB W), 0)]
    Z = (H/W) (sqrt(1 + (V/H)^2) - 1) + V^2 / (2 EA W)

and the lower-end (anchor) tension is ``max(H - CB W LB, 0)``.

Special shapes, solved in closed form:

* a line at least as long as its "L" shape (along the seabed to below the upper end, then hanging
  straight down to it) lies slack: ``H = 0``, ``V = W Lh`` with ``Lh`` the hanging length; the rest lies
  bunched on the seabed (no error: "a line longer than possible"). On a seabed descending from the origin
  end more steeply than friction holds (``k < 0``), the rest lies bunched at the foot below the upper end and
  the grounded part between it and the origin end pulls that end down the slope with ``-k X sqrt(1 + t^2)``;
* the upper end on the seabed (``Z = X t``): a taut grounded line, tension from Hooke's law with the
  friction and slope gradient (a slack one when ``L >= X / cos alpha``);
* a vertical line (``X = 0``) and a weightless line (``W = 0``, straight; slack: no force).

Derivatives
-----------
``d(H, V, HL, VL)/d(X, Z, t)`` [N/m, N] by the implicit-function theorem on the end conditions (the
inverse of the 2x2 Jacobian of ``(X, Z)`` with respect to ``(H, V)``, plus the explicit dependence on
the slope ``t``), and the transverse stiffnesses ``H/X`` and ``HL/X`` (their limits at ``X = 0``).
Lifting an upper end that lies on a flat seabed has an unbounded stiffness; that branch reports zero
``Z`` derivatives (the seabed carries the end).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .catenary import _residual, _suspended, _vertical_VF

__all__ = ["LINE2D_SIZE", "O_D", "O_H", "O_HL", "O_KTL", "O_KTU", "O_LB", "O_V", "O_VL", "QS_BELOW_SEABED",
           "QS_INVALID", "QS_NOT_CONVERGED", "QS_OK", "line_profile_upright", "upright_line"]

QS_OK = 0
QS_NOT_CONVERGED = 1
QS_INVALID = 4
QS_BELOW_SEABED = 6

# layout of the ``out`` array of :func:`upright_line`
O_H = 0  # horizontal tension at the upper end [N]
O_V = 1  # vertical tension at the upper end [N]
O_HL = 2  # horizontal pull on the lower end [N]
O_VL = 3  # vertical pull on the lower end [N]
O_LB = 4  # unstretched length on the seabed [m]
O_KTU = 5  # transverse stiffness of the upper end H/X [N/m]
O_KTL = 6  # transverse stiffness of the lower end HL/X [N/m]
O_D = 7  # d(H, V, HL, VL)/d(X, Z, t), row-major 4 x 3
LINE2D_SIZE = 19

_RTOL = 1e-12  # converged when the end-condition residual is below this times the size of the problem
_MAXIT = 60  # Newton iterations per attempt
_NHALVE = 40  # step halvings of the line search
_VERTICAL = 1e-9  # X below this times the size of the problem: a vertical line
_ON_BED = 1e-9  # upper end within this times the size of the problem of the seabed plane: on it


@njit(cache=True, error_model="numpy")
def _hang_length(h, W, EA):
    """Unstretched length [m] of a line of weight ``W`` hanging straight down over a height ``h``."""
    if h <= 0.0:
        return 0.0
    return 2.0 * h / (1.0 + math.sqrt(1.0 + 2.0 * h * W / EA))


@njit(cache=True, error_model="numpy")
def _touchdown(H, V, L, EA, W, t, CB):
    """End position and Jacobian of a line touching down on the seabed plane of slope ``t``.

    Returns ``(X, Z, JXH, JXV, JZH, JZV, LB, TA, TA_H, TA_V)``: the upper end position [m], its
    derivatives with respect to ``(H, V)`` [m/N], the length on the seabed [m], the tension at the
    lower end ``TA`` [N] and its derivatives [-]. Requires ``H > 0`` and ``H t <= V <= H t + W L``.
    """
    st = math.hypot(1.0, t)
    c = 1.0 / st
    sn = t * c
    k = W * (sn + CB * c)
    Ls = (V - H * t) / W
    LB = L - Ls
    a = V / H
    sa = math.hypot(1.0, a)
    Xs, Zs, P, _, _ = _suspended(H, H * t, W, Ls, EA)
    XsH = P - (a / sa) / W + Ls / EA - H * t / (W * EA)
    XsV = 1.0 / (sa * W) + H / (W * EA)
    ZsH = (1.0 / sa - st) / W - H * t * t / (EA * W)
    ZsV = (a / sa) / W + V / (EA * W)
    TT = H * st  # tension at touchdown
    if k <= 0.0 or TT >= k * LB:
        TA = TT - k * LB
        S = 0.5 * (TT + TA) * LB  # integral of the tension over the grounded length
        S_T = LB
        S_LB = TA
        TA_H = st - k * t / W
        TA_V = k / W
    else:  # the tension reaches zero on the seabed
        TA = 0.0
        S = TT * TT / (2.0 * k)
        S_T = TT / k
        S_LB = 0.0
        TA_H = 0.0
        TA_V = 0.0
    G = LB + S / EA
    GH = (t / W) * (1.0 + S_LB / EA) + S_T * st / EA
    GV = -(1.0 + S_LB / EA) / W
    return (c * G + Xs, sn * G + Zs, c * GH + XsH, c * GV + XsV, sn * GH + ZsH, sn * GV + ZsV, LB, TA, TA_H,
            TA_V)


@njit(cache=True, error_model="numpy")
def _touchdown_t(H, V, L, EA, W, t, CB):
    """Explicit slope derivatives of :func:`_touchdown` at fixed ``(H, V)``: ``(X_t, Z_t, TA_t)``."""
    st = math.hypot(1.0, t)
    c = 1.0 / st
    c3 = c * c * c
    sn = t * c
    k = W * (sn + CB * c)
    k_t = W * c3 * (1.0 - CB * t)
    Ls = (V - H * t) / W
    LB = L - Ls
    LB_t = H / W
    Xs_t = -(H / W) * (c + H / EA)
    Zs_t = -(H * t / W) * (c + H / EA)
    TT = H * st
    TT_t = H * t * c
    if k <= 0.0 or TT >= k * LB:
        TA = TT - k * LB
        S = 0.5 * (TT + TA) * LB
        S_t = LB * TT_t + TA * LB_t - 0.5 * LB * LB * k_t
        TA_t = TT_t - LB * k_t - k * LB_t
    else:
        S = TT * TT / (2.0 * k)
        S_t = (TT / k) * TT_t - (TT * TT / (2.0 * k * k)) * k_t
        TA_t = 0.0
    G = LB + S / EA
    G_t = LB_t + S_t / EA
    return -t * c3 * G + c * G_t + Xs_t, c3 * G + sn * G_t + Zs_t, TA_t


@njit(cache=True, error_model="numpy")
def _res(H, V, X, Z, L, EA, W, contact, t, CB):
    """Residual ``(rX, rZ)`` [m] and Jacobian of the end conditions at ``(H, V)``, either branch."""
    if contact and V - W * L < H * t:
        Xe, Ze, J11, J12, J21, J22, _, _, _, _ = _touchdown(H, V, L, EA, W, t, CB)
        return Xe - X, Ze - Z, J11, J12, J21, J22
    return _residual(H, V, X, Z, L, EA, W, False)


@njit(cache=True, error_model="numpy")
def _clamp(H, V, Hn, Vn, L, W, contact, t):
    """Keep a Newton iterate admissible: ``H > 0`` and, on the seabed, a suspended length >= 0."""
    if not Hn > 0.0:
        Hn = 0.1 * H
    if contact and Vn < Hn * t:
        Vn = Hn * t + 0.5 * max(V - H * t, 0.0)
    return Hn, Vn


@njit(cache=True, error_model="numpy")
def _newton(X, Z, L, EA, W, contact, t, CB, H, V, size):
    """Damped Newton on ``(H, V)`` from a start; returns ``(H, V, ok, iterations)``."""
    if not (H > 0.0 and math.isfinite(H) and math.isfinite(V)):
        return H, V, False, 0
    H, V = _clamp(H, V, H, V, L, W, contact, t)
    rX, rZ, J11, J12, J21, J22 = _res(H, V, X, Z, L, EA, W, contact, t, CB)
    rn = math.hypot(rX, rZ)
    polish = False
    for it in range(1, _MAXIT + 1):
        if rn <= _RTOL * size:
            if polish:
                return H, V, True, it - 1
            polish = True  # one more step (kept only if it lowers the residual): round-off accuracy
        det = J11 * J22 - J12 * J21
        if not (math.isfinite(det) and det != 0.0 and math.isfinite(rn)):
            return H, V, False, it
        dH = -(J22 * rX - J12 * rZ) / det
        dV = -(J11 * rZ - J21 * rX) / det
        lam = 1.0
        for _ in range(_NHALVE):
            Hn, Vn = _clamp(H, V, H + lam * dH, V + lam * dV, L, W, contact, t)
            rXn, rZn, J11n, J12n, J21n, J22n = _res(Hn, Vn, X, Z, L, EA, W, contact, t, CB)
            rnn = math.hypot(rXn, rZn)
            if math.isfinite(rnn) and rnn < rn:
                break
            lam *= 0.5
        if not (math.isfinite(rnn) and rnn < rn):
            return H, V, polish or rn <= 1e3 * _RTOL * size, it
        H, V = Hn, Vn
        rX, rZ, J11, J12, J21, J22 = rXn, rZn, J11n, J12n, J21n, J22n
        rn = rnn
    return H, V, rn <= _RTOL * size, _MAXIT


@njit(cache=True, error_model="numpy")
def _v_for_h(H, X, Z, L, EA, W, contact, t, CB, V0):
    """The ``V`` at which the end height is ``Z`` for a given ``H`` (``Z`` rises with ``V``):
    safeguarded Newton in a bracket. Returns ``(V, X(H, V))``."""
    lo = H * t if contact else -abs(W) * L - 10.0 * (H + abs(W) * L + 1.0)
    hi = max(V0, lo) + abs(W) * L + H + 1.0
    for _ in range(200):  # grow the bracket until Z(hi) >= Z
        if _res(H, hi, X, Z, L, EA, W, contact, t, CB)[1] >= 0.0:
            break
        hi = lo + 2.0 * (hi - lo)
    if not contact:
        for _ in range(200):
            if _res(H, lo, X, Z, L, EA, W, contact, t, CB)[1] <= 0.0:
                break
            lo = hi - 2.0 * (hi - lo)
    v = min(max(V0, lo), hi)
    for _ in range(200):
        rX, rZ, _, _, _, J22 = _res(H, v, X, Z, L, EA, W, contact, t, CB)
        if rZ > 0.0:
            hi = v
        else:
            lo = v
        vn = v - rZ / J22 if J22 > 0.0 else 0.5 * (lo + hi)
        if not (lo < vn < hi):
            vn = 0.5 * (lo + hi)
        if abs(vn - v) <= 1e-15 * (abs(v) + abs(W) * L) or hi - lo <= 1e-15 * (abs(lo) + abs(hi)):
            v = vn
            break
        v = vn
    return v, _res(H, v, X, Z, L, EA, W, contact, t, CB)[0]


@njit(cache=True, error_model="numpy")
def _bracketed(X, Z, L, EA, W, contact, t, CB, size):
    """Last-resort solve: bisection/secant on ``H`` with ``V(H)`` from the height condition
    (``X`` rises with ``H`` along that family). Returns ``(H, V, ok)``."""
    Hlo = 0.0
    Hhi = abs(W) * L + 1.0
    V = 0.0
    for _ in range(200):
        V, rX = _v_for_h(Hhi, X, Z, L, EA, W, contact, t, CB, V)
        if rX >= 0.0:
            break
        Hlo = Hhi
        Hhi *= 4.0
    H = 0.5 * (Hlo + Hhi)
    for _ in range(300):
        H = 0.5 * (Hlo + Hhi)
        V, rX = _v_for_h(H, X, Z, L, EA, W, contact, t, CB, V)
        if rX > 0.0:
            Hhi = H
        else:
            Hlo = H
        if Hhi - Hlo <= 1e-13 * Hhi:
            break
    return _newton(X, Z, L, EA, W, contact, t, CB, H, V, size)[:3]


@njit(cache=True, error_model="numpy")
def _set_derivs(out, HX, HZ, Ht, VX, VZ, Vt, HLX, HLZ, HLt, VLX, VLZ, VLt):
    d = O_D
    out[d + 0], out[d + 1], out[d + 2] = HX, HZ, Ht
    out[d + 3], out[d + 4], out[d + 5] = VX, VZ, Vt
    out[d + 6], out[d + 7], out[d + 8] = HLX, HLZ, HLt
    out[d + 9], out[d + 10], out[d + 11] = VLX, VLZ, VLt


@njit(cache=True, error_model="numpy")
def upright_line(X, Z, L, EA, W, contact, t, CB, H0, V0, out):
    """Solve one line in its upright frame (see the module docstring) and fill ``out``.

    Parameters
    ----------
    X, Z : float
        Horizontal distance ``>= 0`` and height of the upper end above the lower end [m].
    L : float
        Unstretched length [m].
    EA : float
        Axial stiffness [N].
    W : float
        Wet weight per unit length [N/m] (negative: buoyant).
    contact : bool
        The lower end lies on the seabed (used only when ``W > 0``).
    t : float
        Seabed slope ``tan(alpha)`` along the line from the lower end [-].
    CB : float
        Seabed friction coefficient [-] (``>= 0``).
    H0, V0 : float
        Warm start [N] (``H0 <= 0`` or NaN: none).
    out : ndarray, shape (LINE2D_SIZE,)
        Output, see the ``O_*`` offsets; NaN on failure.

    Returns
    -------
    status : int
        ``QS_OK`` (0), ``QS_NOT_CONVERGED`` (1), ``QS_INVALID`` (4: non-finite or ``L, EA <= 0``,
        ``X < 0``) or ``QS_BELOW_SEABED`` (6: the upper end lies below the seabed plane).
    iterations : int
        Newton iterations.
    """
    out[:] = np.nan
    if not (math.isfinite(X) and math.isfinite(Z) and math.isfinite(W) and math.isfinite(t)
            and math.isfinite(CB) and L > 0.0 and EA > 0.0 and X >= 0.0 and CB >= 0.0):
        return QS_INVALID, 0
    contact = contact and W > 0.0
    size = L + X + abs(Z)
    out[O_LB] = 0.0
    if W == 0.0:
        chord = math.hypot(X, Z)
        if chord <= L:  # slack weightless: no force
            out[:] = 0.0
            return QS_OK, 0
        T = EA * (chord / L - 1.0)
        ex = X / chord
        ez = Z / chord
        kt = T / chord
        kl = EA / L
        HX = kl * ex * ex + kt * (1.0 - ex * ex)
        HZ = (kl - kt) * ex * ez
        VZ = kl * ez * ez + kt * (1.0 - ez * ez)
        out[O_H] = out[O_HL] = T * ex
        out[O_V] = out[O_VL] = T * ez
        out[O_KTU] = out[O_KTL] = kt
        _set_derivs(out, HX, HZ, 0.0, HZ, VZ, 0.0, HX, HZ, 0.0, HZ, VZ, 0.0)
        return QS_OK, 0
    if contact:
        st = math.hypot(1.0, t)
        c = 1.0 / st
        sn = t * c
        h = Z - X * t  # height of the upper end above the seabed plane
        if h < -_ON_BED * size:
            out[O_LB] = np.nan
            return QS_BELOW_SEABED, 0
        Lh = _hang_length(h, W, EA)
        Lflat = X * st
        if L >= Lflat + Lh:  # slack: bunched on the seabed, hanging straight down to the upper end
            dVdh = W / math.sqrt(1.0 + 2.0 * max(h, 0.0) * W / EA)
            out[O_H] = out[O_HL] = out[O_VL] = out[O_KTU] = out[O_KTL] = 0.0
            out[O_V] = W * Lh
            out[O_LB] = L - Lh
            k = W * (sn + CB * c)
            if k < 0.0 and X > 0.0:
                # a seabed descending from the origin end faster than friction holds the line: the bunched rest
                # slides to the foot below the upper end and the grounded part, Lflat long (its stretch is
                # taken up by the bunch), pulls the origin end down the slope with TA = -k Lflat
                c3 = c * c * c
                k_t = W * c3 * (1.0 - CB * t)
                TA = -k * Lflat
                TA_X = -k * st
                TA_t = -k_t * Lflat - k * X * t * c
                out[O_HL] = TA * c
                out[O_VL] = TA * sn
                out[O_KTL] = TA * c / X
                _set_derivs(out, 0.0, 0.0, 0.0, -t * dVdh, dVdh, -X * dVdh, c * TA_X, 0.0, c * TA_t - TA * t * c3,
                            sn * TA_X, 0.0, sn * TA_t + TA * c3)
                return QS_OK, 0
            _set_derivs(out, 0.0, 0.0, 0.0, -t * dVdh, dVdh, -X * dVdh, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0)
            return QS_OK, 0
        if h <= _ON_BED * size:  # upper end on the seabed, taut along it
            e = Lflat - L  # elongation [m]
            k = W * (sn + CB * c)
            k_t = W * c * c * c * (1.0 - CB * t)
            TB = (EA * e + 0.5 * k * L * L) / L
            if k > 0.0 and TB < k * L:
                TB = math.sqrt(2.0 * k * EA * e)
                TB_e = k * EA / TB
                TB_k = EA * e / TB
                TA = TA_X = TA_t = 0.0
            else:
                TB_e = EA / L
                TB_k = 0.5 * L
                TA = TB - k * L
            TB_X = TB_e * st
            TB_t = TB_e * X * t * c + TB_k * k_t
            if TA > 0.0:
                TA_X = TB_X
                TA_t = TB_t - L * k_t
            c3 = c * c * c
            out[O_H] = TB * c
            out[O_V] = TB * sn
            out[O_HL] = TA * c
            out[O_VL] = TA * sn
            out[O_LB] = L
            out[O_KTU] = TB * c / X
            out[O_KTL] = TA * c / X
            _set_derivs(out, c * TB_X, 0.0, c * TB_t - TB * t * c3, sn * TB_X, 0.0, sn * TB_t + TB * c3,
                        c * TA_X, 0.0, c * TA_t - TA * t * c3, sn * TA_X, 0.0, sn * TA_t + TA * c3)
            return QS_OK, 0
    if X <= _VERTICAL * size:  # vertical line, HF = 0 (taut if it touches a seabed: the slack one is above)
        V = _vertical_VF(Z, L, EA, W)
        VL = V - W * L
        s1 = 1.0 if V > 0.0 else -1.0
        s2 = 1.0 if VL > 0.0 else -1.0
        VZ = 1.0 / ((s1 - s2) / W + L / EA)
        kt = 0.0
        if V * VL > 0.0:  # taut: the lateral stiffness is the limit of 1/J11 as H -> 0
            kt = 1.0 / (math.log1p(W * L / VL) / W + L / EA)
        out[O_H] = out[O_HL] = 0.0
        out[O_V] = V
        out[O_VL] = VL
        out[O_KTU] = out[O_KTL] = kt
        _set_derivs(out, kt, 0.0, 0.0, 0.0, VZ, 0.0, kt, 0.0, 0.0, 0.0, VZ, 0.0)
        return QS_OK, 0
    # Newton from the warm start, then from MoorDyn's start guess, then bracketing
    it_total = 0
    ok = False
    H = H0
    V = V0
    if H0 > 0.0:
        H, V, ok, it = _newton(X, Z, L, EA, W, contact, t, CB, H0, V0, size)
        it_total += it
    if not ok:
        # MoorDyn's catenary start guess (spec 6.2), mirrored for buoyant lines
        chord = math.hypot(X, Z)
        lam = 0.2
        if L > chord:
            q = 3.0 * ((L * L - Z * Z) / (X * X) - 1.0)
            lam = math.sqrt(q) if q < 1e12 else 1e6
        Hc = max(abs(W * X / (2.0 * lam)), 1e-6 * min(1.0, abs(W) * L))
        Vc = 0.5 * (W * L + abs(W) * Z / math.tanh(lam))
        H, V, ok, it = _newton(X, Z, L, EA, W, contact, t, CB, Hc, Vc, size)
        it_total += it
    if not ok:
        H, V, ok = _bracketed(X, Z, L, EA, W, contact, t, CB, size)
    if not ok:
        return QS_NOT_CONVERGED, it_total
    _derivatives(X, Z, L, EA, W, contact, t, CB, H, V, out)
    return QS_OK, it_total


@njit(cache=True, error_model="numpy")
def _derivatives(X, Z, L, EA, W, contact, t, CB, H, V, out):
    """Fill ``out`` from a converged ``(H, V)`` by the implicit-function theorem."""
    if contact and V - W * L < H * t:
        _, _, J11, J12, J21, J22, LB, TA, TA_H, TA_V = _touchdown(H, V, L, EA, W, t, CB)
        Xt, Zt, TA_t = _touchdown_t(H, V, L, EA, W, t, CB)
        c = 1.0 / math.hypot(1.0, t)
        sn = t * c
        c3 = c * c * c
    else:
        _, _, J11, J12, J21, J22 = _residual(H, V, X, Z, L, EA, W, False)
        LB = 0.0
        Xt = Zt = 0.0
    det = J11 * J22 - J12 * J21
    HX = J22 / det
    HZ = -J12 / det
    VX = -J21 / det
    VZ = J11 / det
    Ht = -(HX * Xt + HZ * Zt)
    Vt = -(VX * Xt + VZ * Zt)
    out[O_H] = H
    out[O_V] = V
    out[O_LB] = LB
    out[O_KTU] = H / X
    if LB > 0.0:
        # lower end: tension TA along the slope
        dX = TA_H * HX + TA_V * VX
        dZ = TA_H * HZ + TA_V * VZ
        dt = TA_t + TA_H * Ht + TA_V * Vt
        out[O_HL] = TA * c
        out[O_VL] = TA * sn
        out[O_KTL] = TA * c / X
        _set_derivs(out, HX, HZ, Ht, VX, VZ, Vt, c * dX, c * dZ, c * dt - TA * t * c3, sn * dX, sn * dZ,
                    sn * dt + TA * c3)
    else:
        out[O_HL] = H
        out[O_VL] = V - W * L
        out[O_KTL] = H / X
        _set_derivs(out, HX, HZ, Ht, VX, VZ, Vt, HX, HZ, Ht, VX, VZ, Vt)


@njit(cache=True, error_model="numpy")
def line_profile_upright(X, Z, L, EA, W, contact, t, CB, H, V, s, px, pz, pT):
    """Shape and tension of a solved line at unstretched arc lengths from its lower end.

    Parameters
    ----------
    X, Z, L, EA, W, contact, t, CB
        The problem, as given to :func:`upright_line`.
    H, V : float
        Its solution [N].
    s : ndarray, shape (n,)
        Unstretched arc lengths from the lower end [m], in ``[0, L]``.
    px, pz, pT : ndarray, shape (n,)
        Output: horizontal distance and height from the lower end [m], tension [N].
    """
    contact = contact and W > 0.0
    n = s.shape[0]
    if W == 0.0 or (H <= 0.0 and not contact):  # straight (weightless) or vertical
        T0 = math.hypot(H, V)
        for i in range(n):
            f = s[i] / L
            if W == 0.0:
                px[i] = X * f
                pz[i] = Z * f
                pT[i] = T0
            else:
                VLs = V - W * L + W * s[i]
                pz[i] = _vertical_Z(V - W * L, W, s[i], EA)
                px[i] = 0.0
                pT[i] = abs(VLs)
        return
    st = math.hypot(1.0, t)
    c = 1.0 / st
    sn = t * c
    if contact and V - W * L < H * t:
        if H <= 0.0:  # slack "L": on the seabed to below the upper end, then straight up
            Ls = V / W
            LB = L - Ls
            k = W * (sn + CB * c)
            for i in range(n):
                if s[i] <= LB:
                    f = min(s[i] / LB, 1.0) if LB > 0.0 else 0.0
                    px[i] = X * f
                    pz[i] = X * t * f
                    pT[i] = -k * (X - px[i]) * st if k < 0.0 else 0.0  # down a slope friction cannot hold
                else:
                    ds = s[i] - LB
                    px[i] = X
                    pz[i] = X * t + ds + W * ds * ds / (2.0 * EA)
                    pT[i] = W * ds
            return
        Ls = (V - H * t) / W
        LB = L - Ls
        k = W * (sn + CB * c)
        TT = H * st
        TA = TT - k * LB  # may be negative: zero tension below s0
        for i in range(n):
            si = s[i]
            sb = min(si, LB)
            # tension integral over [0, sb] of max(TA + k s, 0)
            if TA >= 0.0 or k <= 0.0:
                Ib = TA * sb + 0.5 * k * sb * sb
                Tb = TA + k * sb
            else:
                s0 = -TA / k
                Ib = 0.5 * k * (sb - s0) ** 2 if sb > s0 else 0.0
                Tb = max(TA + k * sb, 0.0)
            g = sb + Ib / EA
            if si <= LB:
                px[i] = c * g
                pz[i] = sn * g
                pT[i] = Tb
            else:
                ds = si - LB
                xs, zs, _, _, _ = _suspended(H, H * t, W, ds, EA)
                px[i] = c * g + xs
                pz[i] = sn * g + zs
                pT[i] = math.hypot(H, H * t + W * ds)
        return
    VL = V - W * L
    for i in range(n):
        xs, zs, _, _, _ = _suspended(H, VL, W, s[i], EA)
        px[i] = xs
        pz[i] = zs
        pT[i] = math.hypot(H, VL + W * s[i])


@njit(cache=True, error_model="numpy")
def _vertical_Z(VA, W, s, EA):
    """Height at ``s`` of a vertical line whose lower-end vertical tension is ``VA``."""
    V = VA + W * s
    Zc = (abs(V) - abs(VA)) / W if W != 0.0 else s
    return Zc + (s / EA) * (VA + 0.5 * W * s)
