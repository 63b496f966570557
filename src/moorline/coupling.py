"""The outer-program interface: :class:`System` with ``init(x, xd)`` and ``step(x, xd, t, dt)``.

It mirrors MoorDyn's coupling API so that coupling scripts port by renaming::

    sys = moorline.System.from_file("mooring.dat")      # MoorDyn_Create
    f = sys.init(x, xd)                                  # MoorDyn_Init
    f = sys.step(x, xd, t, dt)                           # MoorDyn_Step
    sys.lines[0].fairlead_tension()                      # MoorDyn_GetLineFairTen

``x`` and ``xd`` are the coupled degrees of freedom in MoorDyn's order: coupled bodies and rods
(6 each, x y z roll pitch yaw; 3 when pinned), then coupled points (3 each). Forces returned are the
loads the mooring system exerts on the coupled objects [N, N m].
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from .core.catenary import CatenaryStatus
from .core.implicit import (
    RHO_INF,
    S_AVALID,
    S_H,
    S_HJ,
    S_NBACK,
    S_NFAC,
    S_NIT,
    S_NJAC,
    S_NREJ,
    S_NRHS,
    S_NSLOW,
    S_NSTEP,
    advance_implicit,
    build_implicit,
    gen_alpha_parameters,
    new_implicit_work,
    newton_statics,
)
from .core.integrate import Scheme, advance, parse_scheme
from .core.layout import P_FREE, Motion, build_layout, static_motion, step_motion
from .core.rhs import rhs
from .core.seabed import resting_penetration, seabed_at
from .core.stability import choose_dtM, stability_report
from .core.statics import catenary_start, dynamic_relaxation, stationary_solve
from .errors import SimulationError
from .model import BodyKind, Model, RodKind, angles_xyz

log = logging.getLogger("moorline")

#: node speed [m/s] above which a state is taken as unstable
MAX_NODE_SPEED = 500.0
#: Newton statics converges when every residual acceleration is below NEWTON_ACC_TOL [m/s^2] (a
#: force of 1e-5 N per kg of node mass) and the last position update below NEWTON_DX_TOL [m]
NEWTON_ACC_TOL = 1e-5
NEWTON_DX_TOL = 1e-6
NEWTON_MAX_IT = 400
#: Newton iterations from the catenary start before implicit relaxation takes over
NEWTON_FIRST_IT = 30


class LineView:
    """Read access to one line of a running :class:`System` (values of the last evaluation)."""

    def __init__(self, system: System, index: int):
        self._s = system
        self.index = index
        L = system.layout.lines
        self._n = slice(int(L.node_ptr[index]), int(L.node_ptr[index + 1]))
        self._g = slice(int(L.seg_ptr[index]), int(L.seg_ptr[index + 1]))

    @property
    def number(self) -> int:
        """1-based line number, as in the deck."""
        return self.index + 1

    @property
    def n_segments(self) -> int:
        return self._g.stop - self._g.start

    @property
    def unstretched_length(self) -> float:
        return float(self._s.layout.line_L[self.index])

    @property
    def line_type(self) -> str:
        return self._s.layout.line_type_names[self.index]

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (N+1, 3), node 0 = end A."""
        return self._s.work.r[self._n].copy()

    def node_velocities(self) -> np.ndarray:
        """Node velocities [m/s], shape (N+1, 3)."""
        return self._s.work.v[self._n].copy()

    def node_forces(self) -> np.ndarray:
        """Net force on each node [N], shape (N+1, 3) (all loads, spec 3.12)."""
        return self._s.work.F[self._n].copy()

    def node_curvatures(self) -> np.ndarray:
        """Curvature at each node [1/m], shape (N+1,): (4/lam) sin(theta/2) between the adjacent
        segments (spec 3.10); zero at pinned ends. Lines with EI get it from the last evaluation
        (with their clamped ends); for the others it is computed here from the node positions."""
        if self._s.layout.lines.EI[self.index] > 0 or self._s.layout.lines.ei_tab[self.index, 1] > 0:
            return self._s.work.kurv[self._n].copy()
        r = self._s.work.r[self._n]
        d = np.diff(r, axis=0)
        ls = np.linalg.norm(d, axis=1)
        k = np.zeros(len(r))
        ok = (ls[:-1] > 0) & (ls[1:] > 0)
        c = np.einsum("ij,ij->i", d[:-1], d[1:]) / np.where(ok, ls[:-1] * ls[1:], 1.0)
        k[1:-1] = np.where(ok & (c < 1.0 - 2.220446049250313e-16),
                           4.0 / (ls[:-1] + ls[1:]) * np.sqrt(np.clip(0.5 * (1.0 - c), 0.0, None)), 0.0)
        return k

    def node_bending_moments(self) -> np.ndarray:
        """Bending moment magnitude at each node [N m], shape (N+1,): EI kappa, or M(kappa) from
        the moment-curvature table (spec 3.10); zero for lines without EI."""
        L = self._s.layout.lines
        k = self.node_curvatures()
        start, n = int(L.ei_tab[self.index, 0]), int(L.ei_tab[self.index, 1])
        if n > 0:
            return np.interp(k, L.tab_x[start:start + n], L.tab_y[start:start + n])
        return float(L.EI[self.index]) * k

    def node_bending_forces(self) -> np.ndarray:
        """Bending forces on each node [N], shape (N+1, 3) (zero for lines without EI)."""
        return self._s.work.Fbend[self._n].copy()

    def end_moments(self) -> np.ndarray:
        """Bending moment a clamped end A and end B put on its rod [N m], shape (2, 3); zero at
        pinned ends."""
        return self._s.work.end_moment[self.index].copy()

    def segment_tension_vectors(self) -> np.ndarray:
        """Tension plus internal damping force of each segment [N], shape (N, 3), from node k to k+1."""
        w = self._s.work
        return w.T[self._g] + w.Td[self._g]

    def segment_tensions(self) -> np.ndarray:
        """|T + Td| of each segment [N], shape (N,)."""
        return np.linalg.norm(self.segment_tension_vectors(), axis=1)

    def segment_strains(self) -> np.ndarray:
        """Strain l_s/l - 1 of each segment [-], shape (N,)."""
        w = self._s.work
        return w.seg_len[self._g] / self._s.layout.lines.seg_l0[self._g] - 1.0

    def node_water_velocities(self) -> np.ndarray:
        """Water velocity (waves + current) at each node [m/s], shape (N+1, 3)."""
        return self._s.work.U[self._n].copy()

    def node_hydro_forces(self) -> np.ndarray:
        """Drag plus fluid-inertia force on each node [N], shape (N+1, 3)."""
        return self._s.work.Fhyd[self._n].copy()

    def node_seabed_forces(self) -> np.ndarray:
        """Seabed contact plus friction force on each node [N], shape (N+1, 3)."""
        return self._s.work.Fbed[self._n].copy()

    def segment_elastic_tensions(self) -> np.ndarray:
        """Magnitude of the elastic tension of each segment, damping excluded [N], shape (N,)."""
        return np.linalg.norm(self._s.work.T[self._g], axis=1)

    def segment_damping_forces(self) -> np.ndarray:
        """Internal damping force vector of each segment [N], shape (N, 3)."""
        return self._s.work.Td[self._g].copy()

    def segment_strain_rates(self) -> np.ndarray:
        """Strain rate (dl_s/dt)/l of each segment [1/s], shape (N,)."""
        w = self._s.work
        return w.seg_ldot[self._g] / self._s.layout.lines.seg_l0[self._g]

    def node_tensions(self) -> np.ndarray:
        """MoorDyn's node tension [N], shape (N+1,): the mean of the two adjacent segment forces at
        internal nodes, the end segment's force at the ends (MoorDyn's GetLineNodeTen)."""
        sv = self.segment_tension_vectors()
        out = np.empty(len(sv) + 1)
        out[0] = np.linalg.norm(sv[0])
        out[-1] = np.linalg.norm(sv[-1])
        out[1:-1] = np.linalg.norm(0.5 * (sv[:-1] + sv[1:]), axis=1)
        return out

    def fairlead_tension(self) -> float:
        """|T + Td| of the end-B segment [N] (MoorDyn's GetLineFairTen)."""
        return float(np.linalg.norm(self.segment_tension_vectors()[-1]))

    def anchor_tension(self) -> float:
        """|T + Td| of the end-A segment [N]."""
        return float(np.linalg.norm(self.segment_tension_vectors()[0]))

    def end_force(self, end: str) -> np.ndarray:
        """Net force on the end node (``'A'`` or ``'B'``) [N]: what MoorDyn's FairTen/AnchTen report."""
        w = self._s.work
        return w.F[self._n.start if end.upper() == "A" else self._n.stop - 1].copy()


