"""Turn a :class:`moorline.model.Model` into the flat arrays the kernels work on.

All nodes of all lines live in one (n_nodes, 3) array; line ``l`` owns nodes
``node_ptr[l]:node_ptr[l+1]`` and segments ``seg_ptr[l]:seg_ptr[l+1]``. The dynamic state is one
float64 vector ``y = [q | u]``: ``q`` holds the positions of every state row (3 numbers a row:
the internal nodes of every line in line order, then the free points), ``u`` their velocities in
the same order. Line end nodes are not states: they copy the kinematics of what they attach to.

Point kinds and attachment kinds are small integers mirrored from :class:`~moorline.model.PointKind`.
"""

from __future__ import annotations

import logging
import math
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..model import Curve, Model, PointKind

log = logging.getLogger("moorline.core")

# point kinds (kernels compare against these integers)
P_FIXED = int(PointKind.FIXED)
P_COUPLED = int(PointKind.COUPLED)
P_FREE = int(PointKind.FREE)

# attachment kinds of line ends
ATT_POINT = 0
ATT_ROD_A = 1
ATT_ROD_B = 2


class LineArrays(NamedTuple):
    """Line data. Per line arrays have length n_lines; per segment n_seg; per node n_nodes."""

    node_ptr: np.ndarray  # int64 (n_lines+1,)
    seg_ptr: np.ndarray  # int64 (n_lines+1,)
    end_kind: np.ndarray  # int64 (n_lines, 2): attachment kind of end A, end B (ATT_*)
    end_idx: np.ndarray  # int64 (n_lines, 2): index of the point or rod attached
    clamped: np.ndarray  # int64 (n_lines, 2): 1 if the end is clamped to its rod (line with EI on a rod end)
    d: np.ndarray  # (n_lines,) diameter [m]
    A: np.ndarray  # (n_lines,) area [m^2]
    w: np.ndarray  # (n_lines,) mass per length [kg/m]
    Cd: np.ndarray
    Ca: np.ndarray
    CdAx: np.ndarray
    CaAx: np.ndarray
    ea_tab: np.ndarray  # int64 (n_lines, 2): start, count in tab_x/tab_y (count 0: constant EA)
    ba_tab: np.ndarray  # int64 (n_lines, 2): same for the damping table
    EI: np.ndarray  # (n_lines,) bending stiffness [N m^2] (constant-EI lines)
    ei_tab: np.ndarray  # int64 (n_lines, 2): start, count of the curvature-moment table (count 0: constant)
    seg_l0: np.ndarray  # (n_seg,) unstretched segment length [m]
    seg_EA: np.ndarray  # (n_seg,) axial stiffness [N] (constant-EA lines)
    seg_BA: np.ndarray  # (n_seg,) internal damping [N s] (constant-BA lines)
    tab_x: np.ndarray  # flat table abscissae
    tab_y: np.ndarray  # flat table ordinates
    node_row: np.ndarray  # int64 (n_nodes,): state row of the node, -1 for end nodes


class RodArrays(NamedTuple):
    kind: np.ndarray  # int64 (n_rods,) RodKind
    N: np.ndarray  # int64 (n_rods,) segments (0: zero-length rod; its end B in the deck gives its direction)
    rA0: np.ndarray  # (n_rods, 3) deck position of end A [m]
    rB0: np.ndarray  # (n_rods, 3) deck position of end B [m]


class PointArrays(NamedTuple):
    kind: np.ndarray  # int64 (n_points,)
    r0: np.ndarray  # (n_points, 3) deck position [m]
    m: np.ndarray
    V: np.ndarray
    CdA: np.ndarray
    Ca: np.ndarray
    F_ext: np.ndarray  # (n_points, 3)
    row: np.ndarray  # int64 (n_points,): state row of free points, -1 otherwise
    cpl: np.ndarray  # int64 (n_points,): offset of the point in the coupled-DOF vector, -1 otherwise


# seabed contact modes and friction models (mirrors of model.CONTACT_MODES / FRICTION_MODELS)
CONTACT_NORMAL = 0
CONTACT_VERTICAL = 1
FRIC_ISOTROPIC = 0
FRIC_DIRECTIONAL = 1
FRIC_STICKSLIP = 2


class EnvArrays(NamedTuple):
    g: float
    rho: float
    depth: float  # flat seabed at z = -depth (when there is no grid)
    kBot: float
    cBot: float
    contact: int  # CONTACT_NORMAL or CONTACT_VERTICAL
    fric: int  # FRIC_*
    muT: float  # transverse (isotropic: the) kinetic friction coefficient
    muA: float  # axial kinetic friction coefficient
    mc: float  # static / kinetic ratio
    cv: float  # creep damping of the saturated models [N s/m]
    kshear: float  # stick-slip friction spring stiffness per contact area [Pa/m]
    cshear: float  # stick-slip friction spring damping per contact area [Pa s/m]


