"""Water kinematics kernels: fluid velocity, acceleration, surface elevation and dynamic pressure
at a point (spec section 4).

:func:`build_water_kinematics` turns the Python descriptions of :mod:`moorline.model.water`
(:class:`~moorline.model.water.Waves`, :class:`~moorline.model.water.Current`) into a
:class:`WaterKin` tuple of flat arrays; the compiled kernels :func:`fluid_at` (one point) and
:func:`fluid_at_points` (n points, the fast way) evaluate it. Output layout (``out`` of length
:data:`N_OUT` = 8 per point)::

    out[0:3]  U      fluid velocity (ux, uy, uz) [m/s], waves + current
    out[3:6]  dU/dt  fluid acceleration [m/s^2], waves + current (0 for MoorDyn's currents)
    out[6]    zeta   wave surface elevation above the point [m]
    out[7]    p_dyn  wave dynamic pressure [Pa]

Wave modes (``WaterKin.wave_mode``):

* :data:`WAVES_NONE` -- still water; with no current either, every kernel only zeroes ``out``.
* :data:`WAVES_SUM` -- the components are summed at the point (MoorDyn's WaveKin 7): exact,
  cost proportional to the number of components (see ``benchmarks/bench_waterkin.py``).
* :data:`WAVES_GRID` -- values precomputed on an (x, y, z, t) grid by one inverse FFT per grid
  column, interpolated linearly in x, y, the stretched height z' and t (MoorDyn's WaveKin 2 and
  3, spec 4.4-4.7); cost independent of the number of components.
* :data:`WAVES_EXTERNAL` -- U and dU/dt of node i are ``U_ext[i]``, ``Ud_ext[i]``, arrays the
  coupling program fills in place (MoorDyn's WaveKin 1); zeta = p_dyn = 0.

Linear (Airy) fields of a component of frequency w, wave number k, complex amplitude a (cosine
phasing, :mod:`moorline.model.water`) and heading beta, at the stretched height z' <= 0, with
theta = w t - k (x cos beta + y sin beta), C = Re(a e^{i theta}), S = Im(a e^{i theta})::

    zeta = C                               p_dyn = rho g C cosh(k(z'+h)) / cosh(k h)
    u_h  = w C Ch (cos beta, sin beta)     du_h/dt = -w^2 S Ch (cos beta, sin beta)
    u_z  = -w S Sh                         du_z/dt = -w^2 C Sh
    Ch = cosh(k(z'+h)) / sinh(k h),        Sh = sinh(k(z'+h)) / sinh(k h)

The depth ratios are evaluated from e^{k z'} and e^{-2 k h} in a form valid for every k h (no
overflow in deep water); MoorDyn switches to e^{k z'} for k h > 89.4 -- the same values to
round-off. Wheeler stretching (spec 4.2): a point at height z with local seabed z_b and surface
zeta is evaluated at ``z' = min(h (z - z_b) / (zeta - z_b) - h, 0)``.

Wave numbers solve omega^2 = g k tanh(k h) by Newton's method to machine precision
(``dispersion='exact'``, default). MoorDyn uses J. N. Newman's one-step approximation
(``dispersion='newman'``), good to about 7 significant digits (1.0e-7 at worst, measured): the
phase k x of a 6 m wave 400 m away then differs by 4e-5 rad.
"""

from __future__ import annotations

import logging
import math
from typing import NamedTuple

import numpy as np

from ..model.types import Bathymetry
from ..model.water import Current, WaveGrid, Waves
from .jit import derivative_kernel, kernel
from .numerics import bracket
from .seabed import seabed_at

log = logging.getLogger("moorline.core")

__all__ = ["CURRENT_GRID", "CURRENT_NONE", "CURRENT_UNIFORM", "N_OUT", "OUT_DUDT", "OUT_PDYN", "OUT_U", "OUT_ZETA",
           "STRETCH_NONE", "STRETCH_WHEELER", "WAVES_EXTERNAL", "WAVES_GRID", "WAVES_NONE", "WAVES_SUM", "WRAP_CLAMP",
           "WRAP_MOORDYN", "WRAP_PERIODIC", "WaterKin", "build_water_kinematics", "fluid_at", "fluid_at_points",
           "fluid_kinematics", "still_water", "wave_number", "wave_number_newman", "wave_numbers"]

# wave modes
WAVES_NONE = 0
WAVES_SUM = 1
WAVES_GRID = 2
WAVES_EXTERNAL = 3
# current modes
CURRENT_NONE = 0
CURRENT_UNIFORM = 1
CURRENT_GRID = 2
# vertical stretching
STRETCH_NONE = 0
STRETCH_WHEELER = 1
# time records after their last sample (model.water.TIME_WRAPS)
WRAP_PERIODIC = 0
WRAP_MOORDYN = 1
WRAP_CLAMP = 2
_WRAPS = {"periodic": WRAP_PERIODIC, "moordyn": WRAP_MOORDYN, "clamp": WRAP_CLAMP}

# output layout
OUT_U = 0
OUT_DUDT = 3
OUT_ZETA = 6
OUT_PDYN = 7
N_OUT = 8
#: fields per wave-grid node: ux, uy, uz, ax, ay, az, p_dyn
N_GRID_FIELDS = 7

#: default ceiling on the memory of a precomputed wave grid [bytes]
MAX_GRID_BYTES = 4 * 2**30
#: fraction of the wave variance that grid axes built from a bounding box resolve
RESOLVED_VARIANCE = 0.99
#: growth of the vertical spacing with depth of built wave-grid z axes (per level)
Z_GROWTH = 1.12


