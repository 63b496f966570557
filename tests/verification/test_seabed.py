"""Verification of the seabed: bathymetry grids, slope-normal contact and the three friction models
(spec sections 1.11.2, 3.8, 3.9 and 6.2; issue 4).

1. a short heavy line on a planar incline ("block on an incline"): below the static friction angle
   it stays put (stick-slip: only the elastic friction-spring offset; saturated models: the creep
   speed of their linear branch), above it it slides with a = (1 - rho A/w) g (sin a - mu cos a);
2. a line lying on a flat seabed dragged axially (tension = mu_kA x wet weight of the lying
   length) and sideways (seabed force = mu_kT x wet weight);
3. a line up a slope and its mirror image give the same tensions;
4. a flat grid file gives the same results as the plain depth option;
5. the initial catenary respects the bathymetry (no node starts below the local seabed);
6. stick-slip friction keeps a tension gradient along a line pulled back and forth on the seabed,
   with a dissipative tension-offset loop, where the saturated model equalises;
7. the contact force acts along the local grid normal (vertical with ``contact="vertical"``), and
   friction lies in the seabed plane.

Every tolerance is stated next to its assertion with the reason for it. Friction coefficients are
different for the axial and transverse directions wherever the test can tell them apart, so using
the wrong one fails the test.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from moorline.io.bathymetry import read_seafloor_grid
from moorline.model import Bathymetry, Environment, Model, Options
from moorline.motion import Trajectory
from moorline.system import System

RHO = 1025.0
G = 9.80665


def wet_weight(w, d):
    """Submerged weight per unit length [N/m] of a line of mass w [kg/m] and diameter d [m]."""
    return (w - RHO * math.pi * d * d / 4.0) * G


def no_motion():
    """Compiled hold trajectory for a system without coupled DOFs."""
    return Trajectory.hold(np.zeros(0)).as_motion()


def smooth_ramp_distance(t, tr):
    """Distance travelled by a point whose speed rises from 0 to 1 as the C2 smoothstep
    10 x^3 - 15 x^4 + 6 x^5 (x = t/tr) over tr seconds, then stays 1."""
    t = np.asarray(t, dtype=float)
    x = np.clip(t / tr, 0.0, 1.0)
    return np.where(t < tr, tr * (2.5 * x**4 - 3.0 * x**5 + x**6), tr * 0.5 + (t - tr))


# ------------------------------------------------------------------------------------------------
# 1. block on an incline

BLK_D, BLK_W, BLK_EA = 0.1, 100.0, 1.0e7
BLK_N, BLK_L = 3, 3.0  # 3 segments of 1 m
BLK_KBOT, BLK_CBOT, BLK_KSHEAR = 1.0e5, 1.0e4, 1.0e5
BLK_MU, BLK_MC, BLK_CV = 0.3, 1.5, 1.0e5
BLK_WET = wet_weight(BLK_W, BLK_D)  # 901.7 N/m


def block_on_incline(angle, friction, orientation):
    """A 3 m, 3-segment heavy line lying on the plane z = -60 + tan(angle) x, between two free
    massless points, at rest at the equilibrium normal penetration (so nothing but friction
    decides what happens next). No drag, no added mass (Cd = CdAx = Ca = CaAx = 0).

    ``orientation`` 'along': the line points up the slope, so sliding is axial; 'across': it lies
    horizontally across the slope, so sliding is transverse. The directional model gets the
    coefficient under test (0.3) in the sliding direction and 0.6 in the other one.

    Stability at dtM = 1 ms with RK4: contact kBot d/w = 100 s^-2 (10 rad/s, zeta 0.5), friction
    springs the same, creep damping mu cv/m <= 600 s^-1 at the end nodes (0.6 per step; RK4 is
    stable to 2.8), axial segment mode 2 sqrt(EA/(w l^2)) = 632 rad/s (0.63 per step)."""
    a = math.radians(angle)
    gx = np.array([-50.0, 50.0])
    bat = Bathymetry(gx, [-50.0, 50.0], np.tile(-60.0 + math.tan(a) * gx, (2, 1)))
    if friction == "directional":
        mu_kT, mu_kA = (0.6, BLK_MU) if orientation == "along" else (BLK_MU, 0.6)
        coeffs = dict(mu_kT=mu_kT, mu_kA=mu_kA, mc=BLK_MC, cv=BLK_CV)
    else:
        coeffs = dict(mu=BLK_MU, stat_dyn=BLK_MC, fric_damp=BLK_CV)
    env = Environment(g=G, rho=RHO, depth=100.0, kBot=BLK_KBOT, cBot=BLK_CBOT, bathymetry=bat, friction=friction,
                      kShear=BLK_KSHEAR, **coeffs)
    m = Model(env=env, options=Options(dtM=1e-3, tScheme="RK4"))
    m.add_line_type("blk", d=BLK_D, w=BLK_W, EA=BLK_EA, BA=-0.5)
    n = np.array([-math.sin(a), 0.0, math.cos(a)])  # seabed normal
    u = np.array([math.cos(a), 0.0, math.sin(a)]) if orientation == "along" else np.array([0.0, 1.0, 0.0])
    pen = BLK_WET * math.cos(a) / (BLK_KBOT * BLK_D)  # normal penetration carrying W cos a
    l0 = BLK_L / BLK_N
    pos = np.array([np.array([0.0, 0.0, -60.0]) - pen * n + u * (k * l0) for k in range(BLK_N + 1)])
    pa = m.add_point("free", pos[0])
    pb = m.add_point("free", pos[-1])
    m.add_line("blk", pa, pb, L=BLK_L, N=BLK_N)
    s = System(m)
    s.init(solve_ic=False)
    s.set_state(line_positions=[pos], point_positions=np.array([pos[0], pos[-1]]))
    return s


def downslope_history(s, t_end, dt_out=0.01):
    """(t, displacement of every node down the slope [m], shape (n_t, N+1))."""
    r0 = s.lines[0].node_positions()
    # down-slope unit vector of the plane z = z0 + slope x
    bat = s.model.env.bathymetry
    slope = (bat.z[0, 1] - bat.z[0, 0]) / (bat.x[1] - bat.x[0])
    a_dir = -np.array([1.0, 0.0, slope]) / math.hypot(1.0, slope)
    ts, ds = [0.0], [np.zeros(r0.shape[0])]
    for k in range(1, int(round(t_end / dt_out)) + 1):
        s.advance_to(k * dt_out, no_motion())
        ts.append(s.t)
        ds.append((s.lines[0].node_positions() - r0) @ a_dir)
    return np.array(ts), np.array(ds)


SLIDE_CASES = [("isotropic", "along"), ("directional", "along"), ("directional", "across"), ("stickslip", "along")]


@pytest.mark.parametrize("friction, orientation", SLIDE_CASES)
def test_block_slides_above_friction_angle(friction, orientation):
    """30 deg slope: tan a = 0.577 > mc mu = 0.45, so no static branch can hold the line. Once the
    saturated models' sliding speed exceeds mc N/cv (~1 cm/s, after a few ms) and the stick-slip
    springs have reached mc mu N, every node feels the kinetic friction mu N = mu W_i cos a,
    proportional to its weight, so the line slides as a rigid block with
    a = (1 - rho A/w) g (sin a - mu cos a) (no drag, no added mass; buoyancy reduces the weight,
    not the mass). Measured from a quadratic fit of the mean down-slope displacement over
    1 s <= t <= 3 s. Tolerance 2 % (brief); measured 4e-15 (isotropic), 6e-15 (stick-slip) and
    8e-6 (directional across the slope, where the line bows slightly), so a wrong coefficient
    (mu_kT for mu_kA: a = 0.17 instead of 2.17 m/s^2), a missing buoyancy (+9 %) or
    vertical-instead-of-normal contact would fail. The nodes keep their spacing within 1 mm
    (measured 0.4 mm across the slope, 4 um along it)."""
    a = math.radians(30.0)
    s = block_on_incline(30.0, friction, orientation)
    t, d = downslope_history(s, 3.0)
    a_ref = (1.0 - RHO * math.pi * BLK_D**2 / 4.0 / BLK_W) * G * (math.sin(a) - BLK_MU * math.cos(a))
    w = t >= 1.0
    c = np.polyfit(t[w], d[w].mean(axis=1), 2)
    assert 2.0 * c[0] == pytest.approx(a_ref, rel=0.02)
    # it slides as one block
    assert np.ptp(d[-1]) < 1e-3


@pytest.mark.parametrize("friction, orientation", [("isotropic", "along"), ("isotropic", "across"),
                                                   ("directional", "along"), ("directional", "across")])
def test_block_creeps_below_friction_angle_saturated(friction, orientation):
    """Saturated-damping models (MoorDyn-C isotropic, MoorDyn-F directional) below the friction
    angle: tan a = 0.2 < mu = 0.3. These models have no true sticking: each node creeps at the
    speed where the linear branch mu cv v balances its down-slope weight, so the bound is
    v_i <= W_i sin a/(mu cv) = w_wet l sin a/(mu cv) (interior node, 5.9 mm/s; the end nodes have
    half the weight for the same cv). In steady creep the segment forces cancel in the sum over the
    nodes, so the mean node speed is exactly W_line sin a/((N+1) mu cv) (4.4 mm/s).

    The slope is chosen so that the linear branch never saturates, even at a line end dragged by
    the rest of the line (a node carries at most twice its own down-slope weight, 2 tan a = 0.4 <
    mc mu = 0.45). Tolerances: every node below the bound (+0.1 %); mean speed within 1 % (the
    creep time constant m/(mu cv) is 3 ms, so after 1 s only round-off remains; measured < 1e-4);
    total displacement after 3 s below 3 s x bound, i.e. it does not slide (sliding would cover
    metres). Measured: largest node speed 0.99998 of the bound (across the slope; 0.80 along it,
    where the tension-only line lets the lower end node creep on its own), mean speed within 3e-5."""
    a = math.atan(0.2)
    s = block_on_incline(math.degrees(a), friction, orientation)
    t, d = downslope_history(s, 3.0)
    w = t >= 1.0
    v = np.array([np.polyfit(t[w], d[w, i], 1)[0] for i in range(d.shape[1])])
    v_bound = BLK_WET * (BLK_L / BLK_N) * math.sin(a) / (BLK_MU * BLK_CV)
    v_mean = BLK_WET * BLK_L * math.sin(a) / ((BLK_N + 1) * BLK_MU * BLK_CV)
    assert np.all(v > 0.0)  # it creeps down, not up
    assert np.all(v <= v_bound * 1.001)
    assert v.mean() == pytest.approx(v_mean, rel=0.01)
    assert np.max(d[-1]) < 3.0 * v_bound


def test_block_sticks_below_static_angle_stickslip():
    """Stick-slip model between the kinetic and the static friction angle: mu = 0.3 < tan a = 0.35
    < mc mu = 0.45. A kinetic-only model would slide (a = 0.43 m/s^2); here every node must stick,
    displaced only by the elastic stretch of its friction spring, W_i sin a/(kShear d lam_i) =
    w_wet sin a/(kShear d) = 29.8 mm (the same for all nodes: weight and spring both scale with the
    nodal length). The sudden load overshoots by e^(-pi zeta/sqrt(1 - zeta^2)) = 16 % (zeta = 0.5),
    which stays below the static limit (0.35 x 1.16 = 0.41 < 0.45), so no node breaks away.

    Tolerances: after 4 s, when the line-on-springs vibration (sqrt(kShear d/w) = 10 rad/s, zeta
    0.5) has decayed by e^-20, the displacement of every node within 1 % of the spring stretch
    (measured 2e-9), and the line at rest: node speeds below 1e-6 m/s (measured 6e-11; creep at
    the saturated-model rate would be 1e-2 m/s)."""
    a = math.atan(0.35)
    s = block_on_incline(math.degrees(a), "stickslip", "along")
    t, d = downslope_history(s, 4.0)
    stretch = BLK_WET * math.sin(a) / (BLK_KSHEAR * BLK_D)
    np.testing.assert_allclose(d[-1], stretch, rtol=0.01)
    assert np.max(np.abs(s.lines[0].node_velocities())) < 1e-6


# ------------------------------------------------------------------------------------------------
# 2. dragging a line on a flat seabed

DRG_D, DRG_W, DRG_EA, DRG_L, DRG_N = 0.1, 100.0, 1.0e8, 50.0, 10
DRG_DEPTH, DRG_KBOT, DRG_CBOT = 50.0, 1.0e5, 1.0e4
DRG_WET = wet_weight(DRG_W, DRG_D)
DRG_PEN = DRG_WET / (DRG_KBOT * DRG_D)  # equilibrium penetration of a lying node [m]
DRG_V = 0.5  # drag speed [m/s]


def drag_system(friction, coeffs, transverse, strain=0.0):
    """A 50 m line (10 segments) lying straight on a flat seabed at z = -50 m, given as a flat 2x2
    grid so that the ends can sit at the equilibrium penetration of the lying nodes (with the
    plain depth option MoorDyn's rule would move the seabed down to the deepest point); then every
    node, ends included, carries its own wet weight w_wet lam_i on the seabed.

    Axial: end A is a free massless point, end B a coupled point pulled along +x. Transverse: both
    ends coupled, pulled together along +y, with the line pre-strained by ``strain`` so that it
    stays nearly straight (see the transverse test). No drag or added mass; BA damps the axial
    modes."""
    bat = Bathymetry([-100.0, 200.0], [-100.0, 100.0], np.full((2, 2), -DRG_DEPTH))
    env = Environment(g=G, rho=RHO, depth=DRG_DEPTH, kBot=DRG_KBOT, cBot=DRG_CBOT, bathymetry=bat,
                      friction=friction, **coeffs)
    m = Model(env=env, options=Options(dtM=1e-3, tScheme="RK4"))
    m.add_line_type("chain", d=DRG_D, w=DRG_W, EA=DRG_EA, BA=-0.8)
    z = -DRG_DEPTH - DRG_PEN
    a = m.add_point("coupled" if transverse else "free", (0.0, 0.0, z))
    b = m.add_point("coupled", (DRG_L * (1.0 + strain), 0.0, z))
    m.add_line("chain", a, b, L=DRG_L, N=DRG_N)
    s = System(m)
    s.init(solve_ic=False)  # straight chord at the equilibrium penetration: at rest in equilibrium
    return s


def drag_history(s, direction, t_end=10.0, tr=4.0, dt_out=0.05):
    """Pull the coupled points along ``direction`` with a C2 speed ramp to DRG_V over ``tr``;
    record (t, end-B segment tension, coupled force on B, summed seabed force on the line)."""
    x0 = s.deck_coupled_positions()
    t = np.arange(0.0, t_end + 1e-9, 0.05)
    X = x0[None, :] + np.outer(DRG_V * smooth_ramp_distance(t, tr), np.tile(direction, x0.size // 3))
    motion = Trajectory.from_samples(t, X, "cubic").as_motion()
    out = []
    for k in range(1, int(round(t_end / dt_out)) + 1):
        s.advance_to(k * dt_out, motion)
        ln = s.lines[0]
        out.append((s.t, ln.segment_tensions()[-1], *s.coupled_forces()[-3:], *ln.node_seabed_forces().sum(axis=0)))
    return np.array(out)


@pytest.mark.parametrize("friction, coeffs, mu", [
    ("isotropic", dict(mu=0.4, fric_damp=1e5, stat_dyn=1.0), 0.4),
    ("directional", dict(mu_kT=0.7, mu_kA=0.4, mc=1.0, cv=1e5), 0.4),
    ("stickslip", dict(mu=0.4, stat_dyn=1.2), 0.4),
])
def test_axial_drag_tension(friction, coeffs, mu):
    """Steady axial sliding at 0.5 m/s (the saturated models reach their kinetic level above
    mc N/cv = 4.5 cm/s; the stick-slip springs slip at the kinetic level): every node feels
    mu_kA N_i = mu_kA w_wet lam_i against the motion. The end-B segment pulls all nodes but the
    coupled end node (whose friction goes straight to the coupled point): contact length L - l/2,
    so T = mu_kA w_wet (L - l/2); the coupled point carries the friction of the whole lying length,
    F_x = -mu_kA w_wet L. Directional: mu_kA = 0.4, mu_kT = 0.7 (using mu_kT would be 75 % off).

    Checked at every output from t = 6 s (2 s after the end of the smooth ramp) to 10 s.
    Tolerance 2 % (brief); at constant speed the axial waves of the ramp are damped by BA and
    what is left is the residual vibration (measured 5e-6 for the saturated models, 2e-5 for
    stick-slip; the summed seabed force 4e-14)."""
    s = drag_system(friction, coeffs, transverse=False)
    h = drag_history(s, np.array([1.0, 0.0, 0.0]))
    w = h[:, 0] >= 6.0
    l0 = DRG_L / DRG_N
    T_ref = mu * DRG_WET * (DRG_L - 0.5 * l0)
    np.testing.assert_allclose(h[w, 1], T_ref, rtol=0.02)
    np.testing.assert_allclose(-h[w, 2], mu * DRG_WET * DRG_L, rtol=0.02)
    # the seabed friction on the whole line opposes the motion and totals mu w_wet L as well
    np.testing.assert_allclose(-h[w, 5], mu * DRG_WET * DRG_L, rtol=0.02)


@pytest.mark.parametrize("friction, coeffs, mu", [
    ("isotropic", dict(mu=0.4, fric_damp=1e5, stat_dyn=1.0), 0.4),
    ("directional", dict(mu_kT=0.7, mu_kA=0.4, mc=1.0, cv=4.5e4), 0.7),
])
def test_transverse_drag_friction(friction, coeffs, mu):
    """Both ends pulled sideways (+y) together at 0.5 m/s: the total horizontal seabed force on the
    line is -mu_kT w_wet L (every node, ends included, lies at its equilibrium penetration).
    Directional: mu_kT = 0.7, mu_kA = 0.4.

    The friction bows the line; to keep the bow small the line is pre-strained 0.3 % (300 kN
    against 32 kN of friction), so the tangent turns by at most ~0.05 rad. For the directional
    model, which saturates the axial and transverse velocity parts separately, the axial part
    V sin(theta) < 2.5 cm/s then stays on the linear branch (below mc N/cv = 10 cm/s; it adds
    mu_kA cv V sin^2 theta ~ 0.3 % in y) while the transverse part is saturated; the transverse
    force is perpendicular to the tangent (cos theta ~ 1 - 1e-3). The transverse string mode
    excited by the ramp is undamped under Coulomb friction (velocity-independent), so the line
    keeps vibrating: checked at every output between 6 s and 10 s. Tolerance 2 % (brief);
    measured 3e-5 (isotropic) and 0.6 % (directional). Using mu_kA would be 43 % off."""
    s = drag_system(friction, coeffs, transverse=True, strain=3e-3)
    h = drag_history(s, np.array([0.0, 1.0, 0.0]))
    w = h[:, 0] >= 6.0
    np.testing.assert_allclose(-h[w, 6], mu * DRG_WET * DRG_L, rtol=0.02)
    # and nothing along the line on the whole (symmetric bow): |F_x| below 0.1 % of it
    assert np.max(np.abs(h[w, 5])) < 1e-3 * mu * DRG_WET * DRG_L


# ------------------------------------------------------------------------------------------------
# 3. and 4. symmetry and flat-grid equivalence

def chain_type(m):
    m.add_line_type("chain", d=0.1, w=100.0, EA=1.0e8, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.5)


FRICTION_ALL = dict(mu=0.5, fric_damp=1e4, stat_dyn=1.5, mu_kT=0.8, mu_kA=0.4, mc=1.5, cv=1e4)


def surge_run(m, amp_dir, t_end=10.0):
    """init (IC solved) and t_end seconds of a 5 s period sinusoidal motion of the coupled point
    along ``amp_dir``; returns (tensions after IC, tensions at t_end, system)."""
    s = System(m)
    x0 = s.deck_coupled_positions()
    s.init(x0)
    t = np.linspace(0.0, t_end, 101)
    X = x0[None, :] + np.outer(np.sin(2.0 * np.pi * t / 5.0), amp_dir)
    T0 = s.lines[0].segment_tensions()
    s.advance_to(t_end, Trajectory.from_samples(t, X, "cubic").as_motion())
    return T0, s.lines[0].segment_tensions(), s


def slope_model(sign, friction, contact):
    """Anchor on the seabed at (0, 0, -30); the seabed rises as z = -30 + 0.2 sign x (a 7-node grid
    from x = -50 to 250, mirrored for sign = -1); fairlead at (80 sign, 0, -5). L = 84.5 m against an
    84.2 m chord: the lower 40 % of the line lies on the slope, the rest hangs. The IC is solved to
    threshIC = 1e-6 (see the test)."""
    gx = np.linspace(-50.0, 250.0, 7)
    x = -gx[::-1] if sign < 0 else gx
    bat = Bathymetry(x, [-50.0, 50.0], np.tile(-30.0 + 0.2 * sign * x, (2, 1)))
    env = Environment(g=G, rho=RHO, depth=40.0, kBot=1e5, cBot=1e4, bathymetry=bat, contact=contact,
                      friction=friction, **FRICTION_ALL)
    m = Model(env=env, options=Options(dtM=2e-3, tScheme="RK2", TmaxIC=200.0, threshIC=1e-6))
    chain_type(m)
    a = m.add_point("fixed", (0.0, 0.0, -30.0))
    f = m.add_point("coupled", (80.0 * sign, 0.0, -5.0))
    m.add_line("chain", a, f, L=84.5, N=20)
    return m


@pytest.mark.parametrize("friction, contact", [("isotropic", "normal"), ("directional", "normal"),
                                               ("stickslip", "normal"), ("isotropic", "vertical")])
def test_mirrored_slope_gives_same_tensions(friction, contact):
    """x -> -x maps the system onto itself (bathymetry mirrored, fairlead and its surge mirrored),
    so every tension must be the same. Floating point breaks the symmetry only by round-off: the
    mirrored grid interpolates with 1 - t instead of t. Tolerance 1e-8 of the largest tension
    (brief), after the IC and after 10 s of a 2 m surge (5 s period) with friction.

    The IC is solved to threshIC = 1e-6 rather than MoorDyn's 1e-3: the stationary solver's
    step-halving and stopping decisions are discontinuous, and when it stops while the state
    still moves, round-off differences between the two runs can grow to ~1e-5 (seen at the default
    threshold); converged further, both runs reach the same equilibrium (measured 5e-11 after IC,
    1e-12 after the dynamics)."""
    A0, A1, sa = surge_run(slope_model(1, friction, contact), [2.0, 0.0, 0.0])
    B0, B1, sb = surge_run(slope_model(-1, friction, contact), [-2.0, 0.0, 0.0])
    assert sa.ic_report["converged"]
    # part of the line lies on the slope (the test is about the seabed), part hangs
    ra = sa.lines[0].node_positions()
    gap = ra[:, 2] - sa.model.env.bathymetry.height(ra[:, 0], ra[:, 1])
    assert 4 <= np.sum(gap < 0.0) <= 16
    assert np.max(np.abs(A0 - B0)) <= 1e-8 * np.max(A0)
    assert np.max(np.abs(A1 - B1)) <= 1e-8 * np.max(A1)
    rb = sb.lines[0].node_positions()
    np.testing.assert_allclose(rb * [-1.0, 1.0, 1.0], ra, rtol=0, atol=1e-8)


FLAT_DEPTH = 30.0


def flat_model(bathymetry, friction):
    """Anchor on a flat seabed at 30 m, fairlead (80, 0, -5), L = 95 m: about half the line lies on
    the seabed."""
    env = Environment(g=G, rho=RHO, depth=FLAT_DEPTH, kBot=1e5, cBot=1e4, bathymetry=bathymetry,
                      friction=friction, **FRICTION_ALL)
    m = Model(env=env, options=Options(dtM=2e-3, tScheme="RK2", TmaxIC=300.0, threshIC=1e-5))
    chain_type(m)
    a = m.add_point("fixed", (0.0, 0.0, -FLAT_DEPTH))
    f = m.add_point("coupled", (80.0, 0.0, -5.0))
    m.add_line("chain", a, f, L=95.0, N=20)
    return m


@pytest.mark.parametrize("friction", ["isotropic", "directional", "stickslip"])
def test_flat_grid_file_equals_plain_depth(friction, tmp_path):
    """A 3x3 MoorDyn-C seafloor file with every height -30 (read by the package's reader, rows in
    shuffled order) must reproduce the plain-depth seabed: its bilinear height is -30 up to the
    round-off of the interpolation weights, and its normal is exactly vertical (zero height
    differences). Compared after IC and after 10 s of an oblique 3 m surge with friction, on the
    tensions and the node positions; tolerance 1e-9 relative (brief: round-off; measured 6e-11
    after IC, 9e-12 after the dynamics, 1.3e-12 m on the positions).
    As in the mirrored test the IC is converged beyond MoorDyn's threshold (threshIC = 1e-5, reached
    after ~150 s of pseudo time) so that the comparison does not depend on where the stationary
    solver happens to stop."""
    rows = [(x, y) for y in (-50.0, 0.0, 50.0) for x in (-50.0, 50.0, 150.0)]
    rows = rows[4:] + rows[:4]
    text = ("# flat seabed\n3 3\n-50 50 150\n-50 0 50\n"
            + "".join(f"{x:g} {y:g} {-FLAT_DEPTH:g}\n" for x, y in rows))
    path = tmp_path / "flat_grid.txt"
    path.write_text(text)
    grid = read_seafloor_grid(path)
    assert grid.z.shape == (3, 3) and np.all(grid.z == -FLAT_DEPTH)
    amp = [3.0, 0.9, 0.0]
    A0, A1, sa = surge_run(flat_model(None, friction), amp)
    B0, B1, sb = surge_run(flat_model(grid, friction), amp)
    assert sa.ic_report["converged"] and sb.ic_report["converged"]
    ra = sa.lines[0].node_positions()
    assert np.sum(ra[:, 2] < -FLAT_DEPTH) >= 6  # a good part of the line lies on the seabed
    np.testing.assert_allclose(B0, A0, rtol=1e-9, atol=1e-9 * np.max(A0))
    np.testing.assert_allclose(B1, A1, rtol=1e-9, atol=1e-9 * np.max(A1))
    np.testing.assert_allclose(sb.lines[0].node_positions(), ra, rtol=0, atol=1e-9 * 100.0)


# ------------------------------------------------------------------------------------------------
# 5. initial conditions on a bathymetry

def bumpy_grid():
    """A non-planar grid: 10 m cells, a general slope plus a deterministic bump pattern (every cell
    is a twisted bilinear patch)."""
    x = np.arange(-20.0, 121.0, 10.0)
    y = np.arange(-40.0, 41.0, 10.0)
    X, Y = np.meshgrid(x, y)
    Z = -40.0 + 0.15 * X + 0.05 * Y + 1.5 * np.sin(0.7 * X) * np.cos(0.5 * Y)
    return Bathymetry(x, y, Z)


def ic_cases():
    plane_up = Bathymetry([-50.0, 250.0], [-50.0, 50.0], np.tile(-30.0 + 0.2 * np.array([-50.0, 250.0]), (2, 1)))
    gx, gy = np.array([-50.0, 250.0]), np.array([-50.0, 50.0])
    oblique = Bathymetry(gx, gy, -30.0 + 0.15 * gx[None, :] + 0.1 * gy[:, None])
    bumpy = bumpy_grid()
    return {
        # anchor down-slope on the seabed, fairlead up-slope; 95 m of line over an 84 m chord
        "up-slope": (plane_up, (0.0, 0.0), (80.0, 0.0, -5.0), 95.0),
        # slope rising along x and y, line oblique to the fall line
        "oblique": (oblique, (0.0, 0.0), (70.0, 30.0, -5.0), 95.0),
        # non-planar grid, line crossing several twisted cells
        "bumpy": (bumpy, (0.0, 5.0), (90.0, -10.0, -5.0), 110.0),
    }


@pytest.mark.parametrize("case", ["up-slope", "oblique", "bumpy"])
def test_initial_catenary_respects_bathymetry(case):
    """TmaxIC = 0: the dynamics would start from the catenary profile (spec 6.2), which knows only a
    flat seabed at the anchor level. On a rising seabed that profile runs through the ground; the
    package must lift such nodes onto the local seabed. Checked: no node more than 1 mm below the
    bilinear height of the grid at its (x, y) (brief), computed with Bathymetry.height (numpy,
    independent of the kernel's interpolation), and the check is not vacuous: the flat-seabed
    profile would have put nodes metres below it, so at least 3 nodes must rest on the seabed
    (within 1 mm). Measured: lowest gap 0, 23-27 of the 31 nodes on the seabed."""
    bat, (xa, ya), fair, L = ic_cases()[case]
    za = float(bat.height(xa, ya))
    env = Environment(g=G, rho=RHO, depth=60.0, kBot=1e5, cBot=1e4, bathymetry=bat, mu=0.5)
    m = Model(env=env, options=Options(dtM=2e-3, TmaxIC=0.0))
    chain_type(m)
    a = m.add_point("fixed", (xa, ya, za))
    f = m.add_point("coupled", fair)
    m.add_line("chain", a, f, L=L, N=30)
    s = System(m)
    s.init()
    r = s.lines[0].node_positions()
    gap = r[:, 2] - bat.height(r[:, 0], r[:, 1])
    assert np.min(gap) >= -1e-3
    assert np.sum(np.abs(gap) <= 1e-3) >= 3


# ------------------------------------------------------------------------------------------------
# 6. stick-slip: tension gradient and hysteresis

SS_D, SS_W, SS_EA, SS_L, SS_N = 0.1, 150.0, 1.0e7, 100.0, 40
SS_MU, SS_MC = 0.5, 1.5
SS_F = SS_MU * wet_weight(SS_W, SS_D)  # kinetic friction per unit length, 696 N/m
SS_U1, SS_DU, SS_TR, SS_P, SS_NC = 0.26, 0.1, 10.0, 20.0, 3


def ss_offset(t):
    """Fairlead offset: a smooth 10 s ramp to 0.26 m, then cycles between 0.26 m and 0.16 m
    (period 20 s). The line never goes slack: the lowest fairlead tension is ~8 kN."""
    t = np.asarray(t, dtype=float)
    x = np.clip(t / SS_TR, 0.0, 1.0)
    ramp = SS_U1 * x**3 * (10.0 - 15.0 * x + 6.0 * x * x)
    return ramp - np.where(t > SS_TR, 0.5 * SS_DU * (1.0 - np.cos(2.0 * np.pi * (t - SS_TR) / SS_P)), 0.0)


def ss_run(friction):
    """A 100 m rope-like line (EA = 1e7 N, w = 150 kg/m, 40 segments) lying straight on a flat
    seabed between an anchor and a coupled end at the seabed level, IC solved (friction is off in
    the IC, so it starts with a uniform small tension), then pulled axially by ``ss_offset``.

    The rope is soft so that the motion reaches far into the line: the first pull to 0.26 m
    touches s = sqrt(2 EA u/f) = 86 m, the 0.1 m cycles reverse the friction over
    a = sqrt(EA D/f) = 38 m. kBot = 1e6 (1.4 cm penetration), kShear = 1e7: the friction springs
    stretch 0.7 mm at the kinetic limit, small against the 0.1 m motion; cBot = 5e4 damps both.
    The motion is quasi-static (axial wave transit 0.4 s against a 20 s period).
    Returns (t, offset, end-B segment tension, all segment tensions) sampled every 0.1 s."""
    env = Environment(g=G, rho=RHO, depth=30.0, kBot=1e6, cBot=5e4, friction=friction, mu=SS_MU, stat_dyn=SS_MC,
                      kShear=1e7)
    m = Model(env=env, options=Options(dtM=2e-3, tScheme="RK2"))
    m.add_line_type("rope", d=SS_D, w=SS_W, EA=SS_EA, BA=-0.5)
    a = m.add_point("fixed", (0.0, 0.0, -30.0))
    f = m.add_point("coupled", (SS_L, 0.0, -30.0))
    m.add_line("rope", a, f, L=SS_L, N=SS_N)
    s = System(m)
    x0 = s.deck_coupled_positions()
    s.init(x0)
    t_end = SS_TR + SS_NC * SS_P
    tk = np.arange(0.0, t_end + 1e-9, 0.1)
    motion = Trajectory.from_samples(tk, x0[None, :] + np.outer(ss_offset(tk), [1.0, 0.0, 0.0]), "cubic").as_motion()
    rec_t, rec_T = [], []
    for k in range(1, tk.size):
        s.advance_to(tk[k], motion)
        rec_t.append(s.t)
        rec_T.append(s.lines[0].segment_tensions())
    t = np.array(rec_t)
    T = np.array(rec_T)
    return t, ss_offset(t), T[:, -1], T


@pytest.fixture(scope="module")
def ss_results():
    return {fr: ss_run(fr) for fr in ("stickslip", "isotropic")}


def last_cycle(res):
    t, u, Tf, T = res
    w = t >= SS_TR + (SS_NC - 1) * SS_P - 1e-9
    return t[w], u[w], Tf[w], T[w]


def test_stick_slip_keeps_tension_gradient(ss_results):
    """Last of three cycles. At the largest pull, the line has just slid towards the fairlead over
    the touched length, so friction points away from the fairlead everywhere there and the tension
    must fall monotonically from the pulled end into the lying line, by f = mu w_wet per metre
    (the kinetic level; nodes that stopped may hold up to mc f). At the smallest pull the part
    near the fairlead has slid back: there the gradient is reversed (tension rises into the line).
    The saturated model instead creeps under the slightest force difference (mu cv v ~ 2 N per node
    at these speeds against mu N = 1.7 kN), so its tensions equalise along the line.

    Checked: at the largest pull, segment tensions strictly increasing towards the fairlead over
    the outer 3/4 of the line (the touched 86 m) and the mean gradient over the fairlead half within
    [0.9 f, mc f] (measured 1.03 f; the brief: of the order of mu W times the touched length); at
    the smallest pull, strictly decreasing towards the fairlead over the last 12 segments (30 m,
    inside the 38 m reversal zone); and the stick-slip spread over the fairlead half at least 10
    times the saturated one (measured 1300 times; the saturated spread is 0.1 % of its tension,
    checked below 0.5 %). Measured: monotonic over the whole line at the largest pull, reversed
    over the last 14 segments at the smallest."""
    l0 = SS_L / SS_N
    _, u, _, T = last_cycle(ss_results["stickslip"])
    Tmax_pull = T[np.argmax(u)]
    Tmin_pull = T[np.argmin(u)]
    assert np.all(np.diff(Tmax_pull[SS_N // 4:]) > 0.0)
    half = Tmax_pull[SS_N // 2:]
    grad = (half[-1] - half[0]) / ((half.size - 1) * l0)
    assert 0.9 * SS_F <= grad <= SS_MC * SS_F
    assert np.all(np.diff(Tmin_pull[-12:]) < 0.0)
    _, u_i, _, T_i = last_cycle(ss_results["isotropic"])
    Ti_max = T_i[np.argmax(u_i)]
    spread_iso = np.ptp(Ti_max[SS_N // 2:])
    assert spread_iso < 5e-3 * np.mean(Ti_max)
    assert half[-1] - half[0] > 10.0 * spread_iso


def loop_area(u, T):
    """Closed-loop integral of T du over one cycle (trapezoidal): the work done on the line by the
    pulled end, positive when energy is dissipated."""
    u = np.append(u, u[0])
    T = np.append(T, T[0])
    return float(np.sum(0.5 * (T[1:] + T[:-1]) * np.diff(u)))


def test_stick_slip_hysteresis_loop(ss_results):
    """Fairlead tension against fairlead offset over the last cycle. With Coulomb friction the loop
    encloses the energy dissipated by the sliding of the line (positive area); the ideal
    continuous rope with rigid-plastic friction f (Masing loop) gives a tension swing
    dT = sqrt(4 EA f D) and an area dT D/3 = 1759 J for D = 0.1 m. The lumped model reverses the
    friction node by node (about a segment lost at each end of the 38 m reversal zone, -2 l/a =
    -13 %) and the friction springs round the corners: measured 0.90 of the ideal value (0.87 with
    mc = 1, approaching 1 as N grows: 0.91 at N = 80). Tolerances: area between 0.75 and 1.05 of
    the ideal (what would fail: no sticking, a wrong friction level, springs too soft), and at least
    20 times the saturated model's area (measured ~360 times: it only creeps)."""
    _, u, Tf, _ = last_cycle(ss_results["stickslip"])
    area = loop_area(u, Tf)
    ideal = math.sqrt(4.0 * SS_EA * SS_F * SS_DU) * SS_DU / 3.0
    assert area > 0.0
    assert 0.75 * ideal <= area <= 1.05 * ideal
    _, u_i, Tf_i, _ = last_cycle(ss_results["isotropic"])
    area_iso = loop_area(u_i, Tf_i)
    assert area > 20.0 * abs(area_iso)


# ------------------------------------------------------------------------------------------------
# 7. contact direction and friction in the seabed plane

# one twisted bilinear cell: z(0,0) = -30, z(20,0) = -27, z(0,20) = -28, z(20,20) = -21
TW_GRID = Bathymetry([0.0, 20.0], [0.0, 20.0], [[-30.0, -27.0], [-28.0, -21.0]])
TW_KBOT, TW_CBOT, TW_D, TW_N, TW_L = 1.0e5, 1.0e4, 0.1, 4, 12.0


def grid_normal(bat, x, y, h=1e-4):
    """Unit normal (-dz/dx, -dz/dy, 1)/norm of the bilinear surface, by central differences of
    Bathymetry.height (exact for a bilinear patch up to round-off ~1e-11)."""
    zx = (bat.height(x + h, y) - bat.height(x - h, y)) / (2.0 * h)
    zy = (bat.height(x, y + h) - bat.height(x, y - h)) / (2.0 * h)
    n = np.array([-zx, -zy, 1.0])
    return n / np.linalg.norm(n)


def twisted_line(contact, friction="isotropic", mu=0.0):
    """A 4-segment line across the twisted cell, between two fixed points, with its nodes below
    the surface by different amounts (5 to 25 cm, so the line tangent is inclined to the seabed)."""
    coeffs = dict(mu=mu, mu_kT=1.5 * mu, mu_kA=mu, stat_dyn=1.0, mc=1.0, fric_damp=1e5, cv=1e5)
    env = Environment(g=G, rho=RHO, depth=40.0, kBot=TW_KBOT, cBot=TW_CBOT, bathymetry=TW_GRID, contact=contact,
                      friction=friction, **coeffs)
    m = Model(env=env, options=Options(dtM=1e-3))
    m.add_line_type("chain", d=TW_D, w=100.0, EA=1e8)
    xy = np.linspace([3.0, 5.0], [13.0, 11.6], TW_N + 1)
    pen = np.array([0.05, 0.2, 0.08, 0.25, 0.12])
    r = np.column_stack([xy, TW_GRID.height(xy[:, 0], xy[:, 1]) - pen])
    a = m.add_point("fixed", r[0])
    b = m.add_point("fixed", r[-1])
    m.add_line("chain", a, b, L=TW_L, N=TW_N)
    s = System(m)
    s.init(solve_ic=False)
    s.set_state(line_positions=[r])
    return s, r


def angle(a, b):
    return math.atan2(np.linalg.norm(np.cross(a, b)), float(np.dot(a, b)))


@pytest.mark.parametrize("contact", ["normal", "vertical"])
def test_contact_force_direction(contact):
    """Nodes at rest below a twisted bilinear cell, no friction. Slope-normal contact (spec 3.8.2):
    F = (z_b - z) n_z kBot d lam along the local grid normal n = (-dz/dx, -dz/dy, 1)/norm, where the
    gradient is that of the bilinear patch at the node (not of the cell's mean plane: the twist
    turns n by up to 6 deg across the cell). Vertical contact (MoorDyn-C, spec 3.8.1):
    F = (z_b - z) kBot d lam along z. Tolerances: direction within 1e-6 rad (brief), magnitude
    within 1e-9 relative (round-off). Measured 3e-11 rad and 5e-12 (the normal is 13-19 deg off
    the vertical here, so vertical contact in the normal mode, or the reverse, fails)."""
    s, r = twisted_line(contact)
    F = s.lines[0].node_seabed_forces()
    lam = np.full(TW_N + 1, TW_L / TW_N)
    lam[[0, -1]] *= 0.5
    normals = []
    for i in range(TW_N + 1):
        n = grid_normal(TW_GRID, r[i, 0], r[i, 1])
        normals.append(n)
        dz = float(TW_GRID.height(r[i, 0], r[i, 1])) - r[i, 2]
        if contact == "normal":
            assert angle(F[i], n) < 1e-6
            assert np.linalg.norm(F[i]) == pytest.approx(dz * n[2] * TW_KBOT * TW_D * lam[i], rel=1e-9)
        else:
            assert angle(F[i], [0.0, 0.0, 1.0]) < 1e-6
            assert F[i, 2] == pytest.approx(dz * TW_KBOT * TW_D * lam[i], rel=1e-9)
    # the cell is really twisted: the normals along the line differ by more than a degree
    assert angle(normals[0], normals[-1]) > math.radians(1.0)


@pytest.mark.parametrize("friction", ["isotropic", "directional", "stickslip"])
def test_friction_lies_in_seabed_plane(friction):
    """Interior nodes of the twisted-cell line sliding at 1 m/s in the local seabed plane (v . n = 0),
    with friction (cv = 1e5: the saturated models are on their kinetic level). Friction is a
    tangential contact force: whatever the model, the seabed force's component along the local
    normal must be the contact force alone, (z_b - z) n_z kBot d lam, and the rest must lie in the
    seabed plane. The line tangent is inclined to the seabed here (node penetrations 5-25 cm over
    3 m segments), as it is wherever a line lifts off, so a friction split along the unprojected
    3-D tangent leaks into the normal direction. Tolerance 1e-9 of the node's contact force
    (round-off; measured 1e-11 for isotropic and stick-slip, 6 % for directional), and the friction
    must be there (> 1 % of the contact force) so the check is not vacuous; the isotropic model's
    friction must be mu N exactly (1e-9; measured 4e-11)."""
    s, r = twisted_line("normal", friction=friction, mu=0.5)
    v = np.zeros_like(r)
    for i in range(1, TW_N):
        n = grid_normal(TW_GRID, r[i, 0], r[i, 1])
        d = np.array([0.8, 0.6, 0.0]) if i % 2 else np.array([0.2, -1.0, 0.0])
        d -= np.dot(d, n) * n
        v[i] = d / np.linalg.norm(d)
    s.set_state(line_velocities=[v])
    F = s.lines[0].node_seabed_forces()
    lam = TW_L / TW_N
    for i in range(1, TW_N):
        n = grid_normal(TW_GRID, r[i, 0], r[i, 1])
        fn = (float(TW_GRID.height(r[i, 0], r[i, 1])) - r[i, 2]) * n[2] * TW_KBOT * TW_D * lam
        ft = F[i] - np.dot(F[i], n) * n
        assert np.linalg.norm(ft) > 0.01 * fn
        assert np.dot(F[i], n) == pytest.approx(fn, rel=1e-9)
        if friction == "isotropic":
            assert np.linalg.norm(ft) == pytest.approx(0.5 * fn, rel=1e-9)


def test_set_state_restarts_stick_slip_springs_relaxed():
    """``System.set_state`` is documented for starting from another program's initial state; as
    with ``init`` ("friction springs start relaxed at the initial position of every node"), the
    stick-slip friction springs must then start relaxed at the new node positions. A line lying at
    rest on a flat seabed, its interior nodes moved 0.5 m sideways by set_state: at rest on a flat
    seabed every horizontal seabed force must vanish (tolerance 1e-9 of the node weight). A spring
    still anchored where init put the nodes pulls them back with the full static friction."""
    env = Environment(g=G, rho=RHO, depth=30.0, kBot=1e5, cBot=1e4, friction="stickslip", mu=0.5, stat_dyn=1.5)
    m = Model(env=env, options=Options(dtM=1e-3))
    m.add_line_type("chain", d=0.1, w=100.0, EA=1e8)
    a = m.add_point("fixed", (0.0, 0.0, -30.0))
    b = m.add_point("fixed", (40.0, 0.0, -30.0))
    m.add_line("chain", a, b, L=40.0, N=4)
    s = System(m)
    s.init(solve_ic=False)
    r = s.lines[0].node_positions()
    r[1:-1, 1] += 0.5
    r[1:-1, 2] = -30.0 - wet_weight(100.0, 0.1) / (1e5 * 0.1)  # equilibrium penetration
    s.set_state(line_positions=[r])
    F = s.lines[0].node_seabed_forces()
    weight = wet_weight(100.0, 0.1) * 10.0
    assert np.max(np.abs(F[1:-1, :2])) < 1e-9 * weight
