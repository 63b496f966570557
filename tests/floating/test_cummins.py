"""The Cummins equation in the time loop against closed forms, on a body whose radiation damping is
shaped as a real hull's and whose kernel is exactly three exponentials,
K33(t) = sum_k C_k exp(-L_k t) (tests/floating/conftest.py): the radiation memory is then exactly
three first-order states, so heave obeys a fifth-order linear ODE whose solution a general ODE
solver gives to 1e-10 (the reference), and its regular-wave response has the closed form
X / (-w^2 (M + A(w)) - i w B(w) + C) (Capytaine's convention).

The coefficients go the whole way a user's do: sampled on 400 frequencies, impulse response
computed from B(w), state-space fit, time loop. Tolerances: the impulse response from the sampled
band is within 0.12 % of the exact kernel and the fit within 0.1 % of it; those dominate RK4's
error at 0.01 s, so motions agree to a few 1e-4. The implicit scheme is second order and is checked
for its order and at 0.5 % with a step of 1/60 of the period.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import moorline
from moorline.model.water import Waves

from .conftest import A_INF, C33, MASS, X33, C, L, added_mass_33, damping_33, steady_amplitude, three_pole_model


def _heave_decay(scheme, dtM, z0=0.5, t_end=20.0, dt_out=0.25, **opts):
    s = moorline.System(three_pole_model(scheme, dtM, **opts))
    s.init()
    s.set_body_state(0, position=(0.0, 0.0, z0))
    t = np.arange(0.0, t_end + 1e-9, dt_out)
    z = [s.bodies[0].position()[2]]
    for k in range(1, t.size):
        s.step(None, None, t[k - 1], dt_out)
        z.append(s.bodies[0].position()[2])
    return t, np.array(z), s


def _reference(t, z0):
    M = MASS + A_INF
    lam = np.array(L)

    def f(_, u):
        z = u[2:]
        return [u[1], (-C33 * u[0] - np.dot(C, z)) / M, *(u[1] - lam * z)]

    sol = solve_ivp(f, (0.0, t[-1]), [z0, 0.0, 0.0, 0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-13, method="DOP853")
    return sol.y[0]


def test_state_space_fit_finds_the_three_poles():
    s = moorline.System(three_pole_model())
    fl = s.layout.fl
    assert fl.ss_i.tolist() == [2] and fl.ss_j.tolist() == [2]
    assert s.layout.n_radiation == 3
    poles = np.sort(np.linalg.eigvals(fl.ss_A[:3, :3]).real)
    assert poles == pytest.approx(-np.array(L[::-1]), rel=1e-2)


def test_heave_decay_matches_the_exact_solution():
    t, z, s = _heave_decay("RK4", 0.01)
    ref = _reference(t, 0.5)
    assert np.max(np.abs(z - ref)) < 2e-4 * 0.5
    # the body rests at z = 0 and its other DOFs stay at rest
    assert np.max(np.abs(s.bodies[0].pose()[[0, 1, 3, 4, 5]])) < 1e-12


def test_heave_decay_by_convolution_matches_the_exact_solution():
    """Direct convolution of the sampled kernel (dt 0.02 s over 40 s, trapezoidal): second order in
    the sampling interval; with the kernel's own 0.12 % error, under 5e-4 of the amplitude."""
    t, z, _ = _heave_decay("RK4", 0.01, radiation="convolution", irf_dt=0.02, irf_duration=40.0)
    assert np.max(np.abs(z - _reference(t, 0.5))) < 5e-4 * 0.5


def test_implicit_scheme_is_second_order_with_radiation_states():
    errs = []
    for dt in (0.04, 0.02):
        t, z, _ = _heave_decay("GenAlpha", dt, t_end=10.0)
        errs.append(np.max(np.abs(z - _reference(t, 0.5))))
    order = np.log2(errs[0] / errs[1])
    assert 1.8 < order < 2.3
    # generalized-alpha with rho_inf = 0 at w h = 0.05: a period error of about 5e-4 per period
    assert errs[1] < 0.03 * 0.5


