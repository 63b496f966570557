"""The quasi-static line (moorline.quasistatic.line2d) against closed forms.

Each reference here is written independently of the kernel, in plain numpy: the inextensible
catenary cosh curve, Irvine's elastic catenary, MAP++'s published touchdown equations with seabed
friction (Masciola et al. 2013, "MAP++ documentation, theory": the ``CB`` term), Hooke's law, the
elastic hanging line, and a sloped grounded part integrated numerically. The kernel is solved from the
end positions the reference gives and must return the reference's tensions.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from moorline.quasistatic import line_end_forces
from moorline.quasistatic.catenary import catenary_solve
from moorline.quasistatic.line2d import (
    LINE2D_SIZE,
    O_D,
    O_H,
    O_HL,
    O_LB,
    O_V,
    O_VL,
    QS_BELOW_SEABED,
    QS_OK,
    line_profile_upright,
    upright_line,
)

#: relative tension tolerance against a closed form: the kernel converges the end conditions to
#: ~1e-12 of the line size, which moves the tensions by ~1e-10 relative for the stiffest lines here
#: (EA/L * 1e-12 L / T); 1e-8 leaves margin and still catches any wrong term (>= 1e-4 effects)
RTOL = 1e-8


def solve(X, Z, L, EA, W, contact=False, t=0.0, CB=0.0, H0=-1.0, V0=0.0):
    out = np.zeros(LINE2D_SIZE)
    status, _ = upright_line(X, Z, L, EA, W, contact, t, CB, H0, V0, out)
    assert status == QS_OK, status
    return out


def elastic_catenary_end(H, VA, W, L, EA):
    """Irvine's elastic catenary: end position of a line with horizontal tension H and vertical
    tension VA at its first end (along s), weight W per length."""
    VB = VA + W * L
    X = (H / W) * (math.asinh(VB / H) - math.asinh(VA / H)) + H * L / EA
    Z = (H / W) * (math.sqrt(1 + (VB / H) ** 2) - math.sqrt(1 + (VA / H) ** 2)) + (VA * L + 0.5 * W * L * L) / EA
    return X, Z, VB


def map_touchdown_end(H, V, W, L, EA, CB):
    """MAP++'s touchdown equations with seabed friction (flat seabed): upper-end position and anchor
    tension for fairlead tensions (H, V)."""
    LB = L - V / W
    x = (LB + (H / W) * math.asinh(V / H) + H * L / EA
         + (CB * W / (2 * EA)) * (-LB ** 2 + (LB - H / (CB * W)) * max(LB - H / (CB * W), 0.0)) if CB > 0 else
         LB + (H / W) * math.asinh(V / H) + H * L / EA)
    z = (H / W) * (math.sqrt(1 + (V / H) ** 2) - 1) + V ** 2 / (2 * EA * W)
    return x, z, max(H - CB * W * LB, 0.0)


def test_inextensible_hanging_chain_is_a_cosh_curve():
    """y = a cosh(x/a) between x1 and x2: H = W a, vertical tension W a sinh(x/a) at each end."""
    W, a, x1, x2 = 700.0, 150.0, -80.0, 260.0
    L = a * (math.sinh(x2 / a) - math.sinh(x1 / a))
    X, Z = x2 - x1, a * (math.cosh(x2 / a) - math.cosh(x1 / a))
    o = solve(X, Z, L, 1e16, W)  # EA -> infinity (stretch 1e-12 relative)
    assert o[O_H] == pytest.approx(W * a, rel=RTOL)
    assert o[O_V] == pytest.approx(W * a * math.sinh(x2 / a), rel=RTOL)
    assert o[O_VL] == pytest.approx(W * a * math.sinh(x1 / a), rel=RTOL)  # negative: end A on the descending side


@pytest.mark.parametrize("H,VA,W,L,EA", [(5e5, 1e5, 700.0, 900.0, 3.8e8), (2e3, -2e4, 150.0, 400.0, 1e7),
                                           (1e6, 2e5, -300.0, 500.0, 2e9), (80.0, 10.0, 1.0, 50.0, 1e5)])
def test_elastic_catenary_irvine(H, VA, W, L, EA):
    X, Z, VB = elastic_catenary_end(H, VA, W, L, EA)
    assert Z >= 0  # the cases are given with end B above end A (the upright frame)
    o = solve(X, Z, L, EA, W)
    assert o[O_H] == pytest.approx(H, rel=RTOL)
    assert o[O_V] == pytest.approx(VB, rel=RTOL)
    assert o[O_VL] == pytest.approx(VA, rel=RTOL, abs=RTOL * H)


@pytest.mark.parametrize("CB", [0.0, 0.2, 1.0, 5.0])
def test_seabed_touchdown_map_equations(CB):
    """A line with a grounded part, with and without friction (both of MAP++'s friction regimes: the
    grounded tension reaching zero before the anchor for CB = 1 and 5, not for 0.2)."""
    W, L, EA = 698.0, 902.2, 3.84243e8
    H, V = 1.2e5, 1.5e5
    X, Z, TA = map_touchdown_end(H, V, W, L, EA, CB)
    o = solve(X, Z, L, EA, W, contact=True, CB=CB)
    assert o[O_H] == pytest.approx(H, rel=RTOL)
    assert o[O_V] == pytest.approx(V, rel=RTOL)
    assert o[O_HL] == pytest.approx(TA, rel=RTOL, abs=RTOL * H)
    assert o[O_VL] == 0.0
    assert o[O_LB] == pytest.approx(L - V / W, rel=RTOL)
    LB = L - V / W
    assert (CB * W * LB > H) == (CB >= 1.0)  # the two regimes are both exercised


@pytest.mark.parametrize("CB", [0.0, 0.3, 3.0])
def test_grounded_taut_line_with_friction(CB):
    """Both ends on a flat seabed, stretched: tension falls by CB W per metre from the pulled end."""
    W, L, EA, X = 500.0, 200.0, 1e8, 201.0
    o = solve(X, 0.0, L, EA, W, contact=True, CB=CB)
    e = X - L
    TB = EA * e / L + CB * W * L / 2
    if TB < CB * W * L:  # the tension reaches zero on the seabed
        TB = math.sqrt(2 * CB * W * EA * e)
    assert o[O_H] == pytest.approx(TB, rel=RTOL)
    assert o[O_HL] == pytest.approx(max(TB - CB * W * L, 0.0), rel=RTOL, abs=RTOL * TB)
    assert o[O_V] == 0.0


def test_taut_weightless_line_is_hooke():
    L, EA = 100.0, 2e8
    X, Z = 60.0, 80.5
    chord = math.hypot(X, Z)
    o = solve(X, Z, L, EA, 0.0)
    T = EA * (chord / L - 1)
    assert o[O_H] == pytest.approx(T * X / chord, rel=RTOL)
    assert o[O_V] == pytest.approx(T * Z / chord, rel=RTOL)
    slack = solve(X, 79.0, L, EA, 0.0)
    assert np.all(slack[:4] == 0.0)


def test_taut_heavy_line_tends_to_hooke():
    """A very stiff taut span with negligible weight: the catenary tension is Hooke's."""
    L, EA = 100.0, 1e9
    X, Z = 0.0 + 30.0, 95.5
    chord = math.hypot(X, Z)
    o = solve(X, Z, L, EA, 1e-3)
    T = EA * (chord / L - 1)
    assert math.hypot(o[O_H], o[O_V]) == pytest.approx(T, rel=1e-6)  # weight 0.1 N on 1e7 N: 1e-8


