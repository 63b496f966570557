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

from ..model import ELASTIC, SYROPE, SYROPE_WC_TYPES, BodyKind, Curve, Model, PointKind, RodKind
from .features import Features, features_of
from .linestates import N_XC, NWC, VIS_ELASTIC, XC_HIST, XC_VIV, XC_WCLINE, build_working_curve
from .seabed import CONTACT_NORMAL, CONTACT_VERTICAL, FRIC_DIRECTIONAL, FRIC_ISOTROPIC, FRIC_STICKSLIP
from .waterkin import build_water_kinematics, still_water

log = logging.getLogger("moorline.core")

# point kinds (kernels compare against these integers)
P_FIXED = int(PointKind.FIXED)
P_COUPLED = int(PointKind.COUPLED)
P_FREE = int(PointKind.FREE)
P_BODY = int(PointKind.BODY)

# attachment kinds of line ends
ATT_POINT = 0
ATT_ROD_A = 1
ATT_ROD_B = 2


#: lines of at least this many nodes, with linear EA and BA, take the line kernel's vectorised loops
#: over their segments and interior nodes (``LineArrays.vec``); shorter ones its one scalar pass,
#: which is faster for them (benchmarks/RESULTS.md section 6)
VECTOR_MIN_NODES = 16


class LineArrays(NamedTuple):
    """Line data. Per line arrays have length n_lines; per segment n_seg; per node n_nodes."""

    node_ptr: np.ndarray  # int64 (n_lines+1,)
    seg_ptr: np.ndarray  # int64 (n_lines+1,)
    end_kind: np.ndarray  # int64 (n_lines, 2): attachment kind of end A, end B (ATT_*)
    end_idx: np.ndarray  # int64 (n_lines, 2): index of the point or rod attached
    clamped: np.ndarray  # int64 (n_lines, 2): 1 if the end is clamped to its rod (line with EI on a rod end), 2
    #                      if clamped without passing its bending moment to the rod (MoorDyn-C's way, ClampMoment 0)
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
    # line states (core.linestates): viscoelastic and Syrope segments, VIV
    vis: np.ndarray  # int64 (n_lines,): axial model (linestates.VIS_*)
    vis_par: np.ndarray  # (n_lines, 3): EA_D (alpha) [N], EA_D_Lm (beta) [-], BA_D [N s]
    seg_xs: np.ndarray  # int64 (n_seg,): index of the segment's stretch state in the line-state block, -1 none
    node_xs: np.ndarray  # int64 (n_nodes,): index of the node's VIV phase in the line-state block, -1 none
    viv: np.ndarray  # (n_lines, 3): Cl, dF, cF
    viv_h: np.ndarray  # (n_nodes, 2): running RMS of the cross-flow velocity and acceleration (history)
    xs_ctl: np.ndarray  # (linestates.N_XC,): mode, step, history switch, VIV clock (see core.linestates)
    xs_s0: np.ndarray  # (n_xs,): line states at the start of an implicit step
    xs_f0: np.ndarray  # (n_xs,): their rates there
    sy_tab: np.ndarray  # int64 (n_lines, 2): rows of the original working curve in sy_owc
    sy_owc: np.ndarray  # (n_owc, 3): Syrope original working curves: strain, tension [N], slow strain
    sy_par: np.ndarray  # (n_lines, 3): working-curve shape (linestates.WC_*), k1, k2
    sy_T: np.ndarray  # (n_seg, 2): Syrope Tmax, Tmean [N] (history)
    sy_wc: np.ndarray  # (n_seg or 0, NWC, 3): Syrope working curves (history)
    calc: np.ndarray  # int64 (n_lines,): 1 evaluate the line's loads; 0 keep its last ones (local Euler)
    vec: np.ndarray  # int64 (n_lines,): 1 for the lines whose segments and interior nodes are done in the
    #                  line kernel's vectorised loops (VECTOR_MIN_NODES), 0 for its one scalar pass


# rod kinds (mirror model.RodKind) and body kinds (mirror model.BodyKind)
ROD_FIXED = int(RodKind.FIXED)
ROD_PINNED = int(RodKind.PINNED)
ROD_BODY = int(RodKind.BODY)
ROD_BODY_PINNED = int(RodKind.BODY_PINNED)
ROD_COUPLED = int(RodKind.COUPLED)
ROD_COUPLED_PINNED = int(RodKind.COUPLED_PINNED)
ROD_FREE = int(RodKind.FREE)
BODY_FIXED = int(BodyKind.FIXED)
BODY_COUPLED = int(BodyKind.COUPLED)
BODY_COUPLED_PINNED = int(BodyKind.COUPLED_PINNED)
BODY_FREE = int(BodyKind.FREE)
#: RigidArrays.inertia: the velocity-dependent inertial loads of rods and bodies (Options.InertialLoads)
INERTIA_FULL = 0
INERTIA_MOORDYN = 1