class _ObjectView:
    """Read access to object ``index`` of a running :class:`System`; ``_objects`` names the
    model's list of such objects."""

    _objects = ""

    def __init__(self, system: System, index: int):
        self._s = system
        self.index = index

    @property
    def number(self) -> int:
        """1-based number, as in the deck."""
        return self.index + 1

    @property
    def kind(self):
        return getattr(self._s.model, self._objects)[self.index].kind


class PointView(_ObjectView):
    """Read access to one point of a running :class:`System`."""

    _objects = "points"

    def position(self) -> np.ndarray:
        return self._s.work.pr[self.index].copy()

    def velocity(self) -> np.ndarray:
        return self._s.work.pv[self.index].copy()

    def acceleration(self) -> np.ndarray:
        return self._s.work.pa[self.index].copy()

    def force(self) -> np.ndarray:
        """Net force on the point [N]: attached line ends, weight, buoyancy, drag, external force."""
        return self._s.work.pF[self.index].copy()


def _quat_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of the smallest rotation taking unit vector a to b."""
    a = a / np.linalg.norm(a)
    b = b / np.linalg.norm(b)
    c = float(np.dot(a, b))
    if c < -1.0 + 1e-12:  # opposite: half a turn about any axis normal to a
        n = np.cross(a, [1.0, 0.0, 0.0])
        if np.linalg.norm(n) < 1e-6:
            n = np.cross(a, [0.0, 1.0, 0.0])
        n /= np.linalg.norm(n)
        return np.array([0.0, *n])
    q = np.array([1.0 + c, *np.cross(a, b)])
    return q / np.linalg.norm(q)


class RodView(_ObjectView):
    """Read access to one rod of a running :class:`System` (values of the last evaluation)."""

    _objects = "rods"

    def __init__(self, system: System, index: int):
        super().__init__(system, index)
        ptr = system.layout.rigid.rod_node_ptr
        self._n = slice(int(ptr[index]), int(ptr[index + 1]))

    def node_positions(self) -> np.ndarray:
        """Node positions [m], shape (N+1, 3) (one node for a zero-length rod)."""
        return self._s.work.rn_r[self._n].copy()

    def node_velocities(self) -> np.ndarray:
        return self._s.work.rn_v[self._n].copy()

    def node_forces(self) -> np.ndarray:
        """Net force on each node [N] incl. the attached line ends, shape (N+1, 3)."""
        return self._s.work.rn_F[self._n, 8].copy()

    def node_force_components(self) -> dict[str, np.ndarray]:
        """Node loads by kind [N], each (N+1, 3): weight, buoyancy, transverse and axial drag,
        transverse and axial fluid inertia, dynamic pressure, seabed."""
        names = ("weight", "buoyancy", "drag_transverse", "drag_axial", "inertia_transverse", "inertia_axial",
                 "dynamic_pressure", "seabed")
        F = self._s.work.rn_F[self._n]
        return {k: F[:, i].copy() for i, k in enumerate(names)}

    def end_positions(self) -> np.ndarray:
        """Positions of ends A and B [m], shape (2, 3)."""
        return self._s.work.rodr[self.index].copy()

    def axis(self) -> np.ndarray:
        """Unit vector from end A to end B."""
        return self._s.work.rodq[self.index].copy()

    def angular_velocity(self) -> np.ndarray:
        """Angular velocity [rad/s], global axes."""
        return self._s.work.rodw[self.index].copy()

    def inclination(self) -> tuple[float, float]:
        """(phi, beta) [rad]: angle of the axis from vertical (0 = pointing up) and its heading."""
        q = self.axis()
        h = math.hypot(q[0], q[1])
        return math.atan2(h, q[2]), (math.atan2(q[1], q[0]) if h >= 1e-6 else 0.0)

    def roll_pitch(self) -> tuple[float, float]:
        """MoorDyn's rod roll and pitch [rad]: -phi sin(beta), phi cos(beta) (spec 3.14.1)."""
        phi, beta = self.inclination()
        return -phi * math.sin(beta), phi * math.cos(beta)

    def velocity(self) -> np.ndarray:
        """End-A velocity [m/s]."""
        return self._s.work.rodv[self.index, 0].copy()

    def acceleration(self) -> np.ndarray:
        """(a_A, alpha) [m/s^2, rad/s^2], shape (6,) (zero for rods without degrees of freedom,
        the imposed end-A acceleration for coupled-pinned rods)."""
        return self._s.work.rodacc[self.index].copy()

    def submergence(self) -> float:
        """Mean submerged fraction of the rod's nodes [-]."""
        return float(np.mean(self._s.work.rn_vof[self._n]))

    def force(self) -> np.ndarray:
        """Net force and moment about end A [N, N m], shape (6,) (coupled rods: minus M a_in)."""
        return self._s.work.rod6F[self.index].copy()

    def mass_matrix(self) -> np.ndarray:
        """6x6 mass matrix about end A, global axes."""
        return self._s.work.rod6M[self.index].copy()

    def end_tensions(self) -> np.ndarray:
        """|sum of the line end forces| at ends A and B [N] (MoorDyn's TenA, TenB)."""
        return np.linalg.norm(self._s.work.rodF[self.index], axis=1)


