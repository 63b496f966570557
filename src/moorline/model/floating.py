"""Plain descriptions of floating bodies: which deck bodies float, their potential-flow
hydrodynamics, extra loads, joints and power take-offs. No numba, no file formats.

A floating body is a free 6-DOF body of the deck (a MoorDyn BODIES row, its points and rods, and
the lines attached to them) whose loads gain the terms of the Cummins equation::

    (M + A_inf) x'' + int_0^t K(t - tau) x'(tau) dtau + C x = F_exc + F_visc + F_moor + F_pto + F_user

``x`` is the body's displacement from its mean pose (the pose the coefficients are linearised
about), in surge, sway, heave, roll, pitch, yaw about the body's reference point, global axes.
The weight of the body acts at its centre of gravity and turns with it exactly (as every moorline
body); hydrostatics add the buoyancy at rest, ``rho g V`` at the centre of buoyancy, and the
buoyancy (waterplane) part of ``C`` only, so gravity is counted once.

:class:`HydroBodies` names the coefficients of one set of bodies (one WAMIT run, one Capytaine
Dataset: several bodies keep their coupling terms); :class:`FloatingBody` the per-body settings;
:class:`Joint` a prismatic joint (a float sliding on a spar, or a body on a fixed axis) with an
optional linear power take-off.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .types import ModelError

__all__ = ["HULL_SHAPES", "RADIATION_METHODS", "BemRun", "FloatingBody", "Hull", "HydroBodies", "Joint", "MorisonStrip"]

#: how the radiation memory integral is evaluated: a fitted state-space model (fast, the default)
#: or direct convolution of the impulse response function (for checks)
RADIATION_METHODS = ("state_space", "convolution")


def _matrix6(v, name: str) -> np.ndarray:
    """A finite 6x6 matrix from None (zeros), a 6-vector (its diagonal) or a 6x6 array."""
    if v is None:
        return np.zeros((6, 6))
    a = np.asarray(v, dtype=float)
    if a.shape == (6,):
        a = np.diag(a)
    if a.shape != (6, 6):
        raise ModelError(f"{name}: expected 6 values (a diagonal) or a 6x6 matrix, got shape {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ModelError(f"{name}: all values must be finite")
    return a.copy()


def _vector(v, n: int, name: str) -> np.ndarray:
    a = np.asarray(v, dtype=float).ravel()
    if a.size != n or not np.all(np.isfinite(a)):
        raise ModelError(f"{name}: expected {n} finite numbers, got {v!r}")
    return a


#: hull shapes built in code (their parameters [m]): a vertical cylinder (radius, draft), a floating
#: hemisphere (radius), an axisymmetric hull from its meridian profile ((r, z) points, keel to waterline)
HULL_SHAPES = {"cylinder": ("radius", "draft"), "hemisphere": ("radius",), "axisymmetric": ("profile",)}


@dataclass
class Hull:
    """One hull for a Capytaine run: a mesh file (any format meshio reads, or WAMIT .gdf) or a shape
    built in code (:data:`HULL_SHAPES`), in the coordinates of the run (z up, waterline z = 0).

    Parameters
    ----------
    file : path, optional
    shape : str, optional
        A key of :data:`HULL_SHAPES`, with its parameters in ``params``.
    params : dict
    offset : array_like (3,)
        Translation of the shape's axis (shapes are built on the z axis) [m].
    n_theta : int
        Panels around the axis of a shape.
    """

    file: object = None
    shape: str | None = None
    params: dict = field(default_factory=dict)
    offset: np.ndarray = field(default_factory=lambda: np.zeros(3))
    n_theta: int = 24

    def __post_init__(self):
        if (self.file is None) == (self.shape is None):
            raise ModelError("a hull needs either a mesh file or a shape")
        if self.shape is not None:
            if self.shape not in HULL_SHAPES:
                raise ModelError(f"hull shape must be one of {sorted(HULL_SHAPES)}, got {self.shape!r}")
            missing = [k for k in HULL_SHAPES[self.shape] if k not in self.params]
            if missing:
                raise ModelError(f"hull shape {self.shape!r} needs {', '.join(missing)}")
        self.offset = _vector(self.offset, 3, "hull offset")
        self.n_theta = int(self.n_theta)


@dataclass
class BemRun:
    """Coefficients to compute with Capytaine (cached on disk by a hash of everything that changes
    the answer, see :func:`moorline.hydro.compute_coefficients`).

    Parameters
    ----------
    hulls : list of Hull
        One per body of the set, in its order.
    omega : array_like
        Frequencies [rad/s].
    wave_direction : array_like
        Headings [deg] (direction the waves travel toward); converted to radians for Capytaine.
    water_depth : float or None
        [m]; None: the environment's depth (inf for deep water).
    rotation_centers : array_like (n, 3), optional
        Reference points of the run [m]; default each body's deck reference point.
    lid : bool or float
        Lid against irregular frequencies.
    cache_dir : path, optional
    """

    hulls: list
    omega: np.ndarray
    wave_direction: np.ndarray = field(default_factory=lambda: np.zeros(1))
    water_depth: float | None = None
    rotation_centers: np.ndarray | None = None
    lid: object = False
    cache_dir: object = None

    def __post_init__(self):
        if not self.hulls or not all(isinstance(h, Hull) for h in self.hulls):
            raise ModelError("a Capytaine run needs a list of Hull")
        self.omega = np.asarray(self.omega, dtype=float).ravel()
        if self.omega.size < 2 or np.any(~np.isfinite(self.omega)) or np.any(np.diff(self.omega) <= 0) or \
                self.omega[0] <= 0:
            raise ModelError("omega: at least two finite, increasing frequencies > 0 rad/s are needed")
        self.wave_direction = np.atleast_1d(np.asarray(self.wave_direction, dtype=float))


@dataclass
class MorisonStrip:
    """A slender cylinder on a floating body that adds only viscous drag (the potential-flow
    coefficients carry its inertia): -0.5 rho Cd d |u_n| u_n per unit length, u_n the water velocity
    relative to the strip, normal to its axis, at ``n`` points along it.

    Parameters
    ----------
    rA, rB : array_like (3,)
        Ends in body axes, relative to the body's reference point [m].
    d : float
        Diameter [m].
    Cd : float
        Transverse drag coefficient [-].
    n : int
        Number of sub-strips (drag evaluated at their centres, wet part only).
    """

    rA: np.ndarray
    rB: np.ndarray
    d: float
    Cd: float
    n: int = 10

    def __post_init__(self):
        self.rA = _vector(self.rA, 3, "Morison strip end A")
        self.rB = _vector(self.rB, 3, "Morison strip end B")
        self.d = float(self.d)
        self.Cd = float(self.Cd)
        self.n = int(self.n)
        if not (self.d > 0.0 and self.Cd >= 0.0 and self.n >= 1):
            raise ModelError(f"Morison strip: need d > 0, Cd >= 0 and n >= 1, got d={self.d}, Cd={self.Cd}, "
                             f"n={self.n}")
        if np.allclose(self.rA, self.rB):
            raise ModelError("Morison strip: ends A and B coincide")


@dataclass
class FloatingBody:
    """Settings of one floating body (deck body ``body``, 0-based).

    Parameters
    ----------
    body : int
        Index of the deck body (must be a free body).
    linear_damping, quadratic_damping : 6x6 (or 6 diagonal values), optional
        Extra damping about the reference point: -B_lin v and -B_quad (|v| * v) (element-wise
        |v_j| v_j, as HydroDyn's AddBQuad) [N s/m, N m s/rad; N s^2/m^2, ...], global axes.
    stiffness : 6x6 (or 6 diagonal values), optional
        Extra stiffness -K_ext x on the displacement from the mean pose (e.g. a yaw spring).
    force : array_like (6,), optional
        Constant force and moment about the reference point [N, N m] (e.g. a mean thrust).
    morison : list of MorisonStrip
        Drag-only strips.
    displaced_mass : bool
        Set the body's mass to rho times the displaced volume of its coefficients (a body floating
        at its design draft), when the system is built.
    """

    body: int
    linear_damping: np.ndarray | None = None
    quadratic_damping: np.ndarray | None = None
    stiffness: np.ndarray | None = None
    force: np.ndarray = field(default_factory=lambda: np.zeros(6))
    morison: list = field(default_factory=list)
    displaced_mass: bool = False

    def __post_init__(self):
        self.body = int(self.body)
        self.linear_damping = _matrix6(self.linear_damping, f"body {self.body + 1} linear_damping")
        self.quadratic_damping = _matrix6(self.quadratic_damping, f"body {self.body + 1} quadratic_damping")
        self.stiffness = _matrix6(self.stiffness, f"body {self.body + 1} stiffness")
        self.force = _vector(self.force, 6, f"body {self.body + 1} force")
        for s in self.morison:
            if not isinstance(s, MorisonStrip):
                raise ModelError(f"body {self.body + 1}: morison entries must be MorisonStrip, got {type(s).__name__}")


@dataclass
class HydroBodies:
    """The potential-flow coefficients of one set of bodies.

    Parameters
    ----------
    bodies : list of int
        Deck body indices (0-based), in the order of the coefficient set's bodies.
    coefficients : xarray.Dataset, path or BemRun
        Capytaine-convention Dataset (see :mod:`moorline.hydro`), a WAMIT output stem (the path
        without .1/.3/.hst), a Capytaine NetCDF file, or a :class:`BemRun` to compute (and cache).
        Resolved when the system is built.
    reference_points : array_like (n_bodies, 3), optional
        Where each body's coefficient reference point (rotation centre) sits in the system at the
        mean pose [m]; default: the coefficients' own reference points (the BEM run's coordinates
        are the system's). Coefficients are moved to the deck body's reference point, and the
        excitation phase to the body's horizontal position.
    mean_poses : array_like (n_bodies, 6), optional
        Pose (x, y, z [m], roll, pitch, yaw [rad]) of each body's reference point about which the
        hydrostatics are linearised; default: the deck pose.
    radiation : {'state_space', 'convolution'}
    irf_duration, irf_dt : float
        Length [s] and sampling [s] of the radiation impulse response.
    ss_rtol : float
        Relative error of the state-space fit on the impulse response (per DOF pair).
    ss_max_order : int
        Largest order of one DOF pair's state-space model.
    excitation : bool
        Apply the wave excitation (False: radiation and hydrostatics only).
    wamit_options : dict
        Keyword arguments for :func:`moorline.hydro.read_wamit` (rho and g default to the
        environment's).
    """

    bodies: list
    coefficients: object
    reference_points: np.ndarray | None = None
    mean_poses: np.ndarray | None = None
    radiation: str = "state_space"
    irf_duration: float = 60.0
    irf_dt: float = 0.05
    ss_rtol: float = 0.02
    ss_max_order: int = 10
    excitation: bool = True
    wamit_options: dict = field(default_factory=dict)

    def __post_init__(self):
        self.bodies = [int(b) for b in np.atleast_1d(self.bodies)]
        if not self.bodies or len(set(self.bodies)) != len(self.bodies):
            raise ModelError(f"hydrodynamic body set: expected distinct deck body indices, got {self.bodies}")
        n = len(self.bodies)
        if self.reference_points is not None:
            self.reference_points = np.asarray(self.reference_points, dtype=float).reshape(n, 3)
        if self.mean_poses is not None:
            self.mean_poses = np.asarray(self.mean_poses, dtype=float).reshape(n, 6)
        if self.radiation not in RADIATION_METHODS:
            raise ModelError(f"radiation must be one of {RADIATION_METHODS}, got {self.radiation!r}")
        for name in ("irf_duration", "irf_dt", "ss_rtol"):
            v = float(getattr(self, name))
            if not (np.isfinite(v) and v > 0.0):
                raise ModelError(f"{name} must be > 0, got {getattr(self, name)!r}")
            setattr(self, name, v)
        if self.irf_dt >= self.irf_duration:
            raise ModelError(f"irf_dt ({self.irf_dt} s) must be shorter than irf_duration ({self.irf_duration} s)")
        self.ss_max_order = int(self.ss_max_order)
        if self.ss_max_order < 1:
            raise ModelError(f"ss_max_order must be >= 1, got {self.ss_max_order}")


@dataclass
class Joint:
    """A prismatic joint: ``child`` slides along ``axis`` relative to ``parent`` (or to the ground
    when ``parent`` is None); its other five relative DOFs are fixed. A linear power take-off acts
    along the axis: F = -k_pto (s - s0) - c_pto s', s the slide from the initial pose.

    Parameters
    ----------
    child : int
        Deck body index of the sliding body.
    parent : int or None
        Deck body index of the body it slides on, or None for a fixed axis (ground).
    axis : array_like (3,)
        Sliding direction in the parent's body axes (global axes for the ground) [-], normalised.
    pto_stiffness, pto_damping : float
        [N/m] and [N s/m].
    pto_rest : float
        Slide s0 [m] at which the PTO spring is relaxed.
    """

    child: int
    parent: int | None = None
    axis: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    pto_stiffness: float = 0.0
    pto_damping: float = 0.0
    pto_rest: float = 0.0

    def __post_init__(self):
        self.child = int(self.child)
        self.parent = None if self.parent is None else int(self.parent)
        if self.parent == self.child:
            raise ModelError(f"joint of body {self.child + 1}: a body cannot slide on itself")
        a = _vector(self.axis, 3, "joint axis")
        n = float(np.linalg.norm(a))
        if n == 0.0:
            raise ModelError("joint axis must not be zero")
        self.axis = a / n
        self.pto_stiffness = float(self.pto_stiffness)
        self.pto_damping = float(self.pto_damping)
        self.pto_rest = float(self.pto_rest)
        if self.pto_stiffness < 0.0 or self.pto_damping < 0.0:
            raise ModelError("PTO stiffness and damping must be >= 0")