class RigidArrays(NamedTuple):
    """Rods and bodies, and the sizes of the state blocks.

    The state ``y = [Q | U | Z | X]``: ``Q`` holds 3 numbers per 3-DOF row (internal line nodes,
    free points, free zero-length rods) then 7 per 6-DOF block (position, unit quaternion w x y z),
    ``U`` 3 per row (velocity) then 6 per block (velocity, angular velocity in global axes), ``Z``
    the radiation states of floating bodies (first order, :mod:`moorline.core.floating`), ``X`` the
    line states (first order: viscoelastic stretch, VIV phase; :mod:`moorline.core.linestates`).
    6-DOF blocks belong to free rods, pinned rods (all kinds) and free and coupled-pinned bodies;
    the translational part of a pinned object's block is not used (its parent sets it).
    """

    dims: np.ndarray  # int64 (4,): n3 rows, n6 blocks, nz radiation states (after U, see core.floating),
    #                   nx line states (after Z, see core.linestates)
    rod_kind: np.ndarray  # int64 (nr,) ROD_*
    rod_N: np.ndarray  # int64 (nr,) segments (0: zero-length rod)
    rod_body: np.ndarray  # int64 (nr,) parent body, -1 if none
    rod_blk: np.ndarray  # int64 (nr,) 6-DOF block, -1 if none
    rod_row: np.ndarray  # int64 (nr,) 3-DOF row of a free zero-length rod, -1 otherwise
    rod_cpl: np.ndarray  # int64 (nr,) offset in the coupled-DOF vector, -1 if not coupled
    rod_rA0: np.ndarray  # (nr, 3) end A: global deck position, or body axes for rods on bodies [m]
    rod_qrel: np.ndarray  # (nr, 3) unit axis in the parent's frame (body axes for rods on bodies)
    rod_qref: np.ndarray  # (nr, 3) unit axis at the deck pose, global: the quaternion state rotates it
    rod_L: np.ndarray  # (nr,) length [m]
    rod_d: np.ndarray
    rod_w: np.ndarray
    rod_Cd: np.ndarray
    rod_Ca: np.ndarray
    rod_CdEnd: np.ndarray
    rod_CaEnd: np.ndarray
    rod_node_ptr: np.ndarray  # int64 (nr+1,): rod k owns rod nodes ptr[k]:ptr[k+1] (N+1, one if N = 0)
    body_kind: np.ndarray  # int64 (nb,) BODY_*
    body_blk: np.ndarray  # int64 (nb,)
    body_cpl: np.ndarray  # int64 (nb,)
    body_r0: np.ndarray  # (nb, 3) deck reference-point position [m]
    body_Q0: np.ndarray  # (nb, 4) deck orientation quaternion (w, x, y, z)
    body_M0: np.ndarray  # (nb, 6, 6) mass matrix about the reference point in body axes (incl. added mass)
    body_m: np.ndarray  # (nb,) mass [kg] (0 for fixed and coupled bodies, as MoorDyn)
    body_rCG: np.ndarray  # (nb, 3) CG in body axes [m]
    body_V: np.ndarray  # (nb,) volume [m^3]
    body_CdA: np.ndarray  # (nb, 6)
    inertia: np.ndarray  # int64 (1,): INERTIA_FULL or INERTIA_MOORDYN (Options.InertialLoads)


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
    body: np.ndarray  # int64 (n_points,): parent body of body points (r0 then in body axes), -1 otherwise


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
    water: object  # core.waterkin.WaterKin: waves and current
    exc: object  # core.floating.ExcitationArrays: wave excitation of the floating bodies
    #: penetration [m] over which the seabed contact damping grows from zero to full (0: MoorDyn's
    #: step at first contact; the implicit scheme needs a continuous contact force, see System)
    bed_ramp: float = 0.0
    #: penetration [m] over which the contact spring stiffness grows from zero to kBot (0: MoorDyn's
    #: kink at first contact; the implicit scheme's Newton iterations prefer a C1 force)
    bed_blend: float = 0.0


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

    #: what the system has (core.features.Features); numba sees it in the type of Work, so the
    #: kernels of a system are compiled without the code of the features it lacks
    features: Features
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
    rodw: np.ndarray  # (n_rods, 3) rod angular velocity (global axes) [rad/s]
    rodF: np.ndarray  # (n_rods, 2, 3) sum of the line end forces on each rod end
    rodEM: np.ndarray  # (2 n_rods, 3, 3) sum of the line end mass matrices on rod end 2k (A), 2k+1 (B)
    rodMext: np.ndarray  # (n_rods, 3) moments on the rod besides its node forces (clamped cables, ends)
    rod6F: np.ndarray  # (n_rods, 6) net force and moment about end A (coupled rods: minus M a_in)
    rod6M: np.ndarray  # (n_rods, 6, 6) mass matrix about end A
    rodacc: np.ndarray  # (n_rods, 6) acceleration of end A and angular acceleration
    rn_r: np.ndarray  # (n_rod_nodes, 3) rod node positions
    rn_v: np.ndarray  # (n_rod_nodes, 3) rod node velocities
    rn_U: np.ndarray  # (n_rod_nodes, 3) water velocity
    rn_Ud: np.ndarray  # (n_rod_nodes, 3) water acceleration
    rn_zeta: np.ndarray  # (n_rod_nodes,) surface elevation (the rod uses that of its end B)
    rn_pd: np.ndarray  # (n_rod_nodes,) dynamic pressure [Pa]
    rn_F: np.ndarray  # (n_rod_nodes, 9, 3) node loads: W, B, Dp, Dq, Ap, Aq, Pd, seabed, net (incl. lines)
    rn_M: np.ndarray  # (n_rod_nodes, 3, 3) node mass matrices (incl. line ends)
    rn_vof: np.ndarray  # (n_rod_nodes,) submerged fraction of each rod node
    bR: np.ndarray  # (n_bodies, 3, 3) body rotation matrices (body to global)
    br: np.ndarray  # (n_bodies, 3) reference-point positions
    bv: np.ndarray  # (n_bodies, 3)
    bw: np.ndarray  # (n_bodies, 3) angular velocities (global axes)
    bU: np.ndarray  # (n_bodies, 3) water velocity at the reference points
    fk: np.ndarray  # (max objects, 8) scratch of the water-kinematics kernel
    b6F: np.ndarray  # (n_bodies, 6) net force and moment about the reference point
    b6M: np.ndarray  # (n_bodies, 6, 6)
    bacc: np.ndarray  # (n_bodies, 6)
    pr: np.ndarray  # (n_points, 3)
    pv: np.ndarray  # (n_points, 3)
    pa: np.ndarray  # (n_points, 3) acceleration (free points; imposed for coupled)
    pF: np.ndarray  # (n_points, 3) net force on the point
    pM: np.ndarray  # (n_points, 3, 3) mass matrix incl. attached line ends
    pU: np.ndarray  # (n_points, 3) water velocity at points
    xc: np.ndarray  # (n_coupled_dof,) coupled positions at the current time
    vc: np.ndarray  # (n_coupled_dof,) coupled velocities
    ac: np.ndarray  # (n_coupled_dof,) coupled accelerations
    # scratch of the rigid-object kernels, which allocate nothing (they run without numba's
    # reference counting, see core.numerics)
    m33: np.ndarray  # (5, 3, 3)
    v6: np.ndarray  # (3, 6)
    dense: np.ndarray  # (6, 7) augmented matrix of the small dense solves
    seg_s: np.ndarray  # (n_seg,) stretch state of viscoelastic segments used by the evaluation [m]
    seg_sdot: np.ndarray  # (n_seg,) its rate [m/s]
    phi: np.ndarray  # (n_nodes,) VIV lift phase [rad]
    dphi: np.ndarray  # (n_nodes,) its rate [rad/s]
    Flift: np.ndarray  # (n_nodes, 3) VIV lift force [N]
    acc_old: np.ndarray  # (n_nodes, 3) node accelerations of the previous evaluation (VIV)
    kept: np.ndarray  # (8 n_seg + 16 n_nodes + 6 n_points + 1,) the loads MoorDyn's convention keeps
    #                   over the evaluation at a step's end (core.integrate.last_stage_keep), then the
    #                   line states' history flag, then (VIV) the accelerations


