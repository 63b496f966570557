"""A drop-in for MoorDyn's Python API (the ``moordyn`` package, MoorDyn-C v2), on moorline.

A coupling script written for MoorDyn changes one import::

    import moorline.moordyn as moordyn          # instead of: import moordyn

    md = moordyn.Create("mooring.txt")
    moordyn.Init(md, x, xd)
    f = moordyn.Step(md, x, xd, t, dt)           # loads on the coupled DOF, a tuple
    line = moordyn.GetLine(md, 1)                # 1-based, as in MoorDyn
    moordyn.GetLineFairTen(line)
    moordyn.Close(md)

The functions take and return what MoorDyn's do: objects are numbered from 1, positions and
vectors come back as tuples, ``Step`` returns the coupled loads as a tuple of
``NCoupledDOF`` floats, the point, body and rod type codes are MoorDyn's (``POINT_TYPE_*``,
``BODY_TYPE_*``, ``ROD_TYPE_*``), and a missing object raises ``RuntimeError`` as MoorDyn's does.
Loads are reported as MoorDyn reports them (``loads_at="last_stage"``: those of the last derivative
evaluation of a step). Underneath is a :class:`moorline.System` (``instance.system``), so the
rest of moorline (views, ``simulate``, checkpoints) stays at hand.

Differences (docs/moordyn_differences.md): ``SaveState``/``LoadState``, ``Save``/``Load`` and
``Serialize``/``Deserialize`` write and read moorline checkpoints (a restart continues bitwise),
not MoorDyn's binary files; ``BreakLine`` releases the line end onto a copy of the point as
MoorDyn-C 2.7 does (``System.break_line`` defaults to a massless point); the time step, CFL and
time scheme setters, the wave and seafloor objects and the VTK writers are not offered.
"""

from __future__ import annotations

import logging
import os
import tempfile
from pathlib import Path

import numpy as np

from .model import BodyKind, PointKind, RodKind
from .system import System

log = logging.getLogger("moorline")

# MoorDyn's constants (moordyn/moordyn.py of MoorDyn-C 2.7)
LEVEL_NONE = 4096
LEVEL_ERR = 3
LEVEL_WRN = 2
LEVEL_MSG = 1
LEVEL_DBG = 0
ERRCODE_SUCCESS = 0
ERRCODE_INVALID_INPUT_FILE = -1
ERRCODE_INVALID_OUTPUT_FILE = -2
ERRCODE_INVALID_INPUT = -3
ERRCODE_NAN_ERROR = -4
ERRCODE_MEM_ERROR = -5
ERRCODE_INVALID_VALUE = -6
ERRCODE_NON_IMPLEMENTED = -7
ERRCODE_UNHANDLED_ERROR = -255
BODY_TYPE_COUPLED = POINT_TYPE_COUPLED = -1
BODY_TYPE_FREE = POINT_TYPE_FREE = 0
BODY_TYPE_FIXED = POINT_TYPE_FIXED = 1
BODY_TYPE_CPLDPIN = 2
ROD_TYPE_COUPLED = -2
ROD_TYPE_CPLDPIN = -1
ROD_TYPE_FREE = 0
ROD_TYPE_PINNED = 1
ROD_TYPE_FIXED = 2
ENDPOINT_A = ENDPOINT_BOTTOM = 0
ENDPOINT_B = ENDPOINT_TOP = 1

_POINT_TYPE = {PointKind.FIXED: POINT_TYPE_FIXED, PointKind.BODY: POINT_TYPE_FIXED, PointKind.FREE: POINT_TYPE_FREE,
               PointKind.COUPLED: POINT_TYPE_COUPLED}
_BODY_TYPE = {BodyKind.FIXED: BODY_TYPE_FIXED, BodyKind.FREE: BODY_TYPE_FREE, BodyKind.COUPLED: BODY_TYPE_COUPLED,
              BodyKind.COUPLED_PINNED: BODY_TYPE_CPLDPIN}
_ROD_TYPE = {RodKind.FIXED: ROD_TYPE_FIXED, RodKind.BODY: ROD_TYPE_FIXED, RodKind.PINNED: ROD_TYPE_PINNED,
             RodKind.BODY_PINNED: ROD_TYPE_PINNED, RodKind.COUPLED: ROD_TYPE_COUPLED,
             RodKind.COUPLED_PINNED: ROD_TYPE_CPLDPIN, RodKind.FREE: ROD_TYPE_FREE}
