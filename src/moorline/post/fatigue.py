"""Rainflow counting, S-N and T-N curves, Miner's sum, damage along a line and fatigue life.

Cycle counting is the ASTM E1049-85 rainflow method (section 5.4.4) of the ``rainflow``
package (see ``docs/fatigue.md`` for why that one). Damage follows Miner's rule with an S-N
curve N(S) = alpha / S^m::

    D = sum_i n_i / N(S_i) = sum_i n_i S_i^m / alpha

for rainflow ranges S_i counted n_i times (1 for a full cycle, 0.5 for a half cycle).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import rainflow
import xarray as xr

__all__ = ["SECONDS_PER_YEAR", "SNCurve", "api_chain_tn_curve", "critical_location", "dnv_chain_sn_curve",
           "fatigue_damage", "life_years", "miner_sum", "rainflow_cycles"]

#: seconds in a year of 365.25 days [s]
SECONDS_PER_YEAR = 365.25 * 24.0 * 3600.0


def rainflow_cycles(series, *, periodic: bool = False) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Rainflow cycles of a load history (ASTM E1049-85, 5.4.4).

    Parameters
    ----------
    series : array_like (n,)
        The history (stress [Pa], tension [N], ...).
    periodic : bool
        The history is one or more whole periods of a repeating signal (without the first sample
        repeated at the end). It is then rotated to start at its largest value and closed with
        that value, so every cycle is closed: the count is that of the signal repeated for ever,
        per repetition (the largest cycle, from the maximum to the minimum and back, comes out as
        the standard's two half cycles).

    Returns
    -------
    ranges, means, counts : ndarray
        Range and mean of each cycle (units of the series) and its count (1.0 or 0.5).
    """
    x = np.asarray(series, dtype=float).ravel()
    if x.size < 2:
        z = np.zeros(0)
        return z, z.copy(), z.copy()
    if not np.all(np.isfinite(x)):
        raise ValueError("the history has non-finite values")
    if periodic:
        k = int(np.argmax(x))
        x = np.concatenate([x[k:], x[:k], x[k:k + 1]])
    cyc = list(rainflow.extract_cycles(x))
    if not cyc:
        z = np.zeros(0)
        return z, z.copy(), z.copy()
    a = np.array([c[:3] for c in cyc], dtype=float)
    return a[:, 0], a[:, 1], a[:, 2]


@dataclass(frozen=True)
class SNCurve:
    """An S-N curve N(S) = alpha / S^m, optionally with a second slope and an endurance limit.

    Parameters
    ----------
    alpha : float
        Intercept of the (first) slope, in the curve's stress units: N = alpha S^-m.
    m : float
        (First) inverse slope, used for S >= ``knee`` (or everywhere for a one-slope curve).
    m2 : float, optional
        Inverse slope below the knee (two-slope curve); the curve is continuous at the knee,
        N = alpha (knee)^(m2 - m) S^-m2 there.
    knee : float, optional
        Stress range where the slope changes [curve units].
    endurance : float, optional
        Stress ranges below this cause no damage (endurance or cut-off limit) [curve units].
    unit : float
        What one curve unit is in the units of the histories it is applied to: 1e6 for a curve in
        MPa applied to stresses in Pa; the minimum breaking strength [N] for a T-N curve in terms
        of tension range / MBS applied to tensions in N.
    name : str
        Label for reports.
    """

    alpha: float
    m: float
    m2: float | None = None
    knee: float | None = None
    endurance: float | None = None
    unit: float = 1.0
    name: str = ""

    def __post_init__(self):
        if not (self.alpha > 0 and self.m > 0 and self.unit > 0):
            raise ValueError("alpha, m and unit must be > 0")
        if (self.m2 is None) != (self.knee is None):
            raise ValueError("a two-slope curve needs both m2 and knee")
        if self.m2 is not None and not (self.m2 > 0 and self.knee > 0):
            raise ValueError("m2 and knee must be > 0")
        if self.endurance is not None and not self.endurance >= 0:
            raise ValueError("the endurance limit must be >= 0")

    @classmethod
    def one_slope(cls, alpha: float, m: float, *, endurance: float | None = None, unit: float = 1.0,
                  name: str = "") -> SNCurve:
        """N = alpha S^-m (with ranges below ``endurance`` ignored, if given)."""
        return cls(float(alpha), float(m), endurance=endurance, unit=unit, name=name)

    @classmethod
    def two_slope(cls, alpha: float, m1: float, m2: float, *, knee: float | None = None,
                  knee_cycles: float | None = None, endurance: float | None = None, unit: float = 1.0,
                  name: str = "") -> SNCurve:
        """N = alpha S^-m1 above the knee, continued with slope m2 below it. The knee is given as a
        stress range [curve units] or as the number of cycles where the slope changes (e.g. 1e7)."""
        if (knee is None) == (knee_cycles is None):
            raise ValueError("give the knee as a stress range (knee=) or a number of cycles (knee_cycles=)")
        if knee is None:
            knee = (alpha / knee_cycles) ** (1.0 / m1)
        return cls(float(alpha), float(m1), float(m2), float(knee), endurance, unit, name)

    def cycles_to_failure(self, S) -> np.ndarray:
        """N(S) for ranges ``S`` in the units of the histories (divided by ``unit`` here); inf
        below the endurance limit and for S = 0."""
        s = np.asarray(S, dtype=float) / self.unit
        with np.errstate(divide="ignore", over="ignore"):
            n = self.alpha * s ** (-self.m)
            if self.m2 is not None:
                n = np.where(s < self.knee, self.alpha * self.knee ** (self.m2 - self.m) * s ** (-self.m2), n)
        n = np.where(s > 0.0, n, np.inf)
        if self.endurance is not None:
            n = np.where(s < self.endurance, np.inf, n)
        return n

    def damage(self, ranges, counts=None) -> float:
        """Miner's sum sum(n_i / N(S_i)) of cycles with ``ranges`` (history units) and ``counts``
        (default 1 each)."""
        S = np.asarray(ranges, dtype=float).ravel()
        n = np.ones_like(S) if counts is None else np.asarray(counts, dtype=float).ravel()
        if S.size == 0:
            return 0.0
        return float(np.sum(n / self.cycles_to_failure(S)))

    def describe(self) -> str:
        s = f"{self.name + ': ' if self.name else ''}N = {self.alpha:.4g} S^-{self.m:g}"
        if self.m2 is not None:
            s += f" (S >= {self.knee:.4g}), slope {self.m2:g} below"
        if self.endurance is not None:
            s += f", no damage below S = {self.endurance:.4g}"
        return s + (f"; S in units of {self.unit:.4g}" if self.unit != 1.0 else "")