# ------------------------------------------------------------------------ floating bodies
# force components of FloatWork.F (per floating body, 6-vectors about the reference point)
FC_EXCITATION = 0
FC_RADIATION = 1  # memory part; the A_inf part acts through the mass matrix
FC_HYDROSTATIC = 2
FC_DAMPING = 3  # extra linear and quadratic damping
FC_MORISON = 4
FC_PTO = 5
FC_EXTRA = 6  # extra stiffness and constant load
FC_MOORING = 7  # quasi-static mooring (linearised over a step), in the quasi-static mode only
N_FC = 8
FC_NAMES = ("excitation", "radiation", "hydrostatic", "damping", "morison", "pto", "extra", "quasistatic_mooring")

# FloatArrays.ctl
CTL_RADIATION = 0  # 0: state space, 1: convolution
CTL_QS_MOORING = 1  # 1: the quasi-static mooring load ql_F - ql_K (pose - ql_x0) acts
RAD_STATE_SPACE = 0
RAD_CONVOLUTION = 1
# ExcitationArrays.ctl[0]
EXC_OFF = 0
EXC_SUM = 1
EXC_TABLE = 2


class FloatArrays(NamedTuple):
    """Floating bodies (``nf``), their groups, radiation models, joints and Morison strips.
    Global floating DOF ``6 f + d`` is DOF ``d`` (surge ... yaw) of floating body ``f``."""

    body: np.ndarray  # int64 (nf,): deck body of each floating body
    of_body: np.ndarray  # int64 (nb,): floating body of each deck body, -1 if it does not float
    grouped: np.ndarray  # int64 (nf,): 1 when solved with its group (several members or a joint)
    grp_ptr: np.ndarray  # int64 (ng+1,): group g holds grp_members[grp_ptr[g]:grp_ptr[g+1]]
    grp_members: np.ndarray  # int64 (nf,)
    dof_y: np.ndarray  # int64 (6 nf,): index in the state of each DOF's velocity
    C: np.ndarray  # (nf, 6, 6) buoyancy part of the hydrostatic stiffness about the reference point
    F0: np.ndarray  # (nf, 6) buoyancy at rest: force and moment about the reference point
    pose0: np.ndarray  # (nf, 3) mean reference-point position [m]
    R0: np.ndarray  # (nf, 3, 3) mean orientation
    Blin: np.ndarray  # (nf, 6, 6)
    Bquad: np.ndarray  # (nf, 6, 6)
    Kext: np.ndarray  # (nf, 6, 6)
    Fc: np.ndarray  # (nf, 6)
    Ainf: np.ndarray  # (6 nf, 6 nf) infinite-frequency added mass (zero between groups)
    ss_i: np.ndarray  # int64 (npair,): influenced DOF of each state-space pair
    ss_j: np.ndarray  # int64 (npair,): radiating DOF
    ss_ptr: np.ndarray  # int64 (npair+1,): pair p owns states ss_ptr[p]:ss_ptr[p+1]
    ss_A: np.ndarray  # (nz, max order): row r of pair p is ss_A[ss_ptr[p] + r, :order]
    ss_B: np.ndarray  # (nz,)
    ss_C: np.ndarray  # (nz,)
    irf: np.ndarray  # (nt, 6 nf, 6 nf): K[radiating, influenced] at t = k dt (convolution only)
    child_joint: np.ndarray  # int64 (nf,): joint whose child the body is, -1 if none
    jt_child: np.ndarray  # int64 (nj,): floating body that slides
    jt_parent: np.ndarray  # int64 (nj,): floating body it slides on, -1: a fixed axis
    jt_axis: np.ndarray  # (nj, 3): slide direction, parent body axes (global for a fixed axis)
    jt_d0: np.ndarray  # (nj, 3): child reference point at s = 0, parent body axes from the parent's
    #                    reference point (a fixed axis: global position)
    jt_q: np.ndarray  # (nj, 4): child orientation relative to the parent's (a fixed axis: absolute)
    jt_k: np.ndarray  # (nj,) PTO stiffness [N/m]
    jt_c: np.ndarray  # (nj,) PTO damping [N s/m]
    jt_s0: np.ndarray  # (nj,) slide at which the PTO spring is relaxed [m]
    ms_fb: np.ndarray  # int64 (ns,): floating body of each Morison strip
    ms_rA: np.ndarray  # (ns, 3) body axes
    ms_rB: np.ndarray  # (ns, 3)
    ms_d: np.ndarray  # (ns,)
    ms_Cd: np.ndarray  # (ns,)
    ms_n: np.ndarray  # int64 (ns,)
    ql_F: np.ndarray  # (6 nf,): quasi-static mooring load at the pose ql_x0 [N, N m]
    ql_K: np.ndarray  # (6 nf, 6 nf): its stiffness with respect to the pose (Euler angles) [N/m, N/rad, ...]
    ql_x0: np.ndarray  # (6 nf,): the pose it was linearised about (x, y, z, roll, pitch, yaw, Rx Ry Rz)
    par: np.ndarray  # (2,): impulse-response sampling interval [s], joint pull-back rate [1/s]
    ctl: np.ndarray  # int64 (2,): radiation method, quasi-static mooring on (1) or off (0)