_LEVELS = {LEVEL_DBG: logging.DEBUG, LEVEL_MSG: logging.INFO, LEVEL_WRN: logging.WARNING, LEVEL_ERR: logging.ERROR,
           LEVEL_NONE: logging.CRITICAL + 10}


class MoorDyn:
    """What :func:`Create` returns: a moorline :class:`~moorline.System` (``.system``) behind
    MoorDyn's functions."""

    def __init__(self, system: System, path: Path):
        self.system = system
        self.path = path
        self.handler: logging.Handler | None = None
        #: coupled velocities of the last Init/Step call (MoorDyn's input acceleration is the
        #: finite difference (xd - xd_previous) / dt)
        self.xd_prev = np.zeros(system.n_coupled_dof)

    def __repr__(self) -> str:
        return f"<moorline.moordyn.MoorDyn of {self.path}>"


class _Object:
    kind = ""

    def __init__(self, md: MoorDyn, index: int):
        self.md = md
        self.index = index

    @property
    def system(self) -> System:
        return self.md.system

    def __repr__(self) -> str:
        return f"<moorline.moordyn {self.kind} {self.index + 1}>"

    def __eq__(self, other) -> bool:
        return type(other) is type(self) and other.md is self.md and other.index == self.index

    def __hash__(self) -> int:
        return hash((id(self.md), self.kind, self.index))


class MoorDynLine(_Object):
    kind = "line"


class MoorDynPoint(_Object):
    kind = "point"


class MoorDynBody(_Object):
    kind = "body"


class MoorDynRod(_Object):
    kind = "rod"


def _t(v) -> tuple:
    return tuple(float(x) for x in np.asarray(v, dtype=float).ravel())


def _tt(m) -> tuple:
    return tuple(_t(row) for row in np.asarray(m, dtype=float))


def _get(cls, md: MoorDyn, n: int, count: int, what: str):
    if not 1 <= int(n) <= count:
        raise RuntimeError(f"MoorDyn_Get{what}() failed: there is no {what.lower()} {n} (the system has {count}; "
                           f"they are numbered from 1)")
    return cls(md, int(n) - 1)


# ---------------------------------------------------------------------------------- the system
def Create(filepath="") -> MoorDyn:
    """Read the deck ``filepath`` (MoorDyn's default ``Mooring/lines.txt`` when empty)."""
    path = Path(filepath or "Mooring/lines.txt")
    return MoorDyn(System.from_file(path, loads_at="last_stage"), path)


def NCoupledDOF(instance: MoorDyn) -> int:
    return instance.system.n_coupled_dof


def SetVerbosity(instance: MoorDyn, verbosity: int) -> int:
    """The level of moorline's log messages (LEVEL_DBG, LEVEL_MSG, LEVEL_WRN, LEVEL_ERR, LEVEL_NONE)."""
    log.setLevel(_LEVELS.get(int(verbosity), logging.WARNING))
    return ERRCODE_SUCCESS


def SetLogFile(instance: MoorDyn, filepath) -> int:
    """Also write moorline's log messages to ``filepath``."""
    if instance.handler is not None:
        log.removeHandler(instance.handler)
        instance.handler.close()
    instance.handler = logging.FileHandler(filepath)
    log.addHandler(instance.handler)
    return ERRCODE_SUCCESS


def SetLogLevel(instance: MoorDyn, verbosity: int) -> int:
    """The level of the messages written to the log file of :func:`SetLogFile`."""
    if instance.handler is not None:
        instance.handler.setLevel(_LEVELS.get(int(verbosity), logging.WARNING))
    return ERRCODE_SUCCESS


def Log(instance: MoorDyn, level: int, msg: str) -> int:
    log.log(_LEVELS.get(int(level), logging.INFO), "%s", msg)
    return ERRCODE_SUCCESS


def Init(instance: MoorDyn, x, v) -> int:
    """Place the coupled objects at ``x`` with velocities ``v`` and find the initial conditions."""
    instance.system.init(list(x) or None, list(v) or None)
    instance.xd_prev = np.array(list(v) or np.zeros(instance.system.n_coupled_dof), dtype=float)
    return ERRCODE_SUCCESS


def Init_NoIC(instance: MoorDyn, x, v) -> int:
    """As :func:`Init`, starting from the catenary profiles without solving the initial conditions."""
    instance.system.init(list(x) or None, list(v) or None, solve_ic=False)
    instance.xd_prev = np.array(list(v) or np.zeros(instance.system.n_coupled_dof), dtype=float)
    return ERRCODE_SUCCESS