class WaterKin(NamedTuple):
    """Water kinematics as arrays for the kernels (build with :func:`build_water_kinematics` or
    :func:`still_water`). Arrays of a mode that is not used are empty.

    Scalars: ``wave_mode`` (WAVES_*), ``current_mode`` (CURRENT_*), ``g`` [m/s^2], ``rho``
    [kg/m^3], ``depth`` h [m] (dispersion, depth ratios, stretching), ``stretch`` (STRETCH_*),
    ``pdyn`` (1: compute the dynamic pressure of summed components), ``ramp`` [s] (0: none).
    """

    wave_mode: int
    current_mode: int
    g: float
    rho: float
    depth: float
    stretch: int
    pdyn: int
    ramp: float
    # components (WAVES_SUM), shape (nc,)
    c_omega: np.ndarray  # circular frequency [rad/s]
    c_are: np.ndarray  # Re a [m]
    c_aim: np.ndarray  # Im a [m]
    c_heading: np.ndarray  # direction of travel [rad]
    c_cosb: np.ndarray  # cos heading
    c_sinb: np.ndarray  # sin heading
    c_k: np.ndarray  # wave number [rad/m]
    c_ish: np.ndarray  # 1 / (1 - exp(-2 k h)) (0 where k = 0)
    c_ich: np.ndarray  # 1 / (1 + exp(-2 k h))
    c_e2h: np.ndarray  # exp(-2 k h)
    c_work: np.ndarray  # (2, nc) scratch of the sum (kernels allocate nothing: they run without NRT)
    # wave grid (WAVES_GRID)
    wg_x: np.ndarray  # (nx,) [m]
    wg_y: np.ndarray  # (ny,) [m]
    wg_z: np.ndarray  # (nz,) stretched height z' [m]
    wg_dt: float  # sample interval [s]
    wg_wrap: int  # WRAP_PERIODIC or WRAP_MOORDYN
    wg_zeta: np.ndarray  # (nx, ny, nt) elevation [m]
    wg_kin: np.ndarray  # (nx, ny, nz, nt, 7): ux, uy, uz [m/s], ax, ay, az [m/s^2], p_dyn [Pa]
    # current
    cu_u: np.ndarray  # (3,) uniform current [m/s] (CURRENT_UNIFORM)
    cg_x: np.ndarray  # (nx,) current grid axes [m] (CURRENT_GRID)
    cg_y: np.ndarray  # (ny,)
    cg_z: np.ndarray  # (nz,) true height z [m]
    cg_dt: float  # sample interval [s]
    cg_wrap: int  # WRAP_*
    cg_dudt: int  # 1: dU/dt of the time interpolation, 0: zero acceleration (MoorDyn)
    cg_vel: np.ndarray  # (nx, ny, nz, nt, 3) [m/s]
    # seabed height grid for stretching (empty: flat at -depth); z (ny, nx) as model.Bathymetry
    sb_x: np.ndarray
    sb_y: np.ndarray
    sb_z: np.ndarray
    # external kinematics (WAVES_EXTERNAL), filled in place by the coupling program
    U_ext: np.ndarray  # (n, 3) [m/s]
    Ud_ext: np.ndarray  # (n, 3) [m/s^2]


# ------------------------------------------------------------------------------- dispersion
@kernel
def wave_number(omega, g, h):
    """Wave number k >= 0 [rad/m] with omega^2 = g k tanh(k h), to machine precision.

    Newton's method on x = k h, x tanh(x) = omega^2 h / g, from Eckart's estimate (within 5 %);
    it stops when a step changes x by less than 2 ulp. k = 0 for omega = 0; k = omega^2 / g when
    tanh(k h) = 1 in double precision. A negative omega gives -k (as MoorDyn).

    Parameters
    ----------
    omega : float
        Circular frequency [rad/s].
    g : float
        Gravity [m/s^2].
    h : float
        Water depth [m], > 0.
    """
    if omega == 0.0:
        return 0.0
    sign = 1.0 if omega > 0.0 else -1.0
    y = omega * omega * h / g
    if y > 20.0:  # x >= y, so tanh(x) rounds to 1
        return sign * omega * omega / g
    x = y / math.sqrt(math.tanh(y))
    for _ in range(60):
        th = math.tanh(x)
        f = x * th - y
        dx = f / (th + x * (1.0 - th * th))
        x -= dx
        if abs(dx) <= 4.4e-16 * x:
            break
    return sign * x / h


@kernel
def wave_number_newman(omega, g, h):
    """MoorDyn's wave number: J. N. Newman's high-order estimate and one quadratic Newton step
    (about 7 significant digits). Same arguments as :func:`wave_number`."""
    if omega == 0.0:
        return 0.0
    c = omega * omega * h / g
    if c <= 2.0:
        x0 = math.sqrt(c) * (1.0 + c * (0.169 + 0.031 * c))
    else:
        e2 = math.exp(-2.0 * c)
        x0 = c * (1.0 + e2 * (2.0 - 12.0 * e2))
    if c <= 4.8:
        c2 = c * c - x0 * x0
        a = 1.0 / (c - c2)
        b = a * (0.5 * math.log((x0 + c) / (x0 - c)) - x0)
        k = (x0 - b * c2 * (1.0 + a * b * c * x0)) / h
    else:
        k = x0 / h
    return k if omega > 0.0 else -k


def wave_numbers(omega, g: float, h: float, method: str = "exact") -> np.ndarray:
    """Wave numbers [rad/m] of the frequencies ``omega`` [rad/s] in depth ``h`` [m] with gravity
    ``g`` [m/s^2]; ``method`` 'exact' (:func:`wave_number`) or 'newman' (MoorDyn's estimate)."""
    if method not in ("exact", "newman"):
        raise ValueError(f"dispersion method must be 'exact' or 'newman', got {method!r}")
    f = wave_number if method == "exact" else wave_number_newman
    w = np.asarray(omega, dtype=float)
    return np.array([f(float(v), float(g), float(h)) for v in w.ravel()]).reshape(w.shape)