class ExcitationArrays(NamedTuple):
    """The wave excitation of the floating DOFs (part of the environment: off while the initial
    conditions are found, as the waves are)."""

    ctl: np.ndarray  # int64 (1,): EXC_OFF, EXC_SUM or EXC_TABLE
    par: np.ndarray  # (3,): ramp time [s], table interval [s], table period [s]
    w: np.ndarray  # (nc,) component frequencies [rad/s] (EXC_SUM)
    Xr: np.ndarray  # (nc, 6 nf): F = sum_j Xr cos(w_j t) - Xi sin(w_j t) [N, N m]
    Xi: np.ndarray  # (nc, 6 nf)
    G: np.ndarray  # (n_table + 1, 6 nf): force at k dt over one period (EXC_TABLE; last = first)
    dG: np.ndarray  # (n_table + 1, 6 nf): its time derivative


class FloatWork(NamedTuple):
    F: np.ndarray  # (nf, N_FC, 6) load components
    xi: np.ndarray  # (nf, 6) displacement from the mean pose
    vel: np.ndarray  # (6 nf,) velocities
    Mg: np.ndarray  # (6 nf, 6 nf) group mass matrix
    Fg: np.ndarray  # (6 nf,) group loads, then F - M gamma
    T: np.ndarray  # (6 nf, 6 nf) reduced-coordinate map of a group
    gam: np.ndarray  # (6 nf,) velocity-dependent accelerations of a group
    MT: np.ndarray  # (6 nf, 6 nf) scratch M T
    Mr: np.ndarray  # (6 nf, 6 nf) reduced mass matrix
    Fr: np.ndarray  # (6 nf,) reduced loads
    qa: np.ndarray  # (6 nf,) reduced accelerations
    dense: np.ndarray  # (6 nf, 6 nf + 1) augmented matrix of the dense solves
    jt: np.ndarray  # (nj, 3): slide s [m], rate [m/s], PTO power c s'^2 [W]
    fk: np.ndarray  # (8,) water kinematics at one point
    m33: np.ndarray  # (2, 3, 3) scratch
    lu: np.ndarray  # (nz, max order): LU factors of (I - h/2 A) of each pair
    lu_piv: np.ndarray  # int64 (nz,)
    lu_h: np.ndarray  # (npair,): step h the factors belong to (0: none)
    zv: np.ndarray  # (max order,) scratch
    hist: np.ndarray  # (nt, 6 nf): velocity at t = k dt, ring buffer (convolution)
    hctl: np.ndarray  # int64 (2,): index of the next sample, index of the first since the last restart
    hpar: np.ndarray  # (1,): time of the last step end recorded [s]
    vlast: np.ndarray  # (6 nf,): velocities at that time
    jerr: np.ndarray  # (12,): a joint's position/rotation and velocity errors
    qpose: np.ndarray  # (6 nf,): the poses of the floating bodies (quasi-static mooring)
    eye3: np.ndarray  # (3, 3) identity


def empty_float_arrays(n_bodies: int) -> FloatArrays:
    """The FloatArrays of a model without floating bodies."""
    zi = np.zeros(0, dtype=np.int64)
    z = np.zeros
    return FloatArrays(zi, -np.ones(n_bodies, dtype=np.int64), zi, np.zeros(1, dtype=np.int64), zi, zi,
                       z((0, 6, 6)), z((0, 6)), z((0, 3)), z((0, 3, 3)), z((0, 6, 6)), z((0, 6, 6)), z((0, 6, 6)),
                       z((0, 6)), z((0, 0)), zi, zi, np.zeros(1, dtype=np.int64), z((0, 1)), z(0), z(0), z((0, 0, 0)),
                       zi, zi, zi, z((0, 3)), z((0, 3)), z((0, 4)), z(0), z(0), z(0), zi, z((0, 3)), z((0, 3)), z(0),
                       z(0), zi, z(0), z((0, 0)), z(0), np.array([1.0, 0.0]), np.zeros(2, dtype=np.int64))


def no_excitation(n_dof: int) -> ExcitationArrays:
    """Excitation switched off (still water, or while the initial conditions are found)."""
    z = np.zeros
    return ExcitationArrays(np.array([EXC_OFF], dtype=np.int64), np.array([0.0, 1.0, 1.0]), z(0), z((0, n_dof)),
                            z((0, n_dof)), z((1, n_dof)), z((1, n_dof)))


