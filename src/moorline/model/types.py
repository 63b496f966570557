"""Plain descriptions of line types, points, lines and the environment.

Nothing here knows about numba or file formats; the deck reader (:mod:`moorline.io`) and the
Python builders of :class:`moorline.model.Model` both produce these objects, and
:mod:`moorline.core.layout` turns them into flat arrays.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import IntEnum

import numpy as np


class ModelError(ValueError):
    """An inconsistent or physically impossible model (raised by ``Model.validate``)."""


@dataclass
class Curve:
    """A piecewise-linear lookup table, clamped at both ends (MoorDyn's curve files).

    Parameters
    ----------
    x, y : array_like, shape (n,)
        Abscissa (strictly increasing) and ordinate.
    source : str, optional
        Where the table came from (file name), for messages.
    """

    x: np.ndarray
    y: np.ndarray
    source: str = ""

    def __post_init__(self):
        self.x = np.asarray(self.x, dtype=float).ravel()
        self.y = np.asarray(self.y, dtype=float).ravel()
        if self.x.shape != self.y.shape or self.x.size < 2:
            raise ModelError(f"curve {self.source or ''}: needs at least two (x, y) pairs of equal length")
        if np.any(np.diff(self.x) <= 0):
            raise ModelError(f"curve {self.source or ''}: x values must be strictly increasing")

    def __call__(self, x):
        return np.interp(x, self.x, self.y)


#: axial models of a line type (MoorDyn's ElasticMod)
ELASTIC = 1  # EA a number or a strain-tension curve
VISCO_CONSTANT = 2  # viscoelastic, constant dynamic stiffness EA_D (EA field EA_s|EA_d)
VISCO_MEAN = 3  # viscoelastic, dynamic stiffness EA_D + EA_D_Lm * mean tension (EA_s|EA_Dc|EA_D_Lm)
SYROPE = 4  # Syrope polyester model (SYROPE:<settings>|EA_Dc|EA_D_Lm)
#: working-curve shapes of the Syrope model
SYROPE_WC_TYPES = ("LINEAR", "QUADRATIC", "EXP")


@dataclass
class SyropeCurve:
    """The Syrope model's original working curve and the shape of its working curves (MoorDyn's
    Syrope settings file, spec 3.4.3).

    Parameters
    ----------
    owc : Curve
        Original working curve: total strain [-] -> tension [N] (increasing).
    wc_type : {'LINEAR', 'QUADRATIC', 'EXP'}
        Shape of the working curve below the largest tension seen.
    k1, k2 : float
        Shape parameters: LINEAR k1 >= 0 (k1 >= 1 is a stiffness [N]); QUADRATIC 0 <= k1 < 1,
        0 < k2 <= 1; EXP 0 <= k1 < 1, k2 > 0.
    source : str
        Settings file it was read from, for messages.
    """

    owc: Curve
    wc_type: str = "LINEAR"
    k1: float = 0.0
    k2: float = 0.0
    source: str = ""

    def check(self) -> None:
        """Raise :class:`ModelError` when the shape parameters are outside MoorDyn's ranges."""
        w, k1, k2 = self.wc_type.upper(), self.k1, self.k2
        where = f"Syrope settings {self.source}".rstrip()
        if w not in SYROPE_WC_TYPES:
            raise ModelError(f"{where}: WCType must be one of {SYROPE_WC_TYPES}, got {self.wc_type!r}")
        if w == "LINEAR" and not k1 >= 0:
            raise ModelError(f"{where}: a LINEAR working curve needs k1 >= 0, got {k1}")
        if w == "QUADRATIC" and not (0 <= k1 < 1 and 0 < k2 <= 1):
            raise ModelError(f"{where}: a QUADRATIC working curve needs 0 <= k1 < 1 and 0 < k2 <= 1, got k1 = {k1}, "
                             f"k2 = {k2}")
        if w == "EXP" and not (0 <= k1 < 1 and k2 > 0):
            raise ModelError(f"{where}: an EXP working curve needs 0 <= k1 < 1 and k2 > 0, got k1 = {k1}, k2 = {k2}")


