"""Radiation impulse response functions (Cummins' retardation kernel) and Ogilvie's relations.

K(t) = (2/pi) int_0^inf B(w) cos(w t) dw                                   (Cummins 1962, Ogilvie 1964)
B(w) = int_0^inf K(t) cos(w t) dt,   A(w) = A_inf - (1/w) int_0^inf K(t) sin(w t) dt

Band limits. B is known only on [w_1, w_N]. Below w_1 it is taken linear from B(0) = 0 (radiation damping
vanishes in the long-wave limit); above w_N it is continued by a raised-cosine taper from B(w_N) down to zero
over ``taper`` x w_N (default 0.5 w_N). A sharp cut at w_N would make K ring at the period 2 pi / w_N and spoil the
round trip; the taper bounds the error to the part of B beyond w_N, which is what the band should make small
(check it: the round trip of A and B over the band, see ``coefficients_from_irf``).

Integration. Both transforms integrate a piecewise-linear function (B between its frequencies, K between its
time samples) against cos or sin in closed form (Filon-type weights), so there is no aliasing from the
frequency spacing: the only approximation is the linear interpolation itself.

Units: K [N/m per s... i.e. kg/s^2] for translation pairs (B [kg/s] per second), time [s].
"""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

from .dataset import matrix

log = logging.getLogger("moorline.hydro")


def _sin_over(x, t):
    """sin(x t) / t, finite at t = 0 (= x)."""
    return x * np.sinc(x * t / np.pi)


def _linear_cos_weights(nodes, t):
    """Weights W (n_t, n_nodes) with int f(x) cos(x t) dx = W @ f for f linear between ``nodes``."""
    x = np.asarray(nodes, dtype=float)
    t = np.asarray(t, dtype=float)[:, None]
    a, b = x[:-1][None, :], x[1:][None, :]
    h = b - a
    c = 0.5 * (a + b)
    # (cos(bt) - cos(at)) / (t^2 h) = -(sin(ct)/t) sinc(h t / 2)
    dc = -_sin_over(c, t) * np.sinc(h * t / (2 * np.pi))
    w = np.zeros((t.shape[0], x.size))
    w[:, 1:] += _sin_over(b, t) + dc       # rising half of the hat at the right node
    w[:, :-1] += -_sin_over(a, t) - dc     # falling half at the left node
    return w


def _linear_sin_weights(nodes, s):
    """Weights W (n_s, n_nodes) with int f(x) sin(s x) dx = W @ f for f linear between ``nodes`` (s > 0)."""
    x = np.asarray(nodes, dtype=float)
    s = np.asarray(s, dtype=float)[:, None]
    a, b = x[:-1][None, :], x[1:][None, :]
    h = b - a
    c = 0.5 * (a + b)
    # (sin(bs) - sin(as)) / (s^2 h) = cos(cs) sinc(h s / 2) / s
    ds_ = np.cos(c * s) * np.sinc(h * s / (2 * np.pi)) / s
    w = np.zeros((s.shape[0], x.size))
    w[:, 1:] += -np.cos(b * s) / s + ds_
    w[:, :-1] += np.cos(a * s) / s - ds_
    return w


def extended_damping(omega, B, *, taper: float = 0.5, n_taper: int = 64):
    """B continued to the whole frequency axis as described in the module docstring.

    Parameters
    ----------
    omega : array, shape (n_w,)
        Computed frequencies [rad/s], increasing, > 0.
    B : array, shape (n_w, ...)
        Damping at those frequencies.
    taper : float
        Width of the raised-cosine taper beyond the band, as a fraction of omega[-1] [-]; 0 cuts sharply.
    n_taper : int
        Nodes in the taper.

    Returns
    -------
    nodes : array (n_nodes,) [rad/s]
    values : array (n_nodes, ...)
    """
    omega = np.asarray(omega, dtype=float)
    B = np.asarray(B, dtype=float)
    nodes = [np.array([0.0]), omega]
    vals = [np.zeros((1,) + B.shape[1:]), B]
    if taper > 0:
        wt = omega[-1] * (1.0 + taper * np.linspace(0.0, 1.0, n_taper + 1)[1:])
        shape = 0.5 * (1.0 + np.cos(np.pi * (wt - omega[-1]) / (taper * omega[-1])))
        nodes.append(wt)
        vals.append(shape.reshape((-1,) + (1,) * (B.ndim - 1)) * B[-1][None])
    else:
        nodes.append(np.array([omega[-1] * (1 + 1e-9)]))
        vals.append(np.zeros((1,) + B.shape[1:]))
    return np.concatenate(nodes), np.concatenate(vals, axis=0)