def new_float_work(F: FloatArrays) -> FloatWork:
    nf = F.body.size
    nd = 6 * nf
    nj = F.jt_child.size
    nz = F.ss_B.size
    mo = F.ss_A.shape[1]
    z = np.zeros
    return FloatWork(z((nf, N_FC, 6)), z((nf, 6)), z(nd), z((nd, nd)), z(nd), z((nd, nd)), z(nd), z((nd, nd)),
                     z((nd, nd)), z(nd), z(nd), z((max(nd, 1), nd + 1)), z((nj, 3)), z(8), z((2, 3, 3)),
                     z((nz, mo)), np.zeros(nz, dtype=np.int64), z(F.ss_i.size), z(mo), z((F.irf.shape[0], nd)),
                     np.zeros(2, dtype=np.int64), z(1), z(nd), z(12), z(nd), np.eye(3))



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
    rigid: RigidArrays
    points: PointArrays
    env: EnvArrays
    seabed: Seabed
    n_rows: int  # number of 3-DOF state rows
    n_blocks: int  # number of 6-DOF state blocks
    n_coupled_dof: int
    line_N: np.ndarray  # (n_lines,) segments per line
    line_L: np.ndarray  # (n_lines,) unstretched length [m] (negative inputs resolved)
    line_type_names: list
    coupled_points: list  # point indices in coupled-DOF order
    coupled_rods: list
    coupled_bodies: list
    env_ic: EnvArrays  # env with the water kinematics of the initial-condition solve (waves off)
    #: the floating bodies (their own arguments of the kernels, so that the rigid-body and work
    #: tuples every kernel receives stay small: numba passes a tuple's arrays field by field)
    fl: FloatArrays = None

    @property
    def n_state(self) -> int:
        return 6 * self.n_rows + 13 * self.n_blocks + self.n_radiation + self.n_line_states

    @property
    def n_line_states(self) -> int:
        """Number of line states (viscoelastic stretch, VIV phase; at the very end of the state)."""
        return int(self.rigid.dims[3])

    @property
    def xs_offset(self) -> int:
        """Index in the state where the line states start (after the radiation states)."""
        return self.z_offset + self.n_radiation

    @property
    def n_radiation(self) -> int:
        """Number of radiation states of floating bodies (at the end of the state)."""
        return int(self.rigid.dims[2])

    @property
    def z_offset(self) -> int:
        """Index in the state where the radiation states start."""
        return 6 * self.n_rows + 13 * self.n_blocks

    @property
    def u_offset(self) -> int:
        """Index in the state where the velocities start."""
        return 3 * self.n_rows + 7 * self.n_blocks

    def block_slices(self, j: int) -> tuple[slice, slice]:
        """(pose, velocity) slices of 6-DOF block ``j`` in the state: 7 and 6 numbers."""
        q = 3 * self.n_rows + 7 * j
        u = self.u_offset + 3 * self.n_rows + 6 * j
        return slice(q, q + 7), slice(u, u + 6)

    def new_work(self) -> Work:
        nn = int(self.lines.node_ptr[-1])
        ns = int(self.lines.seg_ptr[-1])
        nl = len(self.line_N)
        R = self.rigid
        nr = len(R.rod_kind)
        nrn = int(R.rod_node_ptr[-1])
        nb = len(R.body_kind)
        npnt = len(self.points.kind)
        nc = self.n_coupled_dof
        z = np.zeros
        return Work(features=features_of(self),
                    r=z((nn, 3)), v=z((nn, 3)), U=z((nn, 3)), Ud=z((nn, 3)), zeta=z(nn), T=z((ns, 3)),
                    Td=z((ns, 3)), seg_len=z(ns), seg_ldot=z(ns), seg_F=z(ns), seg_e=z((ns, 3)), q=z((nn, 3)),
                    F=z((nn, 3)), Fhyd=z((nn, 3)), Fbed=z((nn, 3)), W=z((nn, 3)), mass=z((nn, 3)),
                    acc=z((nn, 3)), kurv=z(nn), Fbend=z((nn, 3)), end_moment=z((nl, 2, 3)), rodr=z((nr, 2, 3)),
                    rodv=z((nr, 2, 3)), rodq=z((nr, 3)), rodw=z((nr, 3)), rodF=z((nr, 2, 3)), rodEM=z((2 * nr, 3, 3)),
                    rodMext=z((nr, 3)), rod6F=z((nr, 6)), rod6M=z((nr, 6, 6)), rodacc=z((nr, 6)), rn_r=z((nrn, 3)),
                    rn_v=z((nrn, 3)), rn_U=z((nrn, 3)), rn_Ud=z((nrn, 3)), rn_zeta=z(nrn), rn_pd=z(nrn),
                    rn_F=z((nrn, 9, 3)), rn_M=z((nrn, 3, 3)), rn_vof=z(nrn), bR=z((nb, 3, 3)), br=z((nb, 3)),
                    bv=z((nb, 3)), bw=z((nb, 3)), bU=z((nb, 3)), fk=z((max(nn, nrn, npnt, nb, 1), 8)),
                    b6F=z((nb, 6)), b6M=z((nb, 6, 6)), bacc=z((nb, 6)), pr=z((npnt, 3)), pv=z((npnt, 3)),
                    pa=z((npnt, 3)), pF=z((npnt, 3)), pM=z((npnt, 3, 3)), pU=z((npnt, 3)), xc=z(nc), vc=z(nc),
                    ac=z(nc), m33=z((5, 3, 3)), v6=z((3, 6)), dense=z((6, 7)), seg_s=z(ns), seg_sdot=z(ns),
                    phi=z(nn), dphi=z(nn), Flift=z((nn, 3)), acc_old=z((nn, 3)),
                    kept=z(8 * ns + 16 * nn + 6 * npnt + 1))

    def new_float_work(self) -> FloatWork:
        return new_float_work(self.fl)


def effective_depth(model: Model) -> float:
    """Water depth after MoorDyn's rule: never shallower than the deepest point (flat seabed only;
    with a bathymetry grid the depth is the grid's mean depth)."""
    depth = model.env.depth
    if model.env.bathymetry is not None:
        return float(depth)
    zmin = min((model.point_position(i)[2] for i in range(len(model.points))), default=0.0)
    if -zmin > depth:
        log.warning("water depth %.6g m is shallower than the deepest point (z = %.6g m); "
                    "using depth %.6g m as MoorDyn does", depth, zmin, -zmin)
        depth = -zmin
    return float(depth)