def miner_sum(series, curve: SNCurve, *, periodic: bool = False) -> float:
    """Miner's damage of one load history: rainflow, then sum n S^m / alpha."""
    ranges, _, counts = rainflow_cycles(series, periodic=periodic)
    return curve.damage(ranges, counts)


def fatigue_damage(history: xr.DataArray, curve: SNCurve, *, dim: str = "time", periodic: bool = False) -> xr.DataArray:
    """Miner's damage of every history in ``history`` along ``dim``.

    Parameters
    ----------
    history : xarray.DataArray
        E.g. stress (time, node, theta) [Pa] or tension (time, segment) [N].
    curve : SNCurve
    dim : str
        The time dimension.
    periodic : bool
        See :func:`rainflow_cycles`.

    Returns
    -------
    xarray.DataArray
        Damage [-] over the record, with the other dimensions and their coordinates. The
        attribute ``duration`` is the record length [s] it applies to (for a periodic record, its
        number of samples times the sample interval).
    """
    h = history.transpose(dim, ...)
    a = h.values.reshape(h.shape[0], -1)
    d = np.array([miner_sum(a[:, j], curve, periodic=periodic) for j in range(a.shape[1])])
    out = xr.DataArray(d.reshape(h.shape[1:]), dims=h.dims[1:],
                       coords={k: v for k, v in h.coords.items() if dim not in v.dims})
    t = np.asarray(h[dim].values, dtype=float) if dim in h.coords else None
    if t is not None and t.size > 1:
        out.attrs["duration"] = float(t.size * (t[1] - t[0])) if periodic else float(t[-1] - t[0])
    out.attrs.update(units="1", long_name="Miner damage", sn_curve=curve.describe(), periodic=int(periodic))
    out.name = "damage"
    return out


def critical_location(damage: xr.DataArray) -> dict:
    """Where the damage is largest.

    Parameters
    ----------
    damage : xarray.DataArray
        Damage (or damage rate) with a ``node`` dimension (coordinate ``node_s``) and optionally
        ``theta``.

    Returns
    -------
    dict
        ``damage`` (the largest value), ``node`` (index within the line), ``s`` [m] (unstretched arc
        length from end A) and ``theta`` [deg] (when there is a theta dimension).
    """
    v = damage.values
    if v.size == 0 or not np.any(np.isfinite(v)):
        raise ValueError("no damage values")
    idx = np.unravel_index(int(np.nanargmax(v)), v.shape)
    at = dict(zip(damage.dims, idx, strict=True))
    out = {"damage": float(v[idx])}
    if "node" in at:
        out["node"] = int(at["node"])
        if "node_s" in damage.coords:
            out["s"] = float(damage.node_s.values[at["node"]])
    if "theta" in at:
        out["theta"] = float(damage.theta.values[at["theta"]])
    return out


def life_years(damage_per_year) -> float | np.ndarray:
    """Fatigue life [years] = 1 / annual damage (inf where there is no damage)."""
    d = np.asarray(damage_per_year, dtype=float)
    with np.errstate(divide="ignore"):
        out = np.where(d > 0.0, 1.0 / np.where(d > 0.0, d, 1.0), np.inf)
    return float(out) if out.ndim == 0 else out


def api_chain_tn_curve(kind: str, mbs: float) -> SNCurve:
    """T-N curve N R^M = K of API RP 2SK for chain, R = tension range / minimum breaking strength.

    Parameters
    ----------
    kind : {'studlink', 'studless'}
        Common studlink chain (M = 3.0, K = 1000) or common studless chain (M = 3.36, K = 370).
    mbs : float
        Minimum breaking strength [N] (the reference of R).
    """
    table = {"studlink": (1000.0, 3.0), "studless": (370.0, 3.36)}
    try:
        K, M = table[kind]
    except KeyError:
        raise ValueError(f"kind must be one of {sorted(table)}, got {kind!r}") from None
    return SNCurve.one_slope(K, M, unit=float(mbs), name=f"API RP 2SK {kind} chain T-N")


def dnv_chain_sn_curve(kind: str, d: float) -> SNCurve:
    """S-N curve of DNV-OS-E301 for chain on the nominal stress T / (2 pi d^2 / 4) in MPa,
    N = a_D S^-3, applied to tensions [N].

    Parameters
    ----------
    kind : {'studlink', 'studless'}
        a_D = 1.2e11 (stud chain) or 6.0e10 (studless chain).
    d : float
        Nominal chain diameter [m].
    """
    table = {"studlink": 1.2e11, "studless": 6.0e10}
    try:
        a = table[kind]
    except KeyError:
        raise ValueError(f"kind must be one of {sorted(table)}, got {kind!r}") from None
    area = 2.0 * math.pi * d * d / 4.0
    return SNCurve.one_slope(a, 3.0, unit=area * 1e6, name=f"DNV-OS-E301 {kind} chain")