def passive_damping(B):
    """Nearest symmetric positive semi-definite damping at each frequency (unit-consistent).

    B(w) is symmetrised and, in the scaled form D^-1/2 B D^-1/2 (D_i the peak of B_ii over frequency), its negative
    eigenvalues are set to zero. Radiation damping is symmetric and positive semi-definite in theory (Newman,
    Marine Hydrodynamics, 6.17); BEM noise, irregular frequencies and coupling in narrow gaps break that, and a
    kernel built on negative damping is an energy source in the time domain.

    Parameters
    ----------
    B : array (n_w, n, n)

    Returns
    -------
    B_psd : array (n_w, n, n)
    change : float
        Largest |B_psd - B| entry relative to sqrt(D_i D_j) [-].
    """
    B = np.asarray(B, dtype=float)
    d = np.sqrt(np.maximum(np.abs(np.einsum("wii->wi", B)).max(axis=0), 1e-300))
    Bs = 0.5 * (B + np.swapaxes(B, 1, 2)) / np.outer(d, d)[None]
    lam, V = np.linalg.eigh(Bs)
    Bp = np.einsum("wik,wk,wjk->wij", V, np.maximum(lam, 0.0), V) * np.outer(d, d)[None]
    change = float(np.max(np.abs(Bp - B) / np.outer(d, d)[None]))
    return Bp, change


def impulse_response(ds: xr.Dataset, t, *, taper: float = 0.5, passive: bool = True) -> xr.DataArray:
    """Radiation impulse response K(t) = (2/pi) int_0^inf B(w) cos(w t) dw.

    Parameters
    ----------
    ds : xarray.Dataset
        Coefficient Dataset (uses ``radiation_damping``).
    t : array, shape (n_t,)
        Times [s], >= 0; its last value is the truncation time T_irf used downstream.
    taper : float
        Taper width beyond the computed band as a fraction of the highest frequency (see module docstring).
    passive : bool
        Build K on :func:`passive_damping` (symmetric, positive semi-definite B); the largest change is
        logged and stored in the attribute ``damping_projection_change``. False uses B as given.

    Returns
    -------
    xarray.DataArray
        dims (radiating_dof, influenced_dof, time): ``K.sel(radiating_dof=j, influenced_dof=i)`` is the kernel
        from the velocity of j to the memory force on i, F_i(t) = -sum_j int_0^t K_ij(t - tau) v_j(tau) dtau.
        Units: damping units per second.
    """
    t = np.asarray(t, dtype=float)
    Bm = matrix(ds["radiation_damping"])  # (n_w, i, j)
    change = 0.0
    if passive:
        Bm, change = passive_damping(Bm)
        if change > 1e-3:
            log.info("impulse_response: damping made symmetric positive semi-definite; largest change %.3g of the "
                     "peak diagonal damping", change)
    nodes, vals = extended_damping(ds["omega"].values, Bm, taper=taper)
    W = _linear_cos_weights(nodes, t)
    K = (2.0 / np.pi) * np.einsum("tn,nij->jit", W, vals)
    da = xr.DataArray(K, dims=("radiating_dof", "influenced_dof", "time"),
                      coords={"radiating_dof": ds["radiating_dof"].values,
                              "influenced_dof": ds["influenced_dof"].values, "time": t},
                      name="radiation_impulse_response",
                      attrs={"units": "radiation_damping units per s", "taper": taper,
                             "damping_projection_change": change,
                             "omega_max": float(ds["omega"].values[-1]),
                             "definition": "K(t) = (2/pi) int_0^inf B(w) cos(w t) dw"})
    return da


