"""Sea states: scatter diagrams, their probability weighting, and the buoy motion of a sea state.

A sea state acts on a line through the prescribed motion of the buoy it hangs from (and, in a
sweep, optionally as waves on the line too, :func:`moorline.studies.sea_waves`).
:func:`buoy_motion` makes that motion under a stated RAO assumption:
the buoy is a small point absorber that follows the water surface, so its hang-off point moves
with the linear-wave surface particle at the buoy (heave RAO 1, surge RAO coth(k h), no pitch):

    heave  zeta(t) = sum_j a_j cos(w_j t + phi_j)
    surge  xi(t)   = sum_j a_j coth(k_j h) sin(w_j t + phi_j)     along the wave heading

with k_j from the dispersion relation w^2 = g k tanh(k h). A regular wave of height H and period
T is the single component a = H/2 with phase -pi/2, so heave = (H/2) sin(2 pi t / T) and the
surge lags it by a quarter period (the buoy moves with the wave under a crest). A JONSWAP sea is
a sum of components with random phases from a seed (:func:`wave_components`). Both are ramped in
by r(t) = (1 - cos(pi t / T_ramp)) / 2, the ramp of :class:`moorline.model.water.Waves`, so the
motion starts from rest at the deck position and matches the same components acting as waves on
the lines.

Probabilities of a scatter diagram weight the damage rate of each sea state:
D_year = sum_i p_i d_i * SECONDS_PER_YEAR for damage rates d_i [1/s]; life = 1 / max D_year.
"""

from __future__ import annotations

import csv
import logging
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr

from .fatigue import SECONDS_PER_YEAR

log = logging.getLogger("moorline")

__all__ = ["ScatterDiagram", "SeaState", "buoy_motion", "jonswap_spectrum", "lifetime_damage", "to_scatter_grid",
           "tp_from_tz", "wave_components", "wavenumber"]

G = 9.80665


@dataclass(frozen=True)
class SeaState:
    """One sea state.

    Parameters
    ----------
    Hs : float
        Significant wave height [m].
    Tz : float
        Mean zero-crossing period [s].
    kind : {'regular', 'jonswap'}
        'regular': the regular-wave equivalent H = Hs/sqrt(2), T = Tz (as in the W4P cable study);
        'jonswap': an irregular JONSWAP sea with Tp from Tz (:func:`tp_from_tz`).
    heading : float
        Direction the waves travel to, from +x toward +y [deg].
    gamma : float
        JONSWAP peak enhancement factor [-].
    seed : int
        Random phases of a JONSWAP sea.
    probability : float
        Probability of occurrence [-] (1 for a single design sea state).
    """

    Hs: float
    Tz: float
    kind: str = "regular"
    heading: float = 0.0
    gamma: float = 3.3
    seed: int = 1
    probability: float = 1.0

    def __post_init__(self):
        if self.kind not in ("regular", "jonswap"):
            raise ValueError(f"sea-state kind must be 'regular' or 'jonswap', got {self.kind!r}")
        if not (self.Hs >= 0 and self.Tz > 0):
            raise ValueError(f"need Hs >= 0 and Tz > 0, got Hs = {self.Hs}, Tz = {self.Tz}")

    @property
    def H(self) -> float:
        """Regular-wave equivalent height Hs/sqrt(2) [m]."""
        return self.Hs / math.sqrt(2.0)

    @property
    def T(self) -> float:
        """Regular-wave equivalent period Tz [s] (also the period of the analysis window)."""
        return self.Tz

    @property
    def Tp(self) -> float:
        """JONSWAP peak period [s]."""
        return tp_from_tz(self.Tz, self.gamma)


def tp_from_tz(Tz: float, gamma: float = 3.3) -> float:
    """Peak period of a JONSWAP spectrum with zero-crossing period Tz (DNV-RP-C205, 3.5.5):
    Tz / Tp = 0.6673 + 0.05037 gamma - 0.006230 gamma^2 + 0.0003341 gamma^3."""
    return Tz / (0.6673 + 0.05037 * gamma - 0.006230 * gamma**2 + 0.0003341 * gamma**3)