@dataclass
class LineType:
    """Cross-section properties of a line (one row of LINE TYPES).

    Parameters
    ----------
    name : str
    d : float
        Volume-equivalent diameter [m].
    w : float
        Mass per unit length in air [kg/m].
    EA : float or Curve
        Axial stiffness [N], or a strain -> tension [N] table.
    BA : float or Curve
        Internal axial damping [N s]; a negative value ``-zeta`` is a damping ratio of the
        highest axial segment mode. A table maps strain rate [1/s] to damping force [N].
    EI : float or Curve
        Bending stiffness [N m^2], or a curvature [1/m] -> bending moment [N m] table.
    Cd, Ca, CdAx, CaAx : float
        Transverse drag (area d*l), transverse added mass, tangential drag (area pi*d*l) and
        tangential added-mass coefficients [-].
    Cl, dF, cF : float
        VIV lift coefficient and synchronisation band (MoorDyn columns 11-13).
    elastic : int
        Axial model: ``ELASTIC`` (1), ``VISCO_CONSTANT`` (2), ``VISCO_MEAN`` (3) or ``SYROPE`` (4).
        For 2 and 3, ``EA`` is the static stiffness EA_s; for 4 it is the original working curve.
    EA_D : float
        Dynamic stiffness EA_d [N] (model 2), or its constant part alpha = EA_Dc [N] (3 and 4).
    EA_D_Lm : float
        Slope beta of the dynamic stiffness with the mean tension [-] (models 3 and 4).
    BA_D : float
        Damping [N s] of the dynamic branch (models 2-4); ``BA`` is then the static branch's.
    syrope : SyropeCurve or None
        Working-curve settings of the Syrope model (model 4).
    """

    name: str
    d: float
    w: float
    EA: float | Curve
    BA: float | Curve = 0.0
    EI: float | Curve = 0.0
    Cd: float = 0.0
    Ca: float = 0.0
    CdAx: float = 0.0
    CaAx: float = 0.0
    Cl: float = 0.0
    dF: float = 0.0
    cF: float = 0.0
    elastic: int = ELASTIC
    EA_D: float = 0.0
    EA_D_Lm: float = 0.0
    BA_D: float = 0.0
    syrope: SyropeCurve | None = None

    @property
    def A(self) -> float:
        """Cross-section area pi d^2 / 4 [m^2]."""
        return math.pi * self.d**2 / 4.0

    @property
    def EA_ref(self) -> float:
        """Single stiffness number [N]: EA, or the secant through the last table point."""
        if isinstance(self.EA, Curve):
            return float(self.EA.y[-1] / self.EA.x[-1])
        return float(self.EA)

    @property
    def EA_max(self) -> float:
        """Largest tangent stiffness [N] (used by the stability estimate)."""
        if isinstance(self.EA, Curve):
            c = self.EA
            slopes = np.diff(c.y) / np.diff(c.x)
            first = c.y[0] / c.x[0] if c.x[0] > 0 else 0.0
            return float(max(np.max(slopes), first, self.EA_ref))
        return float(self.EA)

    @property
    def EI_max(self) -> float:
        """Largest bending stiffness [N m^2]: EI, or the steepest slope of the moment-curvature table."""
        if isinstance(self.EI, Curve):
            c = self.EI
            slopes = np.diff(c.y) / np.diff(c.x)
            first = c.y[0] / c.x[0] if c.x[0] > 0 else 0.0
            return float(max(np.max(slopes), first))
        return float(self.EI)

    @property
    def has_bending(self) -> bool:
        return isinstance(self.EI, Curve) or float(self.EI) > 0.0


class PointKind(IntEnum):
    """How a point moves. Mirrored as integer constants in the kernels."""

    FIXED = 0
    COUPLED = 1
    FREE = 2
    BODY = 3