# --------------------------------------------------------------------------- small kernels
@derivative_kernel
def _cell(a, v):
    """(i0, i1, f) for linear interpolation in the increasing axis ``a`` at ``v``, clamped."""
    n = a.size
    if n == 1 or v <= a[0]:
        return 0, 0, 0.0
    if v >= a[n - 1]:
        return n - 1, n - 1, 0.0
    i = bracket(a, 0, n - 1, v)
    return i, i + 1, (v - a[i]) / (a[i + 1] - a[i])


@derivative_kernel
def _time_cell(t, dt, nt, wrap):
    """(i0, i1, f) of a record of nt samples spaced dt from t = 0 (spec 4.7).

    WRAP_PERIODIC: sample index modulo nt, the last interval runs from sample nt-1 to sample 0;
    WRAP_MOORDYN: MoorDyn-C -- upper index floor(t/dt) + 1 wrapped into [0, nt), lower index one
    less but not below 0 (so the first sample is held over the last interval);
    WRAP_CLAMP: the first sample before t = 0, the last one after the end.
    """
    if nt == 1:
        return 0, 0, 0.0
    q = t / dt
    fl = math.floor(q)
    f = q - fl
    n = int(fl)
    if wrap == WRAP_CLAMP:
        if n < 0:
            return 0, 0, 0.0
        if n >= nt - 1:
            return nt - 1, nt - 1, 0.0
        return n, n + 1, f
    if wrap == WRAP_MOORDYN:
        i1 = (n + 1) % nt
        i0 = i1 - 1 if i1 > 0 else 0
        return i0, i1, f
    i0 = n % nt
    return i0, (i0 + 1) % nt, f


@derivative_kernel
def _ramp(t, tr):
    """Ramp factor r(t) = (1 - cos(pi t / tr)) / 2 on [0, tr] and its derivative [1/s]."""
    if tr <= 0.0 or t >= tr:
        return 1.0, 0.0
    if t <= 0.0:
        return 0.0, 0.0
    a = math.pi / tr
    return 0.5 * (1.0 - math.cos(a * t)), 0.5 * a * math.sin(a * t)


@derivative_kernel
def _stretched(z, zeta, zb, h, stretch):
    """Height z' [m] at which the Airy fields are evaluated for a point at height z with the
    local seabed at zb and the surface at zeta (Wheeler), or min(z, 0) without stretching."""
    if stretch == STRETCH_WHEELER:
        d = zeta - zb
        zs = h * (z + (-zb)) / d - h if d > 0.0 else 0.0
    else:
        zs = z
    return zs if zs < 0.0 else 0.0


# Hot-path layout, from measurements: a compiled function that receives the WaterKin tuple pays
# reference counting on every array in it at each call (0.14-0.36 us; 0.56 us when inlined by
# numba), and a loop whose body holds calls for several modes runs several times slower than a
# loop with one call, even when the other branches are never taken. So the tuple is unpacked once
# per call of a public kernel, each mode gets its own loop over the points, and the per-point
# workers take plain arrays and scalars.


@derivative_kernel
def _waves_sum(t, x, y, z, zb, h, stretch, ramp, pdyn, rhog, omega, are, aim, cosb, sinb, kk, ish, ich, e2h, o, work):
    """Sum of the components at one point into o[0:8] (overwrites); ``work`` (2, nc) scratch.

    Depth ratios with one exponential per component: e = exp(k z'), and
    exp(-2 k (z' + h)) = exp(-2 k h) / e^2 (0 in deep water, where exp(-2 k h) underflows)."""
    nc = omega.size
    zeta = 0.0
    for j in range(nc):
        th = omega[j] * t - kk[j] * (x * cosb[j] + y * sinb[j])
        ct = math.cos(th)
        st = math.sin(th)
        c = are[j] * ct - aim[j] * st
        work[0, j] = c
        work[1, j] = are[j] * st + aim[j] * ct
        zeta += c
    r, rd = _ramp(t, ramp)
    zeta *= r
    zs = _stretched(z, zeta, zb, h, stretch)
    ux = 0.0
    uy = 0.0
    uz = 0.0
    ax = 0.0
    ay = 0.0
    az = 0.0
    p = 0.0
    for j in range(nc):
        k = kk[j]
        c = work[0, j]
        s = work[1, j]
        if k == 0.0:  # omega = 0: a level offset, no motion
            p += c
            continue
        w = omega[j]
        e = math.exp(k * zs)
        ee = e * e
        if e2h[j] == 0.0:
            em = -1.0
        elif ee > 0.0:
            em = e2h[j] / ee - 1.0
        else:  # far below the seabed
            em = math.expm1(-2.0 * k * (zs + h))
        ch = e * (2.0 + em) * ish[j]
        sh = -e * em * ish[j]
        uh = w * c * ch
        ah = -w * w * s * ch
        ux += uh * cosb[j]
        uy += uh * sinb[j]
        ax += ah * cosb[j]
        ay += ah * sinb[j]
        uz -= w * s * sh
        az -= w * w * c * sh
        p += c * e * (2.0 + em) * ich[j]
    if pdyn == 0:
        p = 0.0
    o[0] = r * ux
    o[1] = r * uy
    o[2] = r * uz
    o[3] = r * ax + rd * ux
    o[4] = r * ay + rd * uy
    o[5] = r * az + rd * uz
    o[6] = zeta
    o[7] = r * rhog * p