def Step(instance: MoorDyn, x, v, t, dt) -> tuple:
    """Advance from ``t`` to ``t + dt`` with the coupled DOF at ``x + v (tau - t)``; return the
    loads on the coupled DOF (a tuple of NCoupledDOF floats) [N, N m]. As MoorDyn's, the loads on
    coupled bodies and rods are F6 - M a_in with a_in = (v - v of the previous call) / dt."""
    s = instance.system
    n = s.n_coupled_dof
    if not n:
        s.step(None, None, float(t), float(dt))
        return ()
    v = np.asarray(v, dtype=float).ravel()
    f = s.step(np.asarray(x, dtype=float), v, float(t), float(dt))
    if dt > 0:
        rigid = [slot for slot in s.coupled_slots if slot[0] != "point"]
        if rigid:
            a = (v - instance.xd_prev) / float(dt)
            for kind, i, k, o in rigid:
                M6 = s.work.b6M if kind == "body" else s.work.rod6M
                f[o:o + k] -= M6[i][:k, :k] @ a[o:o + k]
        instance.xd_prev = v
    return tuple(f.tolist())  # (Python floats, as _t gives, without a generator per value)


def Close(instance: MoorDyn) -> int:
    if instance.handler is not None:
        log.removeHandler(instance.handler)
        instance.handler.close()
        instance.handler = None
    return ERRCODE_SUCCESS


def GetDt(instance: MoorDyn) -> float:
    """The internal time step dtM [s]."""
    return float(instance.system.dtM)


def GetTimeScheme(instance: MoorDyn) -> str:
    return instance.system.scheme_label


def GetNumberBodies(instance: MoorDyn) -> int:
    return len(instance.system.bodies)


def GetNumberRods(instance: MoorDyn) -> int:
    return len(instance.system.rods)


def GetNumberPoints(instance: MoorDyn) -> int:
    return len(instance.system.points)


def GetNumberLines(instance: MoorDyn) -> int:
    return len(instance.system.lines)


def GetBody(instance: MoorDyn, body: int) -> MoorDynBody:
    return _get(MoorDynBody, instance, body, len(instance.system.bodies), "Body")


def GetRod(instance: MoorDyn, rod: int) -> MoorDynRod:
    return _get(MoorDynRod, instance, rod, len(instance.system.rods), "Rod")


def GetPoint(instance: MoorDyn, point: int) -> MoorDynPoint:
    return _get(MoorDynPoint, instance, point, len(instance.system.points), "Point")


def GetLine(instance: MoorDyn, line: int) -> MoorDynLine:
    return _get(MoorDynLine, instance, line, len(instance.system.lines), "Line")


def GetFASTtens(instance: MoorDyn, n_lines: int) -> tuple:
    """(fairlead horizontal, fairlead vertical, anchor horizontal, anchor vertical) loads of the
    first ``n_lines`` lines [N], as MoorDyn computes them: from the net force F on the end node
    (end B, end A), horizontal |(Fx, Fy)|, vertical Fz - M_xx g with M the node's mass matrix
    (mass and added mass)."""
    s = instance.system
    g = s.layout.env.g
    L = s.layout.lines
    out = ([], [], [], [])
    for li, ln in enumerate(s.lines[:int(n_lines)]):
        for k, (end, n) in enumerate((("B", int(L.node_ptr[li + 1]) - 1), ("A", int(L.node_ptr[li])))):
            f = ln.end_force(end)
            out[2 * k].append(float(np.hypot(f[0], f[1])))
            out[2 * k + 1].append(float(f[2] - _node_mass(s, n)[0, 0] * g))
    return tuple(tuple(lst) for lst in out)


def _node_mass(s: System, n: int) -> np.ndarray:
    """Mass matrix of line node ``n`` [kg]: m I + a_n (I - q q^T) + a_t q q^T."""
    W = s.work
    m, an, at = W.mass[n]
    q = W.q[n]
    qq = np.outer(q, q)
    return m * np.eye(3) + an * (np.eye(3) - qq) + at * qq


def BreakLine(instance: MoorDyn, point: MoorDynPoint, line: MoorDynLine) -> int:
    """Detach ``line`` from ``point`` now; its end goes on a new free point that copies the old
    one (MoorDyn-C's BreakLine; see :meth:`moorline.System.break_line`)."""
    s = instance.system
    ln = s.model.lines[line.index]
    att = s.model.lines[line.index].end_a if ln.end_a.kind == "point" and ln.end_a.index == point.index \
        else ln.end_b
    if att.kind != "point" or att.index != point.index:
        raise RuntimeError(f"MoorDyn_BreakLine() failed: line {line.index + 1} is not attached to point "
                           f"{point.index + 1}")
    s.break_line(line.index, "A" if att == ln.end_a else "B", new_point="copy")
    return ERRCODE_SUCCESS