@pytest.mark.parametrize("scheme, dtM, tol", [("RK4", 0.01, 2e-3), ("GenAlpha", 0.1, 5e-3)])
def test_regular_wave_response_matches_the_closed_form(scheme, dtM, tol):
    """Steady heave amplitude after 80 periods (the free transient decays with the small radiation
    damping at the natural frequency, zeta 0.003). RK4: within 0.2 % (the impulse response and its fit
    carry about 0.1 % of B near its peak); generalized-alpha at 1/60 of the period: 0.5 %."""
    T = 6.0
    w = 2 * np.pi / T
    a = 0.5
    m = three_pole_model(scheme, dtM)
    m.env.waves = Waves.regular(2 * a, T)
    s = moorline.System(m)
    s.init()
    t = np.arange(0.0, 80 * T + 1e-9, T / 40)
    z = [s.bodies[0].position()[2]]
    for k in range(1, t.size):
        s.step(None, None, t[k - 1], t[k] - t[k - 1])
        z.append(s.bodies[0].position()[2])
    got = steady_amplitude(t, np.array(z), w, 10)
    A = added_mass_33(w)
    B = damping_33(w)
    want = X33 * a / (-(w**2) * (MASS + A) - 1j * w * B + C33)
    assert abs(got - want) < tol * abs(want)


def test_excitation_phase_follows_the_body_position():
    """A body placed 20 m down-wave of the coefficients' origin sees the excitation delayed by
    k * 20 m: its steady response is the origin's times exp(i k 20) (Capytaine's exp(-i w t)).
    60 periods let the free transient (zeta 0.003) decay to 1e-5."""
    T = 6.0
    w = 2 * np.pi / T
    k = w * w / 9.80665 * 1.0  # deep water (500 m >> wavelength 56 m)
    out = []
    for x in (0.0, 20.0):
        m = three_pole_model("RK4", 0.01)
        m.bodies[0].r[0] = x
        m.hydro[0].reference_points = np.array([[x, 0.0, 0.0]])
        m.env.waves = Waves.regular(1.0, T)
        s = moorline.System(m)
        s.init()
        t = np.arange(0.0, 60 * T + 1e-9, T / 40)
        z = [s.bodies[0].position()[2]]
        for j in range(1, t.size):
            s.step(None, None, t[j - 1], t[j] - t[j - 1])
            z.append(s.bodies[0].position()[2])
        out.append(steady_amplitude(t, np.array(z), w, 8))
    ratio = out[1] / out[0]
    assert abs(ratio - np.exp(1j * k * 20.0)) < 1e-4


def test_energy_never_grows_without_waves():
    """Radiation is passive: the heave energy (M + A_inf) v^2/2 + C z^2/2 never exceeds its start
    (velocities by central differences at 0.05 s: 1e-6 is their relative error); radiation damping
    at the natural frequency (zeta 0.003) takes a quarter of it in 20 s."""
    t, z, _ = _heave_decay("RK4", 0.01, dt_out=0.05)
    v = np.gradient(z, t)
    E = 0.5 * (MASS + A_INF) * v**2 + 0.5 * C33 * z**2
    assert np.max(E[5:]) <= E[0] * (1.0 + 1e-6)
    assert E[-1] < 0.8 * E[0]


@pytest.mark.slow  # 110 s: the record's excitation is tabulated over its whole repeat period
def test_an_elevation_record_drives_the_body_like_the_regular_wave_it_records():
    """A user's elevation record (Waves.from_elevation: FFT components, tabulated excitation over
    the record's period) of a regular wave gives the regular wave's steady response within 1e-3
    (the record holds whole periods, so its spectrum is the one component plus round-off)."""
    T = 6.0
    w = 2 * np.pi / T
    a = 0.5
    t_rec = np.arange(0.0, 20 * T, T / 40)
    rec = Waves.from_elevation(t_rec, a * np.cos(w * t_rec), dt=T / 40)
    out = []
    for waves in (Waves.regular(2 * a, T), rec):
        m = three_pole_model("RK4", 0.01)
        m.env.waves = waves
        s = moorline.System(m)
        s.init()
        t = np.arange(0.0, 60 * T + 1e-9, T / 40)
        z = [s.bodies[0].position()[2]]
        for k in range(1, t.size):
            s.step(None, None, t[k - 1], t[k] - t[k - 1])
            z.append(s.bodies[0].position()[2])
        out.append(steady_amplitude(t, np.array(z), w, 8))
    assert abs(out[1] - out[0]) < 1e-3 * abs(out[0])