class Seabed(NamedTuple):
    """Bathymetry grid (empty arrays for a flat seabed) and the stick-slip friction state."""

    gx: np.ndarray  # (nx,) grid x [m]
    gy: np.ndarray  # (ny,) grid y [m]
    gz: np.ndarray  # (ny, nx) seabed heights [m]
    anchor: np.ndarray  # (n_nodes, 3) friction-spring anchors of the stick-slip model
    slip: np.ndarray  # (n_nodes, 2) 1 while sliding (axial, transverse), else 0
    ctl: np.ndarray  # int64 (3,): [stick-slip active, commit anchors now, queries outside the grid]


class Work(NamedTuple):
    """Scratch and diagnostic arrays filled by every derivative evaluation."""

    r: np.ndarray  # (n_nodes, 3) node positions
    v: np.ndarray  # (n_nodes, 3) node velocities
    U: np.ndarray  # (n_nodes, 3) water velocity at nodes
    Ud: np.ndarray  # (n_nodes, 3) water acceleration at nodes
    zeta: np.ndarray  # (n_nodes,) free-surface elevation above each node
    T: np.ndarray  # (n_seg, 3) elastic tension vectors (node k -> k+1)
    Td: np.ndarray  # (n_seg, 3) internal damping force vectors
    seg_len: np.ndarray  # (n_seg,) stretched length
    seg_ldot: np.ndarray  # (n_seg,) stretch rate [m/s]
    seg_F: np.ndarray  # (n_seg,) submerged fraction
    seg_e: np.ndarray  # (n_seg, 3) unit vectors from node k to k+1
    q: np.ndarray  # (n_nodes, 3) node tangents
    F: np.ndarray  # (n_nodes, 3) net node force
    Fhyd: np.ndarray  # (n_nodes, 3) drag + fluid inertia
    Fbed: np.ndarray  # (n_nodes, 3) seabed contact + friction
    W: np.ndarray  # (n_nodes, 3) weight + buoyancy
    mass: np.ndarray  # (n_nodes, 3): m, transverse and tangential added mass [kg]
    acc: np.ndarray  # (n_nodes, 3) node accelerations (internal nodes)
    kurv: np.ndarray  # (n_nodes,) curvature [1/m]
    Fbend: np.ndarray  # (n_nodes, 3) bending forces
    end_moment: np.ndarray  # (n_lines, 2, 3) bending moment of clamped ends on their rods [N m]
    rodr: np.ndarray  # (n_rods, 2, 3) rod end positions
    rodv: np.ndarray  # (n_rods, 2, 3) rod end velocities
    rodq: np.ndarray  # (n_rods, 3) rod axis (unit vector from end A to B)
    rodF: np.ndarray  # (n_rods, 2, 3) sum of the line end forces on each rod end
    pr: np.ndarray  # (n_points, 3)
    pv: np.ndarray  # (n_points, 3)
    pa: np.ndarray  # (n_points, 3) acceleration (free points; imposed for coupled)
    pF: np.ndarray  # (n_points, 3) net force on the point
    pM: np.ndarray  # (n_points, 3, 3) mass matrix incl. attached line ends
    pU: np.ndarray  # (n_points, 3) water velocity at points
    xc: np.ndarray  # (n_coupled_dof,) coupled positions at the current time
    vc: np.ndarray  # (n_coupled_dof,) coupled velocities
    ac: np.ndarray  # (n_coupled_dof,) coupled accelerations


class Motion(NamedTuple):
    """Imposed coupled-DOF trajectory: piecewise cubic polynomials in time.

    On ``[t[k], t[k+1]]``: ``x(tau) = c[k,:,0] + c[k,:,1] s + c[k,:,2] s^2 + c[k,:,3] s^3``,
    ``s = tau - t[k]``. A MoorDyn coupling step (x, xd held over [t, t+dt]) is one linear piece.
    Times before the first or after the last knot use the first or last piece.
    """

    t: np.ndarray  # (n_knots,)
    c: np.ndarray  # (n_knots-1, n_dof, 4)