class BodyView(_ObjectView):
    """Read access to one body of a running :class:`System`."""

    _objects = "bodies"

    def position(self) -> np.ndarray:
        """Reference-point position [m]."""
        return self._s.work.br[self.index].copy()

    def rotation_matrix(self) -> np.ndarray:
        """Rotation from body to global axes, shape (3, 3)."""
        return self._s.work.bR[self.index].copy()

    def angles(self) -> np.ndarray:
        """Roll, pitch, yaw [rad] (R = Rx(roll) Ry(pitch) Rz(yaw), pitch in [-pi/2, pi/2])."""
        return angles_xyz(self._s.work.bR[self.index])

    def pose(self) -> np.ndarray:
        """(x, y, z, roll, pitch, yaw) [m, rad]."""
        return np.concatenate([self.position(), self.angles()])

    def velocity(self) -> np.ndarray:
        return self._s.work.bv[self.index].copy()

    def angular_velocity(self) -> np.ndarray:
        """[rad/s], global axes."""
        return self._s.work.bw[self.index].copy()

    def acceleration(self) -> np.ndarray:
        """(a, alpha) of the reference point [m/s^2, rad/s^2], shape (6,)."""
        return self._s.work.bacc[self.index].copy()

    def force(self) -> np.ndarray:
        """Net force and moment about the reference point [N, N m], shape (6,) (coupled bodies:
        the load returned to the caller, F6 - M a_in)."""
        return self._s.work.b6F[self.index].copy()

    def mass_matrix(self) -> np.ndarray:
        return self._s.work.b6M[self.index].copy()


#: the implicit scheme ramps the seabed damping in over this many static penetrations
BED_RAMP_FACTOR = 10.0
#: and the seabed spring stiffness over this many
BED_BLEND_FACTOR = 1.0


def static_penetration(layout) -> float:
    """Static seabed penetration [m] of the heaviest line under its own submerged weight,
    (w - rho A) g / (kBot d) (0 without seabed stiffness or sinking lines)."""
    L, E = layout.lines, layout.env
    if E.kBot <= 0.0:
        return 0.0
    pen = 0.0
    for li in range(len(layout.line_N)):
        wsub = L.w[li] - E.rho * L.A[li]
        if wsub > 0.0 and L.d[li] > 0.0:
            pen = max(pen, wsub * E.g / (E.kBot * L.d[li]))
    return float(pen)


def bed_damping_ramp(layout) -> float:
    """Penetration [m] over which the implicit scheme ramps the seabed contact damping in (a
    smoothstep): BED_RAMP_FACTOR times the static penetration, at least 1 mm. MoorDyn's contact
    force jumps by cBot v_n d l when a node lands: the residual then has no root for Newton's
    method (it cycles between contact and no contact). With the ramp the force is continuous."""
    if layout.env.kBot <= 0.0 or layout.env.cBot <= 0.0:
        return 0.0
    return float(max(BED_RAMP_FACTOR * static_penetration(layout), 1e-3))


def bed_spring_blend(layout) -> float:
    """Penetration [m] over which the implicit scheme blends the seabed spring in (stiffness
    growing linearly from zero to kBot, a C1 force): BED_BLEND_FACTOR times the static
    penetration. The line then rests deeper by about half of it (a few mm for chain)."""
    return float(BED_BLEND_FACTOR * static_penetration(layout))


