"""Plain descriptions of the sea: waves and currents (spec section 4). No numba, no file formats.

Conventions (MoorDyn's): z points up, z = 0 is the still-water level; a heading is the direction a
wave travels (or a current flows), in **degrees**, measured from +x toward +y (0 = toward +x,
90 = toward +y, 180 = toward -x).

A sea state is a sum of linear (Airy) wave components j of circular frequency omega_j [rad/s],
complex amplitude a_j [m] and heading beta_j::

    zeta(x, y, t) = sum_j Re( a_j exp(i (omega_j t - k_j (x cos beta_j + y sin beta_j))) )
                  = sum_j |a_j| cos(omega_j t - k_j l_j + arg a_j)

i.e. **cosine-phased**: a real positive a_j puts a crest at the origin at t = 0. MoorDyn's
WaveKin = 7 reads the same numbers sine-phased; :func:`moorline.io.waterkin.water_from_options`
converts (a -> -i a), so the kinematics are MoorDyn's either way. k_j comes from the dispersion
relation omega^2 = g k tanh(k h), solved when the description is turned into arrays
(:func:`moorline.core.waterkin.build_water_kinematics`), where the depth and gravity are known.

:class:`Waves` holds the components (whatever produced them: a regular wave, a JONSWAP or
Pierson-Moskowitz spectrum with random phases, a spectrum table, a measured elevation record, a
list) and how to evaluate them (direct summation at every point, or a precomputed space-time grid
with linear interpolation). :class:`Current` holds a velocity table on an (x, y, z, t) grid, from a
single value (uniform current) to MoorDyn's 4-D grid. Neither knows about numba.
"""

from __future__ import annotations

import logging
import math
import secrets
from dataclasses import dataclass, field, replace

import numpy as np

from .types import ModelError

log = logging.getLogger("moorline.model")

__all__ = ["Current", "STRETCHING_MODES", "TIME_WRAPS", "WAVE_EVALUATIONS", "WaveGrid", "Waves", "cos2s_directions",
           "jonswap_spectrum", "pierson_moskowitz_spectrum"]

#: vertical stretching of the Airy fields above the still-water level: Wheeler (MoorDyn), or none
#: (fields evaluated at min(z, 0), i.e. held constant above the still-water level)
STRETCHING_MODES = ("wheeler", "none")
#: how wave kinematics are evaluated: summing the components at every point, interpolating a
#: precomputed space-time grid, or taken from per-node arrays set by a coupling program (WaveKin 1)
WAVE_EVALUATIONS = ("sum", "grid", "external")
#: what a time record (wave grid, time-varying current) does after its last sample: repeat with
#: linear interpolation from the last sample back to the first; repeat as MoorDyn-C does (hold the
#: first sample over the last interval, spec 4.7); or hold the last sample for ever
TIME_WRAPS = ("periodic", "moordyn", "clamp")

#: default number of frequencies of a discretised spectrum
N_COMPONENTS = 200
#: default frequency range of a discretised JONSWAP / Pierson-Moskowitz spectrum, in multiples of
#: the peak frequency (0.4 % of the variance lies above 4 omega_p for gamma = 1, less for gamma > 1)
OMEGA_RANGE_PEAK = (0.5, 4.0)
#: relative tolerance within which component frequencies count as multiples of one base frequency
LADDER_RTOL = 1e-7


# ------------------------------------------------------------------------------------ helpers
def _vector(v, name: str, *, complex_ok: bool = False) -> np.ndarray:
    """A finite 1-D float (or complex) array."""
    try:
        a = np.atleast_1d(np.asarray(v, dtype=complex if complex_ok else float)).ravel()
    except (TypeError, ValueError):
        raise ModelError(f"{name}: expected numbers, got {v!r}") from None
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{name}: all values must be finite")
    return a


def _positive(v, name: str) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ModelError(f"{name}: expected a number, got {v!r}") from None
    if not (math.isfinite(x) and x > 0.0):
        raise ModelError(f"{name} must be a finite number > 0, got {v!r}")
    return x


def _finite(v, name: str) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ModelError(f"{name}: expected a number, got {v!r}") from None
    if not math.isfinite(x):
        raise ModelError(f"{name} must be finite, got {v!r}")
    return x


def _axis(v, name: str) -> np.ndarray:
    """A strictly increasing, finite, non-empty 1-D axis."""
    a = _vector(v, name)
    if a.size == 0:
        raise ModelError(f"{name}: at least one value is needed")
    if np.any(np.diff(a) <= 0.0):
        raise ModelError(f"{name}: values must be strictly increasing")
    return a


def _choice(v, name: str, choices) -> str:
    if v not in choices:
        raise ModelError(f"{name} must be one of {', '.join(map(repr, choices))}; got {v!r}")
    return v