# ---------------------------------------------------------------------------------- save and restore
def SaveState(instance: MoorDyn, filepath) -> int:
    """Write a moorline checkpoint of the running system (not MoorDyn's file format)."""
    instance.system.save(filepath)
    return ERRCODE_SUCCESS


def LoadState(instance: MoorDyn, filepath) -> int:
    """Restore a checkpoint written by :func:`SaveState` into a system made from the same deck."""
    instance.system.load(filepath)
    return ERRCODE_SUCCESS


Save = SaveState
Load = LoadState


def Serialize(instance: MoorDyn) -> bytes:
    """The checkpoint of :func:`SaveState` as bytes."""
    with tempfile.TemporaryDirectory() as d:
        p = Path(d) / "state.npz"
        instance.system.save(p)
        return p.read_bytes()


def Deserialize(instance: MoorDyn, data: bytes) -> int:
    """Restore the bytes of :func:`Serialize`."""
    fd, name = tempfile.mkstemp(suffix=".npz")
    try:
        with os.fdopen(fd, "wb") as f:
            f.write(bytes(data))
        instance.system.load(name)
    finally:
        os.unlink(name)
    return ERRCODE_SUCCESS


# ---------------------------------------------------------------------------------- external waves
def ExternalWaveKinInit(instance: MoorDyn) -> int:
    """Number of points whose water kinematics the caller sets (the deck needs WaveKin 1)."""
    return int(instance.system.n_water_nodes)


ExternalWaveKinGetN = ExternalWaveKinInit


def ExternalWaveKinGetCoordinates(instance: MoorDyn) -> list:
    """Those points, as a list of [x, y, z] (line nodes, rod nodes, points, ground, bodies)."""
    return [list(_t(p)) for p in instance.system.water_node_positions()]


GetWaveKinCoordinates = ExternalWaveKinGetCoordinates


def ExternalWaveKinSet(instance: MoorDyn, u, a, t) -> int:
    """Water velocities ``u`` and accelerations ``a`` (lists of n [x, y, z]) at those points; they
    hold until the next call."""
    instance.system.set_water_kinematics(np.asarray(u, dtype=float).reshape(-1, 3),
                                         np.asarray(a, dtype=float).reshape(-1, 3))
    return ERRCODE_SUCCESS


SetWaveKin = ExternalWaveKinSet


# ---------------------------------------------------------------------------------- bodies
def _body(b: MoorDynBody):
    return b.system.bodies[b.index]


def GetBodyID(instance: MoorDynBody) -> int:
    return instance.index + 1


def GetBodyType(instance: MoorDynBody) -> int:
    return _BODY_TYPE[_body(instance).kind]


def GetBodyState(instance: MoorDynBody) -> tuple:
    """(position and roll, pitch, yaw [m, rad]; velocity and angular velocity [m/s, rad/s])."""
    b = _body(instance)
    return _t(b.pose()), _t(np.concatenate([b.velocity(), b.angular_velocity()]))


def GetBodyPos(instance: MoorDynBody) -> tuple:
    return _t(_body(instance).position())


def GetBodyAngle(instance: MoorDynBody) -> tuple:
    return _t(_body(instance).angles())


def GetBodyVel(instance: MoorDynBody) -> tuple:
    return _t(_body(instance).velocity())


def GetBodyAngVel(instance: MoorDynBody) -> tuple:
    return _t(_body(instance).angular_velocity())


def GetBodyForce(instance: MoorDynBody) -> tuple:
    return _t(_body(instance).force())


def GetBodyM(instance: MoorDynBody) -> tuple:
    return _tt(_body(instance).mass_matrix())


# ---------------------------------------------------------------------------------- rods
def _rod(r: MoorDynRod):
    return r.system.rods[r.index]


def GetRodID(instance: MoorDynRod) -> int:
    return instance.index + 1


def GetRodType(instance: MoorDynRod) -> int:
    return _ROD_TYPE[_rod(instance).kind]


def GetRodForce(instance: MoorDynRod) -> tuple:
    return _t(_rod(instance).force())


def GetRodM(instance: MoorDynRod) -> tuple:
    return _tt(_rod(instance).mass_matrix())


def GetRodN(instance: MoorDynRod) -> int:
    return int(instance.system.model.rods[instance.index].N)


def GetRodNumberNodes(instance: MoorDynRod) -> int:
    return GetRodN(instance) + 1


