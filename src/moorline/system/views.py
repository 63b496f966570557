"""Views of one line, point, rod or body of a running :class:`~moorline.system.System`: positions,
velocities, tensions, forces, curvatures, read from the system's state and work arrays (copies,
so a view's result does not change under a later step)."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..model import angles_xyz
from ..post.sections import curvature

if TYPE_CHECKING:
    from .runtime import System


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
        e = d / np.where(ls > 0.0, ls, 1.0)[:, None]
        k = np.zeros(len(r))
        kap, _ = curvature(ls[:-1] + ls[1:], e[:-1], e[1:])
        k[1:-1] = np.where((ls[:-1] > 0.0) & (ls[1:] > 0.0), kap, 0.0)
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