#: point attachment words of MoorDyn decks (upper case) and the kind each means
POINT_KIND_WORDS = {
    "ANCHOR": PointKind.FIXED, "FIXED": PointKind.FIXED, "FIX": PointKind.FIXED,
    "FAIRLEAD": PointKind.COUPLED, "VESSEL": PointKind.COUPLED, "VES": PointKind.COUPLED,
    "COUPLED": PointKind.COUPLED, "CPLD": PointKind.COUPLED,
    "POINT": PointKind.FREE, "CONNECT": PointKind.FREE, "CON": PointKind.FREE, "FREE": PointKind.FREE,
}


@dataclass
class Point:
    """A point: anchor, fairlead, clump weight, buoy or line junction (one row of POINTS).

    Parameters
    ----------
    kind : PointKind
    r : array_like, shape (3,)
        Position [m] (initial guess for free points).
    m : float
        Mass [kg].
    V : float
        Displaced volume [m^3] (always fully counted, as MoorDyn does).
    CdA : float
        Drag coefficient times area [m^2] (isotropic).
    Ca : float
        Added-mass coefficient [-] on ``rho * V``.
    F_ext : array_like, shape (3,)
        Constant external force [N].
    body : int or None
        Index of the body the point is fixed to (kind BODY).
    """

    kind: PointKind
    r: np.ndarray
    m: float = 0.0
    V: float = 0.0
    CdA: float = 0.0
    Ca: float = 0.0
    F_ext: np.ndarray = field(default_factory=lambda: np.zeros(3))
    body: int | None = None

    def __post_init__(self):
        self.kind = PointKind(self.kind)
        self.r = np.asarray(self.r, dtype=float).reshape(3)
        self.F_ext = np.asarray(self.F_ext, dtype=float).reshape(3)


@dataclass
class RodType:
    """Cross-section properties of a rod (one row of ROD TYPES).

    Parameters
    ----------
    name : str
    d : float
        Diameter [m].
    w : float
        Mass per unit length [kg/m].
    Cd, Ca : float
        Transverse drag and added-mass coefficients [-].
    CdEnd, CaEnd : float
        Axial drag and added-mass coefficients applied at each submerged end [-].
    """

    name: str
    d: float
    w: float
    Cd: float = 0.0
    Ca: float = 0.0
    CdEnd: float = 0.0
    CaEnd: float = 0.0


class RodKind(IntEnum):
    """How a rod moves (MoorDyn's rod attachment words)."""

    FIXED = 0
    PINNED = 1
    BODY = 2
    BODY_PINNED = 3
    COUPLED = 4
    COUPLED_PINNED = 5
    FREE = 6


@dataclass
class Rod:
    """A rigid cylinder from end A to end B (one row of RODS).

    Parameters
    ----------
    rod_type : str
    kind : RodKind
    rA, rB : array_like (3,)
        End positions [m] (global frame; body frame for rods on bodies).
    N : int
        Number of segments (0: a zero-length rod joining cables). As in MoorDyn, a zero-length rod
        has both ends at end A (``rB`` is not used) and takes its axis from the cables on it at every
        evaluation, whatever it is attached to: a cable on it is in effect pinned there. A clamp
        (a cable leaving at a fixed angle) needs a rod with segments.
    outputs : str
        MoorDyn rod output flags.
    body : int or None
        Index of the parent body.
    """

    rod_type: str
    kind: RodKind
    rA: np.ndarray
    rB: np.ndarray
    N: int
    outputs: str = ""
    body: int | None = None

    def __post_init__(self):
        self.kind = RodKind(self.kind)
        self.rA = np.asarray(self.rA, dtype=float).reshape(3)
        self.rB = np.asarray(self.rB, dtype=float).reshape(3)

    @property
    def length(self) -> float:
        """|B - A| [m]; 0 for a zero-length rod (N = 0) whatever its end B says, as in MoorDyn."""
        if self.N == 0:
            return 0.0
        return float(np.linalg.norm(self.rB - self.rA))

    @property
    def axis(self) -> np.ndarray:
        """Unit vector from end A to end B (zero for a zero-length rod, whose axis comes from its
        cables at run time)."""
        L = self.length
        return (self.rB - self.rA) / L if L > 0 else np.zeros(3)


