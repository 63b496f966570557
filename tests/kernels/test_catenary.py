"""Tests of the quasi-static elastic catenary (moorline.quasistatic.catenary, spec section 6.2).

Three kinds of check:

* against independent solutions written plainly here: the textbook elastic-catenary end conditions
  solved by nested bracketing (scipy ``brentq``, no Newton, no shared code), the inextensible
  catenary (``cosh``) and direct quadrature of the catenary ODE;
* invariants: end conditions, end tensions, vertical balance, A/B reversal, rotation and
  translation of the 3-D placement, continuity across touchdown, segment stretch;
* edge cases: refusal of too-long lines, vertical and weightless lines, very taut lines, bad
  input, the iteration cap.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from scipy.optimize import brentq

from moorline.quasistatic.catenary import (
    STATUS_INVALID,
    STATUS_NOT_CONVERGED,
    STATUS_OK,
    STATUS_SHORT_SPAN,
    STATUS_SLACK_WEIGHTLESS,
    STATUS_TOO_LONG,
    CatenaryStatus,
    _solve,
    catenary,
    catenary_nodes,
    catenary_profile,
    catenary_solve,
)

RTOL_REF = 1e-6  # forces against the independent solution (brief)
ATOL_END = 1e-6  # end conditions [m] (brief)

# OC3-Hywind mooring chain (Jonkman 2010), MoorDyn's OC3 deck
OC3_L = 902.2
OC3_EA = 384.243e6
OC3_W = (77.7066 - 1025.0 * math.pi * 0.09**2 / 4.0) * 9.80665
OC3_XF = 853.87 - 5.2
OC3_ZF = -70.0 - (-320.0)


# ------------------------------------------------------------------------------------------------
# independent reference: textbook end conditions, solved by bracketing only
# ------------------------------------------------------------------------------------------------
def _ref_ends(H, V, L, EA, W, seabed):
    """X(L), Z(L) of the elastic catenary, lower end at the origin, V = vertical tension at top."""
    VA = V - W * L
    if seabed and W > 0 and VA <= 0:
        LB = L - V / W
        x = LB + H / W * math.asinh(V / H) + H * L / EA
        z = H / W * (math.sqrt(1 + (V / H) ** 2) - 1) + V**2 / (2 * EA * W)
    else:
        x = H / W * (math.asinh(V / H) - math.asinh(VA / H)) + H * L / EA
        z = H / W * (math.sqrt(1 + (V / H) ** 2) - math.sqrt(1 + (VA / H) ** 2)) + L / EA * (VA + W * L / 2)
    return x, z


def reference_solve(XF, ZF, L, EA, W, seabed):
    """(HF, VF at the upper end) by nested brentq: Z(L) rises with V, X(L) then rises with H."""
    Zu = abs(ZF)

    def v_of_h(H):
        def f(V):
            return _ref_ends(H, V, L, EA, W, seabed)[1] - Zu

        span = abs(W) * L + H + 1.0
        lo = 0.0 if (seabed and W > 0) else min(0.0, W * L) - span
        hi = max(0.0, W * L) + span
        while f(lo) > 0:
            lo -= span
            span *= 2
        while f(hi) < 0:
            hi += span
            span *= 2
        return brentq(f, lo, hi, xtol=1e-300, rtol=1e-15, maxiter=500)

    def g(log_h):
        H = math.exp(log_h)
        return _ref_ends(H, v_of_h(H), L, EA, W, seabed)[0] - XF

    lo = math.log(1e-6 * (abs(W) * L + 1.0))
    hi = math.log(abs(W) * L + 1e-3 * EA + 1.0)
    while g(lo) > 0:
        lo -= 5
    while g(hi) < 0:
        hi += 5
    H = math.exp(brentq(g, lo, hi, xtol=1e-15, rtol=1e-15, maxiter=500))
    return H, v_of_h(H)


def quadrature_ends(r, L, EA, W, ZF):
    """End B position by integrating dX/ds = (HF/T)(1 + T/EA), dZ/ds = (V/T)(1 + T/EA).

    Uses only the physical end tensions of the result (VA, VB) and its touchdown length.
    """
    LB = r.touchdown_length
    HF = r.HF
    if ZF >= 0:  # seabed (if any) at end A: s in [0, LB]; hanging from B above
        susp = (LB, L)

        def V(s):
            return r.VB - W * (L - s)
    else:  # seabed (if any) at end B: s in [L - LB, L]
        susp = (0.0, L - LB)

        def V(s):
            return r.VA + W * s

    def dx(s):
        T = math.hypot(HF, V(s))
        return HF / T * (1 + T / EA)

    def dz(s):
        T = math.hypot(HF, V(s))
        return V(s) / T * (1 + T / EA)

    opts = dict(epsabs=1e-12, epsrel=1e-13, limit=200)
    X = quad(dx, *susp, **opts)[0] + LB * (1 + HF / EA)
    Z = quad(dz, *susp, **opts)[0]
    return X, Z


# (XF, ZF, L, EA, W, seabed): slack/taut, with/without seabed, ZF < 0, buoyant, stretchy, light
CASES = {
    "slack_suspended": (80.0, 30.0, 100.0, 1e8, 500.0, False),
    "slack_seabed": (80.0, 30.0, 100.0, 1e8, 500.0, True),
    "slack_seabed_negZF": (80.0, -30.0, 100.0, 1e8, 500.0, True),
    "slack_negZF": (80.0, -30.0, 100.0, 1e8, 500.0, False),
    "deep_U_no_seabed": (20.0, 60.0, 150.0, 1e8, 500.0, False),
    "level_ends": (80.0, 0.0, 100.0, 1e8, 500.0, False),
    "taut": (90.0, 50.0, 100.0, 1e8, 500.0, False),
    "taut_seabed_flag": (90.0, 50.0, 100.0, 1e8, 500.0, True),
    "taut_negZF": (90.0, -50.0, 100.0, 1e8, 500.0, True),
    "buoyant": (80.0, 30.0, 100.0, 1e8, -300.0, False),
    "buoyant_negZF_seabed": (80.0, -30.0, 100.0, 1e8, -300.0, True),
    "buoyant_taut": (95.0, 40.0, 100.0, 1e7, -300.0, False),
    "stretchy_seabed": (80.0, 30.0, 100.0, 1e5, 500.0, True),
    "stretchy_taut": (100.0, 30.0, 100.0, 1e6, 500.0, False),
    "light": (80.0, 30.0, 100.0, 1e8, 0.5, False),
    "almost_L_shape": (60.0, 40.0, 0.99 * 100.0, 1e8, 500.0, True),
    "oc3": (OC3_XF, OC3_ZF, OC3_L, OC3_EA, OC3_W, True),
    "oc3_reversed": (OC3_XF, -OC3_ZF, OC3_L, OC3_EA, OC3_W, True),
}


@pytest.fixture(scope="module", params=sorted(CASES), ids=sorted(CASES))
def case(request):
    XF, ZF, L, EA, W, seabed = CASES[request.param]
    return XF, ZF, L, EA, W, seabed, catenary(XF, ZF, L, EA, W, seabed, n=400)


def test_against_independent_solution(case):
    XF, ZF, L, EA, W, seabed, r = case
    assert r.status == STATUS_OK
    H, V = reference_solve(XF, ZF, L, EA, W, seabed)
    assert r.HF == pytest.approx(H, rel=RTOL_REF)
    assert r.VF == pytest.approx(V, rel=RTOL_REF)
    HF, VF, status = catenary_solve(XF, ZF, L, EA, W, seabed)  # kernel with its default arguments
    assert status == STATUS_OK
    assert (HF, VF) == (r.HF, r.VF)


def test_against_quadrature_of_the_ode(case):
    XF, ZF, L, EA, W, seabed, r = case
    X, Z = quadrature_ends(r, L, EA, W, ZF)
    assert X == pytest.approx(XF, abs=1e-8 * L)
    assert Z == pytest.approx(ZF, abs=1e-8 * L)


def test_end_conditions_and_end_tensions(case):
    XF, ZF, L, EA, W, seabed, r = case
    assert r.s[0] == 0.0 and r.s[-1] == L
    assert abs(r.X[0]) < ATOL_END and abs(r.Z[0]) < ATOL_END
    assert abs(r.X[-1] - XF) < ATOL_END and abs(r.Z[-1] - ZF) < ATOL_END
    assert r.T[-1] == pytest.approx(math.hypot(r.HF, r.VB), rel=1e-12)
    assert r.T[0] == pytest.approx(math.hypot(r.HF, r.VA), rel=1e-12)
    upper_T = r.T[-1] if ZF >= 0 else r.T[0]
    assert upper_T == pytest.approx(math.hypot(r.HF, r.VF), rel=1e-12)  # VF is at the upper end
    assert np.all(r.T >= r.HF * (1 - 1e-12))


def test_vertical_force_balance(case):
    """V(L) - V(0) = W * suspended length: the seabed carries the rest."""
    XF, ZF, L, EA, W, seabed, r = case
    assert r.VB - r.VA == pytest.approx(W * (L - r.touchdown_length), rel=1e-9, abs=1e-9 * abs(W) * L)
    if r.touchdown_length > 0:
        assert (r.VA if ZF >= 0 else r.VB) == 0.0
        assert r.Z.min() >= min(0.0, ZF) - 1e-9  # never below the seabed


def test_swapping_ends_reverses_the_line(case):
    XF, ZF, L, EA, W, seabed, r = case
    q = catenary(XF, -ZF, L, EA, W, seabed, n=400)  # the same line seen from end B
    assert q.status == STATUS_OK
    assert q.HF == pytest.approx(r.HF, rel=1e-10)
    assert q.VF == pytest.approx(r.VF, rel=1e-10, abs=1e-10 * r.HF)  # same upper end
    assert q.VA == pytest.approx(-r.VB, rel=1e-10, abs=1e-10 * r.HF)
    assert q.VB == pytest.approx(-r.VA, rel=1e-10, abs=1e-10 * r.HF)
    assert q.touchdown_length == pytest.approx(r.touchdown_length, rel=1e-10, abs=1e-10 * L)
    np.testing.assert_allclose(q.T, r.T[::-1], rtol=1e-10)
    np.testing.assert_allclose(q.X, XF - r.X[::-1], rtol=0, atol=1e-8 * L)
    np.testing.assert_allclose(q.Z, r.Z[::-1] - ZF, rtol=0, atol=1e-8 * L)


def test_nodes_stretch_and_placement(case):
    XF, ZF, L, EA, W, seabed, r = case
    N = 100
    psi = 0.7
    rA = np.array([3.0, -4.0, -50.0])
    rB = rA + np.array([XF * math.cos(psi), XF * math.sin(psi), ZF])
    out = np.zeros((N + 1, 3))
    status, HF, VF = catenary_nodes(rA, rB, L, N, EA, W, seabed, 1e-5, out)
    assert status == STATUS_OK
    assert HF == pytest.approx(r.HF, rel=1e-12)
    assert VF == pytest.approx(r.VB, rel=1e-12, abs=1e-12 * r.HF)
    assert np.array_equal(out[0], rA) and np.array_equal(out[N], rB)
    # all nodes in the vertical plane through both ends, on the 2-D profile
    s = np.linspace(0.0, L, N + 1)
    X = np.empty(N + 1)
    Z = np.empty(N + 1)
    T = np.empty(N + 1)
    catenary_profile(XF, ZF, L, EA, W, seabed, r.HF, r.VF, s, X, Z, T)
    d = out - rA
    np.testing.assert_allclose(d[:, 0] * math.sin(psi) - d[:, 1] * math.cos(psi), 0.0, atol=1e-9 * L)
    np.testing.assert_allclose(np.hypot(d[:, 0], d[:, 1]), X, rtol=0, atol=1e-9 * L)
    np.testing.assert_allclose(d[:, 2], Z, rtol=0, atol=1e-9 * L)
    # segment length = (L/N)(1 + T/EA), T at mid-segment; the chord of a curved segment is shorter
    # than its arc by about (l kappa)^2 / 24, kappa = |W| HF / T^2 (largest at the lowest tension)
    l = L / N
    sm = (s[:-1] + s[1:]) / 2
    Tm = np.empty(N)
    catenary_profile(XF, ZF, L, EA, W, seabed, r.HF, r.VF, sm, np.empty(N), np.empty(N), Tm)
    Tmin = np.minimum(np.minimum(T[:-1], T[1:]), Tm)
    kl_max = l * abs(W) * r.HF / Tmin**2  # largest change of angle along the segment [rad]
    kl = l * abs(W) * r.HF / Tm**2
    if r.touchdown_length > 0:  # T = HF on the seabed: no curvature there
        kl[Tm <= r.HF * (1 + 1e-12)] = 0.0
        kl_max[Tm <= r.HF * (1 + 1e-12)] = 0.0
    smooth = kl_max < 0.5  # a segment across a sharp corner (almost an "L") is not comparable
    if r.touchdown_length > 0:
        sB = r.touchdown_length if ZF >= 0 else L - r.touchdown_length
        smooth[min(int(sB / l), N - 1)] = False  # curvature jumps inside the touchdown segment
    assert np.count_nonzero(~smooth) <= 2
    seg = np.linalg.norm(np.diff(out, axis=0), axis=1)
    arc = l * (1 + Tm / EA)
    np.testing.assert_allclose(seg[smooth], (arc * (1 - kl**2 / 24))[smooth], rtol=1e-3)
    if kl_max[smooth].max() < 0.05:  # nearly straight segments: their length is the stretched arc
        np.testing.assert_allclose(seg, arc, rtol=1e-3)
    strain = (seg / (1 - kl**2 / 24)) / l - 1
    np.testing.assert_allclose(strain[smooth], (Tm / EA)[smooth], rtol=0, atol=0.02 * kl_max[smooth].max() ** 2 + 1e-7)


def test_rotation_and_translation_invariance():
    XF, ZF, L, EA, W, seabed = CASES["slack_seabed"]
    N = 20
    ref = None
    for psi in (0.0, 1.0, -2.5, math.pi):
        for shift in (np.zeros(3), np.array([100.0, -40.0, -7.0])):
            rA = shift.copy()
            rB = rA + np.array([XF * math.cos(psi), XF * math.sin(psi), ZF])
            out = np.zeros((N + 1, 3))
            status, HF, VF = catenary_nodes(rA, rB, L, N, EA, W, seabed, 1e-5, out)
            assert status == STATUS_OK
            d = out - rA
            local = np.column_stack([d[:, 0] * math.cos(psi) + d[:, 1] * math.sin(psi), d[:, 2]])
            if ref is None:
                ref = (HF, VF, local)
            else:
                assert (HF, VF) == pytest.approx(ref[:2], rel=1e-12)
                np.testing.assert_allclose(local, ref[2], atol=1e-9)


def test_continuity_across_touchdown():
    for XF, ZF, L, EA, W, seabed in (CASES["slack_seabed"], CASES["slack_seabed_negZF"], CASES["oc3"]):
        r = catenary(XF, ZF, L, EA, W, seabed)
        LB = r.touchdown_length
        assert 0 < LB < L
        sB = LB if ZF >= 0 else L - LB  # touchdown point measured from end A
        eps = np.array([-1e-3, -1e-6, -1e-9, 0.0, 1e-9, 1e-6, 1e-3])
        s = sB + eps
        X, Z, T = np.empty(7), np.empty(7), np.empty(7)
        catenary_profile(XF, ZF, L, EA, W, seabed, r.HF, r.VF, s, X, Z, T)
        zsea = min(0.0, ZF)
        # position continuous with the slope of the flat part (1 + HF/EA), Z on the seabed at the
        # touchdown point with zero slope there, tension continuous at HF
        side = 1.0 if ZF >= 0 else -1.0  # direction from the seabed part into the suspended part
        np.testing.assert_allclose(X - X[3], eps * (1 + r.HF / EA), rtol=0, atol=1e-12 * L)
        assert abs(Z[3] - zsea) < 1e-12 * L
        np.testing.assert_allclose(Z[side * eps <= 0], zsea, rtol=0, atol=1e-12 * L)
        kappa = W / r.HF  # curvature at touchdown
        susp = side * eps > 0
        np.testing.assert_allclose(Z[susp] - zsea, kappa * eps[susp] ** 2 / 2, rtol=1e-2, atol=1e-12 * L)
        np.testing.assert_allclose(T, r.HF, rtol=W * 1e-3 / r.HF)


def test_inextensible_equal_height_limit():
    """EA -> inf, level ends, no seabed: XF = (2H/W) asinh(W L/(2H)), sag = (H/W)(cosh(W XF/(2H)) - 1)."""
    XF, L, W = 80.0, 100.0, 500.0
    H = brentq(lambda h: 2 * h / W * math.asinh(W * L / (2 * h)) - XF, 1.0, 1e9, xtol=1e-12, rtol=1e-15)
    sag = H / W * (math.cosh(W * XF / (2 * H)) - 1)
    r = catenary(XF, 0.0, L, 1e15, W, False, n=2)
    assert r.status == STATUS_OK
    assert r.HF == pytest.approx(H, rel=1e-9)
    assert r.VF == pytest.approx(W * L / 2, rel=1e-9)
    assert r.X[1] == pytest.approx(XF / 2, rel=1e-9)
    assert -r.Z[1] == pytest.approx(sag, rel=1e-9)


def test_oc3_hywind_chain():
    r = catenary(OC3_XF, OC3_ZF, OC3_L, OC3_EA, OC3_W, True)
    H, V = reference_solve(OC3_XF, OC3_ZF, OC3_L, OC3_EA, OC3_W, True)
    assert r.status == STATUS_OK
    assert r.HF == pytest.approx(H, rel=RTOL_REF)
    assert r.VF == pytest.approx(V, rel=RTOL_REF)
    assert 7.0e5 < r.HF < 8.0e5  # ~7.37e5 N, fairlead tension ~9.1e5 N
    assert 100.0 < r.touchdown_length < 200.0
    # fairlead at 5.2 m radius, anchor at 853.87 m, 120 deg apart in plan as in the OC3 deck
    N = 20
    for heading in (0.0, 2 * math.pi / 3, 4 * math.pi / 3):
        c, s = math.cos(heading), math.sin(heading)
        rA = np.array([853.87 * c, 853.87 * s, -320.0])
        rB = np.array([5.2 * c, 5.2 * s, -70.0])
        out = np.zeros((N + 1, 3))
        status, HF, VF = catenary_nodes(rA, rB, OC3_L, N, OC3_EA, OC3_W, True, 1e-5, out)
        assert status == STATUS_OK
        assert HF == pytest.approx(H, rel=RTOL_REF)
        assert VF == pytest.approx(V, rel=RTOL_REF)  # end B is the fairlead: pulled down by VF
        assert out[:, 2].min() >= -320.0 - 1e-9


# ------------------------------------------------------------------------------------------------
# edge cases
# ------------------------------------------------------------------------------------------------
def test_too_long_line_on_the_seabed_is_refused():
    XF, ZF, EA, W = 60.0, 40.0, 1e8, 500.0
    Lmax = XF - EA / W + math.sqrt((EA / W) ** 2 + 2 * ZF * EA / W)  # spec 6.2
    for L in (Lmax * (1 + 1e-9), Lmax * 1.5, 10 * Lmax):
        for zf in (ZF, -ZF):
            HF, VF, status = catenary_solve(XF, zf, L, EA, W, True, 1e-5, 1000)
            assert status == STATUS_TOO_LONG and math.isnan(HF) and math.isnan(VF)
    assert catenary(XF, ZF, Lmax * 0.999, EA, W, True).status == STATUS_OK
    # without a seabed (or buoyant) the same line just hangs
    assert catenary(XF, ZF, 1.5 * Lmax, EA, W, False).status == STATUS_OK
    assert catenary(XF, ZF, 1.5 * Lmax, EA, -W, True).status == STATUS_OK
    # catenary_nodes keeps the straight chord
    rA, rB = np.zeros(3), np.array([XF, 0.0, ZF])
    out = np.zeros((11, 3))
    status, HF, VF = catenary_nodes(rA, rB, 1.5 * Lmax, 10, EA, W, True, 1e-5, out)
    assert status == STATUS_TOO_LONG and math.isnan(HF)
    np.testing.assert_allclose(out, np.linspace(rA, rB, 11), atol=1e-12)


def test_both_ends_on_the_seabed():
    r = catenary(100.0, 0.0, 99.0, 1e8, 500.0, True)  # taut along the seabed
    assert r.status == STATUS_OK
    assert r.HF == pytest.approx(1e8 * (100 / 99 - 1), rel=1e-12)
    assert r.VF == 0.0 and r.touchdown_length == 99.0
    np.testing.assert_allclose(r.Z, 0.0)
    assert catenary(100.0, 0.0, 101.0, 1e8, 500.0, True).status == STATUS_TOO_LONG


def test_vertical_line():
    EA, W = 1e8, 500.0
    # taut vertical (L shorter than the hanging length): HF = 0, V from the stretch
    r = catenary(0.0, 100.0, 99.9, EA, W, True)
    assert r.status == STATUS_OK and r.HF == 0.0
    VA = EA * (100.0 - 99.9) / 99.9 - W * 99.9 / 2
    assert r.VA == pytest.approx(VA, rel=1e-12)
    assert r.VB == pytest.approx(VA + W * 99.9, rel=1e-12)
    assert np.all(r.X == 0.0)
    assert r.Z[-1] == pytest.approx(100.0, abs=ATOL_END)
    # slack vertical line hanging folded (no seabed), and its mirror image
    for zf in (30.0, -30.0):
        r = catenary(0.0, zf, 100.0, EA, W, False)
        assert r.status == STATUS_OK and r.HF == 0.0
        assert r.Z[-1] == pytest.approx(zf, abs=ATOL_END)
        assert r.VB - r.VA == pytest.approx(W * 100.0, rel=1e-12)
        assert r.VA < 0 < r.VB
    # with a seabed the slack vertical line is too long to lie as an "L"
    assert catenary(0.0, 30.0, 100.0, EA, W, True).status == STATUS_TOO_LONG
    # tiny spans go through Newton and stay finite and continuous
    r0 = catenary(0.0, 100.0, 150.0, EA, W, False)
    for xf in (1e-12, 1e-8, 1e-5):
        r = catenary(xf, 100.0, 150.0, EA, W, False)
        assert r.status == STATUS_OK
        assert r.VF == pytest.approx(r0.VF, rel=1e-6)
        assert abs(r.X[-1] - xf) < ATOL_END and abs(r.Z[-1] - 100.0) < ATOL_END
    # catenary_nodes keeps the straight chord below 1e-4 m of span (spec 6.1)
    out = np.zeros((5, 3))
    rA, rB = np.array([1.0, 2.0, -100.0]), np.array([1.0 + 5e-5, 2.0, -10.0])
    status, HF, VF = catenary_nodes(rA, rB, 80.0, 4, EA, W, False, 1e-5, out)
    assert status == STATUS_SHORT_SPAN and math.isnan(HF)
    np.testing.assert_allclose(out, np.linspace(rA, rB, 5), atol=1e-12)


def test_weightless_line():
    EA = 1e6
    XF, ZF = 80.0, -60.0  # chord 100
    r = catenary(XF, ZF, 99.0, EA, 0.0)
    T = EA * (100.0 / 99.0 - 1)
    assert r.status == STATUS_OK
    assert r.HF == pytest.approx(T * 0.8, rel=1e-12)
    assert r.VF == pytest.approx(T * 0.6, rel=1e-12)  # pulls the upper end A down along the chord
    assert r.VA == r.VB == pytest.approx(-T * 0.6, rel=1e-12)
    np.testing.assert_allclose(r.T, T)
    np.testing.assert_allclose(r.Z, ZF * r.s / 99.0, atol=1e-12)
    np.testing.assert_allclose(r.X, XF * r.s / 99.0, atol=1e-12)
    # a nearly weightless line agrees with the weightless one (no division by W)
    q = catenary(XF, ZF, 99.0, EA, 1e-9)
    assert q.status == STATUS_OK
    assert q.HF == pytest.approx(r.HF, rel=1e-9)
    # slack and weightless: no defined shape
    assert catenary(XF, ZF, 101.0, EA, 0.0).status == STATUS_SLACK_WEIGHTLESS
    out = np.zeros((3, 3))
    status, HF, VF = catenary_nodes(np.zeros(3), np.array([XF, 0, ZF]), 101.0, 2, EA, 0.0, True, 1e-5, out)
    assert status == STATUS_SLACK_WEIGHTLESS
    np.testing.assert_allclose(out[1], [XF / 2, 0, ZF / 2])


def test_very_taut_line_stretches_to_the_chord():
    XF, ZF, EA, W = 300.0, 400.0, 5e8, 1000.0  # chord 500
    L = 495.0
    r = catenary(XF, ZF, L, EA, W, True, n=1000)
    assert r.status == STATUS_OK
    T_straight = EA * (500.0 / L - 1)
    stretched = np.sum(np.hypot(np.diff(r.X), np.diff(r.Z)))
    sag_excess = (W * L * 0.6 / T_straight) ** 2 / 24  # arc/chord - 1 of a taut parabola
    assert stretched / 500.0 - 1 == pytest.approx(sag_excess, rel=0.05)  # ~1.5e-4
    assert r.T.mean() == pytest.approx(EA * (stretched / L - 1), rel=1e-4)  # the stretch carries T
    assert r.T.mean() == pytest.approx(T_straight, rel=0.02)
    assert r.T[-1] - r.T[0] == pytest.approx(W * L * 0.8, rel=1e-2)  # weight along the chord


def test_invalid_input():
    for args in (
        (80.0, 30.0, 0.0, 1e8, 500.0),
        (80.0, 30.0, 100.0, 0.0, 500.0),
        (-1.0, 30.0, 100.0, 1e8, 500.0),
        (math.nan, 30.0, 100.0, 1e8, 500.0),
        (80.0, 30.0, 100.0, 1e8, math.inf),
    ):
        assert catenary_solve(*args, False, 1e-5, 100)[2] == STATUS_INVALID
    assert catenary_solve(80.0, 30.0, 100.0, 1e8, 500.0, False, 0.0, 100)[2] == STATUS_INVALID
    assert catenary(80.0, 30.0, 100.0, 1e8, 500.0).status is CatenaryStatus.OK


def test_iteration_cap_is_respected():
    # a cap too small to converge: the solve reports failure after at most 3 attempts x cap
    r = catenary(*CASES["oc3"][:5], True, max_iter=2)
    assert r.status == STATUS_NOT_CONVERGED and r.iterations <= 6 and math.isnan(r.HF)
    HF, VF, status = catenary_solve(*CASES["oc3"], 1e-5, 2)
    assert status == STATUS_NOT_CONVERGED


def test_nasty_cases_finish_quickly():
    """3000 random lines (lengths 0.1 m to 10 km, any slope, weights of either sign over eleven
    decades, EA over twelve) and four extreme ones: each solve converges or is reported too long,
    in at most 50 Newton iterations of the 1000 allowed (measured: 14 at most for the random ones,
    19 for the extreme ones). Counted, not timed; the speed is benchmarked elsewhere."""
    rng = np.random.default_rng(1234)
    n_ok = 0
    worst = 0
    for _ in range(3000):
        L = 10 ** rng.uniform(-1, 4)
        ang = rng.uniform(-math.pi / 2, math.pi / 2)
        chord = 10 ** rng.uniform(-3, 0.3) * L
        XF, ZF = chord * math.cos(ang), chord * math.sin(ang)
        W = 10 ** rng.uniform(-6, 5) * rng.choice([-1.0, 1.0])
        EA = 10 ** rng.uniform(0, 12)
        HF, VF, status, iterations = _solve(XF, ZF, L, EA, W, bool(rng.random() < 0.5), 1e-5, 1000)
        assert status in (STATUS_OK, STATUS_TOO_LONG)
        n_ok += status == STATUS_OK
        worst = max(worst, iterations)
    assert worst <= 50
    assert n_ok > 1500
    # near-vertical, hugely slack, extremely soft and extremely light lines
    for args in (
        (1e-9, 100.0, 1e4, 1.0, 1e-6, False),
        (1e4, 0.0, 1e-3, 1e12, 1e5, False),
        (1.0, 0.0, 1e6, 1e8, 700.0, False),
        (50.0, 1e-10, 49.0, 1e8, 700.0, True),
    ):
        HF, VF, status, iterations = _solve(*args, 1e-5, 1000)
        assert status == STATUS_OK and iterations <= 50
