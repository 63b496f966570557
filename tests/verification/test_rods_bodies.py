"""Verification of rods and 6-DOF bodies against closed-form results (spec sections 3.13-3.17).

1. a rod pinned at end A, in air: the rotational inertia about the pin is the exact solid-cylinder
   value m L^2/3 + m d^2/16 for any number of segments (spec 3.14.3); small-angle period against the
   compound pendulum 2 pi sqrt(I_A / (m g L/2)) and the exact (elliptic-integral) period; large
   amplitude period and conservation of mechanical energy with RK4; the same pendulum submerged
   (buoyancy and transverse added mass of the lumped nodes); a coupled-pinned body swinging about
   its pin (period, and the pin load returned to the caller equals F_g - m a_CG);
2. a free body in still water: initial acceleration g (rho V - m) / (m + rho V Ca) (and the
   anisotropic, rotated added-mass case), constant without drag; quadratic drag decay of the
   translation and of the rotation against the closed form v0 / (1 + v0 t rho CdA / (2 M));
   a floating vertical rod (spar): draft m / (rho A) and heave period with the end added mass;
3. a free body spinning at constant rate: R(t) = expm(S(omega) t) R0, R orthonormal, unit
   quaternion state, through pitch = 90 deg (the Euler-angle singularity);
4. points and rods fixed or pinned to a moving body follow it rigidly (positions and velocities);
5. a coupled body driven by a trajectory: the returned 6-DOF load equals the line end force minus
   the end mass times the attachment acceleration, taken about the reference point, computed here
   from the segment tensions; the same for a coupled rod and a coupled point; the coupled-DOF order
   and labels (bodies, rods, points; pinned bodies 3 DOF);
6. linear momentum of an isolated floating system (free body with a CG offset, rods and points
   on it, free points, a free zero-length rod, lines; no drag, no added mass, no seabed): P(t) =
   P(0) + t * net weight, up to the RK4 truncation error, which is shown to vanish as dt^4;
8. A/B reversal: a free rod defined from B to A (ends and line attachments swapped) moves the same
   (exactly for a heaving surface-piercing spar; a rotating rod is a known deviation, below).

Item 7 (zero-length rods in a lazy-wave cable) is in test_lazy_wave.py.

VELOCITY-DEPENDENT INERTIAL LOADS OF RODS. MoorDyn-C writes the equations of free and pinned rods
about end A, [a_A; alpha] = M6^-1 F6 (spec 3.14.4), without the centripetal force
-sum_i M_i omega x (omega x r_i) of their nodes about end A, its moment, and the gyroscopic moment
(source/Rod.cpp, doRHS: those lines are commented out "<<<TEMP<<<"). moorline includes them
(core/rigid.py, _rod_inertial): a spinning free rod then turns about its centre of mass, a conical
pendulum holds its cone, and the A/B reversal holds for a rotating rod (tests below; they failed
before the terms were added). Still a known deviation (strict xfail): a rod pinned to a body passes
the body no reaction to its own rotation (MoorDyn's treatment, spec 3.14.5).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.linalg import expm
from scipy.special import ellipk

from moorline.model import Environment, Model, Options, rotation_xyz
from moorline.motion import Trajectory
from moorline.system import System

RHO = 1025.0
G = 9.80665


def no_motion():
    """Compiled hold trajectory for a system without coupled DOFs."""
    return Trajectory.hold(np.zeros(0)).as_motion()


def skew(w):
    """S(w) a = w x a."""
    return np.array([[0.0, -w[2], w[1]], [w[2], 0.0, -w[0]], [-w[1], w[0], 0.0]])


def new_model(dtM, depth=300.0, **options):
    """Model with RK4 at a fixed dtM and no initial-condition solve unless asked for."""
    opts = {"TmaxIC": 0.0, **options}
    return Model(env=Environment(g=G, rho=RHO, depth=depth), options=Options(dtM=dtM, tScheme="RK4", **opts))


def start(model, x=None, xd=None):
    """System initialised at the deck pose (no IC solve: the tests set their own initial state)."""
    s = System(model)
    s.init(x, xd, solve_ic=False)
    return s


def down_crossings(t, x):
    """Times where x crosses zero going down, linearly interpolated between samples. Near a zero of
    an oscillation x'' ~ 0, so the interpolation error is third order in the sample interval."""
    i = np.where((x[:-1] > 0.0) & (x[1:] <= 0.0))[0]
    return t[i] + x[i] / (x[i] - x[i + 1]) * (t[i + 1] - t[i])


def sample(s, t_end, dt_out, probe, motion=None):
    """Advance ``s`` to ``t_end`` in steps ``dt_out``; return (t, [probe(s), ...])."""
    motion = no_motion() if motion is None else motion
    n = int(round(t_end / dt_out))
    ts, vals = [s.t], [probe(s)]
    for k in range(1, n + 1):
        s.advance_to(k * dt_out, motion)
        ts.append(s.t)
        vals.append(probe(s))
    return np.array(ts), np.array(vals)


def measured_period(t, x):
    """Mean interval between successive down-crossings of x (at least two full periods)."""
    tc = down_crossings(t, x)
    assert len(tc) >= 3, "the run must cover at least two periods"
    return float(np.mean(np.diff(tc)))


def elliptic_period(T_linear, theta0):
    """Exact period of a rigid pendulum of small-amplitude period T_linear at amplitude theta0:
    T = T_linear * (2/pi) K(k), k = sin(theta0/2) (scipy's ellipk takes m = k^2)."""
    return T_linear * 2.0 / math.pi * float(ellipk(math.sin(0.5 * theta0) ** 2))


# ------------------------------------------------------------------------------------------------
# 1. pinned rod pendulum (in air: above z = 0 a rod has no buoyancy, added mass or drag)

PEN_L = 2.0
PEN_D = 0.2
PEN_W = 30.0  # kg/m
PEN_M = PEN_W * PEN_L
PEN_IA = PEN_M * PEN_L**2 / 3.0 + PEN_M * PEN_D**2 / 16.0  # solid cylinder about a diameter of its end face
PEN_IAX = 0.5 * PEN_M * (0.5 * PEN_D) ** 2  # about its own axis
PEN_T0 = 2.0 * math.pi * math.sqrt(PEN_IA / (PEN_M * G * PEN_L / 2.0))  # 2.319 s


def pinned_rod(theta0, N, *, z_pin=10.0, dtM=2e-3, Ca=0.0, depth=50.0):
    """A rod pinned (to the ground) at end A, hanging at theta0 from the downward vertical in the
    x-z plane. No drag: Cd = CdEnd = 0."""
    m = new_model(dtM, depth=depth)
    m.add_rod_type("bar", d=PEN_D, w=PEN_W, Ca=Ca, CaEnd=0.5)
    A = np.array([0.0, 0.0, z_pin])
    m.add_rod("bar", "pinned", A, A + PEN_L * np.array([math.sin(theta0), 0.0, -math.cos(theta0)]), N=N)
    return start(m)


def swing_angle(s):
    q = s.rods[0].axis()
    return math.atan2(q[0], -q[2])


@pytest.mark.parametrize("N", [1, 3, 10])
def test_pinned_rod_inertia_about_end_a(N):
    """The 6x6 mass matrix about end A has the exact inertia of a solid cylinder: m L^2/3 + m d^2/16
    about any transverse axis and m d^2/8 about the rod axis, for any N (the lumped node masses give
    m L^2/3 + m L^2/(6 N^2); spec 3.14.3 corrects it), and the translational block is m I."""
    s = pinned_rod(0.3, N)
    M = s.rods[0].mass_matrix()
    q = s.rods[0].axis()
    t1 = np.cross(q, [0.0, 1.0, 0.0])
    t1 /= np.linalg.norm(t1)
    t2 = np.cross(q, t1)
    # the matrix is assembled from a handful of products: round-off only (1e-12 relative)
    assert t1 @ M[3:, 3:] @ t1 == pytest.approx(PEN_IA, rel=1e-12)
    assert t2 @ M[3:, 3:] @ t2 == pytest.approx(PEN_IA, rel=1e-12)
    assert q @ M[3:, 3:] @ q == pytest.approx(PEN_IAX, rel=1e-12)
    np.testing.assert_allclose(M[:3, :3], PEN_M * np.eye(3), rtol=0, atol=1e-12 * PEN_M)
    # coupling block: first moment of mass about A, m S(r_c) with r_c = L/2 q
    np.testing.assert_allclose(M[3:, :3], PEN_M * skew(0.5 * PEN_L * q), rtol=0, atol=1e-12 * PEN_M * PEN_L)


@pytest.mark.parametrize("N", [1, 10])
def test_pinned_rod_small_angle_period(N):
    """Released at 0.02 rad: the period is the compound pendulum's 2 pi sqrt(I_A / (m g L/2)).
    N = 1 (a single segment) works only thanks to the inertia correction of spec 3.14.3."""
    theta0 = 0.02
    s = pinned_rod(theta0, N)
    t, th = sample(s, 3.2 * PEN_T0, 0.01, swing_angle)
    T = measured_period(t, th)
    # against the exact period at this amplitude: RK4 with dtM = 2 ms (omega dtM = 0.005) is exact to
    # ~1e-10; the zero-crossing interpolation over 10 ms samples is good to ~3e-8 (measured):
    # 1e-6 relative. A wrong inertia term (m d^2/16 is 1.9e-3 of I_A) moves T by ~1e-3.
    assert T == pytest.approx(elliptic_period(PEN_T0, theta0), rel=1e-6)
    # the linear-theory formula itself: the finite amplitude adds theta0^2/16 = 2.5e-5
    assert T == pytest.approx(PEN_T0, rel=5e-5)
    # the swing stays in its plane
    assert abs(s.rods[0].axis()[1]) < 1e-14
    np.testing.assert_allclose(s.rods[0].angular_velocity()[[0, 2]], 0.0, atol=1e-14)


def test_pinned_rod_large_angle_period_and_energy():
    """Released at 2 rad (115 deg): period against T0 (2/pi) K(sin(theta0/2)) (33% longer than T0),
    and the mechanical energy 1/2 omega^T I_A omega + m g z_c is constant (no damping in air)."""
    theta0 = 2.0
    s = pinned_rod(theta0, 10)
    rod = s.rods[0]

    def probe(s):
        om = rod.angular_velocity()
        ke = 0.5 * om @ rod.mass_matrix()[3:, 3:] @ om
        pe = PEN_M * G * rod.end_positions()[:, 2].mean()  # the centre of mass is mid-length
        return swing_angle(s), ke + pe

    T_exact = elliptic_period(PEN_T0, theta0)
    t, vals = sample(s, 3.2 * T_exact, 0.01, probe)
    T = measured_period(t, vals[:, 0])
    # same error budget as the small-angle case (measured 2e-8)
    assert T == pytest.approx(T_exact, rel=1e-6)
    # energy: RK4 at omega dtM <= 0.01 has a relative energy error ~1e-11 per 3 periods (measured
    # 1.2e-11 of the potential-energy swing); 1e-8 still catches any missing or extra load
    swing = PEN_M * G * PEN_L / 2.0 * (1.0 - math.cos(theta0))
    assert np.ptp(vals[:, 1]) < 1e-8 * swing


def test_pinned_rod_pendulum_in_water():
    """A rod of the same size, heavier (w = 80 kg/m; rho A = 32.2 kg/m), pinned and swinging fully
    submerged: restoring moment (m - rho V) g L/2 sin(theta), inertia I_A plus the transverse
    added mass of the lumped nodes, rho Ca A L^3/3 (1 + 1/(2 N^2)) (spec 3.14.2: the inertia
    correction of 3.14.3 applies to the rod's own mass only). The end added mass CaEnd acts along
    the axis and adds nothing to the swing."""
    N = 4
    theta0 = 0.05
    w = 80.0
    Ca = 0.9
    m = new_model(2e-3, depth=100.0)
    m.add_rod_type("bar", d=PEN_D, w=w, Ca=Ca, CaEnd=0.5)
    A = np.array([0.0, 0.0, -20.0])
    m.add_rod("bar", "pinned", A, A + PEN_L * np.array([math.sin(theta0), 0.0, -math.cos(theta0)]), N=N)
    s = start(m)
    area = math.pi * PEN_D**2 / 4.0
    mass = w * PEN_L
    I_tot = mass * PEN_L**2 / 3 + mass * PEN_D**2 / 16 + RHO * Ca * area * PEN_L**3 / 3 * (1 + 0.5 / N**2)
    T_lin = 2.0 * math.pi * math.sqrt(I_tot / ((mass - RHO * area * PEN_L) * G * PEN_L / 2.0))
    t, th = sample(s, 3.2 * T_lin, 0.01, swing_angle)
    # same error budget as in air (1e-6; measured 9e-9); without the 1/(2 N^2) lumping term T moves 4e-3
    assert measured_period(t, th) == pytest.approx(elliptic_period(T_lin, theta0), rel=1e-6)


def test_coupled_pinned_body_pendulum():
    """A coupled-pinned body held at its reference point, CG 1.5 m below it, no volume (no
    buoyancy), swinging about y: period from I_pin = I_y + m r^2 (elliptic, at 0.4 rad), and the
    3 forces returned to the caller are the load of the body on the pin, F_g - m a_CG."""
    mass, r_cg, Iy = 100.0, 1.5, 30.0
    m = new_model(2e-3, depth=100.0)
    m.add_body("coupledpinned", (0.0, 0.0, -10.0), m=mass, rCG=(0.0, 0.0, -r_cg), I=(20.0, Iy, 40.0))
    s = System(m)
    assert s.n_coupled_dof == 3 and s.coupled_dof_labels == ["B1_x", "B1_y", "B1_z"]
    s.init(solve_ic=False)
    theta0 = 0.4
    s.set_body_state(0, angles=(0.0, theta0, 0.0))
    b = s.bodies[0]
    force_err = []

    def probe(s):
        c = b.rotation_matrix() @ np.array([0.0, 0.0, -r_cg])
        om = b.angular_velocity()
        a_cg = np.cross(b.acceleration()[3:], c) + np.cross(om, np.cross(om, c))
        expect = np.array([0.0, 0.0, -mass * G]) - mass * a_cg
        force_err.append(np.max(np.abs(s.coupled_forces() - expect)) / (mass * G))
        return math.atan2(-c[0], -c[2])

    T_lin = 2.0 * math.pi * math.sqrt((Iy + mass * r_cg**2) / (mass * G * r_cg))
    t, th = sample(s, 3.2 * T_lin, 0.01, probe, Trajectory.hold([0.0, 0.0, -10.0]).as_motion())
    # period: same error budget as the rod pendulum (1e-6)
    assert measured_period(t, th) == pytest.approx(elliptic_period(T_lin, theta0), rel=1e-6)
    # pin load: the same quantities recombined, round-off only
    assert max(force_err) < 1e-12
    np.testing.assert_allclose(b.position(), [0.0, 0.0, -10.0], atol=0)


def test_pinned_rod_conical_pendulum():
    """A rod pinned at end A, inclined at alpha = 0.6 rad from the downward vertical and turning
    about the vertical at Omega^2 = m g (L/2) / ((I_A - I_ax) cos alpha): a steady motion of a rigid
    body (the gravity moment about the pin equals the rate of change of angular momentum,
    Omega z x L). The model integrates I alpha = M without the omega x (I omega) part, so the rod
    falls inward instead."""
    alpha = 0.6
    s = pinned_rod(alpha, 10)
    Om = math.sqrt(PEN_M * G * PEN_L / 2.0 / ((PEN_IA - PEN_IAX) * math.cos(alpha)))
    s.set_rod_state(0, angular_velocity=(0.0, 0.0, Om))
    t, inc = sample(s, 2.0 * math.pi / Om, 0.02, lambda s: s.rods[0].inclination()[0])
    # steady motion: the inclination from the upward vertical stays pi - alpha; RK4 error ~1e-10
    np.testing.assert_allclose(inc, math.pi - alpha, atol=1e-6)


# ------------------------------------------------------------------------------------------------
# 2. free body in still water


def free_body(*, m, V, Ca, CdA=(0.0,) * 6, I=(500.0, 500.0, 500.0), angles=(0.0, 0.0, 0.0), dtM=0.01):
    model = new_model(dtM, depth=300.0)
    model.add_body("free", (0.0, 0.0, -100.0), angles, m=m, V=V, Ca=Ca, CdA=CdA, I=I)
    return start(model)


@pytest.mark.parametrize("angles", [(0.0, 0.0, 0.0), (20.0, 30.0, 0.0)], ids=["aligned", "rotated"])
def test_free_body_accelerates_with_added_mass(angles):
    """A buoyant body (rho V = 2050 kg > m = 1000 kg) released from rest, no drag. Aligned with
    the global axes: a_z = g (rho V - m) / (m + rho V Ca_z). Rotated with anisotropic Ca, the added
    mass rho V R diag(Ca) R^T couples the axes and the body rises along an oblique line:
    a = M^-1 (0, 0, g (rho V - m)), M = m I + rho V R diag(Ca) R^T. No moment acts (CG at the
    reference point, buoyancy at the CG): the acceleration is constant."""
    mass, V, Ca = 1000.0, 2.0, np.array([0.8, 0.8, 1.2])
    s = free_body(m=mass, V=V, Ca=Ca, angles=angles)
    R = rotation_xyz(np.radians(angles))
    a = np.linalg.solve(mass * np.eye(3) + RHO * V * R @ np.diag(Ca) @ R.T, [0.0, 0.0, G * (RHO * V - mass)])
    if angles == (0.0, 0.0, 0.0):
        assert a[2] == pytest.approx(G * (RHO * V - mass) / (mass + RHO * V * Ca[2]), rel=1e-14)
    b = s.bodies[0]
    # at t = 0: one 6x6 solve, round-off only
    np.testing.assert_allclose(b.acceleration(), np.r_[a, 0.0, 0.0, 0.0], rtol=0, atol=1e-12 * np.linalg.norm(a))
    T = 3.0
    s.advance_to(T, no_motion())
    # RK4 integrates a constant acceleration exactly: round-off of 300 steps (measured 1e-14 m)
    np.testing.assert_allclose(b.position(), [0.0, 0.0, -100.0] + 0.5 * a * T**2, rtol=0, atol=1e-10)
    np.testing.assert_allclose(b.velocity(), a * T, rtol=0, atol=1e-10)
    np.testing.assert_allclose(b.rotation_matrix(), R, rtol=0, atol=1e-14)


def test_free_body_translational_drag_decay():
    """Neutrally buoyant body (m = rho V) with isotropic CdA = 3 m^2 and Ca = 0.8, rotated, moving
    obliquely at 2 m/s: M dv/dt = -1/2 rho CdA |v| v keeps the direction, and
    |v|(t) = v0 / (1 + v0 t k), s(t) = ln(1 + v0 k t) / k, k = rho CdA / (2 M), M = m (1 + Ca)."""
    V, Ca, CdA = 2.0, 0.8, 3.0
    mass = RHO * V
    s = free_body(m=mass, V=V, Ca=(Ca,) * 3, CdA=(CdA,) * 3 + (0.0,) * 3, angles=(15.0, -25.0, 40.0))
    e = np.array([1.0, 2.0, -0.5]) / np.linalg.norm([1.0, 2.0, -0.5])
    v0 = 2.0
    s.set_body_state(0, velocity=v0 * e)
    k = 0.5 * RHO * CdA / (mass + RHO * V * Ca)  # decay time 1 / (v0 k) = 1.2 s
    b = s.bodies[0]
    worst = 0.0
    for t in np.arange(0.5, 10.001, 0.5):
        s.advance_to(t, no_motion())
        v_exact = v0 / (1.0 + v0 * k * t)
        x_exact = math.log(1.0 + v0 * k * t) / k
        worst = max(worst, np.max(np.abs(b.velocity() - v_exact * e)) / v_exact,
                    np.max(np.abs(b.position() - ([0.0, 0.0, -100.0] + x_exact * e))) / x_exact)
    # RK4 with dtM = 0.01 s on a decay time of 1.2 s: relative error ~1e-10 (measured 1.8e-10);
    # 1e-7 is far inside the 0.5 % and still sees a CdA or added-mass error of 1e-7
    assert worst < 1e-7
    np.testing.assert_allclose(b.angular_velocity(), 0.0, atol=1e-14)


def test_free_body_rotational_drag_decay():
    """Isotropic inertia I = 500 kg m^2, rotational CdA_r = 2 (coefficient of omega |omega|, spec
    3.15), spinning at 1.5 rad/s about an oblique axis: omega(t) = omega0 / (1 + omega0 t k),
    k = rho CdA_r / (2 I), about a fixed axis."""
    I0, CdA = 500.0, 2.0
    s = free_body(m=RHO * 2.0, V=2.0, Ca=(1.0,) * 3, CdA=(0.0,) * 3 + (CdA,) * 3, I=(I0,) * 3,
                  angles=(30.0, 10.0, -20.0), dtM=0.005)
    e = np.array([-0.3, 0.5, 0.8]) / np.linalg.norm([-0.3, 0.5, 0.8])
    w0 = 1.5
    s.set_body_state(0, angular_velocity=w0 * e)
    k = 0.5 * RHO * CdA / I0  # decay time 1 / (w0 k) = 0.33 s
    worst = 0.0
    for t in np.arange(0.25, 5.001, 0.25):
        s.advance_to(t, no_motion())
        w_exact = w0 / (1.0 + w0 * k * t)
        worst = max(worst, np.max(np.abs(s.bodies[0].angular_velocity() - w_exact * e)) / w_exact)
    # RK4 with dtM = 5 ms on a decay time of 0.33 s: ~1e-8 relative (first-step error dominates)
    assert worst < 1e-6


def test_floating_spar_draft_and_heave_period():
    """A free vertical rod piercing the surface (end A at the bottom) floats at draft m / (rho A):
    its buoyancy is the pressure on the submerged end (spec 3.14.2; the side buoyancy of a vertical
    rod is zero). Released 0.5 m too deep it heaves about that draft with
    T = 2 pi sqrt((m + rho CaEnd V_half-sphere) / (rho g A)) (end added mass at the wet end only)."""
    L, d, CaEnd = 20.0, 1.0, 0.7
    area = math.pi * d**2 / 4.0
    w = 0.6 * RHO * area
    draft = w * L / (RHO * area)  # 12 m
    m = new_model(0.01, depth=300.0)
    m.add_rod_type("spar", d=d, w=w, Ca=1.0, CaEnd=CaEnd)
    z0 = -draft - 0.5
    m.add_rod("spar", "free", (0.0, 0.0, z0), (0.0, 0.0, z0 + L), N=10)
    s = start(m)
    Vh = 2.0 / 3.0 * math.pi * (0.5 * d) ** 3
    T = 2.0 * math.pi * math.sqrt((w * L + RHO * CaEnd * Vh) / (RHO * G * area))  # 7.02 s
    t, z = sample(s, 3.2 * T, 0.02, lambda s: s.rods[0].end_positions()[0, 2] + draft)
    # a linear oscillator: same period error budget as the pendulums (1e-6)
    assert measured_period(t, z) == pytest.approx(T, rel=1e-6)
    # about the draft, with the released amplitude (no damping: CdEnd = 0)
    # (samples every 20 ms catch a peak within A (omega dt / 2)^2 / 2 = 2e-5 m; measured 3e-6 m)
    assert 0.5 * (z.max() + z.min()) == pytest.approx(0.0, abs=1e-4)
    assert z.max() == pytest.approx(0.5, abs=1e-4)
    np.testing.assert_allclose(s.rods[0].axis(), [0.0, 0.0, 1.0], atol=0)


# ------------------------------------------------------------------------------------------------
# 3. constant rotation of a free body


@pytest.mark.parametrize(("angles", "omega"), [((10.0, 20.0, 30.0), (0.3, 1.1, -0.4)),
                                               ((0.0, 0.0, 0.0), (0.0, 1.0, 0.0))],
                         ids=["oblique", "pitch-through-90"])
def test_free_body_constant_rotation(angles, omega):
    """Neutrally buoyant body, CG at the reference point, isotropic inertia (no gyroscopic moment
    even physically), no drag, spinning at omega (global axes): omega stays constant and
    R(t) = expm(S(omega) t) R0. The orientation is a quaternion, so passing pitch = 90 deg (the
    second case: R = Ry(t)) is not special; only the reported Euler angles lose precision there."""
    s = free_body(m=2.0 * RHO, V=2.0, Ca=(0.5,) * 3, I=(400.0,) * 3, angles=angles)
    R0 = rotation_xyz(np.radians(angles))
    omega = np.array(omega)
    s.set_body_state(0, angular_velocity=omega)
    q_slice = s.layout.block_slices(int(s.layout.rigid.body_blk[0]))[0]
    b = s.bodies[0]
    times = sorted(set(np.round(np.arange(0.05, 4.0001, 0.05), 10)) | {0.5 * math.pi})
    err_R = err_orth = err_quat = err_euler = 0.0
    pitch_at_90 = None
    for t in times:
        s.advance_to(t, no_motion())
        R = b.rotation_matrix()
        err_R = max(err_R, np.max(np.abs(R - expm(skew(omega) * s.t) @ R0)))
        err_orth = max(err_orth, np.max(np.abs(R @ R.T - np.eye(3))))
        err_quat = max(err_quat, abs(np.linalg.norm(s.y[q_slice][3:]) - 1.0))
        err_euler = max(err_euler, np.max(np.abs(rotation_xyz(b.angles()) - R)))
        if t == 0.5 * math.pi:
            pitch_at_90 = b.angles()[1]
    # RK4 on the linear quaternion ODE, |omega| dtM <= 0.012: ~1e-12 per step, 4e-11 measured over
    # 400 steps; the 1e-8 leaves room for a coarser scheme but not for a wrong rate formula
    assert err_R < 1e-8
    # R is built from the normalised quaternion: orthonormal to round-off
    assert err_orth < 1e-12
    # RK4 does not preserve |Q| exactly; the defect per step is (|omega| dtM / 2)^6 / 144 ~ 1e-16
    # (1.3e-13 measured over 4 s): the state stays a unit quaternion without renormalisation
    assert err_quat < 1e-10
    # reported roll, pitch, yaw rebuild R. At pitch = 90 deg, pitch = asin(R[0, 2]) with R[0, 2]
    # within round-off of 1 and roll, yaw come from entries of size ~1e-8: 1e-6 there
    assert err_euler < 1e-6
    np.testing.assert_allclose(b.angular_velocity(), omega, rtol=0, atol=1e-14)
    np.testing.assert_allclose(b.position(), [0.0, 0.0, -100.0], rtol=0, atol=1e-12)
    if omega[0] == 0.0 and omega[2] == 0.0:
        assert pitch_at_90 == pytest.approx(0.5 * math.pi, abs=1e-6)


# ------------------------------------------------------------------------------------------------
# 4. points and rods on a moving body


def test_body_children_move_rigidly():
    """A free body (CG offset, anisotropic inertia and added mass, drag) tumbling on two lines,
    with two points, a body-fixed rod and a body-pinned rod on it; and a fixed body, rotated, with a
    point and a rod. Every child is at r_B + R r_rel with velocity v_B + omega x (R r_rel) at all
    times (the pinned rod's end A only)."""
    m = new_model(2e-3, depth=300.0)
    m.add_line_type("rope", d=0.05, w=3.0, EA=2e6, BA=-0.5, Cd=1.0, Ca=1.0)
    m.add_rod_type("arm", d=0.3, w=60.0, Cd=0.8, Ca=1.0, CdEnd=0.5, CaEnd=0.5)
    b = m.add_body("free", (0.0, 0.0, -50.0), (5.0, 10.0, 15.0), m=2000.0, V=1.5, rCG=(0.1, 0.0, -0.3),
                   I=(800.0, 900.0, 1000.0), Ca=(0.5, 0.6, 0.7), CdA=(2.0, 2.0, 3.0, 1.0, 1.0, 1.0))
    rel_p = [np.array([2.0, 0.5, -0.5]), np.array([-1.0, 1.5, 0.3])]
    pa = m.add_point("body", rel_p[0], body=b)
    m.add_point("body", rel_p[1], body=b, m=50.0, V=0.02)
    rod_a, rod_b = np.array([0.5, -1.0, -1.0]), np.array([0.5, -3.0, -2.5])
    _, rb = m.add_rod("arm", "body", rod_a, rod_b, N=5, body=b)
    pin_a = np.array([-0.5, -1.0, 1.0])
    m.add_rod("arm", "bodypinned", pin_a, (-2.5, -1.0, 3.5), N=4, body=b)
    fb = m.add_body("fixed", (10.0, -5.0, -120.0), (30.0, -20.0, 60.0))
    m.add_point("body", (1.0, 2.0, 3.0), body=fb)
    m.add_rod("arm", "body", (0.0, 0.0, 0.0), (0.0, 0.0, 2.0), N=2, body=fb)
    an1 = m.add_point("fixed", (30.0, 5.0, -200.0))
    an2 = m.add_point("fixed", (-25.0, -20.0, -200.0))
    m.add_line("rope", an1, pa, L=160.0, N=10)
    m.add_line("rope", an2, rb, L=160.0, N=10)
    s = start(m)
    s.set_body_state(0, velocity=(0.3, -0.2, 0.5), angular_velocity=(0.4, -0.3, 0.6))
    R_fixed = rotation_xyz(np.radians([30.0, -20.0, 60.0]))
    rod_rel = np.linspace(rod_a, rod_b, 6)
    err_r = err_v = 0.0
    for t in np.arange(0.1, 5.0001, 0.1):
        s.advance_to(t, no_motion())
        B = s.bodies[0]
        R, r, v, w = B.rotation_matrix(), B.position(), B.velocity(), B.angular_velocity()
        for i in range(2):
            g = R @ rel_p[i]
            err_r = max(err_r, np.max(np.abs(s.points[i].position() - (r + g))))
            err_v = max(err_v, np.max(np.abs(s.points[i].velocity() - (v + np.cross(w, g)))))
        g = rod_rel @ R.T
        err_r = max(err_r, np.max(np.abs(s.rods[0].node_positions() - (r + g))))
        err_v = max(err_v, np.max(np.abs(s.rods[0].node_velocities() - (v + np.cross(w, g)))))
        g = R @ pin_a
        err_r = max(err_r, np.max(np.abs(s.rods[1].end_positions()[0] - (r + g))))
        err_v = max(err_v, np.max(np.abs(s.rods[1].node_velocities()[0] - (v + np.cross(w, g)))))
        r_fixed = np.array([10.0, -5.0, -120.0])
        err_r = max(err_r, np.max(np.abs(s.points[2].position() - (r_fixed + R_fixed @ [1.0, 2.0, 3.0]))))
        err_r = max(err_r, np.max(np.abs(s.rods[2].end_positions()[1] - (r_fixed + R_fixed @ [0.0, 0.0, 2.0]))))
    # the same products evaluated twice: round-off of metre-sized numbers (measured 7e-15 m)
    assert err_r < 1e-10
    assert err_v < 1e-10
    # the body really moved and turned (the test is not vacuous)
    assert np.linalg.norm(s.bodies[0].position() - [0.0, 0.0, -50.0]) > 1.0
    assert np.max(np.abs(s.bodies[0].rotation_matrix() - rotation_xyz(np.radians([5.0, 10.0, 15.0])))) > 0.3


# ------------------------------------------------------------------------------------------------
# 5. coupled bodies, rods and points


def test_coupled_forces_and_dof_order():
    """Coupled body B1 (6 DOF) moving on a cubic trajectory in all six DOF with a line from a body
    point to an anchor; coupled-pinned body B2 (3 DOF); coupled rod R1 (6 DOF) held still with a
    line at its lower end; coupled point P2 (3 DOF) with a line. The lines have no drag or added
    mass, so each line end node carries its tension, its weight and its mass m_e = w l0/2 only.

    Independent expectation (spec 3.15, 3.17): the load on B1 is F - m_e a_P with F = -T_N +
    (0, 0, -(w - rho A) g l0/2), a_P = a + alpha x r + omega x (omega x r) the body point's
    acceleration (omega, alpha: the Euler-angle rates and their derivative, as MoorDyn), taken about
    the reference point; on R1 the rod's own weight and buoyancy plus the line end force, moment
    about end A; on P2 the line end force."""
    m = new_model(2e-3, depth=300.0)
    w, d = 40.0, 0.1
    m.add_line_type("rope", d=d, w=w, EA=5e7, BA=-0.8)
    wr, dr = 60.0, 0.3
    m.add_rod_type("arm", d=dr, w=wr)
    anchor1 = m.add_point("fixed", (100.0, 0.0, -250.0))
    p2 = m.add_point("coupled", (-80.0, 10.0, -5.0))
    anchor2 = m.add_point("fixed", (-100.0, 30.0, -250.0))
    rA, rB = np.array([0.0, -50.0, -5.0]), np.array([0.0, -50.0, -10.0])
    _, rod_b = m.add_rod("arm", "coupled", rA, rB, N=3)
    anchor3 = m.add_point("fixed", (0.0, -150.0, -250.0))
    b1 = m.add_body("coupled", (0.0, 0.0, -10.0), m=5e5, V=600.0)  # mass and volume unused (coupled)
    m.add_body("coupledpinned", (30.0, 30.0, -20.0), I=(10.0, 10.0, 10.0))
    rel = np.array([8.0, 2.0, -3.0])
    pb = m.add_point("body", rel, body=b1)
    L1, N1 = 290.0, 20
    m.add_line("rope", anchor1, pb, L=L1, N=N1)
    L2, N2 = 270.0, 15
    m.add_line("rope", anchor2, p2, L=L2, N=N2)
    L3, N3 = 280.0, 15
    m.add_line("rope", anchor3, rod_b, L=L3, N=N3)
    s = System(m)
    assert s.n_coupled_dof == 18
    assert s.coupled_dof_labels == (["B1_x", "B1_y", "B1_z", "B1_roll", "B1_pitch", "B1_yaw", "B2_x", "B2_y", "B2_z"]
                                    + ["R1_x", "R1_y", "R1_z", "R1_roll", "R1_pitch", "R1_yaw"]
                                    + ["P2_x", "P2_y", "P2_z"])
    with pytest.raises(ValueError, match="18 coupled DOF"):
        s.init(np.zeros(15))
    # one cubic piece on [0, 8] s: x = x0 + c1 t + c2 t^2 + c3 t^3 (held outside)
    x0 = np.r_[0.0, 0.0, -10.0, 0.0, 0.0, 0.0, 30.0, 30.0, -20.0, rA, 0.0, 0.0, 0.0, -80.0, 10.0, -5.0]
    c1, c2, c3 = np.zeros(18), np.zeros(18), np.zeros(18)
    c1[:6] = [0.5, -0.2, 0.3, 0.05, -0.04, 0.08]
    c2[:6] = [0.05, 0.02, -0.06, 0.01, 0.02, -0.015]
    c3[:6] = [-0.004, 0.003, 0.002, -0.001, 0.0008, 0.001]
    T = 8.0
    c = np.zeros((3, 18, 4))
    c[0, :, 0] = x0
    c[1, :, 0], c[1, :, 1], c[1, :, 2], c[1, :, 3] = x0, c1, c2, c3
    c[2, :, 0] = x0 + c1 * T + c2 * T**2 + c3 * T**3
    traj = Trajectory(np.array([-1e9, 0.0, T, 1e9]), c)
    s.init(traj.position(0.0), traj.velocity(0.0), solve_ic=False)
    motion = traj.as_motion()

    def end_force(li, L, N, wl, dl):
        """Net force on the end-B node of line li from its last segment tension and weight."""
        l0 = L / N
        return -s.lines[li].segment_tension_vectors()[-1] + [0.0, 0.0, -(wl - RHO * math.pi * dl**2 / 4) * G * l0 / 2]

    worst = 0.0
    for t in np.arange(0.5, 7.51, 0.5):
        s.advance_to(t, motion)
        f = s.coupled_forces()
        x = x0 + c1 * t + c2 * t**2 + c3 * t**3
        v = c1 + 2 * c2 * t + 3 * c3 * t**2
        a = 2 * c2 + 6 * c3 * t
        # body 1: the body follows its trajectory
        np.testing.assert_allclose(s.bodies[0].pose(), x[:6], rtol=0, atol=1e-12)
        r = rotation_xyz(x[3:6]) @ rel
        om, al = v[3:6], a[3:6]
        a_p = a[:3] + np.cross(al, r) + np.cross(om, np.cross(om, r))
        F = end_force(0, L1, N1, w, d) - w * L1 / N1 / 2 * a_p
        F6 = np.r_[F, np.cross(r, F)]
        worst = max(worst, np.max(np.abs(f[:6] - F6)) / np.max(np.abs(F6)))
        np.testing.assert_array_equal(s.bodies[0].force(), f[:6])
        # body 2: nothing attached, no mass: no load
        np.testing.assert_allclose(f[6:9], 0.0, atol=1e-12)
        # rod 1 (still): weight + buoyancy (end pressures) of the rod + line 3's end force at end B
        Fl = end_force(2, L3, N3, w, d)
        Fr = np.array([0.0, 0.0, -(wr - RHO * math.pi * dr**2 / 4) * 5.0 * G]) + Fl
        R6 = np.r_[Fr, np.cross(rB - rA, Fl)]
        worst = max(worst, np.max(np.abs(f[9:15] - R6)) / np.max(np.abs(R6)))
        np.testing.assert_array_equal(s.rods[0].force(), f[9:15])
        # point 2: line 2's end force
        Fp = end_force(1, L2, N2, w, d)
        worst = max(worst, np.max(np.abs(f[15:18] - Fp)) / np.max(np.abs(Fp)))
    # the same physics recombined in another order: round-off (measured 2.5e-16); the 1e-8
    assert worst < 1e-8
    # the body point is where the pose puts it
    np.testing.assert_allclose(s.points[pb.index].position(), x[:3] + r, rtol=0, atol=1e-12)


# ------------------------------------------------------------------------------------------------
# 6. linear momentum of an isolated system


def momentum_system(dtM, net_weight_factor):
    """A free body (CG offset, spinning) with two points and a body rod on it, two free points, a
    free zero-length rod joining two lines, four lines between them. ``net_weight_factor`` 1:
    everything neutrally buoyant; > 1: everything that much heavier than water. No drag and no
    added mass anywhere (both exchange momentum with the water), no seabed contact (500 m depth)."""
    f = net_weight_factor
    m = new_model(dtM, depth=500.0)
    d = 0.08
    m.add_line_type("rope", d=d, w=f * RHO * math.pi * d**2 / 4, EA=1e6, BA=-0.5)
    dr = 0.4
    m.add_rod_type("bar", d=dr, w=f * RHO * math.pi * dr**2 / 4)
    m.add_rod_type("joint", d=0.1, w=0.0)
    V = 2.0
    b = m.add_body("free", (0.0, 0.0, -100.0), (10.0, -5.0, 20.0), m=f * RHO * V, V=V, rCG=(0.2, -0.1, 0.3),
                   I=(500.0, 600.0, 700.0))
    pb1 = m.add_point("body", (1.5, 0.0, 0.0), body=b)
    pb2 = m.add_point("body", (-1.5, 0.5, 0.0), body=b)
    _, rb = m.add_rod("bar", "body", (0.0, 1.0, -0.5), (0.0, 3.0, -1.0), N=4, body=b)
    p1 = m.add_point("free", (20.0, 3.0, -95.0), m=f * 50.0, V=50.0 / RHO)
    p2 = m.add_point("free", (-15.0, -5.0, -110.0), m=f * 30.0, V=30.0 / RHO)
    ja, jb = m.add_rod("joint", "free", (-5.0, 20.0, -100.0), (-5.0, 20.0, -100.0), N=0)
    m.add_line("rope", pb1, p1, L=18.0, N=6)
    m.add_line("rope", p2, pb2, L=13.0, N=5)
    m.add_line("rope", rb, ja, L=18.0, N=6)
    m.add_line("rope", jb, p2, L=30.0, N=8)
    s = start(m)
    s.set_body_state(0, velocity=(0.5, -0.3, 0.2), angular_velocity=(0.2, 0.3, -0.4))
    return s


def linear_momentum(s):
    """Sum of m v over every lumped mass, from the model's masses and the reported velocities:
    line nodes (w l0, halved at the ends), free points, rod nodes (w dL), the body (m v_CG)."""
    m, lay = s.model, s.layout
    P = np.zeros(3)
    for li, ln in enumerate(m.lines):
        mm = np.full(ln.N + 1, m.line_types[ln.line_type].w * lay.line_L[li] / ln.N)
        mm[[0, -1]] *= 0.5
        P += mm @ s.lines[li].node_velocities()
    for i, p in enumerate(m.points):
        if p.kind.name == "FREE":
            P += p.m * s.points[i].velocity()
    for k, rod in enumerate(m.rods):
        if rod.N > 0:
            mm = np.full(rod.N + 1, m.rod_types[rod.rod_type].w * rod.length / rod.N)
            mm[[0, -1]] *= 0.5
            P += mm @ s.rods[k].node_velocities()
    for i, bd in enumerate(m.bodies):
        B = s.bodies[i]
        P += bd.m * (B.velocity() + np.cross(B.angular_velocity(), B.rotation_matrix() @ bd.rCG))
    return P


def net_external_force(s):
    """g * sum (rho V - m) over everything (all fully submerged)."""
    m, lay = s.model, s.layout
    F = sum((RHO * m.line_types[ln.line_type].A - m.line_types[ln.line_type].w) * lay.line_L[i]
            for i, ln in enumerate(m.lines))
    F += sum(RHO * p.V - p.m for p in m.points if p.kind.name == "FREE")
    for r in m.rods:
        rt = m.rod_types[r.rod_type]
        F += (RHO * math.pi * rt.d**2 / 4 - rt.w) * r.length
    F += sum(RHO * bd.V - bd.m for bd in m.bodies)
    return np.array([0.0, 0.0, G * F])


@pytest.mark.parametrize("factor", [1.0, 1.3], ids=["neutral", "heavy"])
def test_momentum_of_isolated_system(factor):
    """P(t) - P(0) - t F_net = 0 for the semi-discrete equations (Newton's third law between lines,
    points, the zero-length rod, the body and its children, with the centripetal loads of the body's
    children and CG offset). The body's momentum is not linear in the state (v_B + omega x R r_CG),
    so RK4 keeps it only to its truncation error: the defect must fall as dtM^4."""
    T = 3.0
    defects = []
    for dtM in (0.004, 0.002):
        s = momentum_system(dtM, factor)
        P0, F = linear_momentum(s), net_external_force(s)
        worst = 0.0
        for t in np.arange(0.25, T + 1e-9, 0.25):
            s.advance_to(t, no_motion())
            worst = max(worst, np.max(np.abs(linear_momentum(s) - P0 - F * s.t)))
        defects.append(worst / np.linalg.norm(P0))
    order = math.log2(defects[0] / defects[1])
    # measured: relative defects 7e-6 and 6e-7 (neutral), 1.6e-5 and 1.0e-6 (heavy), order 3.6 and
    # 4.0. A momentum leak in the model (a missing reaction, a wrong end mass) does not shrink with
    # dtM (order ~0 and a defect ~1e-2 or more, see the xfail tests below): require order > 3 and
    # a defect below 1e-5 at dtM = 2 ms
    assert order > 3.0, defects
    assert defects[1] < 1e-5, defects
    if factor != 1.0:
        assert abs(F[2]) > 1e3  # the net weight is really exercised


def test_free_rod_spinning_in_air_cg_is_ballistic():
    """A free rod in air, horizontal, spinning about the vertical through its centre at 2 rad/s:
    gravity acts at the centre of mass, so the CG falls as -g t^2/2 and the spin continues about it.
    The model solves M6 [a_A; alpha] = F6 about end A, which gives a_A = -g z and alpha = 0: end A
    flies straight, the rod sweeps around it, and after half a turn the CG is ~L away."""
    m = new_model(1e-3, depth=10.0)
    m.add_rod_type("bar", d=0.1, w=10.0)
    L, Om = 4.0, 2.0
    m.add_rod("bar", "free", (-0.5 * L, 0.0, 50.0), (0.5 * L, 0.0, 50.0), N=8)
    s = start(m)
    s.set_rod_state(0, velocity=(0.0, -Om * 0.5 * L, 0.0), angular_velocity=(0.0, 0.0, Om))
    t = math.pi / Om
    s.advance_to(t, no_motion())
    cg = s.rods[0].end_positions().mean(axis=0)  # uniform rod: the CG is mid-way between the ends
    # RK4 at dtM = 1 ms: ~1e-12 m; 1e-6 m
    np.testing.assert_allclose(cg, [0.0, 0.0, 50.0 - 0.5 * G * t**2], atol=1e-6)


@pytest.mark.xfail(strict=True, reason="KNOWN DEVIATION (MoorDyn-C, spec 3.14.5): a rod pinned to a body passes no "
                   "reaction to its own rotation (centripetal load taken with the body's omega, rod alpha with "
                   "a_A = 0), so a body carrying a spinning pinned rod is not pushed and momentum is not conserved")
def test_body_with_spinning_pinned_rod_conserves_momentum():
    """Neutral free body (V = 1 m^3) carrying a neutral 4 m rod pinned 0.5 m off its centre,
    spinning at 1 rad/s about z, in water without drag or added mass: no external force, so the
    total momentum (body + rod nodes) is constant. With a body-FIXED rod spinning with the body it
    is (checked first, round-off); with the pinned rod the body never moves and the momentum turns
    with the rod."""
    for kind in ("body", "bodypinned"):
        m = new_model(2e-3, depth=500.0)
        dr = 0.2
        m.add_rod_type("bar", d=dr, w=RHO * math.pi * dr**2 / 4)
        b = m.add_body("free", (0.0, 0.0, -100.0), m=RHO * 1.0, V=1.0, I=(300.0, 300.0, 300.0))
        m.add_rod("bar", kind, (0.5, 0.0, 0.0), (4.5, 0.0, 0.0), N=8, body=b)
        s = start(m)
        if kind == "body":
            s.set_body_state(0, angular_velocity=(0.0, 0.0, 1.0))
        else:
            s.set_rod_state(0, angular_velocity=(0.0, 0.0, 1.0))
        P0 = linear_momentum(s)
        s.advance_to(2.0, no_motion())
        # no linear invariant is broken by RK4 here beyond ~1e-10 (body-fixed case measured 1e-11)
        np.testing.assert_allclose(linear_momentum(s), P0, atol=1e-6 * np.linalg.norm(P0))


# ------------------------------------------------------------------------------------------------
# 8. A/B reversal of a free rod


def rod_with_lines(reverse, case):
    """A free rod with lines at both ends (``case`` '3d': submerged, inclined, two lines to anchors
    on either side; 'spar': vertical, piercing the surface, one line straight down from its lower
    end). ``reverse`` defines the rod from B to A with the line attachments swapped accordingly."""
    m = new_model(2e-3, depth=300.0)
    m.add_line_type("rope", d=0.08, w=15.0, EA=2e7, BA=-0.5, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.3)
    m.add_rod_type("spar", d=1.0, w=0.6 * RHO * math.pi / 4, Cd=0.8, Ca=1.0, CdEnd=0.6, CaEnd=0.7)
    if case == "spar":
        A, B = np.array([0.0, 0.0, -15.0]), np.array([0.0, 0.0, 5.0])
        a1, a2 = m.add_point("fixed", (0.0, 0.0, -250.0)), None
    else:
        A, B = np.array([0.0, 0.0, -60.0]), np.array([8.0, 3.0, -55.0])
        a1, a2 = m.add_point("fixed", (-150.0, 20.0, -250.0)), m.add_point("fixed", (160.0, -30.0, -250.0))
    if reverse:
        eb, ea = m.add_rod("spar", "free", B, A, N=8)
    else:
        ea, eb = m.add_rod("spar", "free", A, B, N=8)
    m.add_line("rope", a1, ea, L=240.0 if case == "spar" else 220.0, N=12)
    if a2 is not None:
        m.add_line("rope", eb, a2, L=240.0, N=12)
    s = start(m)
    # the same rigid translation in both (end-A velocity = velocity of every node)
    s.set_rod_state(0, velocity=(0.0, 0.0, 0.8) if case == "spar" else (0.3, -0.2, 0.5))
    return s


def reversal_difference(case, t_end):
    s1, s2 = rod_with_lines(False, case), rod_with_lines(True, case)
    worst = 0.0
    for t in np.arange(0.5, t_end + 1e-9, 0.5):
        s1.advance_to(t, no_motion())
        s2.advance_to(t, no_motion())
        worst = max(worst, np.max(np.abs(s1.rods[0].node_positions() - s2.rods[0].node_positions()[::-1])))
    return worst, s1


def test_rod_reversal_surface_piercing_spar():
    """A vertical spar piercing the surface, heaving on a line: defined bottom-up or top-down, the
    nodes move identically. This runs the partial-submergence branches with h0 > 0 and h0 < 0
    (spec 3.14.2), the end pressure, end drag and end added mass at either end."""
    worst, s = reversal_difference("spar", 10.0)
    # different state variables (the other end) but the same arithmetic on the axis: round-off
    # (measured 1.6e-13 m)
    assert worst < 1e-9
    assert abs(s.rods[0].end_positions()[0, 2] + 15.0) > 0.1  # it did heave


def test_rod_reversal_rotating_rod():
    """The general case: an inclined submerged rod between two lines, set moving; it pitches and
    yaws. Physically the two definitions are the same body; the model's differ by 0.4 m after
    20 s (measured), because each drops the centripetal loads about its own end A."""
    worst, _ = reversal_difference("3d", 20.0)
    # integrator differences only (different state variables): RK4 at 2 ms, ~1e-10 m
    assert worst < 1e-6