class BodyKind(IntEnum):
    """How a body moves (MoorDyn's body attachment words)."""

    FIXED = 0
    COUPLED = 1
    COUPLED_PINNED = 2
    FREE = 3


#: body attachment words of MoorDyn decks (upper case); any other word means a free body
BODY_KIND_WORDS = {
    "ANCHOR": BodyKind.FIXED, "FIXED": BodyKind.FIXED, "FIX": BodyKind.FIXED,
    "VESSEL": BodyKind.COUPLED, "VES": BodyKind.COUPLED, "COUPLED": BodyKind.COUPLED, "CPLD": BodyKind.COUPLED,
    "VESSELPINNED": BodyKind.COUPLED_PINNED, "VESPIN": BodyKind.COUPLED_PINNED,
    "CPLDPIN": BodyKind.COUPLED_PINNED, "COUPLEDPINNED": BodyKind.COUPLED_PINNED,
    "FREE": BodyKind.FREE, "BODY": BodyKind.FREE,
}


@dataclass
class Body:
    """A 6-DOF rigid body (one row of BODIES).

    Parameters
    ----------
    kind : BodyKind
    r : array_like (3,)
        Reference-point position [m].
    angles : array_like (3,)
        Roll, pitch, yaw [deg]: the rotation Rx(roll) Ry(pitch) Rz(yaw) from body to global axes.
    m : float
        Mass [kg] (without attached rods and points).
    rCG : array_like (3,)
        Centre of gravity relative to the reference point, body axes [m].
    I : array_like (3,)
        Principal moments of inertia about the CG [kg m^2].
    V : float
        Displaced volume of the body itself [m^3].
    CdA : array_like (6,)
        Drag coefficient times area for the x, y, z translations and rotations [m^2] (the
        rotational entries multiply the angular velocity squared, as in MoorDyn).
    Ca : array_like (3,)
        Added-mass coefficients on rho V along the body x, y, z axes [-].

    For fixed and coupled bodies MoorDyn discards mass, volume, inertia, CdA and Ca: only the
    attached rods and points carry mass and loads. moorline does the same.
    """

    kind: BodyKind
    r: np.ndarray
    angles: np.ndarray = field(default_factory=lambda: np.zeros(3))
    m: float = 0.0
    rCG: np.ndarray = field(default_factory=lambda: np.zeros(3))
    I: np.ndarray = field(default_factory=lambda: np.zeros(3))  # noqa: E741
    V: float = 0.0
    CdA: np.ndarray = field(default_factory=lambda: np.zeros(6))
    Ca: np.ndarray = field(default_factory=lambda: np.zeros(3))

    def __post_init__(self):
        self.kind = BodyKind(self.kind)
        self.r = np.asarray(self.r, dtype=float).reshape(3)
        self.angles = np.asarray(self.angles, dtype=float).reshape(3)
        self.rCG = _vec(self.rCG, 3, "rCG")
        self.I = _vec(self.I, 3, "I")
        self.CdA = _vec(self.CdA, 6, "CdA")
        self.Ca = _vec(self.Ca, 3, "Ca")
        self.m = float(self.m)
        self.V = float(self.V)

    @property
    def rotation(self) -> np.ndarray:
        """Rotation matrix (body to global axes) of the deck pose, shape (3, 3)."""
        return rotation_xyz(np.radians(self.angles))

    def to_global(self, r_rel) -> np.ndarray:
        """Deck-pose global position of a point given in body axes [m]."""
        return self.r + self.rotation @ np.asarray(r_rel, dtype=float)

    @property
    def has_inertia(self) -> bool:
        """Free and coupled-pinned bodies keep their own mass properties."""
        return self.kind in (BodyKind.FREE, BodyKind.COUPLED_PINNED)