@derivative_kernel
def _waves_grid(t, x, y, z, zb, h, stretch, ramp, gx, gy, gz, dt, wrap, gzeta, gkin, o):
    """Interpolation in the wave grid at one point into o[0:8] (overwrites)."""
    nt = gzeta.shape[2]
    ix0, ix1, fx = _cell(gx, x)
    iy0, iy1, fy = _cell(gy, y)
    it0, it1, ft = _time_cell(t, dt, nt, wrap)
    zeta = 0.0
    for a in range(2):
        ix = ix0 if a == 0 else ix1
        wx = 1.0 - fx if a == 0 else fx
        for b in range(2):
            iy = iy0 if b == 0 else iy1
            wy = wx * (1.0 - fy if b == 0 else fy)
            zeta += wy * ((1.0 - ft) * gzeta[ix, iy, it0] + ft * gzeta[ix, iy, it1])
    r, rd = _ramp(t, ramp)
    zeta *= r
    zs = _stretched(z, zeta, zb, h, stretch)
    iz0, iz1, fz = _cell(gz, zs)
    for f in range(N_GRID_FIELDS):
        o[f] = 0.0
    for a in range(2):
        ix = ix0 if a == 0 else ix1
        wx = 1.0 - fx if a == 0 else fx
        for b in range(2):
            iy = iy0 if b == 0 else iy1
            wy = wx * (1.0 - fy if b == 0 else fy)
            for c in range(2):
                iz = iz0 if c == 0 else iz1
                wz = wy * (1.0 - fz if c == 0 else fz)
                for d in range(2):
                    it = it0 if d == 0 else it1
                    wt = wz * (1.0 - ft if d == 0 else ft)
                    if wt != 0.0:
                        for f in range(N_GRID_FIELDS):
                            o[f] += wt * gkin[ix, iy, iz, it, f]
    # o[0:6] = U, dU/dt, o[6] = p_dyn: move p_dyn to its slot and apply the ramp
    p = o[6]
    for i in range(3):
        o[3 + i] = r * o[3 + i] + rd * o[i]
        o[i] *= r
    o[6] = zeta
    o[7] = r * p


@derivative_kernel
def _add_current_grid(t, x, y, z, cx, cy, cz, dt, wrap, dudt, vel, o):
    """Add the gridded current velocity (and acceleration) at one point to o[0:6]."""
    nt = vel.shape[3]
    ix0, ix1, fx = _cell(cx, x)
    iy0, iy1, fy = _cell(cy, y)
    iz0, iz1, fz = _cell(cz, z)
    it0, it1, ft = _time_cell(t, dt, nt, wrap)
    v0x = 0.0
    v0y = 0.0
    v0z = 0.0
    v1x = 0.0
    v1y = 0.0
    v1z = 0.0
    for a in range(2):
        ix = ix0 if a == 0 else ix1
        wx = 1.0 - fx if a == 0 else fx
        for b in range(2):
            iy = iy0 if b == 0 else iy1
            wy = wx * (1.0 - fy if b == 0 else fy)
            for c in range(2):
                iz = iz0 if c == 0 else iz1
                w = wy * (1.0 - fz if c == 0 else fz)
                if w != 0.0:
                    v0x += w * vel[ix, iy, iz, it0, 0]
                    v0y += w * vel[ix, iy, iz, it0, 1]
                    v0z += w * vel[ix, iy, iz, it0, 2]
                    v1x += w * vel[ix, iy, iz, it1, 0]
                    v1y += w * vel[ix, iy, iz, it1, 1]
                    v1z += w * vel[ix, iy, iz, it1, 2]
    o[0] += (1.0 - ft) * v0x + ft * v1x
    o[1] += (1.0 - ft) * v0y + ft * v1y
    o[2] += (1.0 - ft) * v0z + ft * v1z
    if dudt != 0 and it0 != it1:
        o[3] += (v1x - v0x) / dt
        o[4] += (v1y - v0y) / dt
        o[5] += (v1z - v0z) / dt


@derivative_kernel
def _seabed_z(sb_x, sb_y, sb_z, h, x, y):
    """Local seabed height [m] for stretching: the grid's, or -h without one."""
    if sb_x.size == 0:
        return -h
    return seabed_at(sb_x, sb_y, sb_z, h, x, y)[0]


# ----------------------------------------------------------------------- loops over points
@derivative_kernel
def _sum_rows(t, r, sb_x, sb_y, sb_z, h, stretch, ramp, pdyn, rhog, omega, are, aim, cosb, sinb, kk, ish, ich, e2h,
              out, work):
    for i in range(r.shape[0]):
        zb = _seabed_z(sb_x, sb_y, sb_z, h, r[i, 0], r[i, 1])
        _waves_sum(t, r[i, 0], r[i, 1], r[i, 2], zb, h, stretch, ramp, pdyn, rhog, omega, are, aim, cosb, sinb,
                   kk, ish, ich, e2h, out[i], work)


@derivative_kernel
def _grid_rows(t, r, sb_x, sb_y, sb_z, h, stretch, ramp, gx, gy, gz, dt, wrap, gzeta, gkin, out):
    for i in range(r.shape[0]):
        zb = _seabed_z(sb_x, sb_y, sb_z, h, r[i, 0], r[i, 1])
        _waves_grid(t, r[i, 0], r[i, 1], r[i, 2], zb, h, stretch, ramp, gx, gy, gz, dt, wrap, gzeta, gkin, out[i])


@derivative_kernel
def _current_rows(t, r, cx, cy, cz, dt, wrap, dudt, vel, out):
    for i in range(r.shape[0]):
        _add_current_grid(t, r[i, 0], r[i, 1], r[i, 2], cx, cy, cz, dt, wrap, dudt, vel, out[i])