def _rng(seed):
    """(generator, seed actually used); a fresh random seed is drawn (and logged) for None."""
    if seed is None:
        seed = secrets.randbits(32)
        log.info("random wave phases: seed %d drawn (pass seed=%d to reproduce this sea)", seed, seed)
    elif isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ModelError(f"seed must be a whole number >= 0 or None, got {seed!r}")
    return np.random.default_rng(int(seed)), int(seed)


# ---------------------------------------------------------------------------------- spectra
def _jonswap_shape(omega: np.ndarray, wp: float, gamma: float) -> np.ndarray:
    """Unnormalised JONSWAP shape omega^-5 exp(-5/4 (wp/omega)^4) gamma^r (0 at omega <= 0)."""
    w = np.asarray(omega, dtype=float)
    out = np.zeros_like(w)
    pos = w > 0.0
    x = w[pos] / wp
    sigma = np.where(w[pos] <= wp, 0.07, 0.09)
    r = np.exp(-0.5 * ((x - 1.0) / sigma) ** 2)
    out[pos] = x**-5 * np.exp(-1.25 * x**-4) * gamma**r
    return out


def _jonswap_m0(gamma: float) -> float:
    """Integral over omega/wp in (0, inf) of the unnormalised shape (exact 1/5 for gamma = 1)."""
    if gamma == 1.0:
        return 0.2
    from scipy.integrate import quad

    def f(x):
        return float(_jonswap_shape(np.array([x]), 1.0, gamma)[0])

    # the peak enhancement lives within a few sigma of x = 1: integrate the pieces separately
    parts = [quad(f, a, b, limit=200, epsabs=0.0, epsrel=1e-12)[0] for a, b in ((0.0, 0.7), (0.7, 1.0), (1.0, 1.5))]
    parts.append(quad(f, 1.5, np.inf, limit=200, epsabs=0.0, epsrel=1e-12)[0])
    return float(sum(parts))