@dataclass
class Layout:
    """Everything the kernels need, plus the Python-side bookkeeping to read results back."""

    lines: LineArrays
    rods: RodArrays
    points: PointArrays
    env: EnvArrays
    seabed: Seabed
    n_rows: int  # number of 3-vector state rows
    n_coupled_dof: int
    line_N: np.ndarray  # (n_lines,) segments per line
    line_L: np.ndarray  # (n_lines,) unstretched length [m] (negative inputs resolved)
    line_type_names: list
    coupled_points: list  # point indices in coupled-DOF order

    @property
    def n_state(self) -> int:
        return 6 * self.n_rows

    def new_work(self) -> Work:
        nn = int(self.lines.node_ptr[-1])
        ns = int(self.lines.seg_ptr[-1])
        nl = len(self.line_N)
        nr = len(self.rods.kind)
        npnt = len(self.points.kind)
        nc = self.n_coupled_dof
        z = np.zeros
        return Work(r=z((nn, 3)), v=z((nn, 3)), U=z((nn, 3)), Ud=z((nn, 3)), zeta=z(nn), T=z((ns, 3)),
                    Td=z((ns, 3)), seg_len=z(ns), seg_ldot=z(ns), seg_F=z(ns), seg_e=z((ns, 3)), q=z((nn, 3)),
                    F=z((nn, 3)), Fhyd=z((nn, 3)), Fbed=z((nn, 3)), W=z((nn, 3)), mass=z((nn, 3)),
                    acc=z((nn, 3)), kurv=z(nn), Fbend=z((nn, 3)), end_moment=z((nl, 2, 3)), rodr=z((nr, 2, 3)),
                    rodv=z((nr, 2, 3)), rodq=z((nr, 3)), rodF=z((nr, 2, 3)), pr=z((npnt, 3)), pv=z((npnt, 3)),
                    pa=z((npnt, 3)), pF=z((npnt, 3)), pM=z((npnt, 3, 3)), pU=z((npnt, 3)), xc=z(nc), vc=z(nc),
                    ac=z(nc))


def effective_depth(model: Model) -> float:
    """Water depth after MoorDyn's rule: never shallower than the deepest point (flat seabed only;
    with a bathymetry grid the depth is the grid's mean depth)."""
    depth = model.env.depth
    if model.env.bathymetry is not None:
        return float(depth)
    zmin = min((p.r[2] for p in model.points), default=0.0)
    if -zmin > depth:
        log.warning("water depth %.6g m is shallower than the deepest point (z = %.6g m); "
                    "using depth %.6g m as MoorDyn does", depth, zmin, -zmin)
        depth = -zmin
    return float(depth)


