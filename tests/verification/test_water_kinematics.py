"""Verification of the water-kinematics kernels (spec section 4).

1. dispersion relation: residual, deep- and shallow-water limits, MoorDyn's 7-digit estimate;
2. Airy kinematics against the textbook formulas (Dean & Dalrymple's cosh/sinh forms, written
   out here independently of the kernel) at several depths and k h, and the linear field
   equations by finite differences: continuity, the kinematic surface condition, linearised
   Euler (dU/dt = -grad p_dyn / rho) and dU/dt = time derivative of U;
3. Wheeler stretching: on the crest, in the trough, at the seabed and above the surface;
4. the precomputed grid against direct summation: equal at the grid's nodes and samples, within
   the linear-interpolation bound in between;
5. JONSWAP / Pierson-Moskowitz: normalisation, Hs and spectral shape recovered from a generated
   record, seeds, directional spreading;
6. currents (uniform, profile, time-varying, 4-D) against plain interpolation, still water,
   external kinematics, ramp, unified wave-current grid, input validation;
7. (oracle) MoorDyn-C itself, through the ``moordyn`` package, for WaveKin 2, 3, 7 and Currents
   1, 2, 5 on decks and files of our own.

Every tolerance is stated next to its assertion with the reason for it.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from moorline.core.waterkin import (
    CURRENT_NONE,
    WAVES_GRID,
    WAVES_NONE,
    build_water_kinematics,
    fluid_at,
    fluid_at_points,
    fluid_kinematics,
    still_water,
    wave_number,
    wave_number_newman,
    wave_numbers,
)
from moorline.io.waterkin import water_from_options
from moorline.model.types import Bathymetry, ModelError
from moorline.model.water import (
    Current,
    WaveGrid,
    Waves,
    cos2s_directions,
    jonswap_spectrum,
    pierson_moskowitz_spectrum,
)

G = 9.80665
RHO = 1025.0

#: kernel vs textbook Airy formulas, relative to each field's amplitude: both are double-precision
#: evaluations of the same expressions in different algebraic forms (round-off ~1e-15, amplified
#: by the phase k l ~ 1e2 of far points)
TOL_AIRY = 1e-10


def build(waves, current=None, depth=50.0, **kw):
    return build_water_kinematics(waves, current, depth=depth, g=G, rho=RHO, **kw)


# ------------------------------------------------------------------------------------------------
# 1. dispersion relation


def test_dispersion_residual_to_machine_precision():
    """|g k tanh(k h) - omega^2| / omega^2 <= 1e-12 from k h = 1e-4 to 1e4 (Newton to 2 ulp)."""
    worst = 0.0
    for h in (0.5, 5.0, 50.0, 500.0, 5000.0):
        for w in np.logspace(-3, 1.5, 80):
            k = wave_number(w, G, h)
            worst = max(worst, abs(G * k * math.tanh(k * h) - w * w) / (w * w))
    assert worst <= 1e-12


def test_dispersion_limits():
    # deep water: tanh(k h) = 1 in double precision once k h > 20, so k = omega^2 / g exactly
    assert wave_number(2.0, G, 1000.0) == 4.0 / G
    assert wave_number(0.5, G, 2000.0) == pytest.approx(0.25 / G, rel=1e-15)
    # shallow water: k h = sqrt(y) (1 + y/6 + 11 y^2/360 + O(y^3)), y = omega^2 h / g (series of
    # x tanh x = y); with y = 1e-7 the neglected term is ~1e-21
    for h, w in ((1.0, 1e-3), (10.0, 3e-4)):
        y = w * w * h / G
        assert wave_number(w, G, h) * h == pytest.approx(math.sqrt(y) * (1 + y / 6 + 11 * y * y / 360), rel=1e-14)
    # the long-wave speed: omega / k -> sqrt(g h) (1 - (k h)^2 / 6), here (k h)^2 / 6 = 3.4e-9
    assert 1e-4 / wave_number(1e-4, G, 20.0) == pytest.approx(math.sqrt(G * 20.0), rel=1e-8)
    assert wave_number(0.0, G, 30.0) == 0.0
    assert wave_number(-0.7, G, 30.0) == -wave_number(0.7, G, 30.0)


def test_newman_estimate_is_seven_digits():
    """MoorDyn's wave number (Newman's estimate) is within 2e-7 of the exact one, but not exact:
    the kernels default to the exact root."""
    w = np.logspace(-2, 1, 300)
    for h in (3.0, 30.0, 300.0):
        exact = wave_numbers(w, G, h)
        newman = np.array([wave_number_newman(v, G, h) for v in w])
        rel = np.abs(newman / exact - 1.0)
        assert rel.max() < 2e-7
        assert rel.max() > 1e-10


# ------------------------------------------------------------------------------------------------
# 2. Airy kinematics


def textbook_airy(a, omega, k, beta, phase, h, t, x, y, z):
    """Linear wave eta = a cos(k l - omega t - phase), l = x cos(beta) + y sin(beta), fields at
    height z (Dean & Dalrymple, Water Wave Mechanics, ch. 4): U, dU/dt, eta, p_dyn."""
    psi = k * (x * math.cos(beta) + y * math.sin(beta)) - omega * t - phase
    ch = math.cosh(k * (z + h)) / math.sinh(k * h)
    sh = math.sinh(k * (z + h)) / math.sinh(k * h)
    cc = math.cosh(k * (z + h)) / math.cosh(k * h)
    uh = a * omega * ch * math.cos(psi)
    ah = a * omega**2 * ch * math.sin(psi)
    return np.array([uh * math.cos(beta), uh * math.sin(beta), a * omega * sh * math.sin(psi),
                     ah * math.cos(beta), ah * math.sin(beta), -a * omega**2 * sh * math.cos(psi),
                     a * math.cos(psi), RHO * G * a * cc * math.cos(psi)])


def field_scales(a, omega, k, h):
    """Largest magnitude of each field over the water column (at the surface)."""
    ch0 = 1.0 / math.tanh(k * h)
    return np.array([a * omega * ch0] * 3 + [a * omega**2 * ch0] * 3 + [a, RHO * G * a])


@pytest.mark.parametrize("h, period", [(5.0, 20.0), (10.0, 12.0), (20.0, 8.0), (50.0, 6.0), (200.0, 10.0),
                                       (100.0, 3.0)])
def test_airy_against_textbook(h, period):
    """Regular wave, heading 35 deg, phase 40 deg; k h from 0.2 to 45; stretching off so that the
    fields are evaluated at z itself."""
    H, beta, phase = 1.6, 35.0, 40.0
    w = Waves.regular(H, period, heading=beta, phase=phase, stretching="none")
    K = build(w, depth=h)
    omega = 2 * math.pi / period
    k = wave_number(omega, G, h)
    scale = field_scales(H / 2, omega, k, h)
    rng = np.random.default_rng(7)
    for _ in range(40):
        x, y = rng.uniform(-300, 300, 2)
        z = -h * rng.uniform(0.0, 1.0)
        t = rng.uniform(0, 200)
        ref = textbook_airy(H / 2, omega, k, math.radians(beta), math.radians(phase), h, t, x, y, z)
        got = fluid_kinematics(K, t, [x, y, z])
        assert np.all(np.abs(got - ref) <= TOL_AIRY * scale), (k * h, got - ref)


def test_airy_deep_water_no_overflow():
    """k h = 2300: cosh(k h) overflows, the kernel's form does not; the fields are e^{k z} times
    their surface values (exact in double precision: e^{-2 k h} underflows)."""
    h, period, a = 5000.0, 3.0, 0.5
    K = build(Waves.regular(2 * a, period, stretching="none"), depth=h)
    omega = 2 * math.pi / period
    k = omega**2 / G
    assert K.c_k[0] == k
    for x, z, t in ((0.0, -1.0, 0.3), (7.0, -4.0, 1.1), (-3.0, -h, 2.0)):
        psi = k * x - omega * t
        e = math.exp(k * z)
        ref = [a * omega * e * math.cos(psi), 0.0, a * omega * e * math.sin(psi),
               a * omega**2 * e * math.sin(psi), 0.0, -a * omega**2 * e * math.cos(psi), a * math.cos(psi),
               RHO * G * a * e * math.cos(psi)]
        got = fluid_kinematics(K, t, [x, 0.0, z])
        assert np.all(np.isfinite(got))
        np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-300)


def irregular(**options):
    """Three components, different headings and phases, on a 0.1 rad/s ladder."""
    return Waves.from_components([0.4, 0.7, 1.1], [0.8, 0.3 - 0.4j, 0.15j], [10.0, -60.0, 150.0], **options)


def test_linear_field_equations_by_finite_differences():
    """The summed fields satisfy continuity, the kinematic surface condition u_z(0) = d zeta/dt,
    linearised Euler rho dU/dt = -grad p_dyn, and dU/dt is the time derivative of U.
    Central differences with step d: truncation ~ (k d)^2 / 6 = 2e-9 of the field scale;
    round-off ~ 1e-16 / (k d) = 1e-12; tolerance 1e-7 of the scale."""
    h = 40.0
    K = build(irregular(stretching="none"), depth=h)
    d, dt = 1e-4 / (1.1**2 / G), 1e-4  # 1e-4 / k of the shortest component [m], 1e-4 [s]
    tol_u, tol_a = 1e-7 * 2.0, 1e-7 * 3.0  # velocity ~ 1 m/s, acceleration ~ 1 m/s^2 scales

    def f(t, x, y, z):
        return fluid_kinematics(K, t, [x, y, z])

    rng = np.random.default_rng(3)
    for _ in range(25):
        x, y = rng.uniform(-100, 100, 2)
        z = -h * rng.uniform(0.02, 0.98)
        t = rng.uniform(0, 100)
        o = f(t, x, y, z)
        div = ((f(t, x + d, y, z)[0] - f(t, x - d, y, z)[0]) + (f(t, x, y + d, z)[1] - f(t, x, y - d, z)[1])
               + (f(t, x, y, z + d)[2] - f(t, x, y, z - d)[2])) / (2 * d)
        assert abs(div) < tol_u
        dudt = (f(t + dt, x, y, z)[0:3] - f(t - dt, x, y, z)[0:3]) / (2 * dt)
        np.testing.assert_allclose(o[3:6], dudt, rtol=0, atol=tol_a)
        grad_p = np.array([f(t, x + d, y, z)[7] - f(t, x - d, y, z)[7], f(t, x, y + d, z)[7] - f(t, x, y - d, z)[7],
                           f(t, x, y, z + d)[7] - f(t, x, y, z - d)[7]]) / (2 * d)
        np.testing.assert_allclose(o[3:6], -grad_p / RHO, rtol=0, atol=tol_a)
        # kinematic surface condition (linear: at z = 0)
        dzeta = (f(t + dt, x, y, 0.0)[6] - f(t - dt, x, y, 0.0)[6]) / (2 * dt)
        assert f(t, x, y, 0.0)[2] == pytest.approx(dzeta, abs=tol_u)


# ------------------------------------------------------------------------------------------------
# 3. Wheeler stretching


def test_wheeler_stretching_crest_trough_seabed_and_air():
    """z' = h (z + h) / (zeta + h) - h: a point on the crest or in the trough gets the z' = 0
    values, a point on the seabed the z' = -h values, a point above the surface the surface
    values (spec 4.2)."""
    h, H, T = 30.0, 4.0, 9.0
    K = build(Waves.regular(H, T), depth=h)  # Wheeler (default)
    K0 = build(Waves.regular(H, T, stretching="none"), depth=h)
    omega = 2 * math.pi / T
    for t in (0.0, T / 2):  # crest, then trough, at x = 0
        zeta = fluid_kinematics(K, t, [0, 0, 0])[6]
        assert zeta == pytest.approx(H / 2 if t == 0 else -H / 2, abs=1e-14)
        at_zero = fluid_kinematics(K0, t, [0, 0, 0.0])
        np.testing.assert_allclose(fluid_kinematics(K, t, [0, 0, zeta])[:6], at_zero[:6], rtol=0, atol=1e-14)
        np.testing.assert_allclose(fluid_kinematics(K, t, [0, 0, zeta + 3.0])[:6], at_zero[:6], rtol=0, atol=1e-14)
        np.testing.assert_allclose(fluid_kinematics(K, t, [0, 0, -h])[:6], fluid_kinematics(K0, t, [0, 0, -h])[:6],
                                   rtol=0, atol=1e-14)
        # mid-depth: the stretched height, not z
        z = -10.0
        zs = h * (z + h) / (zeta + h) - h
        np.testing.assert_allclose(fluid_kinematics(K, t, [0, 0, z])[:6], fluid_kinematics(K0, t, [0, 0, zs])[:6],
                                   rtol=1e-13, atol=1e-15)
        assert abs(fluid_kinematics(K, t, [0, 0, z])[0] - fluid_kinematics(K0, t, [0, 0, z])[0]) > 1e-3 * omega
    # without stretching, a point in the air above the still-water level gets the z = 0 values
    np.testing.assert_allclose(fluid_kinematics(K0, 0.0, [0, 0, 1.5]), fluid_kinematics(K0, 0.0, [0, 0, 0.0]))


def test_wheeler_stretching_on_a_bathymetry():
    """With a seabed grid the local seabed maps to z' = -h (MoorDyn-C): on a slope, a point on the
    seabed gets the same values as a point on a flat seabed at -h."""
    h = 30.0
    bathy = Bathymetry(x=[-100.0, 100.0], y=[0.0], z=[[-40.0, -20.0]])
    w = irregular()
    K = build(w, depth=h, bathymetry=bathy)
    Kf = build(w, depth=h)
    for x in (-60.0, 0.0, 35.0):
        zb = float(bathy.height(x, 0.0))
        np.testing.assert_allclose(fluid_kinematics(K, 4.2, [x, 0.0, zb])[:6],
                                   fluid_kinematics(Kf, 4.2, [x, 0, -h])[:6], rtol=1e-13, atol=1e-15)
    p = [-60.0, 0, -10.0]
    assert abs(fluid_kinematics(K, 4.2, p)[0] - fluid_kinematics(Kf, 4.2, p)[0]) > 1e-3


# ------------------------------------------------------------------------------------------------
# 4. grid against direct summation


def grid_and_sum(stretching, **grid):
    w_grid = irregular(evaluation="grid", stretching=stretching, grid=WaveGrid(**grid))
    w_sum = irregular(stretching=stretching)
    return build(w_grid, depth=40.0), build(w_sum, depth=40.0)


def test_grid_equals_sum_at_nodes():
    """At the grid's nodes and sample times the inverse FFT gives the Airy sum exactly (to
    round-off, 1e-12 of the field scales); with Wheeler stretching too, at points whose stretched
    height is a grid level."""
    xs, ys, zs = np.linspace(-50, 50, 6), np.array([-10.0, 5.0]), np.linspace(-40, 0, 5)
    for stretching in ("none", "wheeler"):
        Kg, Ks = grid_and_sum(stretching, x=xs, y=ys, z=zs, nt=126)
        assert Kg.wave_mode == WAVES_GRID and Kg.wg_kin.shape == (6, 2, 5, 126, 7)
        period = 2 * math.pi / 0.1
        assert Kg.wg_dt == pytest.approx(period / 126, rel=1e-14)
        worst = 0.0
        for n in (0, 17, 125):
            t = n * Kg.wg_dt
            for x in xs[::2]:
                for y in ys:
                    zeta = fluid_kinematics(Ks, t, [x, y, 0.0])[6]
                    for level in zs:
                        z = level if stretching == "none" else -40.0 + (level + 40.0) * (zeta + 40.0) / 40.0
                        g = fluid_kinematics(Kg, t, [x, y, z])
                        s = fluid_kinematics(Ks, t, [x, y, z])
                        worst = max(worst, np.max(np.abs(g - s) / np.array([1, 1, 1, 1, 1, 1, 1, RHO * G])))
        assert worst < 1e-12


def test_grid_interpolation_error_within_linear_bound():
    """Between nodes, multilinear interpolation errs by at most sum_i d_i^2 / 8 max|f_ii| (the
    second derivative along each axis); for an Airy field of amplitude F that is
    F (k^2 (dx^2 + dy^2 + dz^2) + omega^2 dt^2) / 8 (|Ch''| = k^2 Ch). The error is checked
    against the bound and halving every spacing must cut it about fourfold (second order)."""
    h, H, T = 40.0, 2.0, 8.0
    omega = 2 * math.pi / T
    k = wave_number(omega, G, h)
    ws = Waves.regular(H, T, heading=20.0, stretching="none")
    Ks = build(ws, depth=h)
    scale = field_scales(H / 2, omega, k, h)
    rng = np.random.default_rng(11)
    pts = np.c_[rng.uniform(-30, 30, 200), rng.uniform(-4, 4, 200), rng.uniform(-38, -1, 200)]
    times = rng.uniform(0, 3 * T, 200)
    errors = []
    for n in (8, 16):
        dx, dz = 60.0 / n, 40.0 / n
        grid = WaveGrid(x=np.linspace(-30, 30, n + 1), y=np.linspace(-4, 4, n // 4 + 1), z=np.linspace(-40, 0, n + 1),
                        nt=2 * n)
        Kg = build(Waves.regular(H, T, heading=20.0, stretching="none", evaluation="grid", grid=grid), depth=h)
        dy, dt = 8.0 / (n // 4), T / (2 * n)
        bound = scale * (k * k * (dx * dx + dy * dy + dz * dz) + omega * omega * dt * dt) / 8.0
        err = np.zeros(8)
        for p, t in zip(pts, times, strict=True):
            err = np.maximum(err, np.abs(fluid_kinematics(Kg, t, p) - fluid_kinematics(Ks, t, p)))
        assert np.all(err <= bound)
        errors.append(err / scale)
    ratio = errors[0] / errors[1]
    assert np.all((ratio > 3.0) & (ratio < 5.5)), ratio


def test_own_jonswap_grid_from_bounding_box():
    """A JONSWAP sea precomputed on axes built from a node bounding box (12 points per wave
    length of the wave below which 99 % of the variance lies): RMS error of zeta and u_x below
    2 % of their RMS values ((pi/12)^2 / 2 = 3.4 % for that wave, much less for the energetic
    longer ones)."""
    kw = dict(heading=30.0, seed=4, n_components=40)
    Ks = build(Waves.jonswap(3.0, 9.0, **kw), depth=60.0)
    Kg = build(Waves.jonswap(3.0, 9.0, evaluation="grid", grid=WaveGrid(margin=5.0), **kw), depth=60.0,
               bbox=[[-100, 0, -60], [0, 0, 0]])
    assert Kg.wave_mode == WAVES_GRID
    assert Kg.wg_x[0] == -105.0 and Kg.wg_x[-1] == 5.0 and Kg.wg_z[0] == -60.0 and Kg.wg_z[-1] == 0.0
    rng = np.random.default_rng(5)
    pts = np.c_[rng.uniform(-100, 0, 300), rng.uniform(-5, 5, 300), rng.uniform(-55, -2, 300)]
    t = rng.uniform(0, 500, 300)
    g = np.array([fluid_kinematics(Kg, ti, p) for ti, p in zip(t, pts, strict=True)])
    s = np.array([fluid_kinematics(Ks, ti, p) for ti, p in zip(t, pts, strict=True)])
    for f in (0, 6):
        assert np.sqrt(np.mean((g[:, f] - s[:, f]) ** 2)) < 0.02 * np.sqrt(np.mean(s[:, f] ** 2))


def test_grid_memory_guard():
    w = Waves.jonswap(3.0, 9.0, seed=1, evaluation="grid", grid=WaveGrid(points_per_wave=40))
    with pytest.raises(ValueError, match="GiB"):
        build(w, depth=60.0, bbox=[[-2000, -2000, -60], [2000, 2000, 0]])
    with pytest.raises(ValueError, match="bounding box"):
        build(w, depth=60.0)


# ------------------------------------------------------------------------------------------------
# 5. spectra


def test_spectrum_normalisation():
    """JONSWAP is scaled numerically so that int S d omega = Hs^2 / 16; gamma = 1 is the closed-form
    Pierson-Moskowitz spectrum 5/16 Hs^2 wp^4 w^-5 exp(-5/4 (wp/w)^4)."""
    Hs, Tp = 3.5, 7.5
    wp = 2 * math.pi / Tp
    w = np.linspace(1e-3, 60 * wp, 400001)
    for gamma in (1.0, 2.0, 3.3, 7.0):
        s = jonswap_spectrum(w, Hs, Tp, gamma)
        m0 = np.sum(0.5 * (s[1:] + s[:-1]) * np.diff(w))  # the tail above 60 wp holds < 1e-7 of m0
        assert m0 == pytest.approx(Hs**2 / 16, rel=1e-6)
    pm = 5 / 16 * Hs**2 * wp**4 * w[1:2000] ** -5 * np.exp(-1.25 * (wp / w[1:2000]) ** 4)
    np.testing.assert_allclose(pierson_moskowitz_spectrum(w[1:2000], Hs, Tp), pm, rtol=1e-12, atol=1e-300)


def record(K, x, y, times):
    """Elevation record at (x, y) [m] at the given times [s]."""
    return np.array([fluid_kinematics(K, t, [x, y, -1.0])[6] for t in times])


def test_jonswap_record_gives_back_hs_and_spectrum():
    """Waves.jonswap(Hs=3.5, Tp=7.5, gamma=3.3, heading=180, seed=1), 200 components: the record at
    a point over one repeat period (the longest record with new information) has 4 std = Hs within
    3 % (the frequency range (0.5, 4) wp holds 99.8 % of the variance), its periodogram gives back
    S(omega_j) of every component to 1e-6 (the record is exactly periodic: no leakage), and the
    peak lies within one frequency step of 2 pi / Tp."""
    Hs, Tp = 3.5, 7.5
    w = Waves.jonswap(Hs=Hs, Tp=Tp, gamma=3.3, heading=180.0, seed=1)
    K = build(w, depth=80.0)
    n = 8192
    period = w.repeat_period
    times = np.arange(n) * period / n
    zeta = record(K, 12.0, -3.0, times)
    assert 4 * zeta.std() == pytest.approx(Hs, rel=0.03)
    assert 4 * zeta.std() == pytest.approx(w.hs, rel=1e-9)  # Parseval over a whole period
    X = np.fft.rfft(zeta)
    amp = 2 * np.abs(X) / n
    m = np.rint(w.omega / w.base_omega).astype(int)
    s_est = amp[m] ** 2 / (2 * w.base_omega)
    s_ref = jonswap_spectrum(w.omega, Hs, Tp, 3.3)
    big = s_ref > 1e-3 * s_ref.max()
    np.testing.assert_allclose(s_est[big], s_ref[big], rtol=1e-6)
    assert abs(w.omega[np.argmax(s_est)] - 2 * math.pi / Tp) <= w.base_omega
    # energy only at the component frequencies
    others = np.setdiff1d(np.arange(amp.size), m)
    assert amp[others].max() < 1e-9 * amp.max()


def test_seeds():
    times = np.linspace(0, 300, 600)
    kw = dict(Hs=2.0, Tp=10.0, n_components=60)
    r1 = record(build(Waves.jonswap(seed=42, **kw)), 0, 0, times)
    r2 = record(build(Waves.jonswap(seed=42, **kw)), 0, 0, times)
    r3 = record(build(Waves.jonswap(seed=43, **kw)), 0, 0, times)
    np.testing.assert_array_equal(r1, r2)
    assert np.max(np.abs(r1 - r3)) > 1.0
    drawn = Waves.jonswap(seed=None, **kw)
    assert drawn.seed is not None
    np.testing.assert_array_equal(Waves.jonswap(seed=drawn.seed, **kw).amplitude, drawn.amplitude)


def test_directional_spreading():
    """cos-2s spreading about the mean heading: E[cos(theta - theta0)] = s / (s + 1) for the
    continuous function (the discrete equal-energy quantiles approach it as 1/n^1.4: 2e-3 at n = 64),
    symmetric about the mean, and each (frequency, direction) pair its own component."""
    for s in (2.0, 15.0):
        th, share = cos2s_directions(s, 64)
        assert np.sum(share * np.cos(np.radians(th))) == pytest.approx(s / (s + 1), abs=2e-3)
        np.testing.assert_allclose(th, -th[::-1], atol=1e-9)
    w = Waves.jonswap(3.0, 9.0, heading=45.0, seed=2, n_components=30, spreading=4.0, n_directions=8)
    assert w.n_components == 240
    a2 = np.abs(w.amplitude) ** 2
    b = np.radians(w.heading)
    mean = math.degrees(math.atan2(np.sum(a2 * np.sin(b)), np.sum(a2 * np.cos(b))))
    assert mean == pytest.approx(45.0, abs=1e-9)
    assert w.hs == pytest.approx(Waves.jonswap(3.0, 9.0, seed=2, n_components=30).hs, rel=1e-12)


def test_regular_wave_and_heading_convention():
    """Heading 90 deg travels toward +y; a crest at the origin at t = 0 moves to y = c t."""
    h, T = 50.0, 10.0
    K = build(Waves.regular(2.0, T, heading=90.0), depth=h)
    c = 2 * math.pi / T / wave_number(2 * math.pi / T, G, h)
    assert fluid_kinematics(K, 0.0, [0, 0, -5])[6] == pytest.approx(1.0, abs=1e-15)
    assert fluid_kinematics(K, 3.0, [0, 3.0 * c, -5])[6] == pytest.approx(1.0, abs=1e-13)
    assert fluid_kinematics(K, 3.0, [3.0 * c, 0, -5])[6] < 0.9
    u = fluid_kinematics(K, 0.0, [0, 0, -5])
    assert abs(u[0]) < 1e-15 and u[1] > 0  # under a crest the water moves with the wave


def test_from_elevation_reproduces_a_periodic_record():
    """A record that is a sum of harmonics of its length comes back exactly at the origin."""
    n, dt = 64, 0.5
    t = np.arange(n + 1) * dt
    z = 0.3 * np.cos(2 * np.pi * 3 * t / (n * dt) + 0.4) + 0.1 * np.sin(2 * np.pi * 7 * t / (n * dt))
    w = Waves.from_elevation(t, z, dt=dt, heading=30.0)
    assert w.grid.nt == n
    K = build(w)
    np.testing.assert_allclose(record(K, 0.0, 0.0, t[:n] + 0.123), 0.3 * np.cos(2 * np.pi * 3 * (t[:n] + 0.123)
                               / (n * dt) + 0.4) + 0.1 * np.sin(2 * np.pi * 7 * (t[:n] + 0.123) / (n * dt)), atol=1e-13)


# ------------------------------------------------------------------------------------------------
# 6. currents, still water, external, ramp, unified grid


def test_uniform_current_heading():
    K = build(None, Current.uniform(1.0, heading=180.0))
    np.testing.assert_allclose(fluid_kinematics(K, 5.0, [1, 2, -3])[:3], [-1.0, 0.0, 0.0], atol=1e-15)
    K = build(None, Current.uniform(0.5, heading=90.0, vertical=0.01))
    np.testing.assert_allclose(fluid_kinematics(K, 0.0, [0, 0, 0])[:6], [0, 0.5, 0.01, 0, 0, 0], atol=1e-16)


def test_current_profile_interpolation_and_clamping():
    """Linear in z between the levels, clamped below the deepest and above the highest level,
    and not zeroed above the water surface (MoorDyn-C, spec 4.7), even under waves."""
    c = Current.profile([-40.0, -10.0, 0.0], [0.1, 0.4, 0.9], [0.0, -0.2, 0.2])
    K = build(None, c)
    for z, ux, uy in ((-50.0, 0.1, 0.0), (-40.0, 0.1, 0.0), (-25.0, 0.25, -0.1), (-4.0, 0.7, 0.04),
                      (0.0, 0.9, 0.2), (2.5, 0.9, 0.2)):
        np.testing.assert_allclose(fluid_kinematics(K, 3.0, [7.0, 3.0, z])[:6], [ux, uy, 0, 0, 0, 0], atol=1e-15)
    Kw = build(Waves.regular(2.0, 8.0), c)
    Kw0 = build(Waves.regular(2.0, 8.0), None)
    diff = fluid_kinematics(Kw, 0.0, [0, 0, 0.8])[:3] - fluid_kinematics(Kw0, 0.0, [0, 0, 0.8])[:3]
    np.testing.assert_allclose(diff, [0.9, 0.2, 0.0], atol=1e-14)  # the current at the true z, clamped


def test_dynamic_profile_in_time():
    """Linear in t between samples; after the last sample: periodic (back to the first), MoorDyn
    (first sample held over the last interval), or clamped; acceleration 0 unless asked for,
    then the slope of the interpolation."""
    t = [0.0, 2.0, 4.0]
    ux = [[0.0, 0.0], [1.0, 2.0], [0.5, 0.5]]  # (nt, nz)
    z = [-20.0, 0.0]

    def u(K, time, zz=-10.0):
        return fluid_kinematics(K, time, [0, 0, zz])

    Kp = build(None, Current.dynamic_profile(t, z, ux))
    assert u(Kp, 1.0)[0] == pytest.approx(0.75, abs=1e-15)  # mid-depth average 1.5, half way in time
    assert u(Kp, 3.0)[0] == pytest.approx(1.0, abs=1e-15)
    assert u(Kp, 5.0)[0] == pytest.approx(0.25, abs=1e-15)  # periodic: 0.5 -> 0 over [4, 6)
    assert u(Kp, 7.0)[0] == pytest.approx(0.75, abs=1e-15)  # period 6 s
    assert np.all(u(Kp, 1.0)[3:6] == 0.0)
    Km = build(None, Current.dynamic_profile(t, z, ux, time_wrap="moordyn"))
    assert u(Km, 5.0)[0] == 0.0 and u(Km, 4.0)[0] == 0.0  # MoorDyn holds sample 0 from t = 4 s
    assert u(Km, 3.0)[0] == pytest.approx(1.0, abs=1e-15)
    Kc = build(None, Current.dynamic_profile(t, z, ux, time_wrap="clamp"))
    assert u(Kc, 50.0)[0] == pytest.approx(0.5, abs=1e-15)
    assert u(Kc, -3.0)[0] == 0.0
    Ka = build(None, Current.dynamic_profile(t, z, ux, include_acceleration=True))
    assert u(Ka, 1.0)[3] == pytest.approx(0.75, abs=1e-15)
    assert u(Ka, 3.0)[3] == pytest.approx(-0.5, abs=1e-15)
    assert u(Ka, 5.0)[3] == pytest.approx(-0.25, abs=1e-15)


def test_dynamic_profile_resampled_at_smallest_interval():
    """Times 0, 1, 3 s: resampled every 1 s from 0 (MoorDyn), which keeps the piecewise-linear
    history unchanged at every time within the table."""
    c = Current.dynamic_profile([0.0, 1.0, 3.0], [0.0], [[0.0], [1.0], [3.0]], time_wrap="clamp")
    K = build(None, c)
    assert K.cg_dt == 1.0 and K.cg_vel.shape[3] == 4
    for time in np.linspace(0, 3, 13):
        assert fluid_kinematics(K, time, [0, 0, -1])[0] == pytest.approx(np.interp(time, c.t, [0, 1, 3]), abs=1e-14)


def test_current_4d_grid_against_scipy():
    """Trilinear in x, y, z and linear in t inside the grid (scipy's RegularGridInterpolator as
    reference), nearest edge values outside."""
    from scipy.interpolate import RegularGridInterpolator

    rng = np.random.default_rng(9)
    x, y, z, t = np.array([-50.0, 0.0, 20.0, 60.0]), np.array([-5.0, 5.0]), np.array([-30.0, -12.0, 0.0]), \
        np.array([0.0, 10.0, 20.0])
    vel = rng.normal(size=(4, 2, 3, 3, 3))
    K = build(None, Current.grid(x, y, z, t, vel, time_wrap="clamp"))
    ref = RegularGridInterpolator((x, y, z, t), vel)
    for _ in range(100):
        p = np.array([rng.uniform(-70, 80), rng.uniform(-8, 8), rng.uniform(-35, 3), rng.uniform(0, 25)])
        inside = np.clip(p, [x[0], y[0], z[0], t[0]], [x[-1], y[-1], z[-1], t[-1]])
        np.testing.assert_allclose(fluid_kinematics(K, p[3], p[:3])[:3], ref(inside)[0], atol=1e-14)


def test_still_water_and_external_kinematics():
    K = still_water(50.0, G)
    assert K.wave_mode == WAVES_NONE and K.current_mode == CURRENT_NONE
    out = np.full((5, 8), 7.0)
    fluid_at_points(3.0, np.ones((5, 3)), K, out)
    assert np.all(out == 0.0)
    one = np.full(8, 7.0)
    fluid_at(3.0, 0.0, 0.0, -1.0, K, one)
    assert np.all(one == 0.0)
    Ke = build(Waves.external(), Current.uniform(0.5), n_external=3)
    Ke.U_ext[:] = [[1, 2, 3], [4, 5, 6], [7, 8, 9]]
    Ke.Ud_ext[:] = -Ke.U_ext
    out = np.empty((3, 8))
    fluid_at_points(0.0, np.zeros((3, 3)), Ke, out)
    np.testing.assert_array_equal(out[:, 0:3], Ke.U_ext + [0.5, 0, 0])
    np.testing.assert_array_equal(out[:, 3:6], Ke.Ud_ext)
    assert np.all(out[:, 6:8] == 0.0)
    fluid_at(0.0, 0.0, 0.0, 0.0, Ke, one)  # no node index: the current only
    np.testing.assert_array_equal(one, [0.5, 0, 0, 0, 0, 0, 0, 0])
    with pytest.raises(ValueError, match="fewer rows"):
        fluid_at_points(0.0, np.zeros((4, 3)), Ke, np.empty((4, 8)))


@pytest.mark.parametrize("evaluation", ["sum", "grid"])
def test_single_point_and_batch_kernels_agree(evaluation):
    grid = WaveGrid(x=np.linspace(-60, 60, 13), y=np.linspace(-60, 60, 13), z=np.linspace(-50, 0, 11), nt=64)
    bathy = Bathymetry(x=[-60.0, 60.0], y=[0.0], z=[[-55.0, -45.0]])
    K = build(irregular(evaluation=evaluation, grid=grid), Current.dynamic_profile([0.0, 10.0], [-50.0, 0.0],
                                                                                   [[0.2, 1.0], [0.4, 0.5]]),
              bathymetry=bathy)
    rng = np.random.default_rng(2)
    r = np.c_[rng.uniform(-50, 50, 20), rng.uniform(-50, 50, 20), rng.uniform(-50, 1, 20)]
    out = np.empty((20, 8))
    fluid_at_points(12.5, r, K, out)
    one = np.empty(8)
    for i in range(20):
        fluid_at(12.5, r[i, 0], r[i, 1], r[i, 2], K, one)
        np.testing.assert_array_equal(one, out[i])


def test_ramp():
    """r(t) = (1 - cos(pi t / Tr)) / 2: nothing at t <= 0, full waves from Tr on; in between
    U = r U_full and dU/dt is the time derivative of r U_full (checked by central differences,
    step 1e-4 s: truncation ~1e-9). Without stretching, which would evaluate the ramped and the
    full sea at different heights."""
    tr = 20.0
    K = build(irregular(ramp_time=tr, stretching="none"))
    K1 = build(irregular(stretching="none"))
    p = [3.0, -2.0, -6.0]
    assert np.all(fluid_kinematics(K, 0.0, p) == 0.0)
    np.testing.assert_array_equal(fluid_kinematics(K, 25.0, p), fluid_kinematics(K1, 25.0, p))
    half = [0, 1, 2, 6, 7]
    np.testing.assert_allclose(fluid_kinematics(K, 10.0, p)[half], 0.5 * fluid_kinematics(K1, 10.0, p)[half],
                               rtol=1e-14)
    for t in (3.0, 10.0, 17.0):
        d = (fluid_kinematics(K, t + 1e-4, p)[0:3] - fluid_kinematics(K, t - 1e-4, p)[0:3]) / 2e-4
        np.testing.assert_allclose(fluid_kinematics(K, t, p)[3:6], d, atol=1e-7)
    # on a grid the same ramp: U = r U_full, dU/dt = r dU_full/dt + r' U_full
    grid = WaveGrid(x=np.linspace(-20, 20, 5), y=[-5.0, 5.0], z=np.linspace(-50, 0, 6), nt=64)
    Kg = build(irregular(ramp_time=tr, stretching="none", evaluation="grid", grid=grid))
    Kg1 = build(irregular(stretching="none", evaluation="grid", grid=grid))
    t = 7.3
    r, rd = 0.5 * (1 - math.cos(math.pi * t / tr)), 0.5 * math.pi / tr * math.sin(math.pi * t / tr)
    full = fluid_kinematics(Kg1, t, p)
    expect = np.r_[r * full[0:3], r * full[3:6] + rd * full[0:3], r * full[6], r * full[7]]
    np.testing.assert_allclose(fluid_kinematics(Kg, t, p), expect, rtol=1e-13, atol=1e-15)


def test_current_unified_into_wave_grid():
    """on_wave_grid (MoorDyn's UnifyCurrentGrid): the current is sampled at the wave grid levels and
    interpolated with the waves in the stretched height z', so under a crest a point gets the
    current of the level z' (not z); separately it gets the current at z."""
    grid = WaveGrid(x=np.linspace(-40, 40, 9), y=[0.0], z=np.linspace(-30, 0, 31), nt=126)
    waves = irregular(evaluation="grid", grid=grid)
    prof = dict(z=[-30.0, 0.0], ux=[0.0, 0.9])
    Ku = build(waves, Current.profile(**prof, on_wave_grid=True), depth=30.0)
    Ks = build(waves, Current.profile(**prof), depth=30.0)
    K0 = build(waves, None, depth=30.0)
    assert Ku.current_mode == CURRENT_NONE
    t = 0.0
    zeta = fluid_kinematics(K0, t, [0, 0, 0])[6]
    z = -12.0
    zs = 30.0 * (z + 30.0) / (zeta + 30.0) - 30.0
    base = fluid_kinematics(K0, t, [0, 0, z])[0]
    assert fluid_kinematics(Ku, t, [0, 0, z])[0] - base == pytest.approx(0.03 * (zs + 30.0), abs=1e-12)
    assert fluid_kinematics(Ks, t, [0, 0, z])[0] - base == pytest.approx(0.03 * (z + 30.0), abs=1e-12)
    assert abs(zs - z) > 0.1


def test_validation_errors():
    with pytest.raises(ModelError, match="omega"):
        Waves(omega=[-1.0], amplitude=[1.0])
    with pytest.raises(ModelError, match="same length"):
        Waves(omega=[1.0, 2.0], amplitude=[1.0])
    with pytest.raises(ModelError, match="stretching"):
        Waves.regular(1.0, 5.0, stretching="linear")
    with pytest.raises(ModelError, match="Hs"):
        Waves.jonswap(0.0, 8.0)
    with pytest.raises(ModelError, match="gamma"):
        Waves.jonswap(2.0, 8.0, 0.5)
    with pytest.raises(ModelError, match="seed"):
        Waves.jonswap(2.0, 8.0, seed=-1)
    with pytest.raises(ModelError, match="whole multiple"):
        Waves.from_components([1.0, math.sqrt(2.0)], [1.0, 1.0], evaluation="grid")
    with pytest.raises(ModelError, match="n_components or repeat_period"):
        Waves.jonswap(2.0, 8.0, n_components=10, repeat_period=100.0)
    with pytest.raises(ModelError, match="ramp_time"):
        Waves.regular(1.0, 5.0, ramp_time=-1.0)
    with pytest.raises(ModelError, match="shape"):
        Current(velocity=np.zeros((1, 1, 2, 1, 3)))
    with pytest.raises(ModelError, match="strictly increasing"):
        Current.profile([0.0, -1.0], [1.0, 1.0])
    with pytest.raises(ModelError, match="speed"):
        Current.uniform(-1.0)
    with pytest.raises(ValueError, match="depth"):
        build_water_kinematics(None, None, depth=0.0, g=G, rho=RHO)
    with pytest.raises(ValueError, match="bbox"):
        build(Waves.regular(1.0, 5.0), bbox=[[0, 0, 0]])
    with pytest.raises(ValueError, match="dispersion"):
        build(Waves.regular(1.0, 5.0), dispersion="airy")
    assert Waves.jonswap(2.0, 8.0, repeat_period=600.0, seed=1).repeat_period == pytest.approx(600.0)


# ------------------------------------------------------------------------------------------------
# 7. MoorDyn-C as oracle

#: moorline vs MoorDyn-C, per value, relative to 1 + |MoorDyn value| (pressures in Pa): with
#: MoorDyn's dispersion estimate both evaluate the same formulas; the grids differ by FFT
#: round-off (measured 1.7e-9 with the current unified into a grid, 6e-10 for WaveKin 3, 5e-11
#: for WaveKin 2, 1e-12 for the rest)
TOL_ORACLE = 1e-8

ORACLE_DECK = """\
--------------------- MoorDyn Input File ------------------------------------
moorline water-kinematics oracle: a short fixed line, only the kinematics are compared
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
chain      0.1     20         1.0e8      -1.0        0          1.2    1.0    0.2     0.0
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -100    0.0     -30.0    0      0       0      0
2     Fixed     0.0     0.0     -5.0     0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     chain      1        2         105       10      -
---------------------- OPTIONS -----------------------------------------
0             writeLog
0.001         dtM
30            WtrDpth
0.0           TmaxIC
{options}
1             disableOutput
------------------------- need this line --------------------------------------
"""

FREQS = "0.0 0.1 0.0\n0.3 0.2 0.1 0.3\n0.5 0.4 -0.2 0.5\n0.8 0.1 0.3 -0.4\n1.2 0.05 0.0\n"
GRID = "h\nh\nh\n2\n-50 50 21\n1\n-5 0 5\n2\n-31 2 12\n"
PROFILE = "a\nb\nc\n-30 0.1 0.0\n-10 0.5 0.2 0.01\n0 0.8 -0.1\n"


def _dynamic_profile() -> str:
    rows = ["a", "b", "c", "d", "-30 -12 0", ""]
    for t in (0.0, 2.0, 3.0, 7.0):
        rows.append(" ".join(map(str, [t, 0.1 * t, 0.2, 0.3 + 0.01 * t, 0.0, -0.05 * t, 0.1, 0.001, 0.002, 0.003])))
    return "\n".join(rows) + "\n"


def _profile_4d() -> str:
    xs, ys, zs, ts = [-40.0, 0.0, 40.0], [-5.0, 5.0], [-30.0, -10.0, 0.0], [0.0, 5.0, 10.0]
    rows = [f"{len(xs)} {len(ys)} {len(zs)} {len(ts)}"] + [" ".join(map(str, a)) for a in (xs, ys, zs, ts)]
    for x in xs:
        for y in ys:
            for z in zs:
                for t in ts:
                    rows.append(" ".join(map(str, [x, y, z, t, 0.01 * x + 0.02 * t, 0.1 * y - 0.01 * z, 0.001 * t])))
    return "\n".join(rows) + "\n"


def _elevation() -> str:
    t = np.arange(0, 40.05, 0.1)
    z = 0.6 * np.sin(0.7 * t) + 0.2 * np.cos(2.2 * t + 0.3) + 0.1 * np.sin(4.0 * t)
    return "".join(f"{a:.3f} {b:.6f}\n" for a, b in zip(t, z, strict=True))


ORACLE_CASES = {
    # name: (WaveKin, Currents, extra options, files, times)
    "wavekin7": (7, 0, "", {"wave_frequencies.txt": FREQS}, [0.0, 0.37, 3.3, 12.9]),
    "wavekin2": (2, 0, "", {"wave_frequencies.txt": FREQS, "water_grid.txt": GRID},
                 [0.0, 0.37, 3.3, 12.9, 21.0, 30.0, 31.0, 40.2]),
    "wavekin3": (3, 0, "1.0 dtWave", {"wave_elevation.txt": _elevation(), "water_grid.txt": GRID},
                 [0.0, 0.37, 3.3, 21.0, 39.5, 40.2, 77.7]),
    "wavekin7_current1": (7, 1, "", {"wave_frequencies.txt": FREQS, "current_profile.txt": PROFILE}, [0.0, 3.3]),
    "wavekin2_current1_unified": (2, 1, "", {"wave_frequencies.txt": FREQS, "water_grid.txt": GRID,
                                             "current_profile.txt": PROFILE}, [0.0, 3.3, 30.0]),
    "current2": (0, 2, "", {"current_profile_dynamic.txt": _dynamic_profile()}, [0.0, 0.5, 2.5, 6.9, 7.4, 8.2, 15.3]),
    "wavekin2_current2_unified": (2, 2, "", {"wave_frequencies.txt": FREQS, "water_grid.txt": GRID,
                                             "current_profile_dynamic.txt": _dynamic_profile()}, [0.0, 2.5, 7.4, 15.3]),
    "current5": (0, 5, "", {"current_profile_4d.txt": _profile_4d()}, [0.0, 2.5, 7.5, 11.0, 14.0, 17.5]),
}


@pytest.mark.oracle
@pytest.mark.parametrize("case", list(ORACLE_CASES))
def test_moordyn_oracle(case, tmp_path: Path):
    """Our readers and kernels against MoorDyn-C's own GetWavesKin at points inside, outside and
    above the grids, at times on and between samples and past the repeat period (the 4-D case
    includes MoorDyn's skipped first row, the WaveKin 2/3 cases its wrap)."""
    md = pytest.importorskip("moordyn")
    wave_kin, currents, extra, files, times = ORACLE_CASES[case]
    options = f"{wave_kin} WaveKin\n{currents} Currents\n{extra}"
    (tmp_path / "deck.txt").write_text(ORACLE_DECK.format(options=options))
    for name, text in files.items():
        (tmp_path / name).write_text(text)
    waves, current = water_from_options(wave_kin, currents, tmp_path, 30.0, dt_wave=1.0 if extra else 0.25)
    K = build_water_kinematics(waves, current, depth=30.0, g=G, rho=RHO, dispersion="newman")
    rng = np.random.default_rng(0)
    pts = np.c_[rng.uniform(-60, 60, 12), rng.uniform(-6, 6, 12), rng.uniform(-32, 2, 12)]
    system = md.Create(str(tmp_path / "deck.txt"))
    try:
        md.Init(system, np.zeros(0), np.zeros(0))
        mw = md.GetWaves(system)
        t = 0.0
        worst = 0.0
        for tn in times:
            if tn > t:
                md.Step(system, np.zeros(0), np.zeros(0), t, tn - t)  # the waves' clock is then at tn
                t = tn
            for p in pts:
                u, ud, zeta, pdyn = md.GetWavesKin(mw, *p)
                ref = np.r_[u, ud, zeta, pdyn]
                worst = max(worst, float(np.max(np.abs(fluid_kinematics(K, t, p) - ref) / (1.0 + np.abs(ref)))))
    finally:
        md.Close(system)
    assert worst < TOL_ORACLE