def jonswap_spectrum(omega, Hs: float, Tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP wave spectrum S(omega) [m^2 s/rad], scaled so that 4 sqrt(m0) = Hs exactly.

    ``S = C Hs^2 wp^4 omega^-5 exp(-5/4 (wp/omega)^4) gamma^exp(-(omega - wp)^2 / (2 sigma^2 wp^2))``
    with sigma = 0.07 (omega <= wp) or 0.09, wp = 2 pi / Tp, and C from the integral over
    (0, inf) (computed numerically; the usual closed form 1 - 0.287 ln(gamma) is an approximation).
    gamma = 1 gives the Pierson-Moskowitz spectrum, C = 5/16.

    Parameters
    ----------
    omega : array_like
        Circular frequencies [rad/s].
    Hs : float
        Significant wave height [m].
    Tp : float
        Peak period [s].
    gamma : float
        Peak enhancement factor [-], >= 1.

    Returns
    -------
    numpy.ndarray
        S(omega), same shape as omega.
    """
    Hs = _positive(Hs, "Hs")
    Tp = _positive(Tp, "Tp")
    gamma = _finite(gamma, "gamma")
    if gamma < 1.0:
        raise ModelError(f"gamma must be >= 1 (1 = Pierson-Moskowitz), got {gamma!r}")
    wp = 2.0 * math.pi / Tp
    shape = _jonswap_shape(np.asarray(omega, dtype=float), wp, gamma)
    return Hs * Hs / 16.0 * shape / (_jonswap_m0(gamma) * wp)


def pierson_moskowitz_spectrum(omega, Hs: float, Tp: float) -> np.ndarray:
    """Pierson-Moskowitz spectrum ``5/16 Hs^2 wp^4 omega^-5 exp(-5/4 (wp/omega)^4)`` [m^2 s/rad]
    (JONSWAP with gamma = 1); omega [rad/s], Hs [m], Tp [s]."""
    return jonswap_spectrum(omega, Hs, Tp, 1.0)


def cos2s_directions(s: float, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Directions splitting the cos-2s spreading function into n parts of equal energy.

    ``D(theta) = C(s) cos^(2s)(theta / 2)`` for theta in (-180, 180] degrees about the mean
    heading; direction m is the (m + 1/2)/n quantile of D.

    Parameters
    ----------
    s : float
        Spreading exponent [-], > 0 (larger = narrower; s = 15 is a common swell value).
    n : int
        Number of directions, >= 1.

    Returns
    -------
    theta : numpy.ndarray (n,)
        Directions relative to the mean heading [deg].
    weight : numpy.ndarray (n,)
        Share of the energy of each direction (all 1/n).
    """
    s = _positive(s, "spreading exponent s")
    if not isinstance(n, (int, np.integer)) or n < 1:
        raise ModelError(f"number of directions must be a whole number >= 1, got {n!r}")
    th = np.linspace(-math.pi, math.pi, 20001)
    d = np.cos(0.5 * th) ** (2.0 * s)
    cdf = np.concatenate(([0.0], np.cumsum(0.5 * (d[1:] + d[:-1]) * np.diff(th))))
    cdf /= cdf[-1]
    q = (np.arange(n) + 0.5) / n
    return np.degrees(np.interp(q, cdf, th)), np.full(n, 1.0 / n)


def _ladder(omega_lo: float, omega_hi: float, n_components, repeat_period) -> tuple[np.ndarray, float]:
    """Frequencies j * d_omega (whole j) covering [omega_lo, omega_hi], and d_omega."""
    if not (0.0 <= omega_lo < omega_hi):
        raise ModelError(f"frequency range must satisfy 0 <= min < max, got ({omega_lo!r}, {omega_hi!r})")
    if repeat_period is not None:
        if n_components is not None:
            raise ModelError("give either n_components or repeat_period, not both")
        dw = 2.0 * math.pi / _positive(repeat_period, "repeat_period")
        j = np.arange(max(1, math.ceil(omega_lo / dw - 1e-9)), math.floor(omega_hi / dw + 1e-9) + 1)
        if j.size == 0:
            raise ModelError(f"repeat_period {repeat_period} s leaves no frequency in [{omega_lo}, {omega_hi}] rad/s")
    else:
        n = N_COMPONENTS if n_components is None else n_components
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 2:
            raise ModelError(f"n_components must be a whole number >= 2, got {n_components!r}")
        dw = (omega_hi - omega_lo) / (n - 1)
        j0 = max(1, round(omega_lo / dw))
        j = np.arange(j0, j0 + n)
    return j * dw, dw


# ------------------------------------------------------------------------------------- grids
@dataclass(eq=False)
class WaveGrid:
    """Space-time grid on which wave kinematics are precomputed and then interpolated linearly
    (MoorDyn's WaveKin 2 and 3, spec 4.4-4.7).

    Values are computed exactly at the grid nodes (an inverse FFT per (x, y, z) column, which needs
    every frequency to be a whole multiple of one base frequency) and interpolated linearly in x, y,
    z' (the stretched height) and t in between; x, y and z are clamped to the grid, time repeats.

    Parameters
    ----------
    x, y, z : array_like or None
        Grid axes [m], strictly increasing. None: built from the bounding box of the nodes given
        to :func:`~moorline.core.waterkin.build_water_kinematics` (x, y: uniform over the box plus
        ``margin``; z: from -depth to 0, finest near the surface).
    dt : float or None
        Target time step [s]; the step used divides the repeat period 2 pi / base_omega into an
        even number of samples. None: ``points_per_wave`` samples per period of the resolved wave.
    nt : int or None
        Exact number of samples per repeat period (even); overrides ``dt``. MoorDyn's WaveKin 2
        uses 2 (n_w - 1).
    points_per_wave : int
        Resolution of the axes and the time step that are not given: grid points per wave length
        (and samples per period) of the shortest wave that matters, the one below whose frequency
        99 % of the variance lies. Linear interpolation of a sinusoid with n points per wave length
        errs by up to about (pi / n)^2 / 2 of its amplitude.
    margin : float
        Horizontal margin [m] added around the node bounding box: for built axes, and when cropping
        given axes to the box (ticks beyond box + margin are dropped; values inside are unchanged).
    time_wrap : {'periodic', 'moordyn'}
        Interpolation over the last interval of the record: toward the first sample (the record is
        periodic), or MoorDyn-C's hold of the first sample (spec 4.7).
    """

    x: np.ndarray | None = None
    y: np.ndarray | None = None
    z: np.ndarray | None = None
    dt: float | None = None
    nt: int | None = None
    points_per_wave: int = 12
    margin: float = 20.0
    time_wrap: str = "periodic"

    def __post_init__(self):
        for name in ("x", "y", "z"):
            v = getattr(self, name)
            if v is not None:
                setattr(self, name, _axis(v, f"wave grid {name} axis"))
        if self.dt is not None:
            self.dt = _positive(self.dt, "wave grid dt")
        if self.nt is not None and (isinstance(self.nt, bool) or not isinstance(self.nt, (int, np.integer))
                                    or self.nt < 2 or self.nt % 2):
            raise ModelError(f"wave grid nt must be an even whole number >= 2, got {self.nt!r}")
        if not isinstance(self.points_per_wave, (int, np.integer)) or self.points_per_wave < 2:
            raise ModelError(f"points_per_wave must be a whole number >= 2, got {self.points_per_wave!r}")
        self.margin = _finite(self.margin, "wave grid margin")
        if self.margin < 0:
            raise ModelError(f"wave grid margin must be >= 0, got {self.margin!r}")
        _choice(self.time_wrap, "wave grid time_wrap", ("periodic", "moordyn"))


# ------------------------------------------------------------------------------------- waves
@dataclass(eq=False)
class Waves:
    """Linear (Airy) waves: a set of components and how to evaluate them.

    Build it with a constructor: :meth:`regular`, :meth:`jonswap`, :meth:`pierson_moskowitz`,
    :meth:`from_spectrum`, :meth:`from_components`, :meth:`from_elevation`, :meth:`external`.

    Parameters
    ----------
    omega : array_like (n,)
        Circular frequencies [rad/s], >= 0 (a 0 rad/s component is a constant level offset).
    amplitude : array_like (n,), complex
        Complex amplitudes [m], cosine-phased (module docstring).
    heading : float or array_like (n,)
        Direction of travel of each component [deg], from +x toward +y.
    ramp_time : float
        Duration [s] of a smooth start, r(t) = (1 - cos(pi t / ramp_time)) / 2 multiplying elevation,
        velocity and pressure (the acceleration gets r du/dt + dr/dt u). 0 (default, as MoorDyn): the
        waves act with full amplitude from t = 0.
    stretching : {'wheeler', 'none'}
        Wheeler stretching (MoorDyn, spec 4.2), or the fields at min(z, 0).
    dynamic_pressure : bool
        Compute the dynamic pressure. MoorDyn's component summation (WaveKin 7) returns 0.
    evaluation : {'sum', 'grid', 'external'}
        Sum the components at every point (exact; cost grows with n), interpolate a precomputed
        space-time ``grid``, or take velocities and accelerations from per-node arrays set by the
        coupling program (MoorDyn's WaveKin 1; no components).
    grid : WaveGrid or None
        The grid for ``evaluation='grid'`` (None: a default :class:`WaveGrid`).
    base_omega : float or None
        Every omega is a whole multiple of it (needed by the grid); the record then repeats with
        period 2 pi / base_omega. None: found from the frequencies when possible.
    seed : int or None
        Seed of the random phases, when random phases were drawn (provenance).
    source : str
        What produced the components, for messages and provenance.
    spectrum : tuple of two arrays or None
        (omega [rad/s], S [m^2 s/rad]) the components were drawn from, for checks.
    """

    omega: np.ndarray
    amplitude: np.ndarray
    heading: np.ndarray | float = 0.0
    ramp_time: float = 0.0
    stretching: str = "wheeler"
    dynamic_pressure: bool = True
    evaluation: str = "sum"
    grid: WaveGrid | None = None
    base_omega: float | None = None
    seed: int | None = None
    source: str = ""
    spectrum: tuple | None = field(default=None, repr=False)

    def __post_init__(self):
        self.omega = _vector(self.omega, "wave frequencies omega")
        self.amplitude = _vector(self.amplitude, "wave amplitudes", complex_ok=True)
        head = _vector(self.heading, "wave headings")
        n = self.omega.size
        if head.size == 1 and n != 1:
            head = np.full(n, head[0])
        if self.amplitude.size != n or head.size != n:
            raise ModelError(f"waves: omega ({n}), amplitude ({self.amplitude.size}) and heading ({head.size}) "
                             "must have the same length")
        self.heading = head
        if np.any(self.omega < 0.0):
            raise ModelError("wave frequencies omega must be >= 0 rad/s")
        self.ramp_time = _finite(self.ramp_time, "ramp_time")
        if self.ramp_time < 0.0:
            raise ModelError(f"ramp_time must be >= 0 s, got {self.ramp_time!r}")
        _choice(self.stretching, "stretching", STRETCHING_MODES)
        _choice(self.evaluation, "evaluation", WAVE_EVALUATIONS)
        self.dynamic_pressure = bool(self.dynamic_pressure)
        if self.evaluation == "external":
            if n:
                raise ModelError("external waves (set per node by the coupling program) take no components")
        elif n == 0:
            raise ModelError("waves need at least one component (use None for still water)")
        if self.grid is not None and not isinstance(self.grid, WaveGrid):
            raise ModelError(f"grid must be a WaveGrid, got {type(self.grid).__name__}")
        if self.base_omega is None:
            self.base_omega = _find_base(self.omega)
        else:
            self.base_omega = _positive(self.base_omega, "base_omega")
            m = self.omega / self.base_omega
            if np.any(np.abs(m - np.round(m)) > LADDER_RTOL * np.maximum(1.0, m)):
                raise ModelError(f"base_omega = {self.base_omega!r} rad/s: not every frequency is a whole multiple")
        if self.evaluation == "grid" and self.base_omega is None:
            raise ModelError("grid evaluation needs every frequency to be a whole multiple of one base frequency "
                             "(j * d_omega); these frequencies are not: use evaluation='sum'")

    # ---------------------------------------------------------------- derived quantities
    @property
    def n_components(self) -> int:
        """Number of components."""
        return int(self.omega.size)

    @property
    def hs(self) -> float:
        """Spectral significant wave height 4 sqrt(m0) [m], m0 = sum |a|^2 / 2 over omega > 0."""
        a = np.abs(self.amplitude[self.omega > 0.0])
        return float(4.0 * math.sqrt(0.5 * np.sum(a * a)))

    @property
    def repeat_period(self) -> float:
        """Period [s] after which the sea repeats exactly (inf when there is no base frequency)."""
        return math.inf if self.base_omega is None else 2.0 * math.pi / self.base_omega

    # ---------------------------------------------------------------------- constructors
    @classmethod
    def regular(cls, height: float, period: float, *, heading: float = 0.0, phase: float = 0.0, **options) -> Waves:
        """A regular Airy wave ``zeta = H/2 cos(2 pi t / T - k l + phase)``.

        Parameters
        ----------
        height : float
            Wave height H, crest to trough [m].
        period : float
            Period T [s].
        heading : float
            Direction of travel [deg].
        phase : float
            Phase [deg]; 0 puts a crest at the origin at t = 0.
        **options
            Other fields of :class:`Waves` (ramp_time, stretching, evaluation, grid, ...).
        """
        H = _positive(height, "wave height")
        T = _positive(period, "wave period")
        a = 0.5 * H * np.exp(1j * math.radians(_finite(phase, "phase")))
        options.setdefault("source", f"regular wave H={H:g} m T={T:g} s heading={heading:g} deg")
        return cls(omega=[2.0 * math.pi / T], amplitude=[a], heading=_finite(heading, "heading"), **options)

    @classmethod
    def from_spectrum(cls, omega, S, *, heading: float = 0.0, seed: int | None = None, n_components=None,
                      omega_range=None, repeat_period=None, spreading=None, n_directions: int = 16,
                      **options) -> Waves:
        """Random-phase components of a one-sided spectrum given as a table.

        Frequencies are j d_omega (whole j) over ``omega_range``; |a_j| = sqrt(2 S(omega_j) d_omega)
        with S interpolated linearly in the table (0 outside it); phases uniform in [0, 2 pi) from
        ``seed``. Deterministic amplitudes, so the spectral Hs of the components is that of the
        discretised spectrum; the record repeats after 2 pi / d_omega.

        Parameters
        ----------
        omega, S : array_like (m,)
            Spectrum table: frequencies [rad/s] (strictly increasing) and S [m^2 s/rad] (>= 0).
        heading : float
            Mean direction of travel [deg].
        seed : int or None
            Random seed of the phases (None: a fresh seed, logged and kept in :attr:`seed`).
        n_components : int or None
            Number of frequencies (default 200). Exclusive with ``repeat_period``.
        omega_range : (float, float) or None
            Frequency range [rad/s]; default: the table's range.
        repeat_period : float or None
            Instead of ``n_components``: d_omega = 2 pi / repeat_period [s] (a 3 h record needs
            about 10 800 omega_width / (2 pi) components).
        spreading : float or None
            cos-2s spreading exponent s; None: long-crested (one direction).
        n_directions : int
            Directions per frequency with spreading (equal-energy quantiles, :func:`cos2s_directions`),
            each with its own random phase.
        **options
            Other fields of :class:`Waves`.
        """
        w_tab = _axis(omega, "spectrum omega")
        s_tab = _vector(S, "spectrum S")
        if s_tab.size != w_tab.size:
            raise ModelError(f"spectrum table: omega ({w_tab.size}) and S ({s_tab.size}) differ in length")
        if np.any(s_tab < 0.0):
            raise ModelError("spectrum S values must be >= 0")
        lo, hi = (w_tab[0], w_tab[-1]) if omega_range is None else omega_range
        w, dw = _ladder(_finite(lo, "omega_range min"), _finite(hi, "omega_range max"), n_components, repeat_period)
        s = np.interp(w, w_tab, s_tab, left=0.0, right=0.0)
        options.setdefault("source", f"spectrum table ({w_tab.size} rows)")
        return cls._random_phases(w, dw, s, heading, seed, spreading, n_directions, (w_tab, s_tab), options)

    @classmethod
    def jonswap(cls, Hs: float, Tp: float, gamma: float = 3.3, *, heading: float = 0.0, seed: int | None = None,
                n_components=None, omega_range=None, repeat_period=None, spreading=None, n_directions: int = 16,
                **options) -> Waves:
        """Random-phase components of a JONSWAP spectrum (:func:`jonswap_spectrum`).

        Parameters
        ----------
        Hs : float
            Significant wave height [m].
        Tp : float
            Peak period [s].
        gamma : float
            Peak enhancement factor [-] (3.3 North Sea; 1 = Pierson-Moskowitz).
        heading, seed, n_components, repeat_period, spreading, n_directions, **options
            As :meth:`from_spectrum`.
        omega_range : (float, float) or None
            Frequency range [rad/s]; default (0.5, 4) times the peak frequency 2 pi / Tp.
        """
        Hs = _positive(Hs, "Hs")
        Tp = _positive(Tp, "Tp")
        wp = 2.0 * math.pi / Tp
        lo, hi = (OMEGA_RANGE_PEAK[0] * wp, OMEGA_RANGE_PEAK[1] * wp) if omega_range is None else omega_range
        w, dw = _ladder(_finite(lo, "omega_range min"), _finite(hi, "omega_range max"), n_components, repeat_period)
        s = jonswap_spectrum(w, Hs, Tp, gamma)
        name = "Pierson-Moskowitz" if gamma == 1.0 else f"JONSWAP gamma={gamma:g}"
        options.setdefault("source", f"{name} Hs={Hs:g} m Tp={Tp:g} s heading={heading:g} deg")
        fine = np.linspace(max(w[0] - dw, 1e-6), w[-1] + dw, 4001)
        return cls._random_phases(w, dw, s, heading, seed, spreading, n_directions,
                                  (fine, jonswap_spectrum(fine, Hs, Tp, gamma)), options)

    @classmethod
    def pierson_moskowitz(cls, Hs: float, Tp: float, **kwargs) -> Waves:
        """Random-phase components of a Pierson-Moskowitz spectrum (JONSWAP with gamma = 1);
        keyword arguments as :meth:`jonswap`."""
        return cls.jonswap(Hs, Tp, 1.0, **kwargs)

    @classmethod
    def _random_phases(cls, w, dw, s, heading, seed, spreading, n_directions, spectrum, options) -> Waves:
        heading = _finite(heading, "heading")
        rng, seed = _rng(seed)
        if spreading is None:
            theta, share = np.zeros(1), np.ones(1)
        else:
            theta, share = cos2s_directions(spreading, n_directions)
        phase = rng.uniform(0.0, 2.0 * math.pi, size=(w.size, theta.size))
        amp = np.sqrt(2.0 * s * dw)[:, None] * np.sqrt(share)[None, :] * np.exp(1j * phase)
        omega = np.repeat(w, theta.size)
        head = (heading + np.tile(theta, w.size))
        options.setdefault("base_omega", dw)
        return cls(omega=omega, amplitude=amp.ravel(), heading=head, seed=seed, spectrum=spectrum, **options)

    @classmethod
    def from_components(cls, omega, amplitude, heading=0.0, *, phasing: str = "cosine", **options) -> Waves:
        """Waves from a list of components.

        Parameters
        ----------
        omega : array_like (n,)
            Circular frequencies [rad/s], >= 0, any order, repeats allowed (other headings).
        amplitude : array_like (n,), complex
            Complex amplitudes [m].
        heading : float or array_like (n,)
            Directions of travel [deg].
        phasing : {'cosine', 'sine'}
            ``zeta = sum |a| cos(theta + arg a)`` (moorline) or ``sum |a| sin(theta + arg a)``
            (MoorDyn's WaveKin 7 reading of wave_frequencies.txt; stored as -i a).
        **options
            Other fields of :class:`Waves`.
        """
        _choice(phasing, "phasing", ("cosine", "sine"))
        a = _vector(amplitude, "wave amplitudes", complex_ok=True)
        if phasing == "sine":
            a = -1j * a
        options.setdefault("source", f"{a.size} wave components")
        return cls(omega=omega, amplitude=a, heading=heading, **options)

    @classmethod
    def from_elevation(cls, t, zeta, *, dt=None, heading: float = 0.0, cutoff=None, **options) -> Waves:
        """Waves reproducing a measured elevation record at the origin (MoorDyn's WaveKin 3).

        The record is resampled linearly at ``dt`` from t = 0 to its last time (values before its
        first time are held), trimmed to an even number n of samples, and Fourier-transformed; each
        frequency m 2 pi / (n dt) becomes a component travelling along ``heading``, so the sea
        repeats the (resampled) record with period n dt at the origin and shifts it by k l
        elsewhere.

        Parameters
        ----------
        t, zeta : array_like (m,)
            Times [s] (strictly increasing, >= 0) and elevations [m].
        dt : float or None
            Resampling step [s]; None: the median step of ``t``.
        heading : float
            Direction of travel [deg].
        cutoff : float or None
            Drop components above this frequency [rad/s] (MoorDyn: pi rad/s = 0.5 Hz).
        **options
            Other fields of :class:`Waves`. The ``grid`` (default :class:`WaveGrid`) gets the
            record's own time samples (nt = n) unless it sets nt.
        """
        tt = _axis(t, "elevation record times")
        zz = _vector(zeta, "elevation record values")
        if zz.size != tt.size:
            raise ModelError(f"elevation record: {tt.size} times but {zz.size} elevations")
        if tt[0] < 0.0:
            raise ModelError(f"elevation record times must be >= 0 s, first is {tt[0]!r}")
        if tt.size < 2:
            raise ModelError("elevation record needs at least 2 samples")
        step = float(np.median(np.diff(tt))) if dt is None else _positive(dt, "dt")
        n = int(math.floor(tt[-1] / step * (1.0 + 1e-12))) + 1
        if n % 2:
            n -= 1
        if n < 2:
            raise ModelError(f"elevation record of {tt[-1]:g} s is shorter than two steps of {step:g} s")
        samples = np.interp(np.arange(n) * step, tt, zz)
        X = np.fft.rfft(samples)
        a = 2.0 * X / n
        a[0] *= 0.5
        a[-1] *= 0.5
        dw = 2.0 * math.pi / (n * step)
        w = np.arange(a.size) * dw
        if cutoff is not None:
            a[w > _positive(cutoff, "cutoff")] = 0.0
        options.setdefault("source", f"elevation record ({tt.size} samples, resampled to {n} x {step:g} s)")
        grid = options.get("grid")
        if grid is None:
            options["grid"] = WaveGrid(nt=n)
        elif grid.nt is None:
            options["grid"] = replace(grid, nt=n)
        return cls(omega=w, amplitude=a, heading=heading, base_omega=dw, **options)

    @classmethod
    def external(cls, **options) -> Waves:
        """Velocities and accelerations set per node by the coupling program (MoorDyn's WaveKin 1);
        elevation and dynamic pressure are 0."""
        options.setdefault("source", "external (set per node by the coupling program)")
        return cls(omega=np.zeros(0), amplitude=np.zeros(0), heading=np.zeros(0), evaluation="external", **options)


def _find_base(omega: np.ndarray) -> float | None:
    """The largest d such that every omega is a whole multiple of it (within LADDER_RTOL), among
    the smallest positive frequency and the smallest gap divided by 1 ... 1000; None if none."""
    w = np.unique(omega[omega > 0.0])
    if w.size == 0:
        return None
    gaps = np.diff(w)
    found = []
    for base in (float(w[0]), float(gaps.min()) if gaps.size else float(w[0])):
        for j in range(1, 1001):
            m = w / (base / j)
            if np.all(np.abs(m - np.round(m)) <= LADDER_RTOL * np.maximum(1.0, m)):
                found.append(base / j)
                break
    return max(found) if found else None


# ----------------------------------------------------------------------------------- currents
@dataclass(eq=False)
class Current:
    """Current velocity on a rectilinear (x, y, z, t) table, interpolated linearly in each axis
    and clamped at the x, y and z edges (spec 4.7-4.8). An axis of one value makes the current
    uniform along it; one time makes it steady.

    The current is not zeroed above the still-water level or the wave surface (MoorDyn-C): a
    point above the table's highest z gets the top value.

    Build it with :meth:`uniform`, :meth:`profile`, :meth:`dynamic_profile` or :meth:`grid`.

    Parameters
    ----------
    velocity : array_like (nx, ny, nz, nt, 3)
        Velocity (ux, uy, uz) [m/s] at the table nodes.
    x, y, z, t : array_like
        Axes [m], [m], [m], [s], strictly increasing; t >= 0. A non-uniform time axis, or one not
        starting at 0, is resampled from t = 0 at its smallest interval (MoorDyn).
    include_acceleration : bool
        Give dU/dt of the piecewise-linear time interpolation (steps at the samples). MoorDyn
        sets the current acceleration to 0 (default False).
    time_wrap : {'periodic', 'moordyn', 'clamp'}
        After the last time: repeat (interpolating back to the first sample), repeat as MoorDyn-C
        (spec 4.7), or hold the last sample.
    on_wave_grid : bool
        With waves evaluated on a grid: sample this current once at the wave grid's nodes and
        times and interpolate it with the waves, in the stretched height (MoorDyn's
        ``UnifyCurrentGrid = 1``). False: evaluate it separately at the true z.
    source : str
        Where it came from, for messages.
    """

    velocity: np.ndarray
    x: np.ndarray = field(default_factory=lambda: np.zeros(1))
    y: np.ndarray = field(default_factory=lambda: np.zeros(1))
    z: np.ndarray = field(default_factory=lambda: np.zeros(1))
    t: np.ndarray = field(default_factory=lambda: np.zeros(1))
    include_acceleration: bool = False
    time_wrap: str = "periodic"
    on_wave_grid: bool = False
    source: str = ""

    def __post_init__(self):
        for name in ("x", "y", "z", "t"):
            setattr(self, name, _axis(getattr(self, name), f"current {name} axis"))
        if self.t[0] < 0.0:
            raise ModelError(f"current times must be >= 0 s, first is {self.t[0]!r}")
        shape = (self.x.size, self.y.size, self.z.size, self.t.size, 3)
        try:
            v = np.asarray(self.velocity, dtype=float)
        except (TypeError, ValueError):
            raise ModelError("current velocity: expected numbers") from None
        if v.shape != shape:
            raise ModelError(f"current velocity must have shape (nx, ny, nz, nt, 3) = {shape}, got {v.shape}")
        if not np.all(np.isfinite(v)):
            raise ModelError("current velocity values must be finite")
        self.velocity = np.ascontiguousarray(v)
        self.include_acceleration = bool(self.include_acceleration)
        self.on_wave_grid = bool(self.on_wave_grid)
        _choice(self.time_wrap, "current time_wrap", TIME_WRAPS)

    @property
    def is_steady(self) -> bool:
        """One time sample."""
        return self.t.size == 1

    @property
    def is_uniform(self) -> bool:
        """The same velocity everywhere and always."""
        return self.velocity.shape[:4] == (1, 1, 1, 1)

    @classmethod
    def uniform(cls, speed: float, heading: float = 0.0, *, vertical: float = 0.0, **options) -> Current:
        """A current of the same velocity everywhere, at all times.

        Parameters
        ----------
        speed : float
            Horizontal speed [m/s], >= 0.
        heading : float
            Direction the water flows toward [deg], from +x toward +y.
        vertical : float
            Vertical velocity [m/s].
        **options
            Other fields of :class:`Current`.
        """
        s = _finite(speed, "current speed")
        if s < 0.0:
            raise ModelError(f"current speed must be >= 0 (use the heading for the direction), got {speed!r}")
        b = math.radians(_finite(heading, "current heading"))
        v = np.array([s * math.cos(b), s * math.sin(b), _finite(vertical, "vertical current")])
        options.setdefault("source", f"uniform current {s:g} m/s toward {heading:g} deg")
        return cls(velocity=v.reshape(1, 1, 1, 1, 3), **options)

    @classmethod
    def profile(cls, z, ux, uy=None, uz=None, **options) -> Current:
        """A steady current varying with depth only, linear between the levels and clamped outside.

        Parameters
        ----------
        z : array_like (nz,)
            Levels [m] (z up, strictly increasing).
        ux, uy, uz : array_like (nz,)
            Velocity components [m/s] at the levels (None: 0).
        **options
            Other fields of :class:`Current`.
        """
        zz = _axis(z, "current profile z")
        comps = []
        for name, u in (("ux", ux), ("uy", uy), ("uz", uz)):
            c = np.zeros(zz.size) if u is None else _vector(u, f"current profile {name}")
            if c.size != zz.size:
                raise ModelError(f"current profile: {name} has {c.size} values for {zz.size} levels")
            comps.append(c)
        v = np.stack(comps, axis=-1).reshape(1, 1, zz.size, 1, 3)
        options.setdefault("source", f"current profile ({zz.size} levels)")
        return cls(velocity=v, z=zz, **options)

    @classmethod
    def dynamic_profile(cls, t, z, ux, uy=None, uz=None, **options) -> Current:
        """A depth profile varying in time (MoorDyn's Currents = 2).

        Parameters
        ----------
        t : array_like (nt,)
            Times [s], strictly increasing, >= 0.
        z : array_like (nz,)
            Levels [m], strictly increasing.
        ux, uy, uz : array_like (nt, nz)
            Velocity components [m/s] (None: 0).
        **options
            Other fields of :class:`Current`.
        """
        tt = _axis(t, "current times")
        zz = _axis(z, "current profile z")
        comps = []
        for name, u in (("ux", ux), ("uy", uy), ("uz", uz)):
            if u is None:
                c = np.zeros((tt.size, zz.size))
            else:
                c = np.asarray(u, dtype=float)
                if c.shape != (tt.size, zz.size):
                    raise ModelError(f"current profile: {name} must have shape (nt, nz) = {(tt.size, zz.size)}, "
                                     f"got {c.shape}")
            comps.append(c.T)  # (nz, nt)
        v = np.stack(comps, axis=-1).reshape(1, 1, zz.size, tt.size, 3)
        options.setdefault("source", f"time-varying current profile ({tt.size} times x {zz.size} levels)")
        return cls(velocity=v, z=zz, t=tt, **options)

    @classmethod
    def grid(cls, x, y, z, t, velocity, **options) -> Current:
        """A current on a 4-D (x, y, z, t) grid (MoorDyn's Currents = 5); velocity of shape
        (nx, ny, nz, nt, 3) [m/s]."""
        options.setdefault("source", "4-D current grid")
        return cls(velocity=velocity, x=x, y=y, z=z, t=t, **options)