class System:
    """A mooring system ready to integrate.

    Parameters
    ----------
    model : Model
        The description (from :func:`moorline.io.read_deck` or built in Python).
    dtM : float, optional
        Internal time step [s]; default from the model options (``dtM`` or ``CFL``).
    scheme : str, optional
        Time scheme name (Euler, RK2, RK4, BEuler<M>, Midpoint<M>, or moorline's implicit
        ``GenAlpha[rho_inf]``); default the model's ``tScheme``. With GenAlpha, ``dtM`` is the
        largest step (there is no stability limit; the step is halved where Newton struggles).
    loads_at : {'end', 'last_stage'}
        What loads (tensions, forces, curvatures) the views report after a step. ``'end'``
        (default): evaluated at the state and time at the end of the step, consistent with the
        reported positions. ``'last_stage'``: MoorDyn's convention, the loads of the last
        derivative evaluation inside the step (for RK2 the midpoint stage, half a dtM earlier),
        with positions and velocities from the end of the step. The two differ only in the
        fastest (axial segment) modes; use ``'last_stage'`` to compare with MoorDyn sample by sample.
    """

    _STAGE_FIELDS = ("T", "Td", "seg_len", "seg_ldot", "F", "Fhyd", "Fbed", "W", "kurv", "pF", "pa")

    def __init__(self, model: Model, *, dtM: float | None = None, scheme: str | None = None,
                 loads_at: str = "end"):
        if loads_at not in ("end", "last_stage"):
            raise ValueError(f"loads_at must be 'end' or 'last_stage', got {loads_at!r}")
        self.loads_at = loads_at
        self.model = model
        self.layout = build_layout(model)
        self.scheme, self.scheme_params, self.scheme_label = parse_scheme(
            scheme if scheme is not None else model.options.tScheme)
        self.dtM = float(dtM) if dtM is not None else choose_dtM(model, self.layout)
        if not self.dtM > 0:
            raise ValueError(f"dtM must be > 0, got {self.dtM}")
        if self.scheme == Scheme.GENALPHA:
            ramp = bed_damping_ramp(self.layout)
            blend = bed_spring_blend(self.layout)
            self.layout.env = self.layout.env._replace(bed_ramp=ramp, bed_blend=blend)
            self.layout.env_ic = self.layout.env_ic._replace(bed_ramp=ramp, bed_blend=blend)
        self.work = self.layout.new_work()
        n = self.layout.n_state
        self.y = np.zeros(n)
        self._S = np.zeros((5, n))
        self._imp = None  # structure and work of the implicit solves, built on first use
        self.t = 0.0
        self._motion = static_motion(self.deck_coupled_positions())
        self.lines = [LineView(self, i) for i in range(len(model.lines))]
        self.points = [PointView(self, i) for i in range(len(model.points))]
        self.rods = [RodView(self, i) for i in range(len(model.rods))]
        self.bodies = [BodyView(self, i) for i in range(len(model.bodies))]
        self.initialized = False
        self._grid_warned = False
        self.ic_report: dict = {}

    @classmethod
    def from_file(cls, path, **kwargs) -> System:
        """Read a MoorDyn v2 deck (see :func:`moorline.io.read_deck`)."""
        from .io import read_deck

        return cls(read_deck(Path(path)), **kwargs)

    # ------------------------------------------------------------------ coupled DOFs
    @property
    def n_coupled_dof(self) -> int:
        """Number of coupled degrees of freedom: 6 per coupled body or rod (x, y, z, roll, pitch,
        yaw), 3 per coupled-pinned body or rod and per coupled point."""
        return self.layout.n_coupled_dof

    @property
    def coupled_dof_labels(self) -> list[str]:
        """Labels of the coupled DOFs in order (bodies, rods, points), e.g. ``['B1_x', ..., 'B1_yaw',
        'P4_x', ...]``."""
        labels = []
        six = ("x", "y", "z", "roll", "pitch", "yaw")
        for i in self.layout.coupled_bodies:
            n = 6 if self.layout.rigid.body_kind[i] == int(BodyKind.COUPLED) else 3
            labels += [f"B{i + 1}_{c}" for c in six[:n]]
        for k in self.layout.coupled_rods:
            n = 6 if self.layout.rigid.rod_kind[k] == int(RodKind.COUPLED) else 3
            labels += [f"R{k + 1}_{c}" for c in six[:n]]
        labels += [f"P{p + 1}_{c}" for p in self.layout.coupled_points for c in "xyz"]
        return labels

    def deck_coupled_positions(self) -> np.ndarray:
        """Coupled DOF vector with every coupled object where the deck puts it (angles [rad])."""
        out = []
        m = self.model
        for i in self.layout.coupled_bodies:
            b = m.bodies[i]
            out.append(np.concatenate([b.r, np.radians(b.angles)]) if b.kind == BodyKind.COUPLED else b.r)
        for k in self.layout.coupled_rods:
            rod = m.rods[k]
            out.append(np.concatenate([rod.rA, np.zeros(3)]) if rod.kind == RodKind.COUPLED else rod.rA)
        P = self.layout.points
        out += [P.r0[p] for p in self.layout.coupled_points]
        return np.concatenate(out) if out else np.zeros(0)

    def _check_dof(self, x, name):
        if x is None:
            return None
        x = np.asarray(x, dtype=float).ravel()
        if x.size != self.n_coupled_dof:
            raise ValueError(f"{name} has {x.size} values; the system has {self.n_coupled_dof} coupled DOF "
                             f"({', '.join(self.coupled_dof_labels) or 'none'})")
        return x

    # ------------------------------------------------------------------ evaluation
    def _kernel_arrays(self):
        """(lines, rods, points, env, seabed, work): what every kernel call takes."""
        lay = self.layout
        return lay.lines, lay.rigid, lay.points, lay.env, lay.seabed, self.work

    def _evaluate(self, piece: int = -1) -> None:
        """Evaluate every load at the current state and time (refreshes what the views report).
        ``piece``: the coupled-trajectory piece (that of the step just taken, so the coupled
        velocity at the end of a step is the one imposed during it)."""
        dy = self._S[0]
        L, R, P, E, B, W = self._kernel_arrays()
        rhs(self.t, self.y, dy, L, R, P, E, B, self._motion, W, 1.0, piece)

    def coupled_forces(self) -> np.ndarray:
        """Loads of the mooring system on the coupled DOFs [N, N m], in coupled-DOF order: F6 - M a_in
        of coupled bodies and rods (3 forces when pinned), the net force of coupled points."""
        lay = self.layout
        if lay.n_coupled_dof == 0:
            return np.zeros(0)
        W = self.work
        out = []
        for i in lay.coupled_bodies:
            out.append(W.b6F[i, :6 if lay.rigid.body_kind[i] == int(BodyKind.COUPLED) else 3])
        for k in lay.coupled_rods:
            out.append(W.rod6F[k, :6 if lay.rigid.rod_kind[k] == int(RodKind.COUPLED) else 3])
        out += [W.pF[p] for p in lay.coupled_points]
        return np.concatenate(out)

    # ------------------------------------------------------------------ init
    def init(self, x=None, xd=None, *, solve_ic: bool = True) -> np.ndarray:
        """Place coupled objects at ``x``, start every line on its catenary and (with
        ``solve_ic``) find the initial equilibrium with the deck's IC settings; time is reset to 0.

        Parameters
        ----------
        x, xd : array_like (n_coupled_dof,), optional
            Coupled positions [m] and velocities [m/s]; default: the deck positions, at rest.
        solve_ic : bool
            False starts from the catenary profile as MoorDyn's Init_NoIC does.

        Returns
        -------
        ndarray (n_coupled_dof,)
            Forces on the coupled DOFs [N].
        """
        x = self._check_dof(x, "x")
        if x is None:
            x = self.deck_coupled_positions()
        xd = self._check_dof(xd, "xd")
        self.t = 0.0
        self._motion = static_motion(x)
        B = self.layout.seabed
        B.ctl[:] = 0  # stick-slip friction is off while the initial conditions are found
        failed = catenary_start(self.layout, x, self.y, self.work)
        for li, status in failed:
            log.warning("line %d: catenary solve unsuccessful (%s); starting from the straight chord", li + 1,
                        CatenaryStatus(status).name.lower())
        self.ic_report = {"catenary_failed": [li + 1 for li, _ in failed]}
        opts = self.model.options
        if solve_ic and opts.TmaxIC > 0 and self.layout.n_rows + self.layout.n_blocks > 0:
            self._solve_ic()
        if xd is not None:
            self._motion = step_motion(x, xd, 0.0, 1.0)
        self.t = 0.0
        self._reset_scheme()
        self._evaluate()
        # friction springs start relaxed at the initial position of every node
        B.anchor[...] = self.work.r
        B.slip[...] = 0.0
        B.ctl[0] = 1
        self._report_stability()
        self._check_grid()
        self.initialized = True
        return self.coupled_forces()

    def _check_grid(self) -> None:
        B = self.layout.seabed
        if B.ctl[2] > 0 and not self._grid_warned:
            self._grid_warned = True
            log.warning("line nodes reached beyond the bathymetry grid (x %.6g..%.6g, y %.6g..%.6g m) by t = %.6g s; "
                        "the seabed height of the nearest grid edge is used there", B.gx[0], B.gx[-1], B.gy[0],
                        B.gy[-1], self.t)

    def _solve_ic(self) -> None:
        opts = self.model.options
        L, R, P, _, B, W = self._kernel_arrays()
        E = self.layout.env_ic  # waves off, current on (spec 6.1)
        newton = opts.ICNewton == 1 or (opts.ICNewton == -1 and self.scheme == Scheme.GENALPHA)
        if newton and self._newton_ic(L, R, P, E, B, W):
            return
        if self.scheme == Scheme.GENALPHA:
            raise SimulationError("Newton statics did not find the initial equilibrium; the implicit scheme has no "
                                  "explicit fallback at its step: set ICNewton 0 with an explicit tScheme, or give "
                                  "a better start (line lengths, anchor positions)", time=0.0)
        if opts.ICgenDynamic:
            ok, tic, bad = dynamic_relaxation(self.y, self.dtM, int(self.scheme), self.scheme_params, opts.dtIC,
                                              opts.TmaxIC, opts.threshIC, opts.CdScaleIC, L, R, P, E, B,
                                              self._motion, W, self._S, MAX_NODE_SPEED)
            if bad >= 0:
                raise self._instability(tic, int(bad), "during dynamic relaxation of the initial conditions")
            self.ic_report.update(method="dynamic relaxation", converged=bool(ok), pseudo_time=float(tic))
        else:
            seg_min = float(np.min(L.seg_l0)) if L.seg_l0.size else 1.0
            cfl_ic = min(float(opts.CFL), 1.0)
            status, tic, emean, it = stationary_solve(self.y, self.dtM, opts.dtIC, opts.TmaxIC, opts.threshIC,
                                                      cfl_ic, seg_min, L, R, P, E, B, self._motion, W, self._S)
            if status < 0 or not np.all(np.isfinite(self.y)):
                raise SimulationError("the stationary initial-condition solver diverged (non-finite state); "
                                      "try ICgenDynamic 1 or a smaller dtM", time=0.0)
            self.ic_report.update(method="stationary", converged=bool(status == 1), stalled=bool(status == 2),
                                  pseudo_time=float(tic), iterations=int(it), mean_acceleration=float(emean))
        rep = self.ic_report
        g = self.layout.env.g
        if rep["converged"]:
            log.info("initial conditions converged (%s) after %.4g s of pseudo time", rep["method"],
                     rep["pseudo_time"])
        elif rep.get("stalled"):
            level = logging.WARNING if rep["mean_acceleration"] > 0.01 * g else logging.INFO
            log.log(level, "initial-condition solver stopped after %.4g s of pseudo time because its error stalled "
                    "(as MoorDyn's does); mean residual acceleration %.3g m/s^2", rep["pseudo_time"],
                    rep["mean_acceleration"])
        else:
            log.warning("initial conditions did NOT converge (%s) within TmaxIC = %.4g s; the dynamics "
                        "start from the last iterate", rep["method"], opts.TmaxIC)

    def _newton_ic(self, L, R, P, E, B, W) -> bool:
        """Static equilibrium by Newton's method (pseudo-transient continuation from the catenary
        start); when that does not converge quickly (a slack, flexible system far from the start,
        such as a lazy-wave cable), implicit dynamic relaxation (generalized-alpha with maximal
        numerical damping, drag scaled by CdScaleIC, steps of up to dtIC) then Newton again.
        Returns False (state restored) when it does not converge."""
        import time

        opts = self.model.options
        A, IW = self._implicit()
        y_start = self.y.copy()
        t0 = time.perf_counter()
        self._sink_into_seabed(E)
        status, it, resid = newton_statics(self.y, A, IW, L, R, P, E, B, self._motion, W, float(opts.dtIC),
                                           NEWTON_ACC_TOL, NEWTON_DX_TOL, NEWTON_FIRST_IT)
        relax = 0.0
        if status != 1:
            self.y[:] = y_start
            relax = self._implicit_relaxation(A, IW, L, R, P, E, B, W)
            status, it2, resid = newton_statics(self.y, A, IW, L, R, P, E, B, self._motion, W, float(opts.dtIC),
                                                NEWTON_ACC_TOL, NEWTON_DX_TOL, NEWTON_MAX_IT)
            it += it2
        wall = time.perf_counter() - t0
        self.ic_report.update(method="newton" if relax == 0.0 else "implicit relaxation + newton",
                              converged=bool(status == 1), iterations=int(it), max_acceleration=float(resid),
                              pseudo_time=relax, wall_time=wall)
        self._reset_scheme()
        if status == 1:
            log.info("initial conditions: static equilibrium by Newton in %d iterations%s (%.3g s), residual "
                     "%.2g m/s^2", it, f" after {relax:.3g} s of implicit relaxation" if relax else "", wall, resid)
            return True
        log.warning("Newton statics did not converge (%s after %d iterations, residual %.3g m/s^2)%s",
                    "singular or non-finite" if status < 0 else "not converged", it, resid,
                    "" if self.scheme == Scheme.GENALPHA else "; falling back to MoorDyn's initial-condition method")
        self.y[:] = y_start
        return False

    def _sink_into_seabed(self, E) -> None:
        """Lower the internal line nodes the catenary start laid on the seabed to the penetration
        at which the contact law ``E`` carries the line's submerged weight. On the seabed surface
        itself the contact stiffness of the Jacobian is zero (one-sided at MoorDyn's kink, zero
        with the implicit scheme's spring blend): Newton's first step would sink them by metres
        and take dozens of damped iterations to come back (15-segment OC3 chain: 53 iterations,
        4 after sinking)."""
        L, B = self.layout.lines, self.layout.seabed
        if E.kBot <= 0.0:
            return
        for li in range(len(self.layout.line_N)):
            wsub = (L.w[li] - E.rho * L.A[li]) * E.g
            if wsub <= 0.0 or L.d[li] <= 0.0:
                continue
            pen = resting_penetration(wsub / (E.kBot * L.d[li]), E.bed_blend)
            for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
                k = 3 * int(L.node_row[n])
                zb = seabed_at(B.gx, B.gy, B.gz, E.depth, self.y[k], self.y[k + 1])[0]
                if self.y[k + 2] <= zb + 1e-6 * max(1.0, abs(zb)):
                    self.y[k + 2] = zb - pen

    def _implicit_relaxation(self, A, IW, L, R, P, E, B, W) -> float:
        """Implicit dynamic relaxation towards equilibrium (see :meth:`_newton_ic`): until the line
        end tensions change by less than threshIC (relative) over dtIC, or TmaxIC. Returns the
        pseudo time [s]."""
        opts = self.model.options
        saved = A.par.copy()
        am, af, beta, gamma = gen_alpha_parameters(0.0)
        A.par[:4] = (am, af, beta, gamma)
        A.par[8] = opts.CdScaleIC
        st = IW.stat
        h = min(float(opts.dtIC), 1.0)
        st[S_AVALID] = st[S_HJ] = 0.0
        st[S_H] = h
        seg = self.layout.lines.seg_ptr
        ends = np.concatenate([seg[:-1], seg[1:] - 1]) if seg.size > 1 else np.zeros(0, dtype=np.int64)
        prev = None
        t = 0.0
        try:
            while t < opts.TmaxIC:
                t_next = t + float(opts.dtIC)
                t, status, row, _ = advance_implicit(self.y, t, t_next, h, A, IW, L, R, P, E, B, self._motion, W,
                                                     MAX_NODE_SPEED, True)
                if status != 0:
                    break
                ten = np.linalg.norm(W.T[ends], axis=1) if ends.size else np.zeros(0)
                if prev is not None and np.all(np.abs(ten - prev) <= opts.threshIC * np.maximum(np.abs(ten), 1.0)):
                    break
                prev = ten
        finally:
            A.par[:] = saved
        uoff = self.layout.u_offset
        self.y[uoff:] = 0.0
        return t

    def _lines_on_seabed(self) -> np.ndarray:
        """Lines with a node in seabed contact at the last evaluation (for the seabed modes)."""
        L = self.layout.lines
        fbed = np.any(self.work.Fbed != 0.0, axis=1)
        return np.array([np.any(fbed[L.node_ptr[i]:L.node_ptr[i + 1]]) for i in range(len(self.lines))])

    def _report_stability(self) -> None:
        gov, limit, text = stability_report(self.model, self.layout, self.dtM, self.scheme, self._lines_on_seabed(),
                                            self.scheme_label)
        self.stability = {"governing": gov.where, "mode": gov.kind, "rate": gov.rate,
                          "dtM_limit": limit, "text": text}
        if self.dtM > limit:
            log.warning("%s: dtM is likely unstable", text)
        else:
            log.info(text)

    # ------------------------------------------------------------------ stepping
    def step(self, x, xd, t: float, dt: float) -> np.ndarray:
        """Advance from ``t`` to ``t + dt`` with the coupled DOFs at ``x + xd (tau - t)``.

        Returns the forces on the coupled DOFs at the end of the step [N]. With ``dt <= 0``
        nothing is integrated and the current forces are returned.
        """
        if not self.initialized:
            raise RuntimeError("call init() before step()")
        x = self._check_dof(x, "x")
        xd = self._check_dof(xd, "xd")
        if x is None:
            x = self.deck_coupled_positions()
        if xd is None:
            xd = np.zeros(self.n_coupled_dof)
        self.t = float(t)
        if dt <= 0:
            self._motion = step_motion(x, xd, self.t, 0.0)
            self._evaluate()
            return self.coupled_forces()
        self._advance(step_motion(x, xd, self.t, dt), self.t + dt)
        return self.coupled_forces()

    def advance_to(self, t_end: float, motion: Motion) -> None:
        """Integrate to ``t_end`` [s] following the coupled trajectory ``motion`` (compiled loop)."""
        if not self.initialized:
            raise RuntimeError("call init() before advancing")
        self._advance(motion, float(t_end))

    # ------------------------------------------------------------------ implicit solves
    def _implicit(self):
        """(structure, work) of the Newton solves (generalized-alpha steps and statics)."""
        if self._imp is None:
            rho = float(self.scheme_params[0]) if self.scheme == Scheme.GENALPHA else RHO_INF
            A = build_implicit(self.layout, rho)
            self._imp = (A, new_implicit_work(self.layout, A, self.dtM))
        return self._imp

    def _reset_scheme(self) -> None:
        """Forget what the time scheme carries between steps (after the state was set from outside)."""
        self._S[...] = 0.0  # the fixed-point schemes start without a previous derivative
        if self._imp is not None:
            st = self._imp[1].stat
            st[S_AVALID] = 0.0
            st[S_HJ] = 0.0
            st[S_H] = self.dtM

    @property
    def solver_stats(self) -> dict:
        """Counters of the implicit solver: steps, rejected steps, Newton iterations, Jacobians,
        derivative evaluations, and the current step [s] (empty for the explicit schemes)."""
        if self._imp is None:
            return {}
        st = self._imp[1].stat
        A = self._imp[0]
        return {"steps": int(st[S_NSTEP]), "rejected": int(st[S_NREJ]), "iterations": int(st[S_NIT]),
                "jacobians": int(st[S_NJAC]), "refactors": int(st[S_NFAC]), "evaluations": int(st[S_NRHS]),
                "backtracks": int(st[S_NBACK]), "slow_rebuilds": int(st[S_NSLOW]), "step": float(st[S_H]),
                "colours": int(A.col_ptr.size - 1), "bandwidth": (int(A.band[0]), int(A.band[1]))}

    def _advance(self, motion: Motion, t_end: float) -> None:
        self._motion = motion
        L, R, P, E, B, W = self._kernel_arrays()
        last_stage = self.loads_at == "last_stage"
        if self.scheme == Scheme.GENALPHA:
            A, IW = self._implicit()
            t, status, row, piece = advance_implicit(self.y, self.t, t_end, self.dtM, A, IW, L, R, P, E, B, motion,
                                                     W, MAX_NODE_SPEED, True)
            self.t = t
            if status == 1:
                raise self._instability(t, int(row), "")
            if status == 2:
                raise self._newton_failure(t, int(row))
            self._check_grid()
            return
        t, bad, _, piece = advance(self.y, self.t, t_end, self.dtM, int(self.scheme), self.scheme_params, L, R, P,
                                   E, B, motion, W, 1.0, self._S, MAX_NODE_SPEED, not last_stage)
        self.t = t
        if bad >= 0:
            raise self._instability(t, int(bad), "")
        self._check_grid()
        if last_stage:
            kept = [getattr(W, f).copy() for f in self._STAGE_FIELDS] if piece >= 0 else []
            self._evaluate(int(piece))
            for f, a in zip(self._STAGE_FIELDS, kept, strict=False):
                getattr(W, f)[...] = a

    # ------------------------------------------------------------------ state access
    def state_rows(self) -> list[tuple[str, int, int]]:
        """What each state row is: ``('line', line number, node)``, ``('point', number, 0)``,
        ``('rod', number, 0)`` for the 3-DOF rows, then ``('rod', number, 0)`` or
        ``('body', number, 0)`` for each 6-DOF block (numbered after the rows)."""
        lay = self.layout
        rows: list[tuple[str, int, int]] = [("", 0, 0)] * (lay.n_rows + lay.n_blocks)
        L = lay.lines
        for li in range(len(self.lines)):
            for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
                rows[int(L.node_row[n])] = ("line", li + 1, n - int(L.node_ptr[li]))
        P = lay.points
        for p in range(len(P.kind)):
            if P.kind[p] == P_FREE:
                rows[int(P.row[p])] = ("point", p + 1, 0)
        R = lay.rigid
        for k in range(len(R.rod_kind)):
            if R.rod_row[k] >= 0:
                rows[int(R.rod_row[k])] = ("rod", k + 1, 0)
            if R.rod_blk[k] >= 0:
                rows[lay.n_rows + int(R.rod_blk[k])] = ("rod", k + 1, 0)
        for i in range(len(R.body_kind)):
            if R.body_blk[i] >= 0:
                rows[lay.n_rows + int(R.body_blk[i])] = ("body", i + 1, 0)
        return rows

    def set_state(self, line_positions=None, line_velocities=None, point_positions=None,
                  point_velocities=None) -> None:
        """Overwrite the state: internal node positions/velocities of lines (lists of (N+1, 3) arrays,
        ends ignored) and free point positions/velocities ((n_points, 3), non-free rows ignored).
        Used to start from another program's initial state."""
        L = self.layout.lines
        uoff = self.layout.u_offset
        for arrs, off in ((line_positions, 0), (line_velocities, uoff)):
            if arrs is None:
                continue
            for li, a in enumerate(arrs):
                a = np.asarray(a, dtype=float)
                for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
                    row = int(L.node_row[n])
                    self.y[off + 3 * row: off + 3 * row + 3] = a[n - int(L.node_ptr[li])]
        P = self.layout.points
        for arr, off in ((point_positions, 0), (point_velocities, uoff)):
            if arr is None:
                continue
            arr = np.asarray(arr, dtype=float)
            for p in range(len(P.kind)):
                if P.kind[p] == P_FREE:
                    row = int(P.row[p])
                    self.y[off + 3 * row: off + 3 * row + 3] = arr[p]
        self._reset_scheme()
        if self.initialized:
            self._evaluate()
            # stick-slip friction springs restart relaxed at the new node positions
            B = self.layout.seabed
            B.anchor[...] = self.work.r
            B.slip[...] = 0.0
            self._evaluate()

    # ------------------------------------------------------------------ external water kinematics
    @property
    def n_water_nodes(self) -> int:
        """Number of points whose water kinematics an outer program sets (MoorDyn's
        ``ExternalWaveKinInit``): every line node, every rod node, every point, the ground body and
        every body."""
        return int(self.layout.env.water.U_ext.shape[0]) or (
            self.work.r.shape[0] + self.work.rn_r.shape[0] + len(self.points) + 1 + len(self.bodies))

    def water_at(self, points, t: float | None = None) -> np.ndarray:
        """Water kinematics of the model's sea at ``points`` (array_like (n, 3) [m]) at time ``t``
        [s] (default: now), shape (n, 8): velocity (3) [m/s], acceleration (3) [m/s^2], surface
        elevation [m], dynamic pressure [Pa]. External kinematics (WaveKin 1) are per node and give
        only the current here."""
        from .core.waterkin import fluid_kinematics

        p = np.asarray(points, dtype=float).reshape(-1, 3)
        return fluid_kinematics(self.layout.env.water, self.t if t is None else float(t), p)

    def water_node_positions(self) -> np.ndarray:
        """Current positions of the water-kinematics points [m], shape (n_water_nodes, 3), in
        MoorDyn's order (``ExternalWaveKinGetCoordinates``): line nodes (line by line, node 0 to N),
        rod nodes, points, the ground body (origin), bodies."""
        w = self.work
        return np.vstack([w.r, w.rn_r, w.pr, np.zeros((1, 3)), w.br])

    def set_water_kinematics(self, U, Ud) -> None:
        """Set the water velocity [m/s] and acceleration [m/s^2] at every water-kinematics point
        (shape (n_water_nodes, 3), order of :meth:`water_node_positions`); they hold until the next
        call (MoorDyn's ``ExternalWaveKinSet``). Needs ``WaveKin 1`` (external waves) in the model."""
        K = self.layout.env.water
        if K.U_ext.shape[0] == 0:
            raise RuntimeError("the model has no external water kinematics: set WaveKin 1 in the deck or "
                               "env.waves = Waves.external()")
        U = np.asarray(U, dtype=float)
        Ud = np.asarray(Ud, dtype=float)
        if U.shape != K.U_ext.shape or Ud.shape != K.Ud_ext.shape:
            raise ValueError(f"U and Ud must have shape {K.U_ext.shape}, got {U.shape} and {Ud.shape}")
        K.U_ext[...] = U
        K.Ud_ext[...] = Ud

    def set_rod_state(self, k: int, *, end_a=None, axis=None, velocity=None, angular_velocity=None) -> None:
        """Overwrite the state of rod ``k`` (0-based): end-A position [m] and velocity [m/s] of a
        free rod, axis (unit vector A to B; the quaternion becomes the smallest rotation from the
        deck axis) and angular velocity [rad/s] of a free or pinned rod. Values a rod's kind does
        not hold in its state are ignored."""
        lay = self.layout
        R = lay.rigid
        j = int(R.rod_blk[k])
        if j >= 0:
            q, u = lay.block_slices(j)
            free = R.rod_kind[k] == int(RodKind.FREE)
            if end_a is not None and free:
                self.y[q.start:q.start + 3] = end_a
            if axis is not None:
                self.y[q.start + 3:q.stop] = _quat_between(R.rod_qref[k], np.asarray(axis, dtype=float))
            if velocity is not None and free:
                self.y[u.start:u.start + 3] = velocity
            if angular_velocity is not None:
                self.y[u.start + 3:u.stop] = angular_velocity
        elif R.rod_row[k] >= 0:
            o = 3 * int(R.rod_row[k])
            if end_a is not None:
                self.y[o:o + 3] = end_a
            if velocity is not None:
                self.y[lay.u_offset + o:lay.u_offset + o + 3] = velocity
        self._restart()

    def set_body_state(self, i: int, *, position=None, angles=None, velocity=None, angular_velocity=None) -> None:
        """Overwrite the state of body ``i`` (0-based; free or coupled-pinned): reference-point
        position [m] and velocity [m/s] (free bodies), roll, pitch, yaw [rad] (Rx Ry Rz) and angular
        velocity [rad/s]."""
        from .core.layout import quat_from_matrix
        from .model import rotation_xyz

        lay = self.layout
        j = int(lay.rigid.body_blk[i])
        if j < 0:
            return
        q, u = lay.block_slices(j)
        free = lay.rigid.body_kind[i] == int(BodyKind.FREE)
        if position is not None and free:
            self.y[q.start:q.start + 3] = position
        if angles is not None:
            self.y[q.start + 3:q.stop] = quat_from_matrix(rotation_xyz(angles))
        if velocity is not None and free:
            self.y[u.start:u.start + 3] = velocity
        if angular_velocity is not None:
            self.y[u.start + 3:u.stop] = angular_velocity
        self._restart()

    def _restart(self) -> None:
        self._reset_scheme()
        if self.initialized:
            self._evaluate()

    def _where_dof(self, dof: int) -> tuple[str, int, int]:
        """(kind, number, node) of the state row holding velocity-space DOF ``dof``."""
        lay = self.layout
        row = dof // 3 if dof < 3 * lay.n_rows else lay.n_rows + (dof - 3 * lay.n_rows) // 6
        return self.state_rows()[row]

    def _newton_failure(self, t: float, dof: int) -> SimulationError:
        what, num, node = self._where_dof(dof)
        where = f"line {num} node {node}" if what == "line" else f"{what} {num}"
        h = float(self._imp[1].stat[S_H])
        msg = (f"implicit solver ({self.scheme_label}) failed at t = {t:.6g} s: Newton iterations did not converge "
               f"even with the step cut to {h:.3g} s (dtM = {self.dtM:.4g} s); largest residual at {where}. "
               f"Check the model there (a line pulled beyond its breaking stretch, a node far below the seabed, "
               f"a zero mass), or run an explicit scheme to see the motion")
        return SimulationError(msg, time=t, line=num if what == "line" else None,
                               node=node if what == "line" else None, point=num if what == "point" else None,
                               suggested_dtM=h)

    def _instability(self, t: float, row: int, context: str) -> SimulationError:
        what, num, node = self.state_rows()[row]
        lay = self.layout
        if row < lay.n_rows:
            v = self.y[lay.u_offset + 3 * row: lay.u_offset + 3 * row + 3]
        else:
            v = self.y[lay.block_slices(row - lay.n_rows)[1]][:3]
        speed = float(np.linalg.norm(v)) if np.all(np.isfinite(v)) else math.nan
        _, limit, _ = stability_report(self.model, self.layout, self.dtM, self.scheme, self._lines_on_seabed(),
                                       self.scheme_label)
        suggest = min(0.5 * self.dtM, 0.8 * limit)
        where = f"line {num} node {node}" if what == "line" else f"{what} {num}"
        reason = "non-finite state" if not math.isfinite(speed) else f"speed {speed:.3g} m/s > {MAX_NODE_SPEED} m/s"
        msg = (f"simulation unstable at t = {t:.6g} s {context}: {where}: {reason}. "
               f"dtM = {self.dtM:.4g} s with {self.scheme_label}; try dtM <= {suggest:.3g} s")
        return SimulationError(msg, time=t, line=num if what == "line" else None,
                               node=node if what == "line" else None, point=num if what == "point" else None,
                               suggested_dtM=suggest)