def GetRodNodePos(instance: MoorDynRod, i: int) -> tuple:
    return _t(_rod(instance).node_positions()[int(i)])


def GetRodNodeVel(instance: MoorDynRod, i: int) -> tuple:
    return _t(_rod(instance).node_velocities()[int(i)])


# ---------------------------------------------------------------------------------- points
def _point(p: MoorDynPoint):
    return p.system.points[p.index]


def GetPointID(instance: MoorDynPoint) -> int:
    return instance.index + 1


def GetPointType(instance: MoorDynPoint) -> int:
    return _POINT_TYPE[instance.system.model.points[instance.index].kind]


def GetPointPos(instance: MoorDynPoint) -> tuple:
    return _t(_point(instance).position())


def GetPointVel(instance: MoorDynPoint) -> tuple:
    return _t(_point(instance).velocity())


def GetPointForce(instance: MoorDynPoint) -> tuple:
    return _t(_point(instance).force())


def GetPointM(instance: MoorDynPoint) -> tuple:
    """Mass matrix of the point with the attached line end nodes [kg], 3x3."""
    return _tt(instance.system.work.pM[instance.index])


def _attached(p: MoorDynPoint) -> list[tuple[int, int]]:
    out = []
    for li, ln in enumerate(p.system.model.lines):
        for end, att in ((ENDPOINT_A, ln.end_a), (ENDPOINT_B, ln.end_b)):
            if att.kind == "point" and att.index == p.index:
                out.append((li, end))
    return out


def GetPointNAttached(instance: MoorDynPoint) -> int:
    return len(_attached(instance))


def GetPointAttached(instance: MoorDynPoint, i: int) -> tuple:
    """(line, end) of the ``i``-th line end on the point (``end``: ENDPOINT_A or ENDPOINT_B)."""
    li, end = _attached(instance)[int(i)]
    return MoorDynLine(instance.md, li), end


# ---------------------------------------------------------------------------------- lines
def _line(ln: MoorDynLine):
    return ln.system.lines[ln.index]


def GetLineID(instance: MoorDynLine) -> int:
    return instance.index + 1


def GetLineN(instance: MoorDynLine) -> int:
    return _line(instance).n_segments


def GetLineNumberNodes(instance: MoorDynLine) -> int:
    return GetLineN(instance) + 1


def GetLineUnstretchedLength(instance: MoorDynLine) -> float:
    return float(_line(instance).unstretched_length)


def GetLineNodePos(instance: MoorDynLine, i: int) -> tuple:
    return _t(_line(instance).node_positions()[int(i)])


def GetLineNodeVel(instance: MoorDynLine, i: int) -> tuple:
    return _t(_line(instance).node_velocities()[int(i)])


def GetLineNodeForce(instance: MoorDynLine, i: int) -> tuple:
    """Net force on node ``i`` [N]."""
    return _t(_line(instance).node_forces()[int(i)])


def GetLineNodeTen(instance: MoorDynLine, i: int) -> tuple:
    """Tension vector at node ``i`` [N] (tension plus internal damping): the end segment's at the
    ends, the mean of the two adjacent segments' inside (MoorDyn's)."""
    sv = _line(instance).segment_tension_vectors()
    i = int(i)
    n = len(sv)
    if i == 0:
        return _t(sv[0])
    if i == n:
        return _t(sv[-1])
    return _t(0.5 * (sv[i - 1] + sv[i]))


def GetLineNodeCurv(instance: MoorDynLine, i: int) -> float:
    return float(_line(instance).node_curvatures()[int(i)])


def GetLineNodeSeabedForce(instance: MoorDynLine, i: int) -> tuple:
    return _t(_line(instance).node_seabed_forces()[int(i)])


def GetLineNodeBendStiff(instance: MoorDynLine, i: int) -> tuple:
    """Bending force on node ``i`` [N]."""
    return _t(_line(instance).node_bending_forces()[int(i)])


def GetLineNodeM(instance: MoorDynLine, i: int) -> tuple:
    """Mass matrix of node ``i`` (mass and added mass) [kg], 3x3."""
    return _tt(_node_mass(instance.system, int(instance.system.layout.lines.node_ptr[instance.index]) + int(i)))


def GetLineFairTen(instance: MoorDynLine) -> float:
    """|T + Td| of the end-B segment [N]."""
    return float(_line(instance).fairlead_tension())


def GetLineMaxTen(instance: MoorDynLine) -> float:
    """The largest segment tension of the line [N]."""
    return float(np.max(_line(instance).segment_tensions()))