def test_vertical_hanging_line():
    """X = 0: an elastic line hanging straight, Z = L + (L/EA)(V - W L/2)."""
    W, L, EA = 300.0, 120.0, 5e7
    V = 9.0e4
    Z = L + (L / EA) * (V - 0.5 * W * L)
    o = solve(0.0, Z, L, EA, W)
    assert o[O_H] == 0.0
    assert o[O_V] == pytest.approx(V, rel=RTOL)
    assert o[O_VL] == pytest.approx(V - W * L, rel=RTOL)


def test_slack_line_longer_than_possible_lies_on_the_seabed():
    """Longer than its "L" shape: no horizontal tension, the hanging part carries its own weight."""
    W, EA, X, Z = 700.0, 3.8e8, 300.0, 200.0
    Lh = 2 * Z / (1 + math.sqrt(1 + 2 * Z * W / EA))  # elastic hanging length over height Z
    o = solve(X, Z, X + Lh + 50.0, EA, W, contact=True)
    assert o[O_H] == 0.0 and o[O_HL] == 0.0
    assert o[O_V] == pytest.approx(W * Lh, rel=RTOL)
    assert Lh + W * Lh ** 2 / (2 * EA) == pytest.approx(Z, rel=1e-12)


def test_short_taut_line_stretches():
    """A line too short for its span gives the stretch it needs: tension close to EA (chord/L - 1)."""
    W, L, EA, X, Z = 7.0, 900.0, 3.8e8, 850.0, 300.0
    o = solve(X, Z, L, EA, W, contact=True)
    chord = math.hypot(X, Z)
    T = math.hypot(o[O_H], o[O_V])
    assert o[O_LB] == 0.0
    assert T == pytest.approx(EA * (chord / L - 1), rel=0.01)  # sag takes ~0.3 % of the stretch here


