"""Verification of the lumped-mass statics against the analytic elastic catenary, and of the
seabed-contact penetration balance (spec sections 3.2, 3.5, 3.6, 3.8, 3.12, 6.3, 6.4).

The reference is written here, independently of ``moorline.quasistatic.catenary``: the classic elastic
catenary end conditions (Irvine, "Cable Structures", 1981), solved with ``scipy.optimize.fsolve``.
The model side is a single line between a fixed anchor and a coupled fairlead, brought to rest by
the package's stationary initial-condition solver (``System.init(solve_ic=True)``) with a tight
tolerance; the equilibrium is then compared with the continuum solution.

Why the discrete model should agree, and to what accuracy:

* In the lumped-mass chain the horizontal force H is the same in every segment, and the vertical
  force in segment k is the anchor vertical force plus the weight of the nodes below it, i.e. the
  continuum V at the segment mid-arc s = (k + 1/2) l. The segment slopes and stretches are thus a
  mid-point quadrature of the continuum integrals, so the end conditions (and hence H) carry an
  O(l^2) error. Measured: the H error falls from 0.48 % (N = 10) to 0.12 % (N = 20) to 0.03 %
  (N = 40), a factor ~4 per halving of l.
* The line's force on the fairlead point is -T_{N-1} + (half-segment weight) = (-H, -V(L)) exactly in
  the discrete balance, so its magnitude is compared with T(L); the end-B segment force itself is
  the continuum tension at s = L - l/2 (mid-segment), and is compared with that.
* With touchdown the discrete line can only leave the seabed at a node, and the node that does
  carries a partial seabed reaction. Sampled at the nodes, the continuum shape differs from the
  discrete one near touchdown by up to ~W l^2/(2H) in height (1.4 m at l = 20 m, H/W = 143 m),
  which moves H by a fraction that depends on where the touchdown falls between two nodes.
  Scanning the fairlead offset over a few metres (that phase) gave H errors of 0.12-0.54 % at
  N = 20, 0.05-0.22 % at N = 40 and 0.02-0.05 % at N = 80: O(l^2) on average but irregular. So the
  touchdown case is compared at N = 40 (the brief asks for 20 or more segments).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import fsolve

from moorline.model import Environment, Model, Options
from moorline.system import System

RHO = 1025.0
G = 9.80665
D = 0.1  # chain-like line: diameter [m]
W_AIR = 60.0  # mass per length [kg/m]
EA = 1.0e7  # soft enough that the elastic stretch (~1-2.5 %) matters in the comparison
AREA = math.pi * D**2 / 4.0
W_WET = (W_AIR - RHO * AREA) * G  # wet weight per unit length [N/m]
KBOT = 3.0e6  # Environment default [Pa/m]

# both fairleads are 5 m below the free surface: no segment pierces it, so every node is fully
# wet as the reference assumes (spec 3.6)
# case (a): fully suspended, deep water (seabed 700 m below the anchor, never reached)
A_DEPTH, A_ANCHOR, A_FAIR, A_L = 1000.0, (0.0, 0.0, -300.0), (400.0, 0.0, -5.0), 550.0
# case (b): anchor on the seabed, part of the line lying on it (about half its length)
B_DEPTH, B_ANCHOR, B_FAIR, B_L = 100.0, (0.0, 0.0, -100.0), (370.0, 0.0, -5.0), 400.0

TOL_FORCE = 5e-3  # brief: tensions within 0.5 %
N_A, N_B = 20, 40  # segments of the comparison for the suspended and the touchdown case (see above)


# ------------------------------------------------------------------------------------------------
# independent analytic reference


def _solve(res, guess):
    sol, _, ier, msg = fsolve(res, guess, full_output=True, xtol=1e-13)
    assert ier == 1, f"reference solve failed: {msg}"
    assert np.max(np.abs(res(sol))) < 1e-8, "reference end conditions not met"
    return sol


def suspended_catenary(XF, ZF, L, EA, W):
    """Elastic catenary fully off the bottom. Unknowns: H (horizontal force) and VA (vertical
    force at the anchor end, along increasing arc length). Returns (H, VA)."""

    def res(p):
        H, VA = abs(p[0]), p[1]
        VB = VA + W * L
        x = H / W * (math.asinh(VB / H) - math.asinh(VA / H)) + H * L / EA
        z = H / W * (math.hypot(1.0, VB / H) - math.hypot(1.0, VA / H)) + (VA * L + 0.5 * W * L * L) / EA
        return [x - XF, z - ZF]

    H, VA = _solve(res, [W * L, 0.0])
    return abs(H), VA


def suspended_profile(s, H, VA, EA, W):
    """Horizontal and vertical position of arc length ``s`` (unstretched) from the anchor."""
    V = VA + W * s
    x = H / W * (np.arcsinh(V / H) - math.asinh(VA / H)) + H * s / EA
    z = H / W * (np.hypot(1.0, V / H) - math.hypot(1.0, VA / H)) + (VA * s + 0.5 * W * s * s) / EA
    return x, z


def touchdown_catenary(XF, ZF, L, EA, W):
    """Elastic catenary with its lower part lying on a frictionless flat seabed. Unknowns: H and
    VF (vertical force at the fairlead); the suspended length is VF/W. Returns (H, VF, LB) with
    LB = L - VF/W the unstretched length lying on the seabed."""

    def res(p):
        H, VF = abs(p[0]), p[1]
        LB = L - VF / W
        x = LB + H / W * math.asinh(VF / H) + H * L / EA
        z = H / W * (math.hypot(1.0, VF / H) - 1.0) + VF * VF / (2.0 * EA * W)
        return [x - XF, z - ZF]

    H, VF = _solve(res, [W * ZF, 1.5 * W * ZF])
    H = abs(H)
    LB = L - VF / W
    assert 0.0 < LB < L, "reference case is not a touchdown case"
    return H, VF, LB


# ------------------------------------------------------------------------------------------------
# model side


def one_line_model(N, depth, anchor, fair, L, options):
    """The test chain from a fixed anchor to a coupled fairlead."""
    m = Model(env=Environment(g=G, rho=RHO, depth=depth, kBot=KBOT), options=options)
    m.add_line_type("chain", d=D, w=W_AIR, EA=EA, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.5)
    a = m.add_point("fixed", anchor)
    f = m.add_point("coupled", fair)
    m.add_line("chain", a, f, L=L, N=N)
    return m


def settled_line(N, depth, anchor, fair, L):
    """Single line, fixed anchor, coupled fairlead, brought to static equilibrium by the
    stationary IC solver with a tight tolerance (threshIC 1e-6; TmaxIC is a cap, not the usual
    stop). dtM = 0.02 s keeps the pseudo-time iteration stable with the stiff seabed spring."""
    s = System(one_line_model(N, depth, anchor, fair, L, Options(dtM=0.02, threshIC=1e-6, TmaxIC=5000.0, dtIC=1.0)))
    s.init(solve_ic=True)
    assert s.ic_report.get("converged"), f"IC solver did not converge: {s.ic_report}"
    # residual check: the node accelerations at rest must be negligible against g, otherwise the
    # comparison below would test the IC solver's stopping rule rather than the statics
    assert float(np.max(np.abs(s.work.acc))) < 1e-3
    return s


def case_a_errors(N):
    XF, ZF = A_FAIR[0] - A_ANCHOR[0], A_FAIR[2] - A_ANCHOR[2]
    H, VA = suspended_catenary(XF, ZF, A_L, EA, W_WET)
    VB = VA + W_WET * A_L
    s = settled_line(N, A_DEPTH, A_ANCHOR, A_FAIR, A_L)
    Ff = s.points[1].force()  # line's pull on the fairlead (coupled point, no mass of its own)
    Fa = s.points[0].force()  # line's pull on the anchor
    l = A_L / N
    return {
        "H": abs(-Ff[0] - H) / H,
        "T_fair": abs(np.linalg.norm(Ff) - math.hypot(H, VB)) / math.hypot(H, VB),
        "T_seg": abs(s.lines[0].fairlead_tension() - math.hypot(H, VA + W_WET * (A_L - 0.5 * l)))
        / math.hypot(H, VA + W_WET * (A_L - 0.5 * l)),
        "T_anchor": float(np.linalg.norm(Fa - np.array([H, 0.0, VA]))) / math.hypot(H, VA),
        "system": s,
        "ref": (H, VA),
    }


def case_b_errors(N):
    XF, ZF = B_FAIR[0] - B_ANCHOR[0], B_FAIR[2] - B_ANCHOR[2]
    H, VF, LB = touchdown_catenary(XF, ZF, B_L, EA, W_WET)
    susp = VF / W_WET
    x_td = LB * (1.0 + H / EA)  # the lying part is stretched by H/EA
    s = settled_line(N, B_DEPTH, B_ANCHOR, B_FAIR, B_L)
    Ff = s.points[1].force()
    Hm = -Ff[0]
    # touchdown of the model: the first segment that rises clear of the seabed (upper node more
    # than 10 penetration depths above it) has the continuum slope at its mid-point, V/H, with
    # V = W (s_mid - s_td); inverting the catenary slope there locates the touchdown. This uses
    # the model's own H, so it measures the model's shape, not the reference's.
    r = s.lines[0].node_positions()
    pen = W_WET / (KBOT * D)
    j = int(np.argmax(r[:, 2] - (-B_DEPTH) > 10.0 * pen))
    assert j > 1, "no node lies on the seabed"
    slope = (r[j, 2] - r[j - 1, 2]) / (r[j, 0] - r[j - 1, 0])
    x_mid = 0.5 * (r[j, 0] + r[j - 1, 0])
    x_td_model = x_mid - Hm / W_WET * math.asinh(slope) * (1.0 + Hm / EA)
    return {
        "H": abs(Hm - H) / H,
        "T_fair": abs(np.linalg.norm(Ff) - math.hypot(H, VF)) / math.hypot(H, VF),
        "T_seg": abs(s.lines[0].fairlead_tension() - math.hypot(H, VF - 0.5 * W_WET * B_L / N))
        / math.hypot(H, VF - 0.5 * W_WET * B_L / N),
        "touchdown": abs(x_td_model - x_td) / susp,
        "system": s,
        "ref": (H, VF, LB),
    }


# ------------------------------------------------------------------------------------------------
# tests


@pytest.fixture(scope="module")
def errs_a():
    return {N: case_a_errors(N) for N in (10, 20, 40)}


@pytest.fixture(scope="module")
def errs_b():
    return {N: case_b_errors(N) for N in (10, 40)}


def test_suspended_catenary_forces(errs_a):
    e = errs_a[N_A]
    # 0.5 % (brief); measured at N = 20: H 0.12 %, fairlead force 0.05 %, segment 0.05 %, anchor 0.13 %
    assert e["H"] < TOL_FORCE
    assert e["T_fair"] < TOL_FORCE
    assert e["T_seg"] < TOL_FORCE
    assert e["T_anchor"] < TOL_FORCE


def test_suspended_catenary_shape(errs_a):
    """Node i sits at unstretched arc length i*l; its position must match the continuum profile.
    The mid-point-quadrature argument gives an O(l^2) position error; 0.5 % of L (2.75 m) is
    generous at N = 20 (measured 0.03 % of L)."""
    s = errs_a[N_A]["system"]
    H, VA = errs_a[N_A]["ref"]
    r = s.lines[0].node_positions()
    sarc = np.linspace(0.0, A_L, r.shape[0])
    x, z = suspended_profile(sarc, H, VA, EA, W_WET)
    dev = np.hypot(r[:, 0] - (A_ANCHOR[0] + x), r[:, 2] - (A_ANCHOR[2] + z))
    assert np.max(np.abs(r[:, 1])) < 1e-9  # stays in its vertical plane
    assert np.max(dev) < 5e-3 * A_L
    assert np.min(r[:, 2]) > -A_DEPTH  # the case is really off the bottom


def test_suspended_catenary_converges_with_segments(errs_a):
    """Error at 40 segments below the error at 10 (brief). The quadrature argument predicts a
    factor 16; we require at least 4 (first order) so that the test is not brittle."""
    for k in ("H", "T_fair"):
        assert errs_a[40][k] < errs_a[10][k] / 4.0, (k, errs_a[10][k], errs_a[40][k])


def test_touchdown_catenary_forces_and_touchdown(errs_b):
    e = errs_b[N_B]
    # tensions 0.5 % (brief); measured at N = 40: H 0.11 %, fairlead force 0.07 %, segment 0.07 %
    assert e["H"] < TOL_FORCE
    assert e["T_fair"] < TOL_FORCE
    assert e["T_seg"] < TOL_FORCE
    # touchdown 0.5 % of the suspended length (189 m; 0.95 m, i.e. 0.09 segment lengths at
    # N = 40). The slope-based location does not depend on which node carries the partial seabed
    # reaction; measured 0.05 % (0.003-0.13 % over the touchdown-phase scan).
    assert e["touchdown"] < 5e-3
    H, VF, LB = e["ref"]
    r = e["system"].lines[0].node_positions()
    n_lying = int(np.sum(r[:, 2] < -B_DEPTH + 1e-3))
    # sanity: about LB/l nodes (+1 for the anchor node) lie on the seabed
    assert abs(n_lying - (LB / (B_L / N_B) + 1)) <= 1.5


def test_touchdown_catenary_converges_with_segments(errs_b):
    # measured: H error 0.72 % (N = 10) -> 0.11 % (N = 40). The touchdown-phase dependence (module
    # docstring) makes the ratio irregular, so only the brief's "smaller at 40 than at 10".
    for k in ("H", "T_fair", "touchdown"):
        assert errs_b[40][k] < errs_b[10][k], (k, errs_b[10][k], errs_b[40][k])


def test_lying_part_penetration_in_touchdown_case(errs_b):
    """The part lying on the seabed sinks by w_wet/(kBot d) (about 1.7 mm here): nodes 1..3
    (well away from touchdown) within 1 % of it."""
    r = errs_b[N_B]["system"].lines[0].node_positions()
    pen = W_WET / (KBOT * D)
    got = -B_DEPTH - r[1:4, 2]
    np.testing.assert_allclose(got, pen, rtol=1e-2)


@pytest.mark.parametrize("kbot", [KBOT, 1.0e5])
def test_seabed_penetration_balance(kbot):
    """Test 7: a line lying flat on the seabed between two fixed points, no free points. Each
    internal node balances its wet weight W l against the seabed spring kBot d l (z_b - z), so it
    settles at z = -depth - w_wet/(kBot d) (spec 3.8.1; the nodal length cancels). Tolerance 1 %
    (brief); the only coupling is through the two end segments, whose tilt over the penetration
    gives a vertical tension component ~EA (pen/l)^3 / 2, below 1e-4 of the node weight here.
    Measured 3e-7 (default kBot, 1.7 mm) and 4e-5 (kBot = 1e5, 5 cm)."""
    depth, span, N = 150.0, 100.0, 10
    m = Model(env=Environment(g=G, rho=RHO, depth=depth, kBot=kbot, cBot=3.0e5),
              options=Options(dtM=0.01, threshIC=1e-8, TmaxIC=2000.0, dtIC=1.0))
    m.add_line_type("chain", d=D, w=W_AIR, EA=EA, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.5)
    a = m.add_point("fixed", (0.0, 0.0, -depth))
    # a hair longer than the line (strain 1e-6, 10 N), so the catenary start lays it flat (spec 6.2
    # refuses L >= span on the seabed and would fall back to the same straight chord, with a warning)
    b = m.add_point("fixed", (span * (1.0 + 1e-6), 0.0, -depth))
    m.add_line("chain", a, b, L=span, N=N)
    s = System(m)
    s.init(solve_ic=True)
    r = s.lines[0].node_positions()
    pen = W_WET / (kbot * D)
    got = -depth - r[1:-1, 2]
    np.testing.assert_allclose(got, pen, rtol=1e-2)
    # the seabed force on each internal node carries exactly its wet weight
    fb = s.lines[0].node_seabed_forces()[1:-1, 2]
    np.testing.assert_allclose(fb, W_WET * span / N, rtol=1e-2)


@pytest.mark.parametrize("case", ["suspended", "touchdown"])
def test_dynamic_relaxation_reaches_the_same_catenary(case, errs_a, errs_b):
    """The other route to the static state: the legacy dynamic relaxation (ICgenDynamic = 1, spec
    6.4): RK2 dynamics with drag scaled by CdScaleIC until the fairlead tension is steady. dtM =
    3 ms keeps RK2 stable for the seabed-contact damping (rate cBot d/w = 500 1/s). Its end state
    must match the analytic catenary within 0.5 % (brief), and the stationary solver's result within
    0.05 % (both are the same discrete equilibrium; the difference is the residual motion allowed
    by threshIC = 1e-5, measured 2-3e-5)."""
    if case == "suspended":
        depth, anchor, fair, L = A_DEPTH, A_ANCHOR, A_FAIR, A_L
        H, VA = suspended_catenary(fair[0] - anchor[0], fair[2] - anchor[2], L, EA, W_WET)
        VB = VA + W_WET * L
        N, stat = N_A, errs_a[N_A]["system"]
    else:
        depth, anchor, fair, L = B_DEPTH, B_ANCHOR, B_FAIR, B_L
        H, VB, _ = touchdown_catenary(fair[0] - anchor[0], fair[2] - anchor[2], L, EA, W_WET)
        N, stat = N_B, errs_b[N_B]["system"]
    s = System(one_line_model(N, depth, anchor, fair, L,
                              Options(dtM=0.003, tScheme="RK2", ICgenDynamic=1, threshIC=1e-5, TmaxIC=1000.0,
                                      dtIC=2.0, CdScaleIC=5.0)))
    s.init(solve_ic=True)
    assert s.ic_report.get("converged"), s.ic_report
    F = s.points[1].force()
    assert -F[0] == pytest.approx(H, rel=TOL_FORCE)
    assert np.linalg.norm(F) == pytest.approx(math.hypot(H, VB), rel=TOL_FORCE)
    F_stat = stat.points[1].force()
    assert np.linalg.norm(F - F_stat) < 5e-4 * np.linalg.norm(F_stat)