def rotation_xyz(angles) -> np.ndarray:
    """Rotation matrix Rx(roll) Ry(pitch) Rz(yaw) (intrinsic X-Y-Z, MoorDyn's convention).

    Parameters
    ----------
    angles : array_like (3,)
        Roll, pitch, yaw [rad].
    """
    r, p, y = (float(a) for a in angles)
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    Rx = np.array([[1.0, 0.0, 0.0], [0.0, cr, -sr], [0.0, sr, cr]])
    Ry = np.array([[cp, 0.0, sp], [0.0, 1.0, 0.0], [-sp, 0.0, cp]])
    Rz = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
    return Rx @ Ry @ Rz


def angles_xyz(R) -> np.ndarray:
    """Roll, pitch, yaw [rad] of a rotation matrix R = Rx(roll) Ry(pitch) Rz(yaw), pitch in
    [-pi/2, pi/2] (the inverse of :func:`rotation_xyz`)."""
    R = np.asarray(R, dtype=float)
    pitch = math.asin(max(-1.0, min(1.0, R[0, 2])))
    if abs(R[0, 2]) < 1.0 - 1e-12:
        roll = math.atan2(-R[1, 2], R[2, 2])
        yaw = math.atan2(-R[0, 1], R[0, 0])
    else:  # gimbal lock: only roll + yaw (or roll - yaw) is defined; put it all in roll
        roll = math.atan2(R[2, 1], R[1, 1])
        yaw = 0.0
    return np.array([roll, pitch, yaw])


def _vec(v, n, name) -> np.ndarray:
    a = np.asarray(v, dtype=float).ravel()
    if a.size == 1:
        a = np.full(n, a[0])
    if a.size != n:
        raise ValueError(f"{name}: expected 1 or {n} values, got {a.size}")
    return a


@dataclass(frozen=True)
class Attachment:
    """What a line end is attached to: a point (``kind='point'``) or a rod end.

    ``index`` is 0-based; ``end`` is ``'A'`` or ``'B'`` for rods, ``None`` for points.
    """

    kind: str
    index: int
    end: str | None = None

    def __str__(self):
        if self.kind == "point":
            return f"P{self.index + 1}"
        return f"R{self.index + 1}{self.end}"


@dataclass
class Line:
    """A line between two attachments (one row of LINES).

    Parameters
    ----------
    line_type : str
        Name of a :class:`LineType` of the model.
    end_a, end_b : Attachment
        End A (node 0) and end B (node N).
    L : float
        Unstretched length [m]; a negative value ``-f`` means f times the initial distance
        between the two ends.
    N : int
        Number of segments.
    outputs : str
        MoorDyn per-line output flags (``p v U D V K c t s d b``).
    """

    line_type: str
    end_a: Attachment
    end_b: Attachment
    L: float
    N: int
    outputs: str = ""
    #: (Tmax0, Tmean0) [N] of a Syrope line: the largest mean tension it has carried and its
    #: current mean tension (MoorDyn's SYROPE IC section)
    syrope_ic: tuple[float, float] | None = None


@dataclass
class Failure:
    """A line failure (one row of MoorDyn's FAILURE section): the ``lines`` attached at
    ``attachment`` let go of it at ``time`` or once the load they carry there reaches ``tension``,
    whichever comes first. The released ends stay joined to one new free point (no mass, no
    volume: the line end nodes carry their own mass) that starts where the attachment was, with its
    velocity; the run goes on.

    Parameters
    ----------
    attachment : Attachment
        The point or rod end the lines let go of.
    lines : list of int
        0-based indices of the lines released there (each has an end on ``attachment``).
    time : float
        Failure time [s]; ``inf`` (or <= 0 in a deck) for none.
    tension : float
        Failure load [N]: the magnitude of the vector sum of the listed lines' end tensions at the
        attachment (the load through the failing connection); ``inf`` (or <= 0 in a deck) for none.
    """

    attachment: Attachment
    lines: list[int]
    time: float = math.inf
    tension: float = math.inf