def jonswap_spectrum(w, Hs: float, Tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP spectral density S(w) [m^2 s/rad] (DNV-RP-C205 3.5.5.1, sigma 0.07 / 0.09)."""
    w = np.asarray(w, dtype=float)
    wp = 2.0 * math.pi / Tp
    sigma = np.where(w <= wp, 0.07, 0.09)
    with np.errstate(divide="ignore", over="ignore", invalid="ignore"):
        pm = 5.0 / 16.0 * Hs**2 * wp**4 * w**-5.0 * np.exp(-1.25 * (w / wp) ** -4.0)
        s = (1.0 - 0.287 * math.log(gamma)) * pm * gamma ** np.exp(-0.5 * ((w - wp) / (sigma * wp)) ** 2)
    return np.where(w > 0.0, s, 0.0)


def wavenumber(w, depth: float, g: float = G) -> np.ndarray:
    """k solving w^2 = g k tanh(k h) [1/m] (deep water when ``depth`` <= 0)."""
    w = np.atleast_1d(np.asarray(w, dtype=float))
    k = w * w / g
    if depth <= 0:
        return k
    k = np.maximum(k, w / math.sqrt(g * depth))
    for _ in range(50):  # Newton, monotone from above the shallow-water guess
        th = np.tanh(k * depth)
        f = g * k * th - w * w
        df = g * th + g * k * depth * (1.0 - th * th)
        k_new = k - f / df
        if np.all(np.abs(k_new - k) <= 1e-14 * k):
            return k_new
        k = k_new
    return k


def wave_components(sea: SeaState, duration: float, n_components: int = 200):
    """The wave components of a sea state: elevation at the reference point sum a cos(w t + phi).

    Parameters
    ----------
    sea : SeaState
    duration : float
        Record length [s]: a JONSWAP sea's frequency step is at most 2 pi / duration, so the record
        does not repeat within it.
    n_components : int
        Least number of components of a JONSWAP sea (frequencies up to 5 times the peak).

    Returns
    -------
    a, w, phi : ndarray
        Amplitudes [m], circular frequencies [rad/s], phases [rad].
    """
    if sea.kind == "regular":
        return np.array([0.5 * sea.H]), np.array([2.0 * math.pi / sea.T]), np.array([-0.5 * math.pi])
    # equal frequency steps with the record length below the repeat period 2 pi / dw
    wp = 2.0 * math.pi / sea.Tp
    w_hi = 5.0 * wp
    dw = min(w_hi / n_components, 2.0 * math.pi / max(duration, 1e-9))
    w = (np.arange(int(math.ceil(w_hi / dw))) + 0.5) * dw
    w = w[w >= 0.3 * wp]
    S = jonswap_spectrum(w, sea.Hs, sea.Tp, sea.gamma)
    m0 = float(np.sum(S) * dw)
    a = np.sqrt(2.0 * S * dw) * (sea.Hs / (4.0 * math.sqrt(m0)) if m0 > 0 else 0.0)  # exact Hs = 4 sqrt(m0)
    phi = np.random.default_rng(sea.seed).uniform(0.0, 2.0 * math.pi, w.size)
    return a, w, phi


def buoy_motion(sea: SeaState, x0, *, duration: float, dt: float, depth: float, ramp: float,
                g: float = G, n_components: int = 200, labels=None) -> tuple[np.ndarray, np.ndarray]:
    """Samples of the coupled-DOF motion of a buoy in a sea state (see the module docstring).

    Parameters
    ----------
    sea : SeaState
    x0 : array_like (n_dof,)
        Coupled DOFs at rest [m, rad]; every coupled object moves by the same translation (one
        rigid buoy, no rotation).
    duration : float
        Length of the record [s].
    dt : float
        Sample interval [s].
    depth : float
        Water depth [m] for the dispersion relation (<= 0: deep water).
    ramp : float
        Ramp-in time [s]: r(t) = (1 - cos(pi t / ramp)) / 2 up to ``ramp``, then 1.
    g : float
        Gravity [m/s^2].
    n_components : int
        Number of wave components of a JONSWAP sea.
    labels : list of str, optional
        Names of the coupled DOFs (:attr:`moorline.System.coupled_dof_labels`): those ending in
        ``_x``, ``_y``, ``_z`` are translated, the angles stay. Default: all DOFs are points
        (x, y, z of each).

    Returns
    -------
    t : ndarray (n,)
        Times [s] from 0.
    X : ndarray (n, n_dof)
        Coupled DOF positions [m].
    """
    x0 = np.asarray(x0, dtype=float).ravel()
    if labels is None:
        if x0.size % 3:
            raise ValueError(f"{x0.size} coupled DOFs are not points (3 each): give their labels")
        labels = [c for _ in range(x0.size // 3) for c in ("_x", "_y", "_z")]
    if len(labels) != x0.size:
        raise ValueError(f"{len(labels)} labels for {x0.size} coupled DOFs")
    axis = np.array([{"_x": 0, "_y": 1, "_z": 2}.get(str(lab)[-2:], -1) for lab in labels])
    n = int(math.ceil(duration / dt - 1e-9))
    t = np.arange(n + 1) * dt
    a, w, phi = wave_components(sea, duration, n_components)
    k = wavenumber(w, depth, g)
    coth = 1.0 / np.tanh(k * depth) if depth > 0 else np.ones_like(k)
    arg = np.outer(t, w) + phi
    heave = np.cos(arg) @ a
    surge = np.sin(arg) @ (a * coth)
    if ramp > 0:
        r = 0.5 * (1.0 - np.cos(np.pi * np.clip(t / ramp, 0.0, 1.0)))
        heave *= r
        surge *= r
    h = math.radians(sea.heading)
    d = np.column_stack([surge * math.cos(h), surge * math.sin(h), heave, np.zeros_like(t)])
    return t, x0[None, :] + d[:, axis]


class ScatterDiagram:
    """A wave scatter diagram: probability of occurrence per (Hs, Tz) cell.

    Parameters
    ----------
    Hs : array_like (n_hs,)
        Bin centres of the significant wave height [m].
    Tz : array_like (n_tz,)
        Bin centres of the zero-crossing period [s].
    P : array_like (n_hs, n_tz)
        Probabilities (any scale; see ``normalise``).
    normalise : bool
        Scale the probabilities to sum to 1 (a table rounded to units of 1e-5 rarely sums to
        exactly 1e5); the scale factor is logged.
    source : str
    """

    def __init__(self, Hs, Tz, P, *, normalise: bool = True, source: str = ""):
        self.Hs = np.asarray(Hs, dtype=float).ravel()
        self.Tz = np.asarray(Tz, dtype=float).ravel()
        P = np.asarray(P, dtype=float)
        if P.shape != (self.Hs.size, self.Tz.size):
            raise ValueError(f"probability table is {P.shape}, expected ({self.Hs.size}, {self.Tz.size})")
        if np.any(P < 0) or not np.all(np.isfinite(P)):
            raise ValueError("probabilities must be finite and >= 0")
        total = float(P.sum())
        if total <= 0:
            raise ValueError("the scatter diagram has no probability")
        if normalise:
            if abs(total - 1.0) > 1e-12:
                log.info("scatter diagram %s: probabilities sum to %.6g; normalised to 1", source, total)
            P = P / total
        self.P = P
        self.source = source

    @classmethod
    def from_csv(cls, path, *, normalise: bool = True) -> ScatterDiagram:
        """Read a table: '#' comment lines, a header row whose first cell is a label (e.g.
        ``Hs\\Tz``) followed by the Tz bin centres [s], then one row per Hs bin centre [m] with
        its probabilities."""
        path = Path(path)
        rows = [r for r in csv.reader(line for line in path.read_text().splitlines()
                                      if line.strip() and not line.lstrip().startswith("#"))]
        if len(rows) < 2:
            raise ValueError(f"{path}: expected a header row and at least one Hs row")
        try:
            Tz = [float(v) for v in rows[0][1:]]
            Hs = [float(r[0]) for r in rows[1:]]
            P = [[float(v) for v in r[1:]] for r in rows[1:]]
        except ValueError as e:
            raise ValueError(f"{path}: {e}") from None
        if any(len(r) != len(Tz) for r in P):
            raise ValueError(f"{path}: every Hs row needs {len(Tz)} probabilities")
        return cls(Hs, Tz, P, normalise=normalise, source=str(path))

    def sea_states(self, *, kind: str = "regular", min_probability: float = 0.0, **kwargs) -> list[SeaState]:
        """The sea states of the cells with probability > ``min_probability`` (zero cells are
        always skipped), in order of increasing Hs then Tz; ``kwargs`` go to :class:`SeaState`."""
        out = []
        for i in np.argsort(self.Hs):
            for j in np.argsort(self.Tz):
                p = float(self.P[i, j])
                if p > 0.0 and p > min_probability:
                    out.append(SeaState(float(self.Hs[i]), float(self.Tz[j]), kind=kind, probability=p, **kwargs))
        skipped = float(self.P[(self.P > 0) & (self.P <= min_probability)].sum())
        if skipped > 0:
            log.info("scatter diagram: %d cells with probability <= %g skipped (%.3g of the total)",
                     int(((self.P > 0) & (self.P <= min_probability)).sum()), min_probability, skipped)
        return out

    def to_dataarray(self) -> xr.DataArray:
        """The probabilities as a DataArray (Hs, Tz)."""
        return xr.DataArray(self.P, dims=("Hs", "Tz"), coords={"Hs": self.Hs, "Tz": self.Tz}, name="probability")

    def __repr__(self):
        return (f"ScatterDiagram({self.Hs.size} Hs x {self.Tz.size} Tz, {int((self.P > 0).sum())} non-zero cells"
                f"{', ' + self.source if self.source else ''})")


def lifetime_damage(damage_rate: xr.DataArray, probability, *, dim: str = "sea_state") -> xr.DataArray:
    """Probability-weighted annual damage D_year = sum_i p_i d_i * SECONDS_PER_YEAR.

    Parameters
    ----------
    damage_rate : xarray.DataArray
        Damage per second of each sea state [1/s], with dimension ``dim``.
    probability : array_like or xarray.DataArray
        Probability of each sea state along ``dim``.

    Returns
    -------
    xarray.DataArray
        Damage per year [1/year] (the fatigue life is its inverse).
    """
    p = probability if isinstance(probability, xr.DataArray) else xr.DataArray(np.asarray(probability), dims=dim)
    out = (damage_rate * p).sum(dim) * SECONDS_PER_YEAR
    out.name = "damage_per_year"
    out.attrs.update(units="1/year", long_name="probability-weighted damage per year")
    return out



def to_scatter_grid(values: xr.DataArray, *, dim: str = "sea_state") -> xr.DataArray:
    """Arrange per-sea-state values (with coordinates ``Hs`` and ``Tz`` along ``dim``) on the
    (Hs, Tz) grid of the scatter diagram; cells without a sea state are NaN."""
    Hs = np.unique(values.Hs.values)
    Tz = np.unique(values.Tz.values)
    v = values.transpose(dim, ...)
    grid = np.full((Hs.size, Tz.size) + v.shape[1:], np.nan)
    i = np.searchsorted(Hs, v.Hs.values)
    j = np.searchsorted(Tz, v.Tz.values)
    grid[i, j] = v.values
    out = xr.DataArray(grid, dims=("Hs", "Tz") + v.dims[1:], coords={"Hs": Hs, "Tz": Tz}, name=values.name,
                       attrs=values.attrs)
    out.Hs.attrs["units"] = "m"
    out.Tz.attrs["units"] = "s"
    return out