def build_layout(model: Model, floating=None) -> Layout:
    """Validate ``model`` and build the flat arrays of :class:`Layout`.

    ``floating``: ``(FloatArrays, ExcitationArrays)`` of the floating bodies, as
    :func:`moorline.system.floating.floating_arrays` prepares them from the model's
    hydrodynamics (None: no floating bodies). Their state indices (``dof_y``) are filled here.
    """
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
                # 1: clamped, its bending moment acts on the rod; 2: clamped, the moment is not passed
                # to the rod (MoorDyn-C, ClampMoment 0)
                clamped[k, j] = int(lt.has_bending) * (1 if model.options.ClampMoment else 2)
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
    for i, p in enumerate(model.points):
        if p.kind == PointKind.FREE:
            prow[i] = row
            row += 1
    nr = len(model.rods)
    rod_row = -np.ones(nr, dtype=np.int64)
    for k, rod in enumerate(model.rods):
        if rod.kind == RodKind.FREE and rod.N == 0:
            rod_row[k] = row
            row += 1

    # 6-DOF blocks: free rods, pinned rods, free and coupled-pinned bodies
    nblk = 0
    rod_blk = -np.ones(nr, dtype=np.int64)
    for k, rod in enumerate(model.rods):
        if rod.N > 0 and rod.kind in (RodKind.FREE, RodKind.PINNED, RodKind.BODY_PINNED, RodKind.COUPLED_PINNED):
            rod_blk[k] = nblk
            nblk += 1
    nb = len(model.bodies)
    body_blk = -np.ones(nb, dtype=np.int64)
    for i, b in enumerate(model.bodies):
        if b.kind in (BodyKind.FREE, BodyKind.COUPLED_PINNED):
            body_blk[i] = nblk
            nblk += 1

    # coupled DOF vector: bodies, rods, points (MoorDyn's order)
    off = 0
    body_cpl = -np.ones(nb, dtype=np.int64)
    for i in model.coupled_bodies:
        body_cpl[i] = off
        off += 6 if model.bodies[i].kind == BodyKind.COUPLED else 3
    rod_cpl = -np.ones(nr, dtype=np.int64)
    for k in model.coupled_rods:
        rod_cpl[k] = off
        off += 6 if model.rods[k].kind == RodKind.COUPLED else 3
    cpl = -np.ones(npnt, dtype=np.int64)
    for i in model.coupled_points:
        cpl[i] = off
        off += 3

    def col(attr):
        return np.array([getattr(p, attr) for p in model.points], dtype=float)

    points = PointArrays(
        kind=kind,
        r0=np.array([p.r for p in model.points], dtype=float).reshape(npnt, 3),
        m=col("m"), V=col("V"), CdA=col("CdA"), Ca=col("Ca"),
        F_ext=np.array([p.F_ext for p in model.points], dtype=float).reshape(npnt, 3),
        row=prow, cpl=cpl,
        body=np.array([p.body if p.kind == PointKind.BODY else -1 for p in model.points], dtype=np.int64),
    )
    states, nx = _line_state_arrays(model, node_ptr, seg_ptr)
    vis = states[0]
    vec = ((vis == VIS_ELASTIC) & (ea_tab[:, 1] == 0) & (ba_tab[:, 1] == 0)
           & (np.diff(node_ptr) >= VECTOR_MIN_NODES)).astype(np.int64)
    lines = LineArrays(node_ptr, seg_ptr, end_kind, end_idx, clamped, props["d"], props["A"], props["w"],
                       props["Cd"], props["Ca"], props["CdAx"], props["CaAx"], ea_tab, ba_tab, EI, ei_tab, seg_l0,
                       seg_EA, seg_BA, np.array(tab_x, dtype=float), np.array(tab_y, dtype=float), node_row, *states,
                       vec)
    _start_syrope(model, lines)
    if floating is None:
        fl, exc = empty_float_arrays(len(model.bodies)), no_excitation(0)
    else:
        fl, exc = floating
        fl = _place_floating(fl, row, nblk, body_blk)
    rigid = _rigid_arrays(model, np.array([row, nblk, fl.ss_B.size, nx], dtype=np.int64), rod_blk, rod_row,
                          rod_cpl, body_blk, body_cpl)
    e = model.env
    muT, muA, mc, cv = e.friction_coefficients()
    fric = {"isotropic": FRIC_ISOTROPIC, "directional": FRIC_DIRECTIONAL, "stickslip": FRIC_STICKSLIP}[e.friction]
    contact = CONTACT_NORMAL if e.contact == "normal" else CONTACT_VERTICAL
    kshear = float(e.kShear) if e.kShear is not None else float(e.kBot)
    depth = effective_depth(model)
    n_ext = nn + int(rigid.rod_node_ptr[-1]) + npnt + len(model.bodies) + 1
    water, water_ic = _water(model, depth, n_ext)
    env = EnvArrays(float(e.g), float(e.rho), depth, float(e.kBot), float(e.cBot), contact, fric,
                    float(muT), float(muA), float(mc), float(cv), kshear, float(e.cBot), water, exc)
    b = e.bathymetry
    if b is None:
        grid = (np.zeros(0), np.zeros(0), np.zeros((0, 0)))
    else:
        grid = (b.x.copy(), b.y.copy(), b.z.copy())
    seabed = Seabed(*grid, np.zeros((nn, 3)), np.zeros((nn, 2)), np.zeros(3, dtype=np.int64))
    return Layout(lines, rigid, points, env, seabed, row, nblk, off, N, line_L,
                  [ln.line_type for ln in model.lines], model.coupled_points, model.coupled_rods, model.coupled_bodies,
                  env._replace(water=water_ic, exc=no_excitation(exc.Xr.shape[1])), fl)