# --------------------------------------------------------------------------- public kernels
@derivative_kernel
def fluid_at(t, x, y, z, K, out):
    """Water kinematics at one point.

    Each call costs a few hundred ns on top of the physics (the tuple's arrays are reference
    counted at every call of a compiled function that takes it): for many points call
    :func:`fluid_at_points` once, and skip the call altogether in still water
    (``K.wave_mode == WAVES_NONE and K.current_mode == CURRENT_NONE``).

    Parameters
    ----------
    t : float
        Time [s].
    x, y, z : float
        Position [m] (z up, 0 at the still-water level).
    K : WaterKin
        The sea (:func:`build_water_kinematics`).
    out : numpy.ndarray (8,)
        Filled with U (3) [m/s], dU/dt (3) [m/s^2], zeta [m], p_dyn [Pa] (module docstring).
        External waves (WaveKin 1) are per node: :func:`fluid_at_points` gives them; here they
        contribute 0.
    """
    wm = K.wave_mode
    if wm == WAVES_SUM or wm == WAVES_GRID:
        zb = _seabed_z(K.sb_x, K.sb_y, K.sb_z, K.depth, x, y)
        if wm == WAVES_SUM:
            _waves_sum(t, x, y, z, zb, K.depth, K.stretch, K.ramp, K.pdyn, K.rho * K.g, K.c_omega, K.c_are, K.c_aim,
                       K.c_cosb, K.c_sinb, K.c_k, K.c_ish, K.c_ich, K.c_e2h, out, K.c_work)
        else:
            _waves_grid(t, x, y, z, zb, K.depth, K.stretch, K.ramp, K.wg_x, K.wg_y, K.wg_z, K.wg_dt, K.wg_wrap,
                        K.wg_zeta, K.wg_kin, out)
    else:
        for j in range(N_OUT):
            out[j] = 0.0
    if K.current_mode == CURRENT_UNIFORM:
        for j in range(3):
            out[j] += K.cu_u[j]
    elif K.current_mode == CURRENT_GRID:
        _add_current_grid(t, x, y, z, K.cg_x, K.cg_y, K.cg_z, K.cg_dt, K.cg_wrap, K.cg_dudt, K.cg_vel, out)


@derivative_kernel
def fluid_at_points(t, r, K, out):
    """Water kinematics at n points (nodes): one call per derivative evaluation.

    Still water only zeroes ``out`` (about 1 ns per point).

    Parameters
    ----------
    t : float
        Time [s].
    r : numpy.ndarray (n, 3)
        Positions [m]; row i is node i (the row of ``K.U_ext`` with external waves).
    K : WaterKin
        The sea.
    out : numpy.ndarray (n, 8)
        Row i filled as the ``out`` of :func:`fluid_at` for point i; with external waves
        U = ``K.U_ext[i]`` and dU/dt = ``K.Ud_ext[i]`` (plus the current), zeta = p_dyn = 0.
    """
    n = r.shape[0]
    wm = K.wave_mode
    h = K.depth
    if wm == WAVES_SUM or wm == WAVES_GRID:
        if wm == WAVES_SUM:
            _sum_rows(t, r, K.sb_x, K.sb_y, K.sb_z, h, K.stretch, K.ramp, K.pdyn, K.rho * K.g, K.c_omega, K.c_are,
                      K.c_aim, K.c_cosb, K.c_sinb, K.c_k, K.c_ish, K.c_ich, K.c_e2h, out, K.c_work)
        else:
            _grid_rows(t, r, K.sb_x, K.sb_y, K.sb_z, h, K.stretch, K.ramp, K.wg_x, K.wg_y, K.wg_z, K.wg_dt,
                       K.wg_wrap, K.wg_zeta, K.wg_kin, out)
    else:
        for i in range(n):
            for j in range(N_OUT):
                out[i, j] = 0.0
        if wm == WAVES_EXTERNAL:
            if K.U_ext.shape[0] < n or K.Ud_ext.shape[0] < n:
                raise ValueError("external wave kinematics: U_ext / Ud_ext have fewer rows than there are points")
            for i in range(n):
                for j in range(3):
                    out[i, j] = K.U_ext[i, j]
                    out[i, 3 + j] = K.Ud_ext[i, j]
    if K.current_mode == CURRENT_UNIFORM:
        for i in range(n):
            for j in range(3):
                out[i, j] += K.cu_u[j]
    elif K.current_mode == CURRENT_GRID:
        _current_rows(t, r, K.cg_x, K.cg_y, K.cg_z, K.cg_dt, K.cg_wrap, K.cg_dudt, K.cg_vel, out)


def fluid_kinematics(K: WaterKin, t: float, points) -> np.ndarray:
    """Python convenience: kinematics at ``points`` (array_like (n, 3) or (3,)) [m] at time ``t``
    [s]; returns a new (n, 8) array laid out as :func:`fluid_at_points` (a (8,) array for a single
    point)."""
    p = np.asarray(points, dtype=float)
    single = p.ndim == 1
    p = np.ascontiguousarray(p.reshape(-1, 3))
    out = np.empty((p.shape[0], N_OUT))
    fluid_at_points(float(t), p, K, out)
    return out[0] if single else out


# ----------------------------------------------------------------------------- construction
def _empty(*shape) -> np.ndarray:
    return np.zeros(shape, dtype=np.float64)


def still_water(depth: float, g: float, rho: float = 1025.0) -> WaterKin:
    """No waves and no current (every kernel only zeroes its output).

    Parameters
    ----------
    depth : float
        Still-water depth [m].
    g : float
        Gravity [m/s^2].
    rho : float
        Water density [kg/m^3].
    """
    return WaterKin(
        wave_mode=WAVES_NONE, current_mode=CURRENT_NONE, g=float(g), rho=float(rho), depth=float(depth),
        stretch=STRETCH_WHEELER, pdyn=1, ramp=0.0,
        c_omega=_empty(0), c_are=_empty(0), c_aim=_empty(0), c_heading=_empty(0), c_cosb=_empty(0),
        c_sinb=_empty(0), c_k=_empty(0), c_ish=_empty(0), c_ich=_empty(0), c_e2h=_empty(0), c_work=_empty(2, 0),
        wg_x=_empty(0), wg_y=_empty(0), wg_z=_empty(0), wg_dt=1.0, wg_wrap=WRAP_PERIODIC,
        wg_zeta=_empty(0, 0, 0), wg_kin=_empty(0, 0, 0, 0, N_GRID_FIELDS),
        cu_u=_empty(3), cg_x=_empty(0), cg_y=_empty(0), cg_z=_empty(0), cg_dt=1.0, cg_wrap=WRAP_PERIODIC,
        cg_dudt=0, cg_vel=_empty(0, 0, 0, 0, 3),
        sb_x=_empty(0), sb_y=_empty(0), sb_z=_empty(0, 0),
        U_ext=_empty(0, 3), Ud_ext=_empty(0, 3))


