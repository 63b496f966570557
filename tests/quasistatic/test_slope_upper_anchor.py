"""A line whose seabed end is the higher one, on a seabed descending from it (issue 17,
validation/volturnus_seabed): the VolturnUS-S upslope case, the chain's anchor at 708.75 m depth, the chain
lying down the slope from it and lifting off towards a junction 22 m lower than the anchor but 39 m above
the seabed under it. The quasi-static line used to hang as a fully suspended catenary through the seabed
(1.78 MN at the anchor; the dynamic model with contact: 340 kN at the anchor, 273 kN at the junction) and
the free junction of the full system found no equilibrium. It is now solved in the seabed end's frame,
lying down the slope before it lifts off.

Oracles: the inextensible catenary tangent to the slope at its touchdown with the frictionless grounded
balance T_anchor = T_touchdown + W sin(alpha) L_B, solved here independently (scipy); MoorPy 1.3.0's
catenary with its seabed slope ``alpha``; finite differences of the end forces for the stiffness."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from moorline.model import Model
from moorline.model.types import Bathymetry
from moorline.quasistatic import QuasiStaticModel, line_end_forces

SLOPE = 0.125
W = 2456.0  # wet weight [N/m] of the 120 mm chain (288 kg/m, 0.216 m volume diameter)


def _model():
    x = np.arange(-1400.0, 1400.0 + 1e-9, 100.0)
    X, _ = np.meshgrid(x, x)
    m = Model()
    m.env.depth = 850.0
    m.env.bathymetry = Bathymetry(x, x, -(850.0 + SLOPE * X))  # rises towards -x
    m.add_line_type("chain", d=0.216, w=288.0, EA=1.2326e9, BA=-1.0, Cd=1.333, Ca=1.0, CdAx=0.639, CaAx=0.5)
    a = m.add_point("fixed", (-1130.0, 0.0, -(850.0 - SLOPE * 1130.0)))
    j = m.add_point("fixed", (-640.84, 0.0, -731.01))
    m.add_line("chain", a, j, L=500.0, N=25)
    return m


def test_chain_from_an_upper_anchor_rests_on_the_descending_slope():
    m = _model()
    qs = QuasiStaticModel(m)
    sol = qs.solve()
    _, r, T = qs.line_profile(1, 201)
    b = m.env.bathymetry
    # the line stays on or above the seabed (1 cm), and its anchor tension is the dynamic model's 340 kN
    # within 2 % (measured 339.7 kN; the lumped-mass model's touchdown is 20 m segments)
    assert np.all(r[:, 2] >= b.height(r[:, 0], r[:, 1]) - 0.01)
    assert sol.tensions[0, 0] == pytest.approx(340e3, rel=0.02)
    # frictionless on the slope: T - W z is constant along the grounded part and the suspended part alike
    # (the tension changes only by the weight times the height gained; stretch shifts it by < 1e-3)
    w = (288.0 - m.env.rho * math.pi / 4 * 0.216**2) * m.env.g
    assert np.ptp(T - w * r[:, 2]) < 1e-3 * T.max()


def _inextensible(X, Z, L, t):
    """The inextensible frictionless line from a seabed end at the origin down a slope ``t < 0`` to a point
    (X, Z) above the plane: (anchor tension, tension at the other end) [N]."""
    al = math.atan(t)

    def f(p):
        H, Lg = p
        Vt = H * t
        Vf = Vt + W * (L - Lg)
        xs = H / W * (math.asinh(Vf / H) - math.asinh(Vt / H))
        zs = H / W * (math.hypot(1.0, Vf / H) - math.hypot(1.0, Vt / H))
        return [Lg * math.cos(al) + xs - X, Lg * math.sin(al) + zs - Z]

    for start in ([5e4, 0.8 * L], [2e4, 0.9 * L], [1e4, 0.95 * L], [1e5, 0.6 * L]):
        (H, Lg), _, ier, _ = fsolve(f, start, full_output=True, xtol=1e-13)
        if ier == 1 and H > 0.0 and 0.0 < Lg < L:
            break
    assert ier == 1 and max(abs(v) for v in f((H, Lg))) < 1e-8 * L
    return H / math.cos(al) - W * math.sin(al) * Lg, math.hypot(H, H * t + W * (L - Lg))


@pytest.mark.parametrize("X, h", [(480.0, 40.0), (460.0, 60.0), (400.0, 120.0)])
def test_matches_the_inextensible_catenary_on_the_slope(X, h):
    t = -SLOPE
    Z = X * t + h  # h above the plane, below the anchor
    F, _, T = line_end_forces([0.0, 0.0, 0.0], [X, 0.0, Z], 500.0, 1e16, W, seabed_end="A", slope=(t, 0.0))
    TA, TB = _inextensible(X, Z, 500.0, t)
    assert T[0] == pytest.approx(TA, rel=1e-8)
    assert T[1] == pytest.approx(TB, rel=1e-8)
    # the anchor is pulled down the slope (towards +x and downwards), the other end back up towards it
    assert F[0, 0] > 0.0 and F[0, 2] < 0.0 and F[1, 0] < 0.0


@pytest.mark.parametrize("X, h", [(480.0, 40.0), (400.0, 120.0)])
def test_matches_moorpy_catenary_on_the_slope(X, h):
    pytest.importorskip("moorpy")
    from moorpy.Catenary import catenary as mp_catenary

    t, EA = -SLOPE, 1.2326e9
    Z = X * t + h
    fAH, fAV, fBH, fBV, _ = mp_catenary(X, Z, 500.0, EA, W, CB=0.0, alpha=math.degrees(math.atan(t)), Tol=1e-10,
                                        MaxIter=500)
    _, _, T = line_end_forces([0.0, 0.0, 0.0], [X, 0.0, Z], 500.0, EA, W, seabed_end="A", slope=(t, 0.0))
    assert T[0] == pytest.approx(math.hypot(fAH, fAV), rel=1e-3)
    assert T[1] == pytest.approx(math.hypot(fBH, fBV), rel=1e-3)


def test_stiffness_is_the_derivative_of_the_end_forces():
    rA = np.array([10.0, -5.0, -700.0])
    d = np.array([420.0, 180.0, -20.0])  # horizontal 457 m down a slope of gradient (-0.1, -0.05)
    slope = (-0.1, -0.05)
    args = (500.0, 1.2326e9, W)
    F, D, _ = line_end_forces(rA, rA + d, *args, seabed_end="A", slope=slope)
    for j in range(3):
        e = np.zeros(3)
        e[j] = 1e-3
        Fp, _, _ = line_end_forces(rA, rA + d + e, *args, seabed_end="A", slope=slope)
        Fm, _, _ = line_end_forces(rA, rA + d - e, *args, seabed_end="A", slope=slope)
        fd = (Fp - Fm) / 2e-3
        assert np.allclose(D[:, :, j], fd, rtol=1e-4, atol=1e-6 * np.abs(D).max()), (j, D[:, :, j], fd)
    # end B first: the same line, mirrored roles
    Fb, _, _ = line_end_forces(rA + d, rA, *args, seabed_end="B", slope=slope)
    assert np.allclose(Fb[::-1], F, rtol=1e-9, atol=1e-6)


def test_slack_line_slides_to_the_foot_of_the_slope():
    """Longer than its "L" shape (down the slope to below the other end, then straight up to it): without
    friction the rest bunches at the foot and the grounded part pulls the anchor with W sin(alpha) Lflat;
    friction above the slope (CB > |t|) holds it all: no pull."""
    t, X, h = -SLOPE, 300.0, 20.0
    Z = X * t + h
    F, _, T = line_end_forces([0.0, 0.0, 0.0], [X, 0.0, Z], 500.0, 1.2326e9, W, seabed_end="A", slope=(t, 0.0))
    al = math.atan(-t)
    assert T[0] == pytest.approx(W * math.sin(al) * X / math.cos(al), rel=1e-12)
    assert F[0, 2] < 0.0  # down the slope
    assert T[1] == pytest.approx(W * h, rel=1e-4)  # the hanging part (its stretch: h W / 2 EA = 2e-5)
    _, _, Tf = line_end_forces([0.0, 0.0, 0.0], [X, 0.0, Z], 500.0, 1.2326e9, W, seabed_end="A", slope=(t, 0.0),
                               CB=0.2)
    assert Tf[0] == 0.0