def _line_state_arrays(model: Model, node_ptr, seg_ptr) -> tuple[tuple, int]:
    """The line-state fields of :class:`LineArrays` (viscoelastic and Syrope segments, VIV nodes;
    see :mod:`moorline.core.linestates`) and the number of line states."""
    nl = len(model.lines)
    nn, ns = int(node_ptr[-1]), int(seg_ptr[-1])
    vis = np.ones(nl, dtype=np.int64)
    vis_par = np.zeros((nl, 3))
    viv = np.zeros((nl, 3))
    seg_xs = -np.ones(ns, dtype=np.int64)
    node_xs = -np.ones(nn, dtype=np.int64)
    sy_tab = np.zeros((nl, 2), dtype=np.int64)
    sy_par = np.zeros((nl, 3))
    owc: list[np.ndarray] = []
    n_owc = 0
    x = 0
    for k, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        vis[k] = lt.elastic
        vis_par[k] = (lt.EA_D, lt.EA_D_Lm, lt.BA_D)
        if lt.elastic != ELASTIC:
            seg_xs[seg_ptr[k]:seg_ptr[k + 1]] = np.arange(x, x + seg_ptr[k + 1] - seg_ptr[k])
            x += int(seg_ptr[k + 1] - seg_ptr[k])
        if lt.elastic == SYROPE:
            c = lt.syrope.owc
            z = c.x - np.log1p(lt.EA_D_Lm / lt.EA_D * c.y) / lt.EA_D_Lm
            owc.append(np.column_stack([c.x, c.y, z]))
            sy_tab[k] = (n_owc, c.x.size)
            n_owc += c.x.size
            sy_par[k] = (SYROPE_WC_TYPES.index(lt.syrope.wc_type.upper()), lt.syrope.k1, lt.syrope.k2)
    for k, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        if lt.Cl > 0.0:
            viv[k] = (lt.Cl, lt.dF, lt.cF)
            inner = np.arange(node_ptr[k] + 1, node_ptr[k + 1] - 1)
            node_xs[inner] = np.arange(x, x + inner.size)
            x += inner.size
    any_syrope = bool(np.any(vis == SYROPE))
    xs_ctl = np.zeros(N_XC)
    xs_ctl[XC_HIST] = 1.0
    xs_ctl[XC_VIV] = 1.0
    xs_ctl[XC_WCLINE] = 1.0 if model.options.SyropeWorkingCurve == "line" else 0.0
    states = (vis, vis_par, seg_xs, node_xs, viv, np.zeros((nn, 2)), xs_ctl, np.zeros(x), np.zeros(x), sy_tab,
              np.vstack(owc) if owc else np.zeros((0, 3)), sy_par, np.zeros((ns, 2)),
              np.zeros((ns if any_syrope else 0, NWC, 3)), np.ones(nl, dtype=np.int64))
    return states, x


def _start_syrope(model: Model, L: LineArrays) -> None:
    """Syrope history at the start: every segment of a Syrope line at its line's (Tmax0, Tmean0),
    with the working curve of Tmax0."""
    for k, ln in enumerate(model.lines):
        if L.vis[k] != SYROPE:
            continue
        tmax, tmean = ln.syrope_ic
        for s in range(int(L.seg_ptr[k]), int(L.seg_ptr[k + 1])):
            L.sy_T[s] = (tmax, tmean)
            build_working_curve(L, k, s, tmax)


def _water(model: Model, depth: float, n_ext: int):
    """The water kinematics (:class:`~moorline.core.waterkin.WaterKin`) of the run and of the
    initial-condition solve (waves off, current on, as MoorDyn does, spec 6.1)."""

    e = model.env
    waves = e.waves if e.waves_on_lines else None
    if waves is None and e.current is None:
        still = still_water(max(depth, 1e-9), e.g, e.rho)
        return still, still
    pts = [model.end_position(a) for ln in model.lines for a in (ln.end_a, ln.end_b)]
    pts += [model.point_position(i) for i in range(len(model.points))]
    pts += [r for k in range(len(model.rods)) for r in model.rod_ends(k)]
    pts += [b.r for b in model.bodies]
    pts = np.array(pts, dtype=float).reshape(-1, 3)
    reach = max([ln.L for ln in model.lines] + [1.0]) * 0.5
    lo = np.minimum(pts.min(axis=0) - reach, [np.inf, np.inf, -depth])
    hi = np.maximum(pts.max(axis=0) + reach, [-np.inf, -np.inf, 0.0])
    lo[2] = -depth
    bbox = np.array([lo, hi])
    bathy = e.bathymetry
    kw = dict(depth=depth, g=e.g, rho=e.rho, bbox=bbox, bathymetry=bathy)
    water = build_water_kinematics(waves, e.current, n_external=n_ext, **kw)
    water_ic = build_water_kinematics(None, e.current, n_external=n_ext, **kw)
    return water, water_ic


