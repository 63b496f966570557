"""Excitation force transfer functions interpolated in frequency and heading (never extrapolated silently)."""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

log = logging.getLogger("moorline.hydro")


def _heading_bracket(betas: np.ndarray, beta: float):
    """Indices and weight (k0, k1, w1) for linear interpolation in heading, periodic when the set covers the
    circle (uniform gaps including the wrap-around one), else only inside [min, max]."""
    order = np.argsort(betas)
    b = betas[order]
    if b.size == 1:
        if np.isclose(np.mod(beta - b[0] + np.pi, 2 * np.pi) - np.pi, 0.0, atol=1e-9):
            return order[0], order[0], 0.0
        raise ValueError(f"wave direction {beta:.6g} rad is not in the computed set {b.tolist()} rad")
    gaps = np.diff(b)
    wrap = 2 * np.pi - (b[-1] - b[0])
    periodic = wrap > 1e-9 and wrap <= gaps.max() * (1 + 1e-6)
    if periodic:
        x = b[0] + np.mod(beta - b[0], 2 * np.pi)
        if x <= b[-1] + 1e-12:
            k = min(int(np.searchsorted(b, x, side="right")) - 1, b.size - 2)
            k = max(k, 0)
            w = (x - b[k]) / (b[k + 1] - b[k])
            return order[k], order[k + 1], float(np.clip(w, 0.0, 1.0))
        w = (x - b[-1]) / wrap
        return order[-1], order[0], float(w)
    x = beta
    if not (b[0] - 1e-9 <= x <= b[-1] + 1e-9):
        # try the same direction written differently (e.g. 2 pi + beta)
        x = b[0] + np.mod(beta - b[0], 2 * np.pi)
        if x > b[-1] + 1e-9:
            raise ValueError(f"wave direction {beta:.6g} rad is outside the computed headings "
                             f"[{b[0]:.6g}, {b[-1]:.6g}] rad, which do not cover the circle: no extrapolation")
    k = int(np.clip(np.searchsorted(b, x, side="right") - 1, 0, b.size - 2))
    w = (x - b[k]) / (b[k + 1] - b[k])
    return order[k], order[k + 1], float(np.clip(w, 0.0, 1.0))


def excitation_transfer(ds: xr.Dataset, omega, wave_direction: float, *, variable: str = "excitation_force",
                        outside: str = "raise") -> np.ndarray:
    """Excitation force per unit wave amplitude at given frequencies and one heading.

    Linear interpolation of the complex values (real and imaginary parts) in omega and in heading; headings are
    periodic in 2 pi when the computed set covers the circle, otherwise a heading outside the set raises.

    Parameters
    ----------
    ds : xarray.Dataset
        Coefficient Dataset.
    omega : array, shape (n_w,)
        Frequencies [rad/s].
    wave_direction : float
        Direction the waves travel toward [rad] (Capytaine/WAMIT convention).
    variable : str
        ``excitation_force``, ``Froude_Krylov_force`` or ``diffraction_force``.
    outside : {"raise", "zero"}
        Frequencies outside [omega_1, omega_N]: raise a ValueError, or return zero there with a logged warning.

    Returns
    -------
    array, complex, shape (n_w, n_dof)
        Capytaine convention: force(t) = Re{X a exp(-i omega t)} for a wave of amplitude a at the global origin.
    """
    if outside not in ("raise", "zero"):
        raise ValueError(f"outside must be 'raise' or 'zero', got {outside!r}")
    w = np.atleast_1d(np.asarray(omega, dtype=float))
    X = ds[variable].transpose("omega", "wave_direction", "influenced_dof").values
    wd = ds["omega"].values
    k0, k1, wb = _heading_bracket(ds["wave_direction"].values, float(wave_direction))
    Xb = (1 - wb) * X[:, k0] + wb * X[:, k1]
    inside = (w >= wd[0] * (1 - 1e-12)) & (w <= wd[-1] * (1 + 1e-12))
    if not inside.all():
        bad = w[~inside]
        msg = (f"{bad.size} frequencies outside the computed band [{wd[0]:.6g}, {wd[-1]:.6g}] rad/s "
               f"(e.g. {bad[0]:.6g})")
        if outside == "raise":
            raise ValueError(msg + ": no extrapolation (pass outside='zero' to get zero there)")
        log.warning("excitation_transfer: %s set to zero", msg)
    out = np.zeros((w.size, Xb.shape[1]), dtype=complex)
    wi = np.clip(w[inside], wd[0], wd[-1])
    for i in range(Xb.shape[1]):
        out[inside, i] = np.interp(wi, wd, Xb[:, i].real) + 1j * np.interp(wi, wd, Xb[:, i].imag)
    return out