@dataclass
class Bathymetry:
    """Seabed heights on a rectangular x-y grid, interpolated bilinearly.

    Parameters
    ----------
    x : array_like (nx,)
        Grid x coordinates [m], strictly increasing.
    y : array_like (ny,)
        Grid y coordinates [m], strictly increasing.
    z : array_like (ny, nx)
        Seabed height [m] at (y[j], x[i]) (negative below the still-water level).
    source : str
        File it was read from, for messages.
    """

    x: np.ndarray
    y: np.ndarray
    z: np.ndarray
    source: str = ""

    def __post_init__(self):
        self.x = np.asarray(self.x, dtype=float).ravel()
        self.y = np.asarray(self.y, dtype=float).ravel()
        self.z = np.asarray(self.z, dtype=float).reshape(self.y.size, self.x.size)
        for name, v in (("x", self.x), ("y", self.y)):
            if v.size < 1 or np.any(np.diff(v) <= 0):
                raise ModelError(f"bathymetry {self.source}: {name} coordinates must be strictly increasing")
        if not np.all(np.isfinite(self.z)):
            raise ModelError(f"bathymetry {self.source}: heights must be finite")

    @property
    def mean_depth(self) -> float:
        """Minus the mean grid height [m] (MoorDyn's depth for wave kinematics)."""
        return float(-np.mean(self.z))

    def height(self, x, y):
        """Bilinear seabed height [m] at (x, y), clamped to the grid edges (plain numpy)."""
        xs = np.clip(np.asarray(x, dtype=float), self.x[0], self.x[-1])
        ys = np.clip(np.asarray(y, dtype=float), self.y[0], self.y[-1])
        i = np.clip(np.searchsorted(self.x, xs, side="right") - 1, 0, max(self.x.size - 2, 0))
        j = np.clip(np.searchsorted(self.y, ys, side="right") - 1, 0, max(self.y.size - 2, 0))
        if self.x.size == 1:
            tx = np.zeros_like(xs)
            i1 = i
        else:
            tx = (xs - self.x[i]) / (self.x[i + 1] - self.x[i])
            i1 = i + 1
        if self.y.size == 1:
            ty = np.zeros_like(ys)
            j1 = j
        else:
            ty = (ys - self.y[j]) / (self.y[j + 1] - self.y[j])
            j1 = j + 1
        z = self.z
        return ((1 - tx) * (1 - ty) * z[j, i] + tx * (1 - ty) * z[j, i1] + (1 - tx) * ty * z[j1, i]
                + tx * ty * z[j1, i1])


#: seabed contact: along the local seabed normal (moorline), or vertical only (MoorDyn-C)
CONTACT_MODES = ("normal", "vertical")
#: seabed friction models: MoorDyn-C isotropic saturated damping, MoorDyn-F directional saturated
#: damping, and moorline's elastic stick-slip (friction springs with anchors)
FRICTION_MODELS = ("isotropic", "directional", "stickslip")