def _sloped_end(H, V, W, L, EA, t, CB, n=200001):
    """Upper-end position of a line touching down on a slope tan(alpha) = t, by numerical
    integration of the grounded part (trapezoid, n points) plus Irvine's suspended catenary."""
    c = 1 / math.hypot(1, t)
    sn = t * c
    Ls = (V - H * t) / W
    LB = L - Ls
    s = np.linspace(0.0, LB, n)  # from the anchor
    TT = H / c
    k = W * (sn + CB * c)
    T = np.maximum(TT - k * (LB - s), 0.0)
    stretched = LB + np.trapezoid(T, s) / EA
    Xs, Zs, _ = elastic_catenary_end(H, H * t, W, Ls, EA)
    return c * stretched + Xs, sn * stretched + Zs, max(TT - k * LB, 0.0)


@pytest.mark.parametrize("t,CB", [(0.1, 0.0), (0.1, 0.5), (-0.05, 0.0), (-0.2, 0.1), (0.25, 2.0)])
def test_sloped_seabed_touchdown(t, CB):
    W, L, EA = 698.0, 900.0, 3.8e8
    H, V = 5.0e5, 4.5e5
    X, Z, TA = _sloped_end(H, V, W, L, EA, t, CB)
    o = solve(X, Z, L, EA, W, contact=True, t=t, CB=CB)
    # trapezoid error on the grounded integral: the tension is piecewise linear (exact) except at its
    # kink to zero, where it is O(ds^2 k) ~ 1e-5 N m on 1e8 N m: 1e-9 relative in X
    assert o[O_H] == pytest.approx(H, rel=1e-7)
    assert o[O_V] == pytest.approx(V, rel=1e-7)
    c = 1 / math.hypot(1, t)
    assert math.hypot(o[O_HL], o[O_VL]) == pytest.approx(TA, rel=1e-7, abs=1e-7 * H)
    assert o[O_HL] == pytest.approx(TA * c, rel=1e-7, abs=1e-7 * H)


def test_matches_the_frictionless_catenary_of_the_dynamic_start():
    """Flat, frictionless: the same solution as moorline.quasistatic.catenary (the start guess)."""
    rng = np.random.default_rng(3)
    for _ in range(300):
        L = rng.uniform(10, 1000)
        X = rng.uniform(0.05, 1.1) * L
        Z = rng.uniform(0, 0.9) * L
        EA = 10 ** rng.uniform(5, 10)
        W = rng.choice([-1.0, 1.0]) * 10 ** rng.uniform(0, 3)
        contact = bool(rng.integers(2))
        H, V, st = catenary_solve(X, Z, L, EA, W, contact, 1e-10, 1000)
        if st != 0:
            continue
        o = solve(X, Z, L, EA, W, contact)
        assert o[O_H] == pytest.approx(H, rel=1e-7, abs=1e-7 * abs(W) * L)
        assert o[O_V] == pytest.approx(V, rel=1e-7, abs=1e-7 * abs(W) * L)


def _random_case(rng):
    L = rng.uniform(10, 1000)
    shape = rng.integers(4)
    EA = 10 ** rng.uniform(5, 10)
    W = rng.choice([1.0, 1.0, -1.0]) * 10 ** rng.uniform(0, 3)
    contact = bool(rng.integers(2)) and W > 0
    t = rng.uniform(-0.3, 0.3) if contact and rng.integers(2) else 0.0
    CB = rng.uniform(0, 2) if contact and rng.integers(2) else 0.0
    if shape == 0:  # taut
        X = rng.uniform(0.6, 1.05) * L
        Z = rng.uniform(0, 0.8) * L
    elif shape == 1:  # slack, long
        X = rng.uniform(0.01, 0.6) * L
        Z = rng.uniform(0, 0.5) * L
    elif shape == 2:  # near vertical
        X = rng.uniform(0.0, 1e-3) * L
        Z = rng.uniform(0.2, 1.0) * L
    else:
        X = rng.uniform(0.01, 1.2) * L
        Z = rng.uniform(0, 1.0) * L
    if contact:
        Z = max(Z, X * t + 1e-3 * L)
    return X, Z, L, EA, W, contact, t, CB