def _check_positive(v, name: str) -> float:
    try:
        x = float(v)
    except (TypeError, ValueError):
        raise ValueError(f"{name}: expected a number, got {v!r}") from None
    if not (math.isfinite(x) and x > 0.0):
        raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    return x


def _depth_ratio_factors(k: np.ndarray, h: float) -> tuple[np.ndarray, np.ndarray]:
    """1 / (1 - e^{-2kh}) (0 where k = 0) and 1 / (1 + e^{-2kh})."""
    with np.errstate(divide="ignore"):
        ish = np.where(k > 0.0, -1.0 / np.expm1(-2.0 * k * h), 0.0)
    return ish, 1.0 / (1.0 + np.exp(-2.0 * k * h))


def _bbox(bbox) -> np.ndarray | None:
    if bbox is None:
        return None
    b = np.asarray(bbox, dtype=float)
    if b.shape != (2, 3) or not np.all(np.isfinite(b)) or np.any(b[1] < b[0]):
        raise ValueError("bbox must be [[xmin, ymin, zmin], [xmax, ymax, zmax]] (finite, min <= max), "
                         f"got {bbox!r}")
    return b


def _crop(axis: np.ndarray, lo: float, hi: float) -> np.ndarray:
    """The ticks of ``axis`` that cover [lo, hi] (one tick beyond each end when there is one):
    linear interpolation inside [lo, hi] is unchanged."""
    i0 = max(int(np.searchsorted(axis, lo, side="right")) - 1, 0)
    i1 = min(int(np.searchsorted(axis, hi, side="left")), axis.size - 1)
    return axis[i0:i1 + 1]


def _resolved_omega(waves: Waves) -> float:
    """Frequency below which RESOLVED_VARIANCE of the variance of the (omega > 0) components lies."""
    pos = waves.omega > 0.0
    if not np.any(pos):
        return 0.0
    w = waves.omega[pos]
    order = np.argsort(w)
    var = np.cumsum(np.abs(waves.amplitude[pos][order]) ** 2)
    j = int(np.searchsorted(var, RESOLVED_VARIANCE * var[-1]))
    return float(w[order][min(j, w.size - 1)])


def _grid_axes(spec: WaveGrid, waves: Waves, bbox, depth: float, g: float):
    """x, y, z axes of the wave grid: given ones (cropped to bbox + margin), else built."""
    w_r = _resolved_omega(waves)
    step = 2.0 * math.pi / wave_number(w_r, g, depth) / spec.points_per_wave if w_r > 0.0 else depth
    axes = []
    for i, name in enumerate(("x", "y")):
        given = getattr(spec, name)
        if given is not None:
            axes.append(given if bbox is None else _crop(given, bbox[0, i] - spec.margin, bbox[1, i] + spec.margin))
            continue
        if bbox is None:
            raise ValueError(f"wave grid: no {name} axis given and no node bounding box (bbox) to build one from")
        lo, hi = bbox[0, i] - spec.margin, bbox[1, i] + spec.margin
        n = 1 if hi == lo else max(2, math.ceil((hi - lo) / step) + 1)
        axes.append(np.linspace(lo, hi, n))
    if spec.z is not None:
        z = spec.z
        above = np.nonzero(z >= 0.0)[0]
        if above.size:  # z' <= 0: levels above the first one at or above 0 are never used
            z = z[: above[0] + 1]
        axes.append(z)
    else:
        levels = [0.0]
        dz = min(step, depth)
        while levels[-1] > -depth:
            levels.append(max(levels[-1] - dz, -depth))
            dz *= Z_GROWTH
        axes.append(np.array(levels[::-1]))
    return axes


class _Bins(NamedTuple):
    """How components fall into the frequency bins of a real FFT."""

    order: np.ndarray  # components sorted by bin
    starts: np.ndarray  # first sorted component of each occupied bin
    bins: np.ndarray  # the occupied bins
    unique: bool  # one component per occupied bin (no reduction needed)


def _bins(m: np.ndarray) -> _Bins:
    order = np.argsort(m, kind="stable")
    ms = m[order]
    starts = np.concatenate(([0], np.nonzero(np.diff(ms))[0] + 1))
    return _Bins(order, starts, ms[starts], starts.size == m.size)


def _irfft_bins(b: _Bins, values: np.ndarray, weight: np.ndarray, nt: int) -> np.ndarray:
    """Inverse real FFT (n = nt) along the last axis of the component values (..., nc) summed into
    their bins and weighted."""
    spec = np.zeros(values.shape[:-1] + (weight.size,), dtype=complex)
    v = values[..., b.order]
    spec[..., b.bins] = v if b.unique else np.add.reduceat(v, b.starts, axis=-1)
    return np.fft.irfft(spec * weight, n=nt, axis=-1)