def coefficients_from_irf(K, t, omega, added_mass_inf):
    """Ogilvie's relations from a sampled kernel: B(w) = int_0^T K cos, A(w) = A_inf - (1/w) int_0^T K sin.

    Parameters
    ----------
    K : array (n_dof, n_dof, n_t) or DataArray (radiating_dof, influenced_dof, time)
        Kernel samples, in the same [radiating, influenced] layout as :func:`impulse_response`.
    t : array, shape (n_t,)
        Sample times [s] (the last is the truncation time).
    omega : array, shape (n_w,)
        Frequencies [rad/s], > 0.
    added_mass_inf : array (n_dof, n_dof) or DataArray
        A_inf in [radiating, influenced] layout (as ``ds.added_mass_inf``).

    Returns
    -------
    A, B : arrays, shape (n_w, n_dof, n_dof)
        In [omega, radiating, influenced] layout, like ``ds.added_mass``.
    """
    K = np.asarray(getattr(K, "values", K), dtype=float)
    a_inf = np.asarray(getattr(added_mass_inf, "values", added_mass_inf), dtype=float)
    omega = np.asarray(omega, dtype=float)
    Wc = _linear_cos_weights(t, omega)
    Ws = _linear_sin_weights(t, omega)
    B = np.einsum("wt,jit->wji", Wc, K)
    A = a_inf[None] - np.einsum("wt,jit->wji", Ws, K) / omega[:, None, None]
    return A, B


def estimate_added_mass_inf(omega, A, B, *, taper: float = 0.5, t_max: float | None = None):
    """A_inf from A(w) and B(w) by Ogilvie's relation, averaged over the upper half of the band.

    Used when a source has no infinite-frequency solve. A_inf = A(w) + (1/w) int K sin, evaluated at every
    frequency of the upper half of the band and averaged.

    Parameters
    ----------
    omega : array (n_w,) [rad/s]
    A, B : arrays (n_w, n_dof, n_dof), [omega, i, j] layout.

    Returns
    -------
    array (n_dof, n_dof)
    """
    omega = np.asarray(omega, dtype=float)
    if t_max is None:
        t_max = 40.0 * 2 * np.pi / omega[0] if omega[0] > 0 else 200.0
    dt = min(np.pi / (omega[-1] * (1 + taper)) / 4, t_max / 2000)
    t = np.arange(0.0, t_max + dt / 2, dt)
    nodes, vals = extended_damping(omega, np.asarray(B), taper=taper)
    K = (2 / np.pi) * np.einsum("tn,nij->ijt", _linear_cos_weights(nodes, t), vals)
    upper = omega >= 0.5 * omega[-1]
    Ws = _linear_sin_weights(t, omega[upper])
    est = np.asarray(A)[upper] + np.einsum("wt,ijt->wij", Ws, K) / omega[upper, None, None]
    return est.mean(axis=0)


def radiation_convolution_force(K, dt: float, velocity_history):
    """Reference radiation memory force by direct convolution (plain numpy, trapezoid rule).

    F_i(t_n) = -sum_j int_0^{min(t_n, T)} K_ij(tau) v_j(t_n - tau) dtau, with v = 0 before the first sample.

    Parameters
    ----------
    K : array (n_dof, n_dof, n_k) or DataArray
        Kernel sampled at tau_k = k dt, k = 0..n_k-1 (so T = (n_k - 1) dt), [radiating, influenced] layout.
    dt : float
        Sample spacing of both K and the velocity [s].
    velocity_history : array, shape (n_t, n_dof)
        Body velocities [m/s, rad/s] at t_n = n dt.

    Returns
    -------
    array, shape (n_t, n_dof)
        Force on each DOF [N, N m].
    """
    K = np.asarray(getattr(K, "values", K), dtype=float)
    v = np.asarray(velocity_history, dtype=float)
    n_t, n = v.shape
    w = np.ones(K.shape[-1])
    w[0] = w[-1] = 0.5
    F = np.zeros((n_t, n))
    for j in range(n):
        if not np.any(v[:, j]):
            continue
        for i in range(n):
            k = K[j, i] * w
            if not np.any(k):
                continue
            F[:, i] -= dt * np.convolve(v[:, j], k)[:n_t]
    return F
