"""Verification of zero-length rods joining cables with bending stiffness (spec 3.14.4, 3.10).

A three-section lazy-wave power cable in 100 m of water: a heavy cable clamped at the seabed to a
fixed vertical rod (a bend-stiffener base), a buoyancy section (net buoyant, twice the bending
stiffness), and a heavy cable up to a coupled point 10 m below the surface. The sections are joined
by FREE zero-length rods (line end B on the rod's end A, the next line's end A on its end B), whose
axis is the EI-weighted mean direction of the two end segments, sum sigma EI e / l (spec 3.14.4),
and to which both cable ends are clamped.

Checked, after the initial-condition solve (dynamic relaxation) and at every second of 60 s of
+-2 m heave at the top:

- the lazy-wave shape: the buoyancy section arches above both joints (hog) and the upper cable
  sags below its joint (sag);
- force balance at each joint: the joint itself has no mass, so the two lines' end-node forces add
  up to the end nodes' masses times the joint's acceleration (zero at rest). Written out with the
  segment tensions: T_b - T_a = M a - (W_a + W_b + H_a + H_b + B_a + B_b), with W the weight and
  buoyancy of the two half segments at the joint (computed here from the line types), H drag and
  fluid inertia, B bending forces. The tension is continuous across the joint up to these nodal
  loads: | |T_a| - |T_b| | <= |W_a + W_b| + |H_a| + |H_b| + |B_a| + |B_b| + |M a|;
- the joint transmits direction: its axis is sum EI e / l of the two end segments, it lies in
  their plane between them, and the bending moments of the two clamped ends on the joint cancel
  (moment continuity) up to the O(theta^2) difference between sin(theta)/l (what the axis rule
  balances) and (4/l) sin(theta/2) (the clamped-end curvature): |M_a + M_b| <= |M_a| theta^2/4
  (measured 0.45 of that bound), and exactly |M_a| cos(theta_a/2) = |M_b| cos(theta_b/2). The
  buoyancy section has twice the cable's EI, so an unweighted axis would leave a 2:1 imbalance;
- the curvature at the joint is finite and no larger than twice that of the neighbouring nodes
  (a joint that did not transmit moment would leave a kink there).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from moorline.model import Environment, Model, Options
from moorline.motion import Trajectory
from moorline.system import System

RHO = 1025.0
G = 9.80665
DEPTH = 100.0
TOP = np.array([110.0, 0.0, -10.0])
CABLE = {"d": 0.12, "w": 25.0, "EI": 2.0e3, "Ca": 1.0}
BUOY = {"d": 0.35, "w": 60.0, "EI": 4.0e3, "Ca": 1.0}
SECTIONS = [("cable", 62.0, 16), ("buoy", 30.0, 10), ("cable", 80.0, 16)]  # (type, length, segments)


def lazy_wave_model(**options) -> Model:
    """The deck (RK4 at 4 ms, initial conditions by dynamic relaxation unless ``options`` say otherwise)."""
    m = Model(env=Environment(g=G, rho=RHO, depth=DEPTH),
              options=Options(**({"tScheme": "RK4", "dtM": 0.004, "TmaxIC": 200.0, "ICgenDynamic": 1} | options)))
    for name, p in (("cable", CABLE), ("buoy", BUOY)):
        m.add_line_type(name, d=p["d"], w=p["w"], EA=2.0e7, BA=-0.5, EI=p["EI"], Cd=1.2, Ca=p["Ca"], CdAx=0.01)
    m.add_rod_type("base", d=0.3, w=50.0)
    m.add_rod_type("joint", d=0.12, w=0.0)
    _, base = m.add_rod("base", "fixed", (0.0, 0.0, -99.0), (0.0, 0.0, -95.0), N=1)
    j1a, j1b = m.add_rod("joint", "free", (30.0, 0.0, -50.0), (30.0, 0.0, -50.0), N=0)
    j2a, j2b = m.add_rod("joint", "free", (55.0, 0.0, -50.0), (55.0, 0.0, -50.0), N=0)
    top = m.add_point("coupled", TOP)
    ends = [(base, j1a), (j1b, j2a), (j2b, top)]
    for (lt, L, N), (a, b) in zip(SECTIONS, ends, strict=True):
        m.add_line(lt, a, b, L=L, N=N)
    return m


def lazy_wave() -> System:
    """The cable at its static equilibrium (dynamic relaxation, converged)."""
    s = System(lazy_wave_model())
    s.init()
    assert s.ic_report["converged"], s.ic_report
    return s


def shape(s):
    r = [s.lines[i].node_positions() for i in range(3)]
    return {"buoy_top": r[1][:, 2].max(), "buoy_top_node": int(np.argmax(r[1][:, 2])), "joint1": r[0][-1, 2],
            "joint2": r[2][0, 2], "sag": r[2][:, 2].min(), "top": r[2][-1, 2]}


def unit(v):
    return v / np.linalg.norm(v)


def joint_checks(s):
    """Check the two joints (rods 2 and 3 join lines 1-2 and 2-3); return the largest relative
    force-balance residual and the largest tension jump over its bound."""
    worst_balance = 0.0
    for k, (la, lb) in enumerate(((0, 1), (1, 2))):
        A, B = s.lines[la], s.lines[lb]
        pa, pb = SECTIONS[la], SECTIONS[lb]
        ta, tb = (CABLE, BUOY) if la == 0 else (BUOY, CABLE)
        ra, rb = A.node_positions(), B.node_positions()
        joint = s.rods[1 + k]
        x = joint.node_positions()[0]
        np.testing.assert_array_equal(ra[-1], x)
        np.testing.assert_array_equal(rb[0], x)
        # end segments, both pointing along the cable (line a arrives, line b leaves)
        va, vb = ra[-1] - ra[-2], rb[1] - rb[0]
        la_, lb_ = np.linalg.norm(va), np.linalg.norm(vb)
        ea, eb = va / la_, vb / lb_
        q = joint.axis()

        # axis: EI-weighted mean direction (spec 3.14.4); one normalised sum, round-off only
        np.testing.assert_allclose(q, unit(ta["EI"] * ea / la_ + tb["EI"] * eb / lb_), rtol=0, atol=1e-12)
        tha, thb = math.acos(min(1.0, q @ ea)), math.acos(min(1.0, q @ eb))
        phi = math.acos(min(1.0, ea @ eb))
        # between the two segments, in their plane: the angles add up (acos near 1 loses ~1e-8 rad)
        assert abs(tha + thb - phi) < 1e-7
        assert tha <= phi + 1e-9 and thb <= phi + 1e-9

        # moment continuity across the joint (see the module docstring for the theta^2/4 bound)
        Ma, Mb = A.end_moments()[1], B.end_moments()[0]
        assert np.linalg.norm(Ma + Mb) <= np.linalg.norm(Ma) * max(tha, thb) ** 2 / 4 + 1e-9
        # exactly: the axis rule balances EI sin(theta)/l, the moments are EI (4/l) sin(theta/2), so
        # |M_a| cos(theta_a/2) = |M_b| cos(theta_b/2) (round-off and acos near 1: 1e-9 relative)
        assert abs(np.linalg.norm(Ma) * math.cos(tha / 2) - np.linalg.norm(Mb) * math.cos(thb / 2)) \
            <= 1e-9 * np.linalg.norm(Ma)

        # curvature at the joint (both clamped ends) against the neighbouring nodes
        ka, kb = A.node_curvatures(), B.node_curvatures()
        assert np.isfinite(ka[-1]) and np.isfinite(kb[0])
        neighbours = max(ka[-2], kb[1])
        assert max(ka[-1], kb[0]) <= 2.0 * neighbours + 1e-4
        # the bend across the joint, as an interior node would see it, is no sharper either
        assert 2.0 * phi / (la_ + lb_) <= 2.0 * neighbours + 1e-4

        # force balance of the massless joint, from the segment tensions and nodal loads
        Ta, Tb = A.segment_tension_vectors()[-1], B.segment_tension_vectors()[0]
        l0a, l0b = pa[1] / pa[2], pb[1] / pb[2]
        Wa = np.array([0.0, 0.0, -(ta["w"] - RHO * math.pi * ta["d"] ** 2 / 4) * G * l0a / 2])
        Wb = np.array([0.0, 0.0, -(tb["w"] - RHO * math.pi * tb["d"] ** 2 / 4) * G * l0b / 2])
        Ha, Hb = A.node_hydro_forces()[-1], B.node_hydro_forces()[0]
        Ba, Bb = A.node_bending_forces()[-1], B.node_bending_forces()[0]
        # end-node masses: w l0/2 plus transverse added mass rho A Ca l0/2 across the clamped tangent
        # (= the joint axis); CaAx = 0
        m_end = ta["w"] * l0a / 2 + tb["w"] * l0b / 2
        ma_end = sum(RHO * math.pi * p["d"] ** 2 / 4 * p["Ca"] * l0 / 2 for p, l0 in ((ta, l0a), (tb, l0b)))
        M = m_end * np.eye(3) + ma_end * (np.eye(3) - np.outer(q, q))
        acc = s.work.rodacc[1 + k, :3]  # the joint's acceleration (no public view for it)
        residual = Tb - Ta + Wa + Wb + Ha + Hb + Ba + Bb - M @ acc
        worst_balance = max(worst_balance, np.linalg.norm(residual) / np.linalg.norm(Ta))
        bound = np.linalg.norm(Wa + Wb) + sum(np.linalg.norm(f) for f in (Ha, Hb, Ba, Bb, M @ acc))
        assert abs(np.linalg.norm(Ta) - np.linalg.norm(Tb)) <= bound * (1 + 1e-9)
    return worst_balance


def check_lazy_wave_shape(sh, margin):
    # hog: the buoyancy section arches above both joints, its crest inside the section
    assert sh["buoy_top"] > max(sh["joint1"], sh["joint2"]) + margin, sh
    assert 0 < sh["buoy_top_node"] < SECTIONS[1][2], sh
    # sag: the upper cable dips below its joint before rising to the top
    assert sh["sag"] < sh["joint2"] - margin, sh
    assert sh["sag"] < sh["top"], sh
    # nothing on the seabed
    assert sh["sag"] > -DEPTH + 10.0, sh


def test_lazy_wave_static():
    s = lazy_wave()
    sh = shape(s)
    # measured: crest -33.6 m, joints -49.4 and -37.8 m, sag -50.1 m: a 4 m hog and a 12 m sag
    check_lazy_wave_shape(sh, margin=2.0)
    # the balance is the same loads summed in another order: round-off of the 8 kN tension
    # (measured 2e-17 relative); 1e-9
    assert joint_checks(s) < 1e-9


def test_lazy_wave_heave_60s():
    s = lazy_wave()
    heave = Trajectory.from_function(lambda t: TOP + [0.0, 0.0, 2.0 * math.sin(2.0 * math.pi * t / 8.0)], 60.0, 0.1,
                                     interpolation="cubic")
    motion = heave.as_motion()
    worst = 0.0
    top_tension = []
    for t in np.arange(1.0, 60.0 + 1e-9, 1.0):
        s.advance_to(t, motion)  # raises SimulationError if the run goes unstable
        assert np.all(np.isfinite(s.y))
        sh = shape(s)
        assert sh["top"] == pytest.approx(TOP[2] + 2.0 * math.sin(2.0 * math.pi * t / 8.0), abs=1e-9)
        check_lazy_wave_shape(sh, margin=1.0)
        worst = max(worst, joint_checks(s))
        top_tension.append(s.lines[2].fairlead_tension())
    # in motion the joint carries its end nodes' inertia (|a| up to 2.6 m/s^2 at the samples); the balance still holds
    # to round-off (measured 2e-16 relative)
    assert worst < 1e-9
    # the heave is felt along the cable (top tension range measured 3.0 kN about 7.3 kN)
    assert np.ptp(top_tension) > 1000.0