def build_layout(model: Model) -> Layout:
    """Validate ``model`` and build the flat arrays of :class:`Layout`."""
    model.validate()
    nl = len(model.lines)
    N = np.array([ln.N for ln in model.lines], dtype=np.int64)
    node_ptr = np.zeros(nl + 1, dtype=np.int64)
    node_ptr[1:] = np.cumsum(N + 1)
    seg_ptr = np.zeros(nl + 1, dtype=np.int64)
    seg_ptr[1:] = np.cumsum(N)
    nn, ns = int(node_ptr[-1]), int(seg_ptr[-1])

    end_kind = np.zeros((nl, 2), dtype=np.int64)
    end_idx = np.zeros((nl, 2), dtype=np.int64)
    clamped = np.zeros((nl, 2), dtype=np.int64)
    EI = np.zeros(nl)
    ei_tab = np.zeros((nl, 2), dtype=np.int64)
    props = {k: np.zeros(nl) for k in ("d", "A", "w", "Cd", "Ca", "CdAx", "CaAx")}
    ea_tab = np.zeros((nl, 2), dtype=np.int64)
    ba_tab = np.zeros((nl, 2), dtype=np.int64)
    seg_l0 = np.zeros(ns)
    seg_EA = np.zeros(ns)
    seg_BA = np.zeros(ns)
    tab_x: list[float] = []
    tab_y: list[float] = []
    line_L = np.zeros(nl)

    def add_table(c: Curve):
        start = len(tab_x)
        tab_x.extend(c.x.tolist())
        tab_y.extend(c.y.tolist())
        return start, len(c.x)

    for k, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        for j, att in enumerate((ln.end_a, ln.end_b)):
            if att.kind == "point":
                end_kind[k, j] = ATT_POINT
            else:
                end_kind[k, j] = ATT_ROD_A if att.end == "A" else ATT_ROD_B
                clamped[k, j] = int(lt.has_bending)
            end_idx[k, j] = att.index
        if isinstance(lt.EI, Curve):
            ei_tab[k] = add_table(lt.EI)
        else:
            EI[k] = lt.EI
        for name in props:
            props[name][k] = getattr(lt, name)
        L = ln.L
        if L < 0:
            dist = np.linalg.norm(model.end_position(ln.end_b) - model.end_position(ln.end_a))
            L = -L * dist
        line_L[k] = L
        l0 = L / ln.N
        s0, s1 = seg_ptr[k], seg_ptr[k + 1]
        seg_l0[s0:s1] = l0
        if isinstance(lt.EA, Curve):
            ea_tab[k] = add_table(lt.EA)
        seg_EA[s0:s1] = lt.EA_ref
        if isinstance(lt.BA, Curve):
            ba_tab[k] = add_table(lt.BA)
        elif lt.BA < 0:
            # damping ratio of the highest axial segment mode (spec 3.3)
            seg_BA[s0:s1] = -lt.BA * l0 * math.sqrt(lt.EA_ref * lt.w)
        else:
            seg_BA[s0:s1] = lt.BA

    node_row = -np.ones(nn, dtype=np.int64)
    row = 0
    for k in range(nl):
        for n in range(node_ptr[k] + 1, node_ptr[k + 1] - 1):
            node_row[n] = row
            row += 1

    npnt = len(model.points)
    kind = np.array([int(p.kind) for p in model.points], dtype=np.int64)
    prow = -np.ones(npnt, dtype=np.int64)
    cpl = -np.ones(npnt, dtype=np.int64)
    coupled = []
    for i, p in enumerate(model.points):
        if p.kind == PointKind.FREE:
            prow[i] = row
            row += 1
        elif p.kind == PointKind.COUPLED:
            cpl[i] = 3 * len(coupled)
            coupled.append(i)

    def col(attr):
        return np.array([getattr(p, attr) for p in model.points], dtype=float)

    points = PointArrays(
        kind=kind,
        r0=np.array([p.r for p in model.points], dtype=float).reshape(npnt, 3),
        m=col("m"), V=col("V"), CdA=col("CdA"), Ca=col("Ca"),
        F_ext=np.array([p.F_ext for p in model.points], dtype=float).reshape(npnt, 3),
        row=prow, cpl=cpl,
    )
    lines = LineArrays(node_ptr, seg_ptr, end_kind, end_idx, clamped, props["d"], props["A"], props["w"],
                       props["Cd"], props["Ca"], props["CdAx"], props["CaAx"], ea_tab, ba_tab, EI, ei_tab, seg_l0,
                       seg_EA, seg_BA, np.array(tab_x, dtype=float), np.array(tab_y, dtype=float), node_row)
    nrod = len(model.rods)
    rods = RodArrays(np.array([int(r.kind) for r in model.rods], dtype=np.int64),
                     np.array([r.N for r in model.rods], dtype=np.int64),
                     np.array([r.rA for r in model.rods], dtype=float).reshape(nrod, 3),
                     np.array([r.rB for r in model.rods], dtype=float).reshape(nrod, 3))
    e = model.env
    muT, muA, mc, cv = e.friction_coefficients()
    fric = {"isotropic": FRIC_ISOTROPIC, "directional": FRIC_DIRECTIONAL, "stickslip": FRIC_STICKSLIP}[e.friction]
    contact = CONTACT_NORMAL if e.contact == "normal" else CONTACT_VERTICAL
    kshear = float(e.kShear) if e.kShear is not None else float(e.kBot)
    env = EnvArrays(float(e.g), float(e.rho), effective_depth(model), float(e.kBot), float(e.cBot), contact, fric,
                    float(muT), float(muA), float(mc), float(cv), kshear, float(e.cBot))
    b = e.bathymetry
    if b is None:
        grid = (np.zeros(0), np.zeros(0), np.zeros((0, 0)))
    else:
        grid = (b.x.copy(), b.y.copy(), b.z.copy())
    seabed = Seabed(*grid, np.zeros((nn, 3)), np.zeros((nn, 2)), np.zeros(3, dtype=np.int64))
    return Layout(lines, rods, points, env, seabed, row, 3 * len(coupled), N, line_L,
                  [ln.line_type for ln in model.lines], coupled)


def static_motion(x: np.ndarray) -> Motion:
    """A trajectory that holds the coupled DOFs at ``x``."""
    x = np.asarray(x, dtype=float)
    c = np.zeros((1, x.size, 4))
    c[0, :, 0] = x
    return Motion(np.array([0.0, 1.0]), c)


def step_motion(x, xd, t: float, dt: float) -> Motion:
    """MoorDyn's coupling-step trajectory: ``x + xd (tau - t)`` on ``[t, t + dt]``."""
    x = np.asarray(x, dtype=float)
    c = np.zeros((1, x.size, 4))
    c[0, :, 0] = x
    c[0, :, 1] = np.asarray(xd, dtype=float)
    return Motion(np.array([t, t + max(dt, 1e-300)]), c)