@dataclass
class Environment:
    """Water, gravity and seabed.

    Parameters
    ----------
    g : float
        Gravity [m/s^2].
    rho : float
        Water density [kg/m^3].
    depth : float
        Still-water depth [m, positive]; the flat seabed is z = -depth (when there is no bathymetry).
    kBot, cBot : float
        Seabed contact stiffness [Pa/m] and damping [Pa s/m].
    bathymetry : Bathymetry or None
        Seabed height grid; None for a flat seabed at z = -depth.
    contact : {'normal', 'vertical'}
        Contact force along the local seabed normal, from the penetration measured normal to the
        surface (default), or vertical as MoorDyn-C applies it even on a slope.
    friction : {'isotropic', 'directional', 'stickslip'}
        Seabed friction model (see :meth:`friction_coefficients`).
    mu, fric_damp, stat_dyn : float
        MoorDyn-C isotropic friction: coefficient, creep damping [N s/m], static/kinetic ratio.
    mu_kT, mu_kA, mc, cv : float
        MoorDyn-F directional friction: transverse and axial kinetic coefficients, static/kinetic
        ratio, creep damping [N s/m].
    kShear : float or None
        Stick-slip friction spring stiffness per unit contact area [Pa/m]; None: kBot.
    """

    g: float = 9.80665
    rho: float = 1025.0
    depth: float = 0.0
    kBot: float = 3.0e6
    cBot: float = 3.0e5
    bathymetry: Bathymetry | None = None
    contact: str = "normal"
    friction: str = "isotropic"
    mu: float = 0.0
    fric_damp: float = 200.0
    stat_dyn: float = 1.0
    mu_kT: float = 0.0
    mu_kA: float = 0.0
    mc: float = 1.0
    cv: float = 200.0
    kShear: float | None = None
    #: waves (:class:`moorline.model.water.Waves`) and current (:class:`~moorline.model.water.Current`)
    waves: object | None = None
    current: object | None = None
    #: the waves act on lines, points and rods (True, MoorDyn's WaveKin > 0) or only on floating
    #: bodies through their excitation (False: the lines see the current alone, as MoorDyn with
    #: WaveKin 0 coupled to WEC-Sim or HydroDyn)
    waves_on_lines: bool = True

    def friction_coefficients(self) -> tuple[float, float, float, float]:
        """(mu transverse, mu axial, static/kinetic ratio, creep damping [N s/m]) of the chosen model.

        isotropic: (mu, mu, stat_dyn, fric_damp), saturating the whole sliding velocity (MoorDyn-C);
        directional: (mu_kT, mu_kA, mc, cv), axial and transverse saturated separately (MoorDyn-F);
        stickslip: the directional coefficients when mu_kT or mu_kA is set, else the isotropic ones
        (the damping is unused: the friction springs of stiffness kShear carry the force).
        """
        if self.friction == "isotropic":
            return self.mu, self.mu, self.stat_dyn, self.fric_damp
        if self.friction == "directional" or self.mu_kT > 0 or self.mu_kA > 0:
            return self.mu_kT, self.mu_kA, self.mc, self.cv
        return self.mu, self.mu, self.stat_dyn, self.fric_damp


@dataclass
class Options:
    """Numerical settings (MoorDyn OPTIONS that are not physical constants)."""

    dtM: float | None = None
    CFL: float = 0.5
    tScheme: str = "RK2"
    dtIC: float = 1.0
    TmaxIC: float = 120.0
    CdScaleIC: float = 5.0
    threshIC: float = 0.001
    ICgenDynamic: int = 0
    #: static equilibrium by Newton's method for the initial conditions (moorline): 1 yes, 0 MoorDyn's
    #: method (ICgenDynamic), -1 automatic (Newton with the implicit GenAlpha scheme)
    ICNewton: int = -1
    dtOut: float = 0.0
    #: the bending moment of a cable clamped to a rod acts on the rod (1, moorline) or is not passed
    #: to it (0, MoorDyn-C 2.7)
    ClampMoment: int = 1
    #: velocity-dependent inertial loads of rods and bodies: 'full' (moorline: the centripetal and
    #: gyroscopic loads of free and pinned rods, and a body's centrifugal force of its CG offset with
    #: its rigid mass) or 'moordyn' (MoorDyn-C 2.7: rods without them, and that centrifugal force with
    #: the body's translational mass including its added mass)
    InertialLoads: str = "full"
    #: MoorDyn's saved state (a MoorDyn-C SaveState file) to start from, read after the catenary
    #: start and before the initial-condition solve (None: none)
    fileIC: str | None = None
    WriteUnits: int = 1
    disableOutput: int = 0
    writeLog: int = 0
    #: Syrope working curves: one per segment ('segment', moorline), or one per line rebuilt by
    #: whichever of its segments last raised its largest tension ('line', MoorDyn-C)
    SyropeWorkingCurve: str = "segment"
    #: MoorDyn's water-kinematics options as the deck gave them (the waves and current they read are
    #: in :class:`Environment`); kept so that a deck written back names the same files
    WaveKin: int = 0
    Currents: int = 0
    dtWave: float = 0.25
    #: options read from a deck that this version does not act on yet, {key: value text}
    not_acted_on: dict[str, str] = field(default_factory=dict)