def _build_wave_grid(waves: Waves, k: np.ndarray, *, depth, g, rho, bbox, max_bytes):
    """Wave grid arrays (x, y, z, dt, wrap, zeta, kin) by one inverse real FFT per column."""
    spec = waves.grid if waves.grid is not None else WaveGrid()
    dw = waves.base_omega
    m = np.rint(waves.omega / dw).astype(np.int64)
    mmax = int(m.max())
    period = 2.0 * math.pi / dw
    if spec.nt is not None:
        nt = int(spec.nt)
        if 2 * mmax > nt:
            raise ValueError(f"wave grid: nt = {nt} samples per {period:g} s cannot carry frequency "
                             f"{mmax * dw:g} rad/s (needs nt >= {2 * mmax})")
    else:
        w_r = _resolved_omega(waves)
        target = spec.dt if spec.dt is not None else (
            2.0 * math.pi / w_r / spec.points_per_wave if w_r > 0.0 else period)
        nt = max(2 * mmax, math.ceil(period / target - 1e-9), 2)
        nt += nt % 2
    x, y, z = _grid_axes(spec, waves, bbox, depth, g)
    nx, ny, nz = x.size, y.size, z.size
    nbytes = 8 * nx * ny * nt * (1 + nz * N_GRID_FIELDS)
    if nbytes > max_bytes:
        raise ValueError(f"wave grid of {nx} x {ny} x {nz} points x {nt} times would take {nbytes / 2**30:.2f} GiB "
                         f"(limit {max_bytes / 2**30:.2f} GiB): use evaluation='sum', coarser or cropped axes "
                         "(a node bounding box), or raise max_grid_bytes")
    log.info("wave grid %d x %d x %d x %d (dt = %g s, %.3g GiB) from %d components", nx, ny, nz, nt, period / nt,
             nbytes / 2**30, waves.n_components)
    nb = nt // 2 + 1
    weight = np.full(nb, 0.5 * nt)
    weight[0] = nt
    weight[-1] = nt  # nt is even: the last bin is the Nyquist frequency
    beta = np.radians(waves.heading)
    cb, sb = np.cos(beta), np.sin(beta)
    w = waves.omega
    ish, ich = _depth_ratio_factors(k, depth)
    kz = k[None, :] * z[:, None]
    e = np.exp(kz)
    em = np.expm1(-2.0 * k[None, :] * (z[:, None] + depth))
    ch = e * (2.0 + em) * ish[None, :]
    sh = np.where(k[None, :] > 0.0, -e * em * ish[None, :], 1.0)
    cc = np.where(k[None, :] > 0.0, e * (2.0 + em) * ich[None, :], 1.0)
    pfac = rho * g if waves.dynamic_pressure else 0.0
    b = _bins(m)
    iw = 1j * w
    zeta = np.empty((nx, ny, nt))
    kin = np.empty((nx, ny, nz, nt, N_GRID_FIELDS))
    # columns (x, y), x-major, in chunks of about 2e6 complex values per (chunk, z, component) array
    chunk = max(1, int(2e6 // max(1, nz * w.size)))
    cx = np.repeat(x, ny)
    cy = np.tile(y, nx)
    zeta_c = zeta.reshape(nx * ny, nt)
    kin_c = kin.reshape(nx * ny, nz, nt, N_GRID_FIELDS)
    for c0 in range(0, nx * ny, chunk):
        c1 = min(c0 + chunk, nx * ny)
        A = waves.amplitude[None, :] * np.exp(-1j * k[None, :] * (cx[c0:c1, None] * cb + cy[c0:c1, None] * sb))
        zeta_c[c0:c1] = _irfft_bins(b, A, weight, nt)
        A = A[:, None, :]  # (chunk, 1, nc) against the depth factors (nz, nc)
        uh = w * A * ch
        uz = iw * A * sh
        fields = (uh * cb, uh * sb, uz, iw * uh * cb, iw * uh * sb, iw * uz, pfac * A * cc)
        for f, values in enumerate(fields):
            kin_c[c0:c1, :, :, f] = _irfft_bins(b, values, weight, nt)
    wrap = _WRAPS[spec.time_wrap]
    return x, y, z, period / nt, wrap, zeta, kin


def _current_arrays(current: Current):
    """(x, y, z, dt, wrap, dudt, vel) of a current, its time axis resampled from t = 0 at the
    smallest interval (spec 4.8) when it is not uniform already."""
    t = current.t
    v = current.velocity
    if t.size == 1:
        dt = 1.0
    else:
        dt = float(np.min(np.diff(t)))
        n = int(math.floor(t[-1] / dt * (1.0 + 1e-12))) + 1
        ts = np.arange(n) * dt
        if not (t.size == n and np.allclose(t, ts, rtol=0.0, atol=1e-12 * max(1.0, t[-1]))):
            i = np.clip(np.searchsorted(t, ts, side="right") - 1, 0, t.size - 2)
            f = np.clip((ts - t[i]) / (t[i + 1] - t[i]), 0.0, 1.0)[None, None, None, :, None]
            v = v[:, :, :, i, :] * (1.0 - f) + v[:, :, :, i + 1, :] * f
    return (current.x, current.y, current.z, dt, _WRAPS[current.time_wrap], int(current.include_acceleration),
            np.ascontiguousarray(v, dtype=np.float64))


def build_water_kinematics(waves: Waves | None, current: Current | None, *, depth: float, g: float, rho: float,
                           bbox=None, bathymetry: Bathymetry | None = None, dispersion: str = "exact",
                           n_external: int = 0, max_grid_bytes: float = MAX_GRID_BYTES) -> WaterKin:
    """Arrays for the water-kinematics kernels from the Python descriptions.

    Parameters
    ----------
    waves : Waves or None
        The waves (None: none).
    current : Current or None
        The current (None: none).
    depth : float
        Water depth h [m] of the dispersion relation, the depth ratios and Wheeler stretching.
        With a bathymetry MoorDyn uses the average depth (:attr:`Bathymetry.mean_depth`).
    g : float
        Gravity [m/s^2].
    rho : float
        Water density [kg/m^3] (dynamic pressure).
    bbox : array_like (2, 3) or None
        ``[[xmin, ymin, zmin], [xmax, ymax, zmax]]`` of the nodes [m]. Used by grid evaluation:
        to build axes that were not given, and to crop given axes to the box plus the grid's
        margin (values inside unchanged; a point leaving box + margin gets the edge values).
    bathymetry : Bathymetry or None
        Seabed heights: Wheeler stretching then uses the local seabed height (MoorDyn-C).
    dispersion : {'exact', 'newman'}
        Wave numbers to machine precision, or MoorDyn's 7-digit estimate.
    n_external : int
        Number of nodes (rows of ``U_ext``/``Ud_ext``) for external waves.
    max_grid_bytes : float
        Refuse a wave grid larger than this [bytes].

    Returns
    -------
    WaterKin
    """
    depth = _check_positive(depth, "depth")
    g = _check_positive(g, "g")
    rho = _check_positive(rho, "rho")
    if dispersion not in ("exact", "newman"):
        raise ValueError(f"dispersion must be 'exact' or 'newman', got {dispersion!r}")
    if isinstance(n_external, bool) or not isinstance(n_external, (int, np.integer)) or n_external < 0:
        raise ValueError(f"n_external must be a whole number >= 0, got {n_external!r}")
    if waves is not None and not isinstance(waves, Waves):
        raise ValueError(f"waves must be a moorline.model.water.Waves or None, got {type(waves).__name__}")
    if current is not None and not isinstance(current, Current):
        raise ValueError(f"current must be a moorline.model.water.Current or None, got {type(current).__name__}")
    box = _bbox(bbox)
    K = still_water(depth, g, rho)._asdict()
    if bathymetry is not None:
        K.update(sb_x=np.ascontiguousarray(bathymetry.x, dtype=float),
                 sb_y=np.ascontiguousarray(bathymetry.y, dtype=float),
                 sb_z=np.ascontiguousarray(bathymetry.z, dtype=float))

    if waves is not None:
        K.update(stretch=STRETCH_WHEELER if waves.stretching == "wheeler" else STRETCH_NONE,
                 pdyn=int(waves.dynamic_pressure), ramp=float(waves.ramp_time))
        if waves.evaluation == "external":
            K.update(wave_mode=WAVES_EXTERNAL, U_ext=_empty(int(n_external), 3), Ud_ext=_empty(int(n_external), 3))
        else:
            k = wave_numbers(waves.omega, g, depth, dispersion)
            if waves.evaluation == "sum":
                keep = waves.amplitude != 0.0
                kk = k[keep]
                a = waves.amplitude[keep]
                beta = np.radians(waves.heading[keep])
                ish, ich = _depth_ratio_factors(kk, depth)
                K.update(wave_mode=WAVES_SUM, c_omega=np.ascontiguousarray(waves.omega[keep]),
                         c_are=np.ascontiguousarray(a.real), c_aim=np.ascontiguousarray(a.imag),
                         c_heading=beta, c_cosb=np.cos(beta), c_sinb=np.sin(beta), c_k=kk, c_ish=ish, c_ich=ich,
                         c_e2h=np.exp(-2.0 * kk * depth), c_work=np.zeros((2, kk.size)))
            else:
                x, y, z, dt, wrap, zeta, kin = _build_wave_grid(waves, k, depth=depth, g=g, rho=rho, bbox=box,
                                                                max_bytes=max_grid_bytes)
                K.update(wave_mode=WAVES_GRID, wg_x=x, wg_y=y, wg_z=z, wg_dt=float(dt), wg_wrap=wrap, wg_zeta=zeta,
                         wg_kin=kin)

    if current is not None:
        if current.is_uniform and not current.include_acceleration:
            K.update(current_mode=CURRENT_UNIFORM, cu_u=np.ascontiguousarray(current.velocity.reshape(3)))
        else:
            cx, cy, cz, cdt, cwrap, cdudt, cvel = _current_arrays(current)
            K.update(current_mode=CURRENT_GRID, cg_x=cx, cg_y=cy, cg_z=cz, cg_dt=float(cdt), cg_wrap=cwrap,
                     cg_dudt=cdudt, cg_vel=cvel)
        if current.on_wave_grid and K["wave_mode"] == WAVES_GRID:
            _current_onto_wave_grid(K)
    return _typed(K)


def _typed(K: dict) -> WaterKin:
    """The tuple with C-contiguous float64 arrays, Python ints and floats, so that every sea
    compiles to the same kernel signature (one compilation, one cache entry)."""
    proto = still_water(1.0, 1.0)
    fields = {}
    for name, ref in zip(WaterKin._fields, proto, strict=True):
        v = K[name]
        if isinstance(ref, np.ndarray):
            fields[name] = np.ascontiguousarray(v, dtype=np.float64)
        else:
            fields[name] = type(ref)(v)
    return WaterKin(**fields)


def _current_onto_wave_grid(K: dict) -> None:
    """Add the current, sampled at the wave grid's nodes (true z) and times, into the wave grid
    and drop it as a separate field (MoorDyn's UnifyCurrentGrid = 1, spec 4.8). A current uniform
    in x and y is sampled at x = y = 0 and a steady one at t = 0, as MoorDyn does."""
    only = _typed({**K, "wave_mode": WAVES_NONE})
    x, y, z, kin = K["wg_x"], K["wg_y"], K["wg_z"], K["wg_kin"]
    if K["current_mode"] == CURRENT_GRID and K["cg_x"].size == 1 and K["cg_y"].size == 1:
        x, y = np.zeros(1), np.zeros(1)
    steady = K["current_mode"] == CURRENT_UNIFORM or K["cg_vel"].shape[3] == 1
    pts = np.stack(np.meshgrid(x, y, z, indexing="ij"), axis=-1).reshape(-1, 3)
    out = np.empty((pts.shape[0], N_OUT))
    for it in range(1 if steady else kin.shape[3]):
        fluid_at_points(it * K["wg_dt"], pts, only, out)
        u = out[:, 0:6].reshape(x.size, y.size, z.size, 1, 6)
        if steady:
            kin[..., 0:6] += u
        else:
            kin[:, :, :, it:it + 1, 0:6] += u
    K.update(current_mode=CURRENT_NONE)
