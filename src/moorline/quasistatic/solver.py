"""The quasi-static mooring model: :class:`QuasiStaticModel` (built once from a
:class:`~moorline.model.Model`) and its :meth:`~QuasiStaticModel.solve`.

Every line is an elastic catenary in its vertical plane (:mod:`.line2d`); free points (bridle
junctions, clump weights, buoys) and free bodies are in static equilibrium; coupled bodies and coupled
points are given (the coupled degrees of freedom, in the order of :class:`moorline.System`: coupled
bodies with 6 each, coupled-pinned bodies 3, then coupled points 3 each). One call of
:meth:`QuasiStaticModel.solve` runs one compiled kernel (:func:`.network.network_solve`),
warm-started from the previous solution, and returns the loads of the moorings on the coupled
degrees of freedom, their stiffness (implicit-function theorem through the free points and bodies),
the end tensions and, on request, the tension gradients.

What the quasi-static model represents and what it does not
-----------------------------------------------------------
* Line weight, buoyancy, elasticity (EA; a tabulated EA uses its secant ``EA_ref``), seabed contact
  at the lower end of a line anchored on the seabed (flat or, on a bathymetry grid, the plane through
  the anchor with the grid's local depth and slope there), MAP++-style seabed friction ``CB``.
* Not represented: bending stiffness (ignored, with a warning), rods (an error), hydrodynamic loads
  (drag, added mass; currents and waves), the seabed under points, a line touching the seabed away
  from an anchored lower end (a line hanging between two free or coupled points is taken as
  suspended).
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass

import numpy as np

from ..core.seabed import seabed_at
from ..model import BodyKind, Curve, Model, PointKind, rotation_xyz
from .hydrostatics import BodyHydrostatics
from .line2d import LINE2D_SIZE, line_profile_upright
from .network import (
    BF_BUOY,
    BF_C,
    BF_CB,
    BF_CG,
    BF_FEXT,
    BF_Q0,
    BF_R,
    BF_ROT,
    BF_SIZE,
    BF_WT,
    LF_CB,
    LF_EA,
    LF_GX,
    LF_GY,
    LF_H,
    LF_L,
    LF_SIZE,
    LF_V,
    LF_W,
    LI_BED,
    LW_CONTACT,
    LW_LB,
    LW_LOA,
    LW_SIZE,
    LW_SLOPE,
    LW_T,
    NET_LINE_FAILED,
    NET_SINGULAR,
    OPT_FTOL,
    OPT_LSCALE,
    OPT_MAXIT,
    OPT_MAXROT,
    OPT_MAXSTEP,
    PT_BODY,
    PT_DOF,
    PT_FIXED,
    angles_of,
    apply_step,
    euler_rate_matrix,
    line3d,
    network_solve,
    positions,
    tension_gradients,
)

__all__ = ["QuasiStaticError", "QuasiStaticModel", "QuasiStaticSolution"]

log = logging.getLogger("moorline.quasistatic")

#: a fixed point within this distance of the seabed (relative to the local depth, at least 1 cm)
#: counts as lying on it: its lines touch down there [-]
BED_TOL = 1e-4
#: default force tolerance of the equilibrium, relative to the force scale of the system [-]
DEFAULT_TOL = 1e-10
_SIX = ("x", "y", "z", "roll", "pitch", "yaw")


class QuasiStaticError(ValueError):
    """A system the quasi-static model cannot represent, or an equilibrium it cannot find."""


@dataclass
class QuasiStaticSolution:
    """One quasi-static solution (arrays are copies: they stay valid after the next solve).

    Attributes
    ----------
    x : ndarray, shape (nc,)
        The coupled DOF values it was solved at [m, rad].
    loads : ndarray, shape (nc,)
        Loads of the moorings on the coupled DOFs [N, N m]: forces on coupled points, force and moment
        about the reference point (global axes) on coupled bodies; the line ends and the weight and
        buoyancy of the points attached to them (not the body's own weight or hydrostatics).
    stiffness : ndarray, shape (nc, nc) or None
        ``K = -d loads / d x`` with the free points and bodies in equilibrium [N/m, N/rad, N m/m,
        N m/rad]; rotation columns are small rotations about the global axes (see
        :attr:`stiffness_euler` for Euler-angle increments). Restoring terms are positive on the
        diagonal. The rotation block differs from its transpose by ``S(M)`` (``M``: the mooring
        moment about the reference point), as for any moment that turns with the body.
    tensions : ndarray, shape (nL, 2)
        Tension at end A (anchor) and end B (fairlead) of every line [N].
    tension_gradient : ndarray, shape (nL, 2, nc) or None
        ``d tensions / d x`` [N/m, N/rad] (small rotations), when asked for.
    points : ndarray, shape (nP, 3)
        Positions of all points [m].
    bodies : ndarray, shape (nB, 6)
        Poses of all bodies (x, y, z [m], roll, pitch, yaw [rad]).
    iterations : int
        Newton iterations of the network solve (0 without free DOFs).
    """

    x: np.ndarray
    loads: np.ndarray
    stiffness: np.ndarray | None
    tensions: np.ndarray
    tension_gradient: np.ndarray | None
    points: np.ndarray
    bodies: np.ndarray
    iterations: int
    _euler_cols: np.ndarray | None = None

    @property
    def stiffness_euler(self) -> np.ndarray | None:
        """The stiffness with respect to Euler-angle increments of the coupled bodies
        (``K_euler = K T``, ``w = T d(roll, pitch, yaw)``), to linearise in the pose vector itself
        as ``loads(x) ~ loads(x0) - K_euler (x - x0)``; equal to :attr:`stiffness` at zero roll and pitch."""
        if self.stiffness is None:
            return None
        return self.stiffness if self._euler_cols is None else self.stiffness @ self._euler_cols


class QuasiStaticModel:
    """A mooring system for quasi-static analysis, built once from a :class:`~moorline.model.Model`.

    Parameters
    ----------
    model : Model
        The system (from :func:`moorline.io.read_deck` or built in Python). Rods are an error;
        bending stiffness is ignored with a warning.
    bodies_free : None, bool or iterable of int, optional
        Which bodies are in equilibrium (6 free DOFs) and which are given (6 coupled DOFs). None
        (default): as the deck says (FREE bodies free, COUPLED bodies given, COUPLEDPINNED bodies given
        in translation with free rotations). False: every body that is not FIXED is given (the
        time-domain coupling, where the dynamic model moves the bodies). True: every body that is not
        FIXED is free. An iterable of 1-based body numbers: those are free, every other non-FIXED
        body is given.
    hydrostatics : dict of int to BodyHydrostatics, optional
        Hydrostatics of free bodies by 1-based body number. A free body without it gets MoorDyn's
        body buoyancy: the deck volume at the centre of gravity, with no waterplane stiffness.
    external_loads : dict of int to array_like (6,), optional
        Constant loads on free bodies by 1-based body number (mean thrust, wind, current drag on the
        hull): force and moment about the reference point, global axes [N, N m].
    seabed_friction : float, "deck" or dict of str to float, optional
        Seabed friction coefficient ``CB`` of the lines (MAP++'s model, see :mod:`.line2d`): one value,
        a value per line type name, or "deck" for the deck's axial seabed friction coefficient
        (``mu_kA``, else ``FrictionCoefficient``). Default 0 (frictionless, as the dynamic model's
        statics).
    tol : float, optional
        Force tolerance of the equilibrium relative to the system's force scale [-].
    max_iter : int, optional
        Newton iteration cap of the network solve.
    """

    def __init__(self, model: Model, *, bodies_free=None, hydrostatics=None, external_loads=None,
                 seabed_friction=0.0, tol: float = DEFAULT_TOL, max_iter: int = 200):
        self.model = model
        self._check(model)
        env = model.env
        self.rho = float(env.rho)
        self.g = float(env.g)
        self._modes = self._body_modes(bodies_free)
        self.hydrostatics = {int(k): v for k, v in (hydrostatics or {}).items()}
        self.external_loads = {int(k): np.asarray(v, dtype=float).reshape(6) for k, v in (external_loads or {}).items()}
        for name, d in (("hydrostatics", self.hydrostatics), ("external_loads", self.external_loads)):
            for k in d:
                if not 1 <= k <= len(model.bodies):
                    raise QuasiStaticError(f"{name}: no body {k} ({len(model.bodies)} bodies)")
        for k in self.hydrostatics:
            if not isinstance(self.hydrostatics[k], BodyHydrostatics):
                raise QuasiStaticError(f"hydrostatics of body {k}: expected a BodyHydrostatics")
        self._build_dofs()
        self._build_points()
        self._build_bodies()
        self._build_lines(seabed_friction)
        self._build_scales(tol, max_iter)
        self._xc0 = self.deck_coupled_positions()
        self._start = (self.pf.copy(), self.bf.copy())
        self.last: QuasiStaticSolution | None = None
        self._predict = None  # (x, Euler columns) of the last solve whose Y is valid

    @classmethod
    def from_model(cls, model: Model, **kwargs) -> QuasiStaticModel:
        """Same as the constructor (keyword arguments there)."""
        return cls(model, **kwargs)

    # ------------------------------------------------------------------ building
    @staticmethod
    def _check(model: Model) -> None:
        if model.rods:
            raise QuasiStaticError(f"the deck has {len(model.rods)} rod(s): the quasi-static model cannot represent "
                                   "rods (rigid cylinders); use the dynamic model")
        for k, ln in enumerate(model.lines, 1):
            for end, att in (("A", ln.end_a), ("B", ln.end_b)):
                if att.kind != "point":
                    raise QuasiStaticError(f"line {k} end {end} is attached to {att}: the quasi-static model cannot "
                                           "represent rods")
        used = {ln.line_type for ln in model.lines}
        for name in sorted(used):
            lt = model.line_types[name]
            if lt.has_bending:
                log.warning("line type %r has bending stiffness EI: the quasi-static model ignores it", name)
            if isinstance(lt.EA, Curve):
                log.warning("line type %r has a tabulated EA: the quasi-static model uses its secant stiffness "
                            "EA_ref = %.6g N", name, lt.EA_ref)
        if not model.lines:
            raise QuasiStaticError("the model has no lines")

    def _body_modes(self, bodies_free) -> list[str]:
        """Per body: 'fixed', 'free', 'coupled' (6 given DOFs) or 'pinned' (translation given,
        rotations free)."""
        bodies = self.model.bodies
        if bodies_free is None:
            word = {BodyKind.FIXED: "fixed", BodyKind.FREE: "free", BodyKind.COUPLED: "coupled",
                    BodyKind.COUPLED_PINNED: "pinned"}
            return [word[b.kind] for b in bodies]
        if bodies_free is True or bodies_free is False:
            free = set(range(len(bodies))) if bodies_free else set()
        else:
            free = set()
            for k in bodies_free:
                k = int(k)
                if not 1 <= k <= len(bodies):
                    raise QuasiStaticError(f"bodies_free: no body {k} ({len(bodies)} bodies)")
                if bodies[k - 1].kind == BodyKind.FIXED:
                    raise QuasiStaticError(f"bodies_free: body {k} is FIXED in the deck")
                free.add(k - 1)
        return ["fixed" if b.kind == BodyKind.FIXED else "free" if i in free else "coupled"
                for i, b in enumerate(bodies)]

    def _build_dofs(self) -> None:
        """Number the DOFs: free ones first (bodies, then points), coupled ones in System order."""
        m = self.model
        nb, npt = len(m.bodies), len(m.points)
        self.bi = np.full((nb, 7), -1, dtype=np.int64)
        self.bi[:, 0] = 0
        self.pdof = np.full((npt, 3), -1, dtype=np.int64)
        k = 0
        labels_free = []
        for b, mode in enumerate(self._modes):
            if mode == "free":
                self.bi[b, 1:7] = np.arange(k, k + 6)
                labels_free += [f"B{b + 1}_{c}" for c in _SIX]
                k += 6
            elif mode == "pinned":
                self.bi[b, 4:7] = np.arange(k, k + 3)
                labels_free += [f"B{b + 1}_{c}" for c in _SIX[3:]]
                k += 3
        for p, pt in enumerate(m.points):
            if pt.kind == PointKind.FREE:
                self.pdof[p] = np.arange(k, k + 3)
                labels_free += [f"P{p + 1}_{c}" for c in "xyz"]
                k += 3
        self.nu = k
        labels = []
        self._coupled_bodies = []
        for b, mode in enumerate(self._modes):
            if mode in ("coupled", "pinned"):
                n = 6 if mode == "coupled" else 3
                self.bi[b, 1:1 + n] = np.arange(k, k + n)
                labels += [f"B{b + 1}_{c}" for c in _SIX[:n]]
                self._coupled_bodies.append(b)
                k += n
        self._coupled_points = []
        for p, pt in enumerate(m.points):
            if pt.kind == PointKind.COUPLED:
                self.pdof[p] = np.arange(k, k + 3)
                labels += [f"P{p + 1}_{c}" for c in "xyz"]
                self._coupled_points.append(p)
                k += 3
        self.nz = k
        self.free_dof_labels = labels_free
        self.coupled_dof_labels = labels
        for b in range(nb):  # a body's own loads count where it has free DOFs
            self.bi[b, 0] = int(np.any((self.bi[b, 1:] >= 0) & (self.bi[b, 1:] < self.nu)))
        self.rotdof = np.zeros(self.nz, dtype=np.bool_)
        for b in range(nb):
            for j in range(4, 7):
                if self.bi[b, j] >= 0:
                    self.rotdof[self.bi[b, j]] = True

    @property
    def coupled_bodies(self) -> list[int]:
        """0-based indices of the bodies whose DOFs are given (in the order of ``x``)."""
        return list(self._coupled_bodies)

    @property
    def n_coupled_dof(self) -> int:
        """Number of coupled DOFs (length of the ``x`` of :meth:`solve`)."""
        return self.nz - self.nu

    def deck_coupled_positions(self) -> np.ndarray:
        """The coupled DOF vector with every coupled object where the deck puts it [m, rad]."""
        m = self.model
        out = []
        for b in self._coupled_bodies:
            body = m.bodies[b]
            out.append(np.concatenate([body.r, np.radians(body.angles)]) if self._modes[b] == "coupled" else body.r)
        out += [m.points[p].r for p in self._coupled_points]
        return np.concatenate(out) if out else np.zeros(0)

    def _build_points(self) -> None:
        m = self.model
        npt = len(m.points)
        self.pf = np.zeros((npt, 6))
        self.pi = np.full((npt, 5), -1, dtype=np.int64)
        for p, pt in enumerate(m.points):
            self.pf[p, :3] = pt.r
            self.pf[p, 3:] = pt.F_ext + np.array([0.0, 0.0, self.g * (self.rho * pt.V - pt.m)])
            if pt.kind == PointKind.BODY:
                self.pi[p, 0] = PT_BODY
                self.pi[p, 1] = pt.body
            elif pt.kind in (PointKind.FREE, PointKind.COUPLED):
                self.pi[p, 0] = PT_DOF
                self.pi[p, 1] = -1
                self.pi[p, 2:5] = self.pdof[p]
            else:
                self.pi[p, 0] = PT_FIXED
                self.pi[p, 1] = -1

    def _build_bodies(self) -> None:
        m = self.model
        self.bf = np.zeros((len(m.bodies), BF_SIZE))
        for b, body in enumerate(m.bodies):
            row = self.bf[b]
            row[BF_R:BF_R + 3] = body.r
            row[BF_ROT:BF_ROT + 9] = body.rotation.ravel()
            q_deck = np.concatenate([body.r, np.radians(body.angles)])
            row[BF_Q0:BF_Q0 + 6] = q_deck
            if not self.bi[b, 0]:
                if b + 1 in self.hydrostatics or b + 1 in self.external_loads:
                    log.warning("body %d has no free DOFs: its hydrostatics and external loads are not used", b + 1)
                continue
            row[BF_WT] = body.m * self.g
            row[BF_CG:BF_CG + 3] = body.rCG
            hs = self.hydrostatics.get(b + 1)
            if hs is None:
                row[BF_BUOY] = self.rho * self.g * body.V  # MoorDyn: the deck volume at the CG
                row[BF_CB:BF_CB + 3] = body.rCG
            else:
                if body.V > 0:
                    log.info("body %d: the hydrostatics given replace the deck volume %.6g m^3", b + 1, body.V)
                q0 = q_deck if hs.reference_pose is None else hs.reference_pose
                row[BF_Q0:BF_Q0 + 6] = q0
                row[BF_BUOY] = self.rho * self.g * hs.displaced_volume
                row[BF_CB:BF_CB + 3] = hs.center_of_buoyancy
                row[BF_C:BF_C + 36] = hs.waterplane_stiffness(self.rho, self.g, rotation_xyz(q0[3:])).ravel()
            if b + 1 in self.external_loads:
                row[BF_FEXT:BF_FEXT + 6] = self.external_loads[b + 1]

    def _seabed(self, x, y):
        """Seabed height [m] and gradient (dz/dx, dz/dy) at (x, y); None without a seabed."""
        env = self.model.env
        bath = env.bathymetry
        if bath is None:
            if env.depth <= 0.0:
                return None
            return -env.depth, 0.0, 0.0
        zb, nx, ny, nz, outside = seabed_at(bath.x, bath.y, bath.z, float(env.depth), float(x), float(y))
        if outside:
            log.warning("an anchor at (%.6g, %.6g) lies outside the bathymetry grid: the nearest edge is used", x, y)
        return zb, -nx / nz, -ny / nz

    def _build_lines(self, seabed_friction) -> None:
        m = self.model
        nL = len(m.lines)
        self.lf = np.zeros((nL, LF_SIZE))
        self.li = np.zeros((nL, 3), dtype=np.int64)
        self.lw = np.zeros((nL, LW_SIZE))
        fixed = [self._is_fixed(p) for p in range(len(m.points))]
        deck_pos = [m.point_position(p) for p in range(len(m.points))]
        for k, ln in enumerate(m.lines):
            lt = m.line_types[ln.line_type]
            a, b = ln.end_a.index, ln.end_b.index
            L = ln.L if ln.L > 0 else -ln.L * float(np.linalg.norm(deck_pos[b] - deck_pos[a]))
            if not L > 0:
                raise QuasiStaticError(f"line {k + 1}: unstretched length must be > 0 (got {L})")
            self.li[k, 0], self.li[k, 1] = a, b
            row = self.lf[k]
            row[LF_L] = L
            row[LF_EA] = lt.EA_ref
            row[LF_W] = (lt.w - self.rho * lt.A) * self.g
            row[LF_CB] = self._friction(seabed_friction, lt)
            row[LF_H] = -1.0
            for end, p in ((1, a), (2, b)):
                if not fixed[p]:
                    continue
                sb = self._seabed(*deck_pos[p][:2])
                if sb is None:
                    continue
                zb, gx, gy = sb
                tol = BED_TOL * max(100.0, abs(zb))
                if deck_pos[p][2] <= zb + tol:
                    if deck_pos[p][2] < zb - tol:
                        log.warning("line %d end %s: point %d lies %.4g m below the seabed; taken as on it", k + 1,
                                    "AB"[end - 1], p + 1, zb - deck_pos[p][2])
                    if self.li[k, LI_BED] == 0:
                        self.li[k, LI_BED] = end
                        row[LF_GX], row[LF_GY] = gx, gy
            if row[LF_CB] > 0 and self.li[k, LI_BED] == 0:
                log.info("line %d has no end anchored on the seabed: its friction coefficient is not used", k + 1)

    def _is_fixed(self, p: int) -> bool:
        pt = self.model.points[p]
        if pt.kind == PointKind.FIXED:
            return True
        return pt.kind == PointKind.BODY and self.model.bodies[pt.body].kind == BodyKind.FIXED

    def _friction(self, spec, lt) -> float:
        if isinstance(spec, str):
            if spec != "deck":
                raise QuasiStaticError(f"seabed_friction: expected a number, a dict or 'deck', got {spec!r}")
            return float(self.model.env.friction_coefficients()[1])
        if isinstance(spec, dict):
            v = float(spec.get(lt.name, 0.0))
        else:
            v = float(spec)
        if not v >= 0:
            raise QuasiStaticError(f"seabed friction coefficient of line type {lt.name!r} must be >= 0, got {v}")
        return v

    def _build_scales(self, tol: float, max_iter: int) -> None:
        fs = [1.0]
        fs += list(np.abs(self.lf[:, LF_W]) * self.lf[:, LF_L])
        fs += list(np.linalg.norm(self.pf[:, 3:], axis=1))
        fs += list(self.bf[:, BF_WT]) + list(self.bf[:, BF_BUOY])
        self.force_scale = float(max(fs))
        ls = [1.0] + [float(np.linalg.norm(self.pf[p, :3])) for p in range(len(self.pf)) if self.pi[p, 0] == PT_BODY]
        self.length_scale = float(max(ls))
        self.opt = np.zeros(5)
        self.opt[OPT_FTOL] = float(tol) * self.force_scale
        self.opt[OPT_LSCALE] = self.length_scale
        self.opt[OPT_MAXIT] = int(max_iter)
        self.opt[OPT_MAXSTEP] = 0.25 * float(np.min(self.lf[:, LF_L]))
        self.opt[OPT_MAXROT] = 0.2
        nP = len(self.pf)
        self._r = np.zeros((nP, 3))
        self._rho = np.zeros((nP, 3))
        self._fp = np.zeros((nP, 3))
        self._Q = np.zeros(self.nz)
        self._K = np.zeros((self.nz, self.nz))
        self._A = np.zeros((self.nu, self.nu))
        self._piv = np.zeros(self.nu, dtype=np.int64)
        nc = self.nz - self.nu
        self._Kc = np.zeros((nc, nc))
        self._Y = np.zeros((self.nu, nc))

    # ------------------------------------------------------------------ solving
    def reset(self) -> None:
        """Forget the warm start: free points and bodies back to their deck positions."""
        self.pf[:, :] = self._start[0]
        self.bf[:, :] = self._start[1]
        self.lf[:, LF_H] = -1.0
        self.last = None
        self._predict = None

    def solve(self, x=None, *, stiffness: bool = True, gradients: bool = False) -> QuasiStaticSolution:
        """Equilibrium of the free points and bodies with the coupled DOFs at ``x``.

        Parameters
        ----------
        x : array_like, shape (nc,), optional
            Coupled DOFs [m, rad] in :attr:`coupled_dof_labels` order (coupled bodies: x, y, z, roll,
            pitch, yaw with ``R = Rx Ry Rz``; coupled points: x, y, z); default: the deck positions.
        stiffness : bool
            Also compute the condensed stiffness (and the tension gradients with ``gradients``).
        gradients : bool
            Also compute the gradients of the end tensions with respect to ``x``.

        Returns
        -------
        QuasiStaticSolution

        Raises
        ------
        QuasiStaticError
            When a line has no solution (an end below the seabed) or the equilibrium is not found.
        """
        xc = self._xc0 if x is None else np.asarray(x, dtype=float).reshape(-1)
        if xc.shape[0] != self.nz - self.nu:
            raise QuasiStaticError(f"x has {xc.shape[0]} values; the system has {self.nz - self.nu} coupled DOFs "
                                   f"({', '.join(self.coupled_dof_labels) or 'none'})")
        want = bool(stiffness or gradients)
        saved = None
        if self._predict is not None:
            # first-order predictor of the free DOFs from the last solve: du = -Y dc
            x_last, E = self._predict
            dc = xc - x_last
            if np.any(dc):
                saved = (self.pf.copy(), self.bf.copy())
                dz = -(self._Y @ (dc if E is None else E @ dc))
                big = float(np.max(np.abs(dz[~self.rotdof[:self.nu]]), initial=0.0))
                if big <= self.opt[OPT_MAXSTEP]:
                    apply_step(dz, 1.0, self.nu, self.pf, self.pi, self.bf, self.bi)
        self._predict = None
        status, it, info, res = network_solve(self.lf, self.li, self.pf, self.pi, self.bf, self.bi, self.rotdof,
                                              self.nu, xc, self.opt, self.lw, self._r, self._rho, self._fp, self._Q,
                                              self._K, self._A, self._piv, self._Kc, self._Y, want)
        if status != 0 and saved is not None:  # retry from the last solution itself
            self.pf[:, :], self.bf[:, :] = saved
            status, it, info, res = network_solve(self.lf, self.li, self.pf, self.pi, self.bf, self.bi, self.rotdof,
                                                  self.nu, xc, self.opt, self.lw, self._r, self._rho, self._fp,
                                                  self._Q, self._K, self._A, self._piv, self._Kc, self._Y, want)
        if status != 0:
            self._raise(status, it, info, res, xc)
        euler = self._euler_columns(xc)
        if want and self.nu:
            self._predict = (xc.copy(), euler)
        nc = self.nz - self.nu
        G = None
        if gradients:
            G = np.zeros((len(self.li), 2, nc))
            tension_gradients(self.li, self.pi, self.bi, self.lw, self._rho, self.nu, self._Y, G)
        sol = QuasiStaticSolution(
            x=xc.copy(), loads=self._Q[self.nu:].copy(), stiffness=self._Kc.copy() if stiffness else None,
            tensions=self.lw[:, LW_T:LW_T + 2].copy(), tension_gradient=G, points=self._r.copy(),
            bodies=self.body_poses(), iterations=int(it), _euler_cols=euler)
        self.last = sol
        return sol

    def _raise(self, status, it, info, res, xc):
        hints = ""
        if status != NET_LINE_FAILED:
            below = []
            r = self.point_positions()
            for p in range(len(r)):
                sb = self._seabed(r[p, 0], r[p, 1]) if self.pi[p, 0] != PT_FIXED else None
                if sb is not None and r[p, 2] < sb[0]:
                    below.append(f"point {p + 1} reached {sb[0] - r[p, 2]:.3g} m below the seabed")
            if below:
                hints = ("; " + ", ".join(below) + " (the quasi-static model has no seabed contact for points: a "
                         "clump weight must hang above the seabed)")
        # put the start back so the next call does not begin from a diverged state
        self.reset()
        if status == NET_LINE_FAILED:
            ln = int(info)
            a, b = self.li[ln, 0] + 1, self.li[ln, 1] + 1
            raise QuasiStaticError(f"line {ln + 1} (points {a} -> {b}) has no quasi-static solution at x = "
                                   f"{np.round(xc, 6).tolist()}: an end lies below the seabed, or the catenary did not "
                                   "converge")
        if status == NET_SINGULAR:
            raise QuasiStaticError("the free points and bodies have no stiffness in some direction (slack lines, or a "
                                   "free body without hydrostatics): no unique equilibrium")
        raise QuasiStaticError(f"equilibrium not found after {it} Newton iterations (residual {res:.4g} N, tolerance "
                               f"{self.opt[OPT_FTOL]:.3g} N); free DOFs: {', '.join(self.free_dof_labels)}{hints}")

    def _euler_columns(self, xc) -> np.ndarray | None:
        """``blockdiag(I, T)`` over the coupled DOFs (``T`` of each coupled body's roll and pitch)."""
        nc = self.nz - self.nu
        M = None
        T = np.zeros((3, 3))
        for b in self._coupled_bodies:
            k = self.bi[b, 4]
            if k < self.nu:
                continue
            j = k - self.nu
            roll, pitch = xc[j], xc[j + 1]
            if roll == 0.0 and pitch == 0.0:
                continue
            if M is None:
                M = np.eye(nc)
            euler_rate_matrix(roll, pitch, T)
            M[j:j + 3, j:j + 3] = T
        return M

    def body_poses(self) -> np.ndarray:
        """Current poses of all bodies, shape (nB, 6) [m, rad]."""
        out = np.zeros((len(self.bf), 6))
        for b in range(len(self.bf)):
            out[b, :3] = self.bf[b, BF_R:BF_R + 3]
            out[b, 3:] = angles_of(self.bf[b, BF_ROT:BF_ROT + 9].reshape(3, 3))
        return out

    def point_positions(self) -> np.ndarray:
        """Current positions of all points, shape (nP, 3) [m]."""
        r = np.zeros((len(self.pf), 3))
        positions(self.pf, self.pi, self.bf, r, np.zeros_like(r))
        return r

    def line_state(self) -> dict[str, np.ndarray]:
        """Per-line quantities of the last solve: ``H``, ``V`` [N] (upright frame, upper end),
        ``grounded_length`` [m], ``contact`` (bool), ``slope`` (tan alpha), ``lower_is_a`` (bool)."""
        return {"H": self.lf[:, LF_H].copy(), "V": self.lf[:, LF_V].copy(),
                "grounded_length": self.lw[:, LW_LB].copy(), "contact": self.lw[:, LW_CONTACT] > 0.5,
                "slope": self.lw[:, LW_SLOPE].copy(), "lower_is_a": self.lw[:, LW_LOA] > 0.5}

    def line_profile(self, line: int, n: int = 51) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Shape of a line in the last solution.

        Parameters
        ----------
        line : int
            1-based line number.
        n : int
            Number of samples, equally spaced in unstretched arc length.

        Returns
        -------
        s : ndarray, shape (n,)
            Unstretched arc length from end A [m].
        r : ndarray, shape (n, 3)
            Positions [m].
        T : ndarray, shape (n,)
            Tension [N].
        """
        if self.last is None:
            self.solve(stiffness=False)
        k = int(line) - 1
        if not 0 <= k < len(self.li):
            raise QuasiStaticError(f"no line {line} ({len(self.li)} lines)")
        r = self.point_positions()
        lo_a = self.lw[k, LW_LOA] > 0.5
        rlo, rup = (r[self.li[k, 0]], r[self.li[k, 1]]) if lo_a else (r[self.li[k, 1]], r[self.li[k, 0]])
        d = rup - rlo
        X = math.hypot(d[0], d[1])
        u = d[:2] / X if X > 0 else np.array([1.0, 0.0])
        row = self.lf[k]
        L = row[LF_L]
        s = np.linspace(0.0, L, int(n))
        s_lo = s if lo_a else L - s
        px, pz, pT = np.zeros(n), np.zeros(n), np.zeros(n)
        line_profile_upright(X, d[2], L, row[LF_EA], row[LF_W], bool(self.lw[k, LW_CONTACT] > 0.5),
                             self.lw[k, LW_SLOPE], row[LF_CB], row[LF_H], row[LF_V], s_lo, px, pz, pT)
        pos = np.column_stack([rlo[0] + px * u[0], rlo[1] + px * u[1], rlo[2] + pz])
        return s, pos, pT

    def check_seabed(self, tol: float = 0.0) -> list[str]:
        """Warnings for free points below the seabed and suspended lines that dip below it in the last
        solution (the quasi-static model gives points no seabed contact and lets only lines anchored on
        the seabed touch it)."""
        out = []
        r = self.point_positions()
        for p in range(len(r)):
            if self.pi[p, 0] == PT_FIXED:
                continue
            sb = self._seabed(r[p, 0], r[p, 1])
            if sb is not None and r[p, 2] < sb[0] - tol:
                out.append(f"point {p + 1} lies {sb[0] - r[p, 2]:.4g} m below the seabed")
        for k in range(len(self.li)):
            if self.lw[k, LW_CONTACT] > 0.5:
                continue
            _, pos, _ = self.line_profile(k + 1, 41)
            low = int(np.argmin(pos[:, 2]))
            sb = self._seabed(pos[low, 0], pos[low, 1])
            if sb is not None and pos[low, 2] < sb[0] - tol:
                out.append(f"line {k + 1} sags {sb[0] - pos[low, 2]:.4g} m below the seabed (it is not anchored on it, "
                           "so the quasi-static model keeps it suspended)")
        for msg in out:
            log.warning(msg)
        return out


def line_end_forces(rA, rB, L, EA, W, *, seabed_end=None, slope=(0.0, 0.0), CB=0.0):
    """Forces of one line on its two ends and their tensions (plain-Python access to the kernel).

    Parameters
    ----------
    rA, rB : array_like, shape (3,)
        End positions [m].
    L, EA, W : float
        Unstretched length [m], axial stiffness [N], wet weight per length [N/m].
    seabed_end : {None, 'A', 'B'}
        The end lying on the seabed (its lines touch down there).
    slope : (float, float)
        Seabed gradient (dz/dx, dz/dy) at that end [-].
    CB : float
        Seabed friction coefficient [-].

    Returns
    -------
    F : ndarray, shape (2, 3)
        Forces on end A and end B [N].
    D : ndarray, shape (2, 3, 3)
        Their derivatives with respect to ``rB - rA`` [N/m].
    T : ndarray, shape (2,)
        Tensions at A and B [N].
    """
    lf = np.array([L, EA, W, CB, slope[0], slope[1], -1.0, 0.0], dtype=float)
    li = np.array([0, 1, {None: 0, "A": 1, "B": 2}[seabed_end]], dtype=np.int64)
    lw = np.zeros(LW_SIZE)
    st = line3d(np.asarray(rA, dtype=float), np.asarray(rB, dtype=float), lf, li, np.zeros(LINE2D_SIZE), lw)
    if st != 0:
        raise QuasiStaticError(f"line has no quasi-static solution (status {st})")
    return lw[0:6].reshape(2, 3), lw[6:24].reshape(2, 3, 3), lw[LW_T:LW_T + 2].copy()

