"""Impulse responses, Ogilvie round trip, state-space fits, passivity and the packed format."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

from moorline.hydro import (
    coefficients_from_irf,
    fit_state_space,
    impulse_response,
    matrix,
    radiation_convolution_force,
)

T_IRF, DT = 60.0, 0.02


@pytest.fixture(scope="module")
def rm3_fit(rm3):
    t = np.arange(0.0, T_IRF, DT)
    return t, impulse_response(rm3, t), fit_state_space(rm3, t=t)


def _active(ds):
    """DOF indices whose damping is not solver noise (yaw of the axisymmetric RM3 hulls is ~1e-10 of the rest)."""
    return [i for i, lab in enumerate(ds.influenced_dof.values) if not str(lab).endswith("Yaw")]


def test_rm3_round_trip_damping(rm3_fit, rm3):
    """B(w) rebuilt from K within 2 % of the peak of each diagonal entry over the whole band (measured 0.3 %);
    K built on the symmetric positive semi-definite projection of B, so compare with that."""
    from moorline.hydro import passive_damping
    t, K, _ = rm3_fit
    A, B = coefficients_from_irf(K, t, rm3.omega.values, rm3.added_mass_inf)
    Bp = np.swapaxes(passive_damping(matrix(rm3.radiation_damping))[0], 1, 2)
    for i in _active(rm3):
        peak = np.abs(Bp[:, i, i]).max()
        assert np.abs(B[:, i, i] - Bp[:, i, i]).max() <= 0.02 * peak, i


def test_rm3_round_trip_added_mass(rm3_fit, rm3):
    """A(w) = A_inf - (1/w) int K sin over the band: after removing the mean offset (A_inf of the file is not the
    Kramers-Kronig-consistent value: 3.8 % of peak A11 for the float in surge), within 2 % of the peak of each
    diagonal entry below 0.8 w_max (the last 20 % of the band holds the irregular-frequency dip of the float heave,
    where A rises 14 % in 0.5 rad/s and B turns negative)."""
    t, K, _ = rm3_fit
    w = rm3.omega.values
    A, _ = coefficients_from_irf(K, t, w, rm3.added_mass_inf)
    band = w <= 0.8 * w[-1]
    for i in _active(rm3):
        ref = rm3.added_mass.values[:, i, i]
        d = (A[:, i, i] - ref)[band]
        assert np.abs(d - d.mean()).max() <= 0.02 * np.abs(ref).max(), i


def test_rm3_state_space(rm3_fit, rm3):
    """Every fitted A_r is stable; relative L2 kernel error of the Hankel fit <= 0.5 % on every pair (target 0.2 %,
    reached by all but the surge/sway pairs, 0.30 % at order 8-10), <= 2 % after the passivity correction
    (measured 1.45 %); the fitted model is passive (scaled margin >= -1e-6); the packed arrays reproduce the
    pair matrices."""
    t, K, fit = rm3_fit
    assert all(np.all(np.linalg.eigvals(p.A).real < 0) for p in fit.pairs)
    assert all(p.error_fit <= 0.005 for p in fit.pairs)
    assert all(p.error <= 0.02 for p in fit.pairs)
    assert fit.passivity_report.passive and fit.passivity().margin >= -1e-6
    packed = fit.pack()
    assert packed.state_ptr[-1] == sum(p.order for p in fit.pairs) == packed.A.shape[0]
    for k, p in enumerate(fit.pairs):
        s0, s1 = packed.state_ptr[k], packed.state_ptr[k + 1]
        np.testing.assert_array_equal(packed.A[s0:s1, :p.order], p.A)
        assert (packed.pair_i[k], packed.pair_j[k]) == (p.i, p.j)
    assert packed.pair_i.dtype == np.int64 and packed.state_ptr.dtype == np.int64
    Kss = fit.kernel(t)
    i = list(rm3.influenced_dof.values).index("body1__Heave")
    assert np.linalg.norm(Kss.values[i, i] - K.values[i, i]) <= 0.02 * np.linalg.norm(K.values[i, i])


def test_rm3_state_space_force_against_convolution(rm3_fit, rm3):
    """Radiation force of the state-space model within 1 % RMS of the direct convolution (trapezoid, T = 60 s)
    for a broadband velocity (white noise band-passed to 0.3-3 rad/s, 4th-order Butterworth) on the float and
    spar heave and pitch, 300 s."""
    t, K, fit = rm3_fit
    rng = np.random.default_rng(1)
    n = int(300 / DT)
    sos = signal.butter(4, [0.3 / np.pi * DT, 3.0 / np.pi * DT], btype="band", output="sos")
    v = np.zeros((n, 12))
    for i in (2, 4, 8, 10):
        v[:, i] = signal.sosfilt(sos, rng.standard_normal(n))
    v[:200] *= np.linspace(0, 1, 200)[:, None]
    f_conv = radiation_convolution_force(K, DT, v)
    f_ss = fit.radiation_force(v, DT)
    for i in (2, 4, 8, 10):
        rms = np.sqrt(np.mean(f_conv[:, i] ** 2))
        assert np.sqrt(np.mean((f_ss[:, i] - f_conv[:, i]) ** 2)) <= 0.01 * rms, i


def test_frequency_response_of_fit(rm3_fit, rm3):
    """B_ss(w) = Re K_ss(iw) and A_ss = A_inf + Im K_ss / w track the data over the band (heave, float): within 5 %
    of the peak for B and of the A range for A, on 0.3 rad/s <= w <= 0.8 w_max (below, A_ss = A_inf + Im K_ss / w
    divides the small fit error by w)."""
    _, _, fit = rm3_fit
    w = rm3.omega.values
    A, B = fit.frequency_response(w)
    i = 2
    band = (w <= 0.8 * w[-1]) & (w >= 0.3)
    b_ref = rm3.radiation_damping.values[:, i, i]
    assert np.abs(B[band, i, i] - b_ref[band]).max() <= 0.05 * b_ref.max()
    a_ref = rm3.added_mass.values[:, i, i]
    span = a_ref.max() - a_ref.min()
    d = A[band, i, i] - a_ref[band]
    assert np.abs(d - d.mean()).max() <= 0.05 * span