def test_every_geometry_converges_and_its_profile_reaches_the_upper_end():
    """Taut, slack, grounded, near-vertical, buoyant, sloped and frictional lines: the solution exists
    and the profile integrated from the lower end ends at the upper end."""
    rng = np.random.default_rng(11)
    px, pz, pT = np.zeros(2), np.zeros(2), np.zeros(2)
    for _ in range(2000):
        X, Z, L, EA, W, contact, t, CB = _random_case(rng)
        o = solve(X, Z, L, EA, W, contact, t, CB)
        line_profile_upright(X, Z, L, EA, W, contact, t, CB, o[O_H], o[O_V], np.array([0.0, L]), px, pz, pT)
        size = L + X + Z
        # the profile reproduces the end conditions to the solver's convergence (1e-12 of the size);
        # a slack line bunched on the seabed ends exactly below the upper end by construction
        assert px[1] == pytest.approx(X, abs=1e-9 * size)
        assert pz[1] == pytest.approx(Z, abs=1e-9 * size)
        assert pT[1] == pytest.approx(math.hypot(o[O_H], o[O_V]), rel=1e-9, abs=1e-9 * abs(W) * L)


def test_derivatives_match_central_differences():
    """d(H, V, HL, VL)/d(X, Z, t) against central differences on random geometries.

    Steps of 1e-6 L (and 1e-6 in t): truncation error O(h^2) ~ 1e-12 relative, round-off ~ 1e-16
    T / 1e-6 = 1e-10 relative, so 1e-5 of the largest derivative is a safe bound away from the
    piecewise branches (a case within two steps of a branch switch is skipped: one-sided there)."""
    rng = np.random.default_rng(5)
    n = 0
    while n < 600:
        X, Z, L, EA, W, contact, t, CB = _random_case(rng)
        if X < 1e-2 * L:
            continue
        o = solve(X, Z, L, EA, W, contact, t, CB)
        D = o[O_D:O_D + 12].reshape(4, 3)
        hs = (1e-6 * L, 1e-6 * L, 1e-6)
        ok = True
        fd = np.zeros((4, 3))
        for j, h in enumerate(hs):
            args_p = [X, Z, t]
            args_m = [X, Z, t]
            args_p[j] += h
            args_m[j] -= h
            op = solve(args_p[0], args_p[1], L, EA, W, contact, args_p[2], CB, o[O_H], o[O_V])
            om = solve(args_m[0], args_m[1], L, EA, W, contact, args_m[2], CB, o[O_H], o[O_V])
            branch = (op[O_LB] > 0) != (om[O_LB] > 0) or ((op[O_HL] > 0) != (om[O_HL] > 0))
            if branch or op[O_H] == 0 or om[O_H] == 0:
                ok = False
            fd[:, j] = (op[[O_H, O_V, O_HL, O_VL]] - om[[O_H, O_V, O_HL, O_VL]]) / (2 * h)
        if not ok:
            continue
        n += 1
        scale = np.max(np.abs(D))
        assert np.max(np.abs(fd - D)) <= 1e-5 * scale, (X, Z, L, EA, W, contact, t, CB)


def test_upper_end_below_the_seabed_is_refused():
    out = np.zeros(LINE2D_SIZE)
    status, _ = upright_line(100.0, 5.0, 150.0, 1e8, 500.0, True, 0.2, 0.0, -1.0, 0.0, out)
    assert status == QS_BELOW_SEABED
    assert np.all(np.isnan(out))


def test_end_reversal_mirrors_the_forces():
    """The same line given A->B and B->A: end forces swap (MoorPy's invariance test)."""
    W, L, EA = 700.0, 900.0, 3.8e8
    rA, rB = np.array([800.0, 100.0, -320.0]), np.array([5.0, 2.0, -70.0])
    for bed in ("A", None):
        F1, D1, T1 = line_end_forces(rA, rB, L, EA, W, seabed_end=bed, CB=0.4)
        F2, D2, T2 = line_end_forces(rB, rA, L, EA, W, seabed_end={"A": "B", None: None}[bed], CB=0.4)
        assert np.allclose(F1, F2[::-1], rtol=1e-12, atol=1e-9 * np.max(np.abs(F1)))
        assert np.allclose(T1, T2[::-1], rtol=1e-12)
        # derivatives are with respect to rB - rA, which changes sign
        assert np.allclose(D1, -D2[::-1], rtol=1e-9, atol=1e-9 * np.max(np.abs(D1)))
