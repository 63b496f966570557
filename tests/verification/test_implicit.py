"""Verification of the implicit generalized-alpha scheme and the Newton static solve (issue 6).

1. the banded LU with partial pivoting solves like a dense solver;
2. the dependency pattern the coloured Jacobian relies on contains every nonzero of the true
   Jacobian (dense finite differences of the derivative) on systems with bending stiffness,
   zero-length rods, free points and seabed contact, and on MoorDyn's body-and-rod deck;
3. Newton statics reaches the same equilibrium as MoorDyn's stationary solver, with a residual
   acceleration below its tolerance;
4. GenAlpha agrees with RK4 at small steps on a chain catenary in surge (with seabed contact), a
   chain dragged over a seabed with Coulomb friction, and a cable with bending stiffness clamped to
   a rod (1 % RMS of the fairlead tension, relative to its mean);
5. it stays stable and accurate at dt = 0.05 s and 0.1 s on the chain (no stability limit), and
   keeps the fairlead tension of an axially stiff lazy-wave cable at dt = 0.05 s and 0.1 s;
6. its observed order of accuracy is 2 (theory: second order for any rho_inf);
7. the implicit path's seabed contact law is C1 and MoorDyn's beyond its ramps (explicit schemes keep
   MoorDyn's law exactly), Newton statics starts seabed nodes at their resting penetration, and a
   chain whose touchdown nodes land and lift off costs few derivative evaluations per step.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from moorline.core.implicit import gen_alpha_parameters
from moorline.core.jacobian import band_lu, band_solve, dependency_graph
from moorline.core.rhs import rhs
from moorline.model import Environment, Model, Options
from moorline.motion import Trajectory
from moorline.system import System

SHARED = Path(os.environ.get("MOORLINE_SHARED", Path(__file__).resolve().parents[3] / "shared"))


def smooth_sine(x0, amp, period, ramp, direction):
    d = np.tile(np.asarray(direction, dtype=float), len(x0) // 3)

    def X(t):
        u = min(t / ramp, 1.0)
        return x0 + d * amp * u**3 * (6 * u * u - 15 * u + 10) * math.sin(2 * math.pi * t / period)

    return X


def fairlead_tension(model_fn, scheme, dtM, X_of, T, dt_out, **kw):
    """Fairlead tension history [N] sampled every dt_out, and the system."""
    s = System(model_fn(), scheme=scheme, dtM=dtM, **kw)
    x0 = s.deck_coupled_positions()
    X = X_of(x0)
    s.init(X(0.0), np.zeros_like(x0))
    m = Trajectory.from_function(X, T, min(dt_out, 0.1), "cubic").as_motion()
    out = []
    for k in range(1, int(round(T / dt_out)) + 1):
        s.advance_to(k * dt_out, m)
        out.append(np.linalg.norm(s.coupled_forces()[:3]))
    return np.array(out), s


def rms_rel(a, ref):
    return float(np.sqrt(np.mean((a - ref) ** 2)) / np.mean(ref))


# ------------------------------------------------------------------------------------------------
# 1. banded LU


@pytest.mark.parametrize("kl,ku", [(1, 1), (5, 5), (8, 3), (0, 2)])
def test_band_lu_matches_dense_solve(kl, ku):
    rng = np.random.default_rng(kl * 10 + ku)
    n = 40
    A = np.zeros((n, n))
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            A[i, j] = rng.normal()
    A[np.arange(n), np.arange(n)] *= 0.1  # small diagonal: partial pivoting must swap rows
    AB = np.zeros((2 * kl + ku + 1, n))
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            AB[kl + ku + i - j, j] = A[i, j]
    piv = np.zeros(n, dtype=np.int64)
    assert band_lu(AB, n, kl, ku, piv) == 0
    b = rng.normal(size=n)
    x = b.copy()
    band_solve(AB, n, kl, ku, piv, x)
    # conditioning of these matrices is ~1e3: 1e-10 leaves a wide margin over round-off
    assert np.allclose(x, np.linalg.solve(A, b), rtol=0, atol=1e-10 * np.abs(np.linalg.solve(A, b)).max())


# ------------------------------------------------------------------------------------------------
# systems


def chain_model(N=20, depth=200.0, friction=None):
    """One 850 m studless chain leg in 200 m of water (as examples/catenary_3line), fairlead coupled."""
    env = Environment(depth=depth, kBot=3e6, cBot=3e5)
    if friction:
        env.mu = friction
        env.fric_damp = 2e5
    m = Model(env=env, options=Options(TmaxIC=60.0))
    m.add_line_type("chain", d=0.216, w=286.56, EA=1.2298e9, BA=-0.8, Cd=1.33, Ca=1.0, CdAx=0.64, CaAx=0.5)
    a = m.add_point("fixed", (800.0, 0.0, -depth))
    f = m.add_point("coupled", (45.0, 0.0, -14.0))
    m.add_line("chain", a, f, L=850.0, N=N)
    return m


def cable_model(N=35):
    """examples/wec_cable: 70 m cable with EI clamped to a fixed rod, top end coupled."""
    m = Model(env=Environment(depth=50.0, kBot=1e5, cBot=1e3), options=Options(TmaxIC=200.0, ICgenDynamic=1))
    m.add_line_type("cable", d=0.04, w=2.75, EA=94.3e3, BA=-0.5, EI=350.0, Cd=1.2, Ca=1.0, CdAx=0.01)
    m.add_rod_type("connector", d=0.3, w=50.0, Cd=1.0, Ca=1.0)
    _, rb = m.add_rod("connector", "fixed", (42.0, 0.0, -48.0), (40.0, 0.0, -48.0), N=2)
    top = m.add_point("coupled", (0.0, 0.0, -2.0))
    m.add_line("cable", rb, top, L=70.0, N=N)
    return m


# ------------------------------------------------------------------------------------------------
# 2. sparsity pattern


def dense_pattern(s):
    """Nonzero pattern (units x units) of the dense finite-difference Jacobian of the
    accelerations with respect to positions and velocities."""
    lay = s.layout
    n3, n6 = lay.n_rows, lay.n_blocks
    uoff = lay.u_offset
    L, R, P, E, B, W, F, FW = s._kernel_arrays()
    y0 = s.y.copy()
    rng = np.random.default_rng(3)
    y0[uoff:] = 0.05 * rng.normal(size=y0.size - uoff)  # moving: drag and damping terms count
    f0 = np.zeros_like(y0)
    rhs(0.0, y0, f0, L, R, P, E, B, s._motion, W, F, FW, 1.0, -1)
    unit_of_q = [r for r in range(n3) for _ in range(3)] + [n3 + j for j in range(n6) for _ in range(7)]
    unit_of_u = [r for r in range(n3) for _ in range(3)] + [n3 + j for j in range(n6) for _ in range(6)]
    nu = n3 + n6
    pat = np.zeros((nu, nu), dtype=bool)
    f1 = np.zeros_like(y0)
    for col in range(y0.size):
        y = y0.copy()
        y[col] += 1e-6 * max(1.0, abs(y0[col]))
        if col < uoff and col >= 3 * n3 and (col - 3 * n3) % 7 >= 3:
            q = y[3 * n3 + 7 * ((col - 3 * n3) // 7) + 3:3 * n3 + 7 * ((col - 3 * n3) // 7) + 7]
            q /= np.linalg.norm(q)
        rhs(0.0, y, f1, L, R, P, E, B, s._motion, W, F, FW, 1.0, -1)
        changed = np.nonzero(f1[uoff:] != f0[uoff:])[0]
        cu = unit_of_q[col] if col < uoff else unit_of_u[col - uoff]
        for i in changed:
            pat[unit_of_u[i], cu] = True
    return pat


def check_pattern(s):
    pat = dense_pattern(s)
    adj = dependency_graph(s.layout)
    missing = [(i, j) for i, j in zip(*np.nonzero(pat), strict=True) if j not in adj[i]]
    assert not missing, f"Jacobian entries outside the colouring pattern: {missing[:10]}"


def test_pattern_chain_and_cable():
    for model in (chain_model(N=12), cable_model(N=12)):
        s = System(model, scheme="GenAlpha", dtM=0.05)
        s.init()
        check_pattern(s)


def test_pattern_lazy_wave_with_zero_length_rods():
    from tests.verification.test_lazy_wave import lazy_wave

    s0 = lazy_wave()
    s = System(s0.model, scheme="GenAlpha", dtM=0.05)
    s.y[:] = s0.y
    s.initialized = True
    check_pattern(s)


@pytest.mark.skipif(not (SHARED / "conformance").exists(), reason="../shared/conformance not present")
def test_pattern_bodies_and_rods():
    s = System.from_file(SHARED / "conformance/inputs/bodies_and_rods/BodiesAndRods.dat", scheme="GenAlpha",
                         dtM=0.05)
    s.init(solve_ic=False)  # the pattern is structural: any state will do
    check_pattern(s)


# ------------------------------------------------------------------------------------------------
# 3. Newton statics


def test_newton_statics_matches_stationary_solver():
    m = chain_model(N=20)
    m.options.threshIC = 1e-7
    m.options.TmaxIC = 300.0
    ref = System(m, scheme="RK2", dtM=0.004)
    ref.model.options.ICNewton = 0
    ref.init()
    m2 = chain_model(N=20)
    s = System(m2, scheme="GenAlpha", dtM=0.1)
    s.init()
    assert s.ic_report["method"].endswith("newton") and s.ic_report["converged"]
    assert s.ic_report["max_acceleration"] < 1e-5
    # the stationary solver stops at a relative tension change of threshIC per dtIC: 1e-4 of the
    # tension is well above what it leaves
    f_ref = ref.coupled_forces()
    f = s.coupled_forces()
    assert np.allclose(f, f_ref, rtol=0, atol=1e-4 * np.linalg.norm(f_ref))
    assert np.allclose(s.lines[0].node_positions(), ref.lines[0].node_positions(), atol=0.01)


def test_newton_statics_for_explicit_scheme_on_request():
    m = chain_model(N=20)
    m.options.ICNewton = 1
    s = System(m, scheme="RK2", dtM=0.004)
    s.init()
    assert s.ic_report["method"].endswith("newton") and s.ic_report["converged"]


# ------------------------------------------------------------------------------------------------
# 4-5. agreement with RK4


def test_chain_in_surge_agrees_with_rk4_and_is_stable_at_large_steps():
    X_of = lambda x0: smooth_sine(x0, 6.0, 20.0, 10.0, (1, 0, 0))  # noqa: E731
    T, dto = 40.0, 0.2
    ref, _ = fairlead_tension(chain_model, "RK4", 0.005, X_of, T, dto)
    keep = slice(int(10.0 / dto), None)
    errs = {}
    for dt in (0.05, 0.1, 0.2):
        ten, s = fairlead_tension(chain_model, "GenAlpha", dt, X_of, T, dto)
        errs[dt] = rms_rel(ten[keep], ref[keep])
        assert s.solver_stats["steps"] >= T / dt - 1  # the step was not cut to stay stable
    # 1 % of the mean tension at dt = 0.05 s (issue 6; measured 0.5 %). Larger steps stay stable
    # (measured 3.2 % at 0.1 s, nearly all of it in the 1-5 Hz response to the chain landing on the
    # seabed, which the reference resolves); 0.2 s is only required to run
    assert errs[0.05] < 0.01, errs
    assert errs[0.1] < 0.05, errs
    assert np.isfinite(errs[0.2]), errs


def test_friction_drag_agrees_with_rk4():
    X_of = lambda x0: smooth_sine(x0, 8.0, 30.0, 10.0, (1, 0, 0))  # noqa: E731
    T, dto = 40.0, 0.1
    model = lambda: chain_model(friction=0.8)  # noqa: E731
    ref, sr = fairlead_tension(model, "RK4", 0.005, X_of, T, dto)
    ten, s = fairlead_tension(model, "GenAlpha", 0.05, X_of, T, dto)
    assert np.any(sr.work.Fbed[:, 0] != 0.0)  # friction acts
    keep = slice(int(10.0 / dto), None)
    assert rms_rel(ten[keep], ref[keep]) < 0.01, s.solver_stats


def test_cable_with_bending_agrees_with_rk4():
    X_of = lambda x0: smooth_sine(x0, 1.5, 8.0, 8.0, (0, 0, 1))  # noqa: E731
    T, dto = 24.0, 0.05
    ref, _ = fairlead_tension(cable_model, "RK4", 0.002, X_of, T, dto)
    ten, s = fairlead_tension(cable_model, "GenAlpha", 0.005, X_of, T, dto)
    keep = slice(int(8.0 / dto), None)
    assert rms_rel(ten[keep], ref[keep]) < 0.01, s.solver_stats


def test_lazy_wave_cable_tension_at_large_steps():
    """The lazy-wave cable of test_lazy_wave (EA 2e7 N on 5 m segments: 1 mm of stretch is 4 kN,
    half the top tension) in 2 m, 8 s heave. Evaluating the derivative at the weighted state
    (1 - alpha_f) x1 + alpha_f x0 with the coupled end at X(t + (1 - alpha_f) h) put the top
    segment alpha_f h^2 X''/(2 (1 + rho)) off its length at every step end: a tension error of
    EA/l times that, 50 % RMS at 0.1 s and 12 % at 0.05 s, growing as h^2 whatever rho_inf. Weighting
    the derivatives at the two step ends instead removes it (measured 0.08 % at 0.1 s)."""
    from tests.verification.test_lazy_wave import lazy_wave_model

    model = lambda: lazy_wave_model(ICNewton=1)  # noqa: E731  (the same Newton equilibrium for both)
    X_of = lambda x0: smooth_sine(x0, 2.0, 8.0, 4.0, (0, 0, 1))  # noqa: E731
    T, dto = 10.0, 0.1
    ref, _ = fairlead_tension(model, "RK4", 0.004, X_of, T, dto)  # 4e-5 from RK4 at 1 ms
    keep = slice(int(4.0 / dto), None)
    errs = {}
    for dt in (0.05, 0.1):
        ten, s = fairlead_tension(model, "GenAlpha", dt, X_of, T, dto)
        errs[dt] = rms_rel(ten[keep], ref[keep])
        assert s.solver_stats["step"] == dt
    # measured 0.04 % and 0.08 % (before: 12 % and 50 %)
    assert errs[0.05] < 0.005 and errs[0.1] < 0.005, errs


# ------------------------------------------------------------------------------------------------
# 6. order of accuracy


def suspended_model():
    """A chain hanging between two coupled points, clear of the seabed (smooth dynamics)."""
    m = Model(env=Environment(depth=500.0))
    m.add_line_type("chain", d=0.1, w=60.0, EA=5e8, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.4, CaAx=0.5)
    a = m.add_point("coupled", (-100.0, 0.0, -50.0))
    b = m.add_point("coupled", (100.0, 0.0, -50.0))
    m.add_line("chain", a, b, L=230.0, N=10)
    return m


def test_observed_order_is_two():
    X_of = lambda x0: smooth_sine(x0, 5.0, 12.0, 4.0, (1, 0, 1))  # noqa: E731
    T = 8.0

    def final_positions(h):
        s = System(suspended_model(), scheme="GenAlpha", dtM=h)
        x0 = s.deck_coupled_positions()
        X = X_of(x0)
        s.init(X(0.0), np.zeros_like(x0))
        # one spline for every run; its knots (which steps never cross) at the largest step
        s.advance_to(T, Trajectory.from_function(X, T, 0.2, "cubic").as_motion())
        return s.lines[0].node_positions()

    ref = final_positions(0.2 / 128)
    errs = [np.abs(final_positions(h) - ref).max() for h in (0.1, 0.05, 0.025)]
    orders = [math.log2(errs[i] / errs[i + 1]) for i in range(2)]
    # second order: 2 within the pre-asymptotic scatter of a nonlinear system
    assert all(1.7 < p < 2.6 for p in orders), (errs, orders)


def test_gen_alpha_parameters():
    am, af, beta, gamma = gen_alpha_parameters(1.0)
    assert (am, af, beta, gamma) == (0.5, 0.5, 0.25, 0.5)  # trapezoidal rule
    am, af, beta, gamma = gen_alpha_parameters(0.0)
    assert gamma == pytest.approx(0.5 - am + af) and beta == pytest.approx(0.25 * (1 - am + af) ** 2)


# ------------------------------------------------------------------------------------------------
# 7. seabed contact of the implicit path and the cost of a step


def contact_env(scheme):
    return System(chain_model(N=10), scheme=scheme, dtM=0.1).layout.env


def normal_force(E, pen, vn, area=1.0):
    """Normal contact force of a node ``pen`` below a flat seabed at z = 0 moving at ``vn``."""
    from moorline.core.seabed import _contact

    return _contact(E, 0.0, 0.0, 0.0, 1.0, -pen, 0.0, 0.0, vn, area)[3]


def test_explicit_schemes_keep_moordyns_contact_law():
    E = contact_env("RK4")
    assert E.bed_ramp == 0.0 and E.bed_blend == 0.0
    for pen, vn in ((1e-4, -0.3), (0.01, 0.5), (0.2, 0.0)):
        assert normal_force(E, pen, vn) == pen * E.kBot - vn * E.cBot  # bit for bit


def test_implicit_contact_law_is_c1_and_matches_moordyn_past_the_ramps():
    from moorline.core.seabed import contact_slope, resting_penetration

    E = contact_env("GenAlpha")
    w, ramp = E.bed_blend, E.bed_ramp
    assert 0.0 < w < ramp  # one static penetration and ten of the 216 mm chain (about 4 and 40 mm)
    vn = -0.4  # landing
    # continuous and continuously differentiable: across each join (0, w, ramp) the force and its
    # slope on a grid of step dp change by O(dp) (a jump in the slope would change it by O(1))
    for p0 in (0.0, w, ramp):
        dp = 1e-7 * max(p0, w)
        f = [normal_force(E, p0 + k * dp, vn) for k in (-2, -1, 0, 1, 2)]
        slopes = np.diff(f) / dp
        scale = E.kBot + abs(vn) * E.cBot / ramp
        assert abs(f[3] - f[1]) < 3.0 * scale * dp, p0
        assert np.ptp(slopes) < 1e-3 * scale, (p0, slopes)
    # zero force and slope at first contact
    assert normal_force(E, 0.0, vn) == 0.0
    # past both ramps: MoorDyn's law with the spring shifted by w / 2
    pen = 2.0 * ramp
    assert normal_force(E, pen, vn) == pytest.approx((pen - 0.5 * w) * E.kBot - vn * E.cBot, rel=1e-12)
    # the analytic slopes the Jacobian update uses agree with finite differences of the force
    for pen in (0.3 * w, 0.7 * ramp, 3.0 * ramp):
        k, c, nx, ny, nz = contact_slope(E, 0.0, 0.0, 0.0, 1.0, -pen, 0.0, 0.0, vn, 1.0)
        dp = 1e-6 * w
        k_fd = (normal_force(E, pen + dp, vn) - normal_force(E, pen - dp, vn)) / (2 * dp)
        c_fd = -(normal_force(E, pen, vn + 1e-6) - normal_force(E, pen, vn - 1e-6)) / 2e-6
        assert (nx, ny, nz) == (0.0, 0.0, 1.0)
        assert k == pytest.approx(k_fd, rel=1e-5) and c == pytest.approx(c_fd, rel=1e-5)
    # the spring carries the static load at the resting penetration
    pen_s = 0.37 * w
    assert normal_force(E, resting_penetration(pen_s, w), 0.0) == pytest.approx(pen_s * E.kBot, rel=1e-9)


@pytest.mark.skipif(not (SHARED / "conformance").exists(), reason="../shared/conformance not present")
def test_newton_statics_from_the_catenary_start_needs_few_iterations():
    # nodes the catenary start lays on the seabed start at their resting penetration: without
    # that the first Newton step sank them by metres, and the OC3 chain needed 30 iterations,
    # implicit relaxation and 5 more (measured now: 4 iterations)
    s = System.from_file(SHARED / "conformance/inputs/catenary_3line/lines.txt", scheme="GenAlpha", dtM=0.1)
    s.init()
    assert s.ic_report["method"] == "newton" and s.ic_report["converged"], s.ic_report
    assert s.ic_report["iterations"] <= 8, s.ic_report


def test_chain_with_seabed_contact_costs_few_evaluations_per_step():
    # the touchdown nodes land and lift off every period; the Jacobian follows their contact
    # terms without derivative evaluations, and the modified Newton iterations stop on their
    # estimated error. Counted over the whole run, initial conditions included (this deck's
    # Newton statics still falls back to implicit relaxation, about 700 evaluations): 4.2
    # evaluations per step at dt 0.05 s (6.3 before; 6.3 against 13.3 at dt 0.1 s), 0.76 % RMS
    # against RK4 (0.56 % before, rho_inf 0.7 and MoorDyn's spring); the bound of 1 % is the
    # issue's accuracy target, as in the tests above
    X_of = lambda x0: smooth_sine(x0, 6.0, 20.0, 10.0, (1, 0, 0))  # noqa: E731
    T, dto = 40.0, 0.1
    ref, _ = fairlead_tension(chain_model, "RK4", 0.005, X_of, T, dto)
    ten, s = fairlead_tension(chain_model, "GenAlpha", 0.05, X_of, T, dto)
    st = s.solver_stats
    keep = slice(int(10.0 / dto), None)
    assert rms_rel(ten[keep], ref[keep]) < 0.01, st
    assert st["refactors"] > 0, st  # contact terms were followed
    assert st["evaluations"] / st["steps"] < 6.0, st
    assert st["jacobians"] < 0.15 * st["steps"], st


@pytest.mark.skipif(not (SHARED / "conformance").exists(), reason="../shared/conformance not present")
def test_static_jacobian_retry_with_another_diagonal_is_the_jacobian_rebuilt():
    # Newton statics retries a rejected iteration with a smaller pseudo step on the -df/dx it
    # kept, not a new finite-difference Jacobian: the factors, so the increments, must be those of
    # a Jacobian built with that diagonal, bit for bit. MoorDyn's BodiesAndRods has a free body,
    # so both the banded block and the Schur-complement border are exercised (at the deck's
    # start: the body has no equilibrium near it, and none is needed here).
    from moorline.core.jacobian import factor
    from moorline.core.statics import STATIC_FD_REL, StaticEval, solve_increment

    s = System.from_file(SHARED / "conformance/inputs/bodies_and_rods/BodiesAndRods.dat", scheme="GenAlpha")
    L, R, P, _, B, W, F, FW = s._kernel_arrays()
    E = s._kernel_env_ic()
    A, IW = s._implicit()
    assert A.band[2] > 0  # a border
    ev = StaticEval(s.y, A, IW, L, R, P, E, B, s._motion, W, F, FW)
    IW.y0[:s.y.size] = s.y
    d_small, d_big = 1.0, 1e3

    def increment(make):
        ev.residual()
        assert make() == 0
        solve_increment(A, IW)
        return IW.da.copy()

    def assembled_with(diag):
        # the Jacobian assembled with its diagonal in the columns, as before the retry kept -df/dx
        ev.fd_steps(IW, ev.n3, ev.n6, STATIC_FD_REL, 1.0)
        ev.clear(IW)
        for cu in range(A.col_ptr.size - 1):
            for k in range(6):
                if ev.state(A, IW, s.y, cu, k, ev.n3, ev.n6):
                    ev.rhs(0.0, s.y, IW.f1, *ev.nt, 1.0, np.int64(-1))
                    ev.columns(A, IW, ev.uoff, cu, k, diag)
        s.y[:] = IW.y0[:s.y.size]
        return factor(A, IW)

    rebuilt = increment(lambda: ev.jacobian(d_big))
    assert np.array_equal(increment(lambda: assembled_with(d_big)), rebuilt)
    ev.jacobian(d_small)
    retried = increment(lambda: ev.refactor(d_big))
    assert np.array_equal(rebuilt, retried)
    assert not np.array_equal(increment(lambda: ev.refactor(d_small)), retried)
    assert np.array_equal(increment(lambda: ev.refactor(d_big)), rebuilt)


def _unit_dependencies(s):
    """For each unit (3-DOF row or 6-DOF block) of a system at rest, the units whose positions
    its accelerations actually depend on: one derivative evaluation per unit and component,
    nonzero differences (the dense finite-difference Jacobian's pattern)."""
    from moorline.core.jacobian import displace
    from moorline.core.statics import StaticEval

    L, R, P, _, B, W, F, FW = s._kernel_arrays()
    A, IW = s._implicit()
    ev = StaticEval(s.y, A, IW, L, R, P, s._kernel_env_ic(), B, s._motion, W, F, FW)
    n3, n6 = s.layout.n_rows, s.layout.n_blocks
    udof = [3 * u for u in range(n3)] + [3 * n3 + 6 * j for j in range(n6)]
    ncomp = [3] * n3 + [6] * n6
    unit_of = np.repeat(np.arange(n3 + n6), ncomp)
    ev.residual()
    f0 = IW.f0[ev.uoff:ev.uoff + unit_of.size].copy()
    y0 = s.y.copy()
    IW.y0[:y0.size] = y0
    deps = [set() for _ in range(n3 + n6)]
    for u in range(n3 + n6):
        for k in range(ncomp[u]):
            dq = np.zeros(unit_of.size)
            dq[udof[u] + k] = 1e-6
            displace(IW.y0, dq, s.y, n3, n6, 1.0)
            ev.velocities(s.y, ev.R)
            ev.rhs(0.0, s.y, IW.f1, *ev.nt, 1.0, np.int64(-1))
            for i in np.nonzero(IW.f1[ev.uoff:ev.uoff + unit_of.size] - f0)[0]:
                deps[unit_of[i]].add(u)
            s.y[:] = y0
    return deps


@pytest.mark.parametrize("deck", ["lazy_wave", "complex_system"])
def test_jacobian_colouring_covers_every_dependency_across_rods(deck):
    # the coloured Jacobian is right only if no unit depends on two units of one colour: the
    # dependency graph must hold every dependency. Lines on a rod are linked as one line through
    # it, within their reach (2 with bending stiffness), not all the nodes near the rod with each
    # other, and a junction sees the units within that reach of it (reach + 1 units, the end's
    # own included): on the lazy-wave cable (two free zero-length joints) a Jacobian then costs
    # 15 derivative evaluations instead of 27; on MoorDyn's complex_system (a body, zero-length
    # rods, stiffener lines), 21 instead of 42
    from moorline.core.implicit import jacobian_evaluations
    from moorline.core.jacobian import dependency_graph

    path = {"lazy_wave": Path(__file__).parents[2] / "benchmarks/decks/lazy_wave_cable.dat",
            "complex_system": SHARED / "public_decks/FloatingArrayDesign+MoorDyn/tests/Mooring/local_euler/"
                                       "complex_system.txt"}[deck]
    if not path.exists():
        pytest.skip(f"{path} not present")
    s = System.from_file(path, scheme="GenAlpha")
    s.init()
    adj = dependency_graph(s.layout)
    deps = _unit_dependencies(s)
    assert sum(len(d) for d in deps) > len(deps)  # the check sees couplings at all
    missing = {v: sorted(deps[v] - adj[v]) for v in range(len(adj)) if deps[v] - adj[v]}
    assert not missing
    A, _ = s._implicit()
    evals = jacobian_evaluations(A.ncomp, A.col_ptr, A.col_units)
    assert evals == {"lazy_wave": 15, "complex_system": 21}[deck]