def quat_from_matrix(R: np.ndarray) -> np.ndarray:
    """Unit quaternion (w, x, y, z) of a rotation matrix (Shepperd's method, stable for any angle)."""
    R = np.asarray(R, dtype=float)
    tr = np.trace(R)
    if tr > 0:
        s = 2.0 * math.sqrt(1.0 + tr)
        q = [0.25 * s, (R[2, 1] - R[1, 2]) / s, (R[0, 2] - R[2, 0]) / s, (R[1, 0] - R[0, 1]) / s]
    elif R[0, 0] > R[1, 1] and R[0, 0] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[0, 0] - R[1, 1] - R[2, 2])
        q = [(R[2, 1] - R[1, 2]) / s, 0.25 * s, (R[0, 1] + R[1, 0]) / s, (R[0, 2] + R[2, 0]) / s]
    elif R[1, 1] > R[2, 2]:
        s = 2.0 * math.sqrt(1.0 + R[1, 1] - R[0, 0] - R[2, 2])
        q = [(R[0, 2] - R[2, 0]) / s, (R[0, 1] + R[1, 0]) / s, 0.25 * s, (R[1, 2] + R[2, 1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + R[2, 2] - R[0, 0] - R[1, 1])
        q = [(R[1, 0] - R[0, 1]) / s, (R[0, 2] + R[2, 0]) / s, (R[1, 2] + R[2, 1]) / s, 0.25 * s]
    q = np.array(q)
    return q / np.linalg.norm(q) * (1.0 if q[0] >= 0 else -1.0)


def quat_product(a, b) -> np.ndarray:
    """Hamilton product a (x) b of quaternions (w, x, y, z)."""
    aw, ax, ay, az = a
    bw, bx, by, bz = b
    return np.array([aw * bw - ax * bx - ay * by - az * bz, aw * bx + ax * bw + ay * bz - az * by,
                     aw * by - ax * bz + ay * bw + az * bx, aw * bz + ax * by - ay * bx + az * bw])


def quat_between(a: np.ndarray, b: np.ndarray) -> np.ndarray:
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


def _skew(r) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


def body_mass_matrix(body, rho: float) -> np.ndarray:
    """6x6 mass matrix of a body about its reference point, body axes: the rigid mass at its CG
    moved to the reference point, plus translational added mass rho V Ca (spec 3.15)."""
    M = np.zeros((6, 6))
    if not body.has_inertia:
        return M
    m = body.m
    S = _skew(body.rCG)
    M[:3, :3] = m * np.eye(3)
    M[:3, 3:] = -m * S
    M[3:, :3] = m * S
    M[3:, 3:] = np.diag(body.I) - m * S @ S
    M[:3, :3] += np.diag(rho * body.V * body.Ca)
    return M


def _place_floating(fl: FloatArrays, n3: int, n6: int, body_blk) -> FloatArrays:
    """The floating arrays with the state index of each floating DOF's velocity."""
    dof_y = np.zeros(6 * fl.body.size, dtype=np.int64)
    uoff = 3 * n3 + 7 * n6
    for f, i in enumerate(fl.body):
        j = int(body_blk[i])
        if j < 0:
            raise ValueError(f"body {i + 1} floats but is not a free body")
        dof_y[6 * f:6 * f + 6] = uoff + 3 * n3 + 6 * j + np.arange(6)
    return fl._replace(dof_y=dof_y)


def _rigid_arrays(model: Model, dims, rod_blk, rod_row, rod_cpl, body_blk, body_cpl) -> RigidArrays:
    nr = len(model.rods)
    nb = len(model.bodies)
    f = np.zeros
    rod_L, rA0, qrel, qref = f(nr), f((nr, 3)), f((nr, 3)), f((nr, 3))
    props = {k: f(nr) for k in ("d", "w", "Cd", "Ca", "CdEnd", "CaEnd")}
    for k, rod in enumerate(model.rods):
        rt = model.rod_types[rod.rod_type]
        for name in props:
            props[name][k] = getattr(rt, name)
        rod_L[k] = rod.length if rod.N > 0 else 0.0
        rA0[k] = rod.rA
        qrel[k] = rod.axis
        on_body = rod.kind in (RodKind.BODY, RodKind.BODY_PINNED)
        qref[k] = model.bodies[rod.body].rotation @ rod.axis if on_body else rod.axis
    nodes = np.array([r.N + 1 for r in model.rods], dtype=np.int64)
    ptr = np.zeros(nr + 1, dtype=np.int64)
    ptr[1:] = np.cumsum(nodes)
    bodies = model.bodies
    rho = model.env.rho
    keep = [b.has_inertia for b in bodies]
    return RigidArrays(
        dims=dims,
        rod_kind=np.array([int(r.kind) for r in model.rods], dtype=np.int64),
        rod_N=np.array([r.N for r in model.rods], dtype=np.int64),
        rod_body=np.array([r.body if r.kind in (RodKind.BODY, RodKind.BODY_PINNED) else -1 for r in model.rods],
                          dtype=np.int64),
        rod_blk=rod_blk, rod_row=rod_row, rod_cpl=rod_cpl, rod_rA0=rA0, rod_qrel=qrel, rod_qref=qref, rod_L=rod_L,
        rod_d=props["d"], rod_w=props["w"], rod_Cd=props["Cd"], rod_Ca=props["Ca"], rod_CdEnd=props["CdEnd"],
        rod_CaEnd=props["CaEnd"], rod_node_ptr=ptr,
        body_kind=np.array([int(b.kind) for b in bodies], dtype=np.int64),
        body_blk=body_blk, body_cpl=body_cpl,
        body_r0=np.array([b.r for b in bodies], dtype=float).reshape(nb, 3),
        body_Q0=np.array([quat_from_matrix(b.rotation) for b in bodies], dtype=float).reshape(nb, 4),
        body_M0=np.array([body_mass_matrix(b, rho) for b in bodies], dtype=float).reshape(nb, 6, 6),
        body_m=np.array([b.m if k else 0.0 for b, k in zip(bodies, keep, strict=True)], dtype=float),
        body_rCG=np.array([b.rCG for b in bodies], dtype=float).reshape(nb, 3),
        body_V=np.array([b.V if k else 0.0 for b, k in zip(bodies, keep, strict=True)], dtype=float),
        body_CdA=np.array([b.CdA if k else np.zeros(6) for b, k in zip(bodies, keep, strict=True)],
                          dtype=float).reshape(nb, 6),
        inertia=np.array([INERTIA_MOORDYN if model.options.InertialLoads == "moordyn" else INERTIA_FULL],
                         dtype=np.int64),
    )


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
