"""Initial conditions of a :class:`~moorline.system.System` (spec section 6): rigid objects at their
deck pose, every line on its quasi-static catenary (the start guess), then the static equilibrium
by one of three strategies:

- Newton statics (the default, ``ICNewton -1`` or ``1``): pseudo-transient Newton on the whole
  system, free points, rods, bodies and slack lines included
  (:func:`moorline.core.statics.newton_statics`), with implicit dynamic relaxation as its fallback
  for slack, flexible systems far from the start;
- MoorDyn's stationary solver (its default, :func:`moorline.core.statics.stationary_solve`);
- MoorDyn's legacy dynamic relaxation (``ICgenDynamic 1``).

MoorDyn's two methods run when Newton fails (explicit schemes only), or first with ``ICNewton 0``
(MoorDyn's behaviour). Whatever the method, the residual of the starting state (largest
acceleration of a free DOF with the velocities at zero) is measured and reported; a start that
is not at rest is logged as an error (:func:`report_residual`).
"""

from __future__ import annotations

import logging
import time
from typing import TYPE_CHECKING

import numpy as np

from ..core.implicit import S_AVALID, S_H, S_HJ, advance_implicit, gen_alpha_parameters
from ..core.integrate import Scheme
from ..core.layout import ATT_POINT, ATT_ROD_A, P_BODY, P_COUPLED, P_FREE, Layout
from ..core.linestates import (
    MODE_RATE,
    MODE_STATIC,
    VIS_ELASTIC,
    VIS_SYROPE,
    XC_HIST,
    XC_MODE,
    XC_VIV,
    end_line_states,
    store_line_states,
)
from ..core.rhs import rhs
from ..core.rigid import body_kinematics, body_point_kinematics, rod_kinematics, rod_nodes
from ..core.seabed import resting_penetration, seabed_at
from ..core.statics import StaticEval, dynamic_relaxation, newton_statics, stationary_solve
from ..errors import SimulationError
from ..quasistatic.catenary import STATUS_OK, STATUS_SHORT_SPAN, catenary_nodes, grounded_catenary_nodes

if TYPE_CHECKING:
    from .runtime import System

log = logging.getLogger("moorline")

#: node speed [m/s] above which a state is taken as unstable
MAX_NODE_SPEED = 500.0
#: Newton statics converges when every residual acceleration is below NEWTON_ACC_TOL [m/s^2] (a
#: force of 1e-5 N per kg of node mass) and the last position update below NEWTON_DX_TOL [m]. The
#: update bound is far below any physical scale so that the start does not depend on the path the
#: iterations took: near the root Newton converges quadratically, and one more iteration takes the
#: update from about 1e-6 m to round-off. With 1e-6 m, two mirror-image systems (one reaching the
#: root by Newton alone, the other after implicit relaxation) started 1.6e-8 of the tension apart;
#: with 1e-9 m, 2e-12 (tests/verification/test_seabed.py, mirrored slope).
NEWTON_ACC_TOL = 1e-5
NEWTON_DX_TOL = 1e-9
NEWTON_MAX_IT = 400
#: Newton iterations from the catenary start before implicit relaxation takes over, with the
#: implicit scheme (whose time step, which the relaxation runs, is compiled anyway)
NEWTON_FIRST_IT = 30
#: the same with an explicit scheme. An iteration is cheap (a coloured Jacobian and a banded solve:
#: 0.1 ms on the README's 3-line chain), but from the catenary start the pseudo-transient iterations
#: of a chain lying on the seabed creep: that chain converged in 167 of them (41 since NEWTON_GROWTH,
#: below; the budget is kept for harder starts). With 30 it fell back on
#: the implicit relaxation, whose kernels (the generalized-alpha step) an explicit deck otherwise
#: never needs: a third of the README example's first-run compile time went to them.
NEWTON_FIRST_IT_EXPLICIT = 250
#: seabed-blend continuation (:func:`newton_ic`): blend widths [m] of the contact spring's C1 ramp
#: (``core.seabed._spring``), widest first. MoorDyn's contact spring starts at full stiffness at
#: zero penetration: a node at the touchdown has no contact stiffness in the Jacobian on one side
#: and full stiffness on the other, and Newton steps it in and out of the seabed. A metre of blend
#: makes the contact soft enough for the touchdown to move freely; each narrower width starts from
#: the previous equilibrium, and the last solve has the deck's own contact law. MoorPy's case2
#: (chain and polyester with a free joint): 650 iterations and no convergence before, about 500
#: over the four solves now.
BLEND_WIDTHS = (1.0, 0.1, 0.01)
#: least growth of Newton's pseudo step per iteration that lowers the residual (``min_growth`` of
#: :func:`~moorline.core.statics.newton_statics`), in every solve of :func:`newton_ic`. Growing it
#: by the residual ratio alone held the step small while the residual fell slowly (a touchdown
#: creeping along a chain): with 2, the README's 3-line chain converges in 41 iterations instead of
#: 168, the wave-energy cable example in 54 without continuation instead of 312 with it, and seven
#: public decks that needed a continuation converge in the first solve; none that converged before
#: stopped converging (71 decks)
NEWTON_GROWTH = 2.0
#: relaxation-Newton alternation (:func:`newton_ic`), after the deck's own relaxation budget:
#: chunks of RELAX_CHUNK [s] of implicit relaxation at steps of RELAX_STEP [s], each from rest
#: and followed by a short Newton, until Newton converges or after RELAX_BUDGET [s] of pseudo time.
#: The step is independent of dtIC (MoorDyn's convergence-test interval: 1 ms in lifting.txt,
#: whose slack, undamped line then needs thousands of steps); restarting each chunk from rest
#: takes out the kinetic energy a lightly damped system would otherwise keep (MHK_RM1's almost
#: vertical chain hangs: 45 s).
RELAX_STEP = 0.5
RELAX_CHUNK = 5.0
RELAX_BUDGET = 300.0
#: ... and it stops early when RELAX_PATIENCE chunks in a row have not halved the best residual
#: Newton reached (a system with no equilibrium near, such as BodiesAndRods.dat's body without
#: buoyancy sinking on nylon lines, took 36 s of wall time for the whole budget)
RELAX_PATIENCE = 6


def end_points(layout: Layout, li: int, W) -> tuple[np.ndarray, np.ndarray]:
    """Initial positions of the two ends of line ``li`` from the point and rod-end positions
    that :func:`rigid_start` put in ``W``."""
    out = []
    for j in range(2):
        kind = layout.lines.end_kind[li, j]
        k = int(layout.lines.end_idx[li, j])
        if kind != ATT_POINT:
            out.append(W.rodr[k, 0 if kind == ATT_ROD_A else 1].copy())
        else:
            out.append(W.pr[k].copy())
    return out[0], out[1]


def rigid_start(layout: Layout, x_coupled: np.ndarray, y: np.ndarray, W) -> None:
    """Put free points, rods and bodies at their deck pose in the state ``y`` (coupled objects
    at ``x_coupled``, velocities zero) and evaluate the kinematics of bodies, rods and points
    into the Work arrays ``W`` (rod ends ``W.rodr``, points ``W.pr``)."""
    R = layout.rigid
    P = layout.points
    y[:] = 0.0
    for p in range(len(P.kind)):
        if P.kind[p] == P_FREE:
            row = int(P.row[p])
            y[3 * row:3 * row + 3] = P.r0[p]
    for k in range(len(R.rod_kind)):
        if R.rod_row[k] >= 0:
            row = int(R.rod_row[k])
            y[3 * row:3 * row + 3] = R.rod_rA0[k]
        j = int(R.rod_blk[k])
        if j >= 0:
            q, _ = layout.block_slices(j)
            y[q.start:q.start + 3] = R.rod_rA0[k] if R.rod_body[k] < 0 else 0.0
            y[q.start + 3] = 1.0  # the quaternion rotates the deck axis: identity at the start
    for i in range(len(R.body_kind)):
        j = int(R.body_blk[i])
        if j >= 0:
            q, _ = layout.block_slices(j)
            y[q.start:q.start + 3] = R.body_r0[i]
            y[q.start + 3:q.start + 7] = R.body_Q0[i]
    W.xc[:] = x_coupled
    W.vc[:] = 0.0
    W.ac[:] = 0.0
    if len(R.body_kind):
        body_kinematics(y, R, W)
    if len(R.rod_kind):
        rod_kinematics(y, R, W)
        rod_nodes(R, W)
    for p in range(len(P.kind)):
        if P.kind[p] == P_COUPLED:
            o = int(P.cpl[p])
            W.pr[p] = x_coupled[o:o + 3]
        elif P.kind[p] != P_BODY:
            W.pr[p] = P.r0[p]
    if len(R.body_kind):
        body_point_kinematics(P, W)


def wet_weight(L, E, li: int) -> float:
    """Submerged weight per unit length of line ``li`` of LineArrays ``L`` in the water of
    EnvArrays ``E`` [N/m] (negative: buoyant)."""
    return float((L.w[li] - E.rho * L.A[li]) * E.g)


def end_on_seabed(layout: Layout, r) -> bool:
    """True when a line end at ``r`` lies on (or below) the local seabed: the catenary start then
    solves the line with a seabed through it (spec 6.2)."""
    E, B = layout.env, layout.seabed
    return bool(r[2] <= seabed_at(B.gx, B.gy, B.gz, E.depth, r[0], r[1])[0] * (1.0 - 1e-5))


def catenary_start(layout: Layout, x_coupled: np.ndarray, y: np.ndarray, W, cat_tol: float = 1e-5) -> list[int]:
    """Place rigid objects at their deck pose (:func:`rigid_start`), then every line on its
    quasi-static catenary (spec 6.2); velocities zero. Returns ``(line index, status)`` of the
    lines whose catenary solve failed and were left on the straight chord (a vertical line is
    placed on its chord by design and is not a failure)."""
    rigid_start(layout, x_coupled, y, W)
    L = layout.lines
    failed = []
    for li in range(len(layout.line_N)):
        rA, rB = end_points(layout, li, W)
        N = int(layout.line_N[li])
        out = np.zeros((N + 1, 3))
        Wl = wet_weight(L, layout.env, li)
        # a seabed at the lower end's level, if an end lies on (or below) the local seabed
        seabed = end_on_seabed(layout, rA) or end_on_seabed(layout, rB)
        EA = float(L.seg_EA[L.seg_ptr[li]])
        status, _, _ = catenary_nodes(rA, rB, float(layout.line_L[li]), N, EA, Wl, seabed, cat_tol, out)
        if status not in (STATUS_OK, STATUS_SHORT_SPAN):
            failed.append((li, int(status)))
        place_line(layout, li, out, y)
    return failed


def place_line(layout: Layout, li: int, out: np.ndarray, y: np.ndarray) -> None:
    """Put line ``li``'s internal nodes at ``out`` (all N + 1 nodes) in ``y``, none below the
    seabed, and start its internal states there."""
    L, E, B = layout.lines, layout.env, layout.seabed
    N = out.shape[0] - 1
    # the catenary knows only a flat seabed: nothing starts below the real one (a line laid
    # on a slope starts on it, not through it)
    for j in range(1, N):
        zb = seabed_at(B.gx, B.gy, B.gz, E.depth, out[j, 0], out[j, 1])[0]
        if out[j, 2] < zb:
            out[j, 2] = zb
    for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
        row = int(L.node_row[n])
        y[3 * row:3 * row + 3] = out[n - int(L.node_ptr[li])]
    start_line_states(layout, li, out, y)


def fold_too_long_lines(sys: System, W) -> None:
    """Newton's start for the lines whose catenary is "too long" (left on their straight chord by
    :func:`catenary_start`, as MoorDyn leaves them, every segment slack): the folded "L" of
    :func:`folded_l_nodes`."""
    lay = sys.layout
    for number in sys.ic_report.get("catenary_too_long", []):
        li = number - 1
        rA, rB = end_points(lay, li, W)
        out = np.zeros((int(lay.line_N[li]) + 1, 3))
        folded_l_nodes(rA, rB, float(lay.line_L[li]), out.shape[0] - 1, out)
        place_line(lay, li, out, sys.y)


def ground_dipping_lines(sys: System, W) -> list[int]:
    """Newton's start for the sinking lines that hang from two ends above the seabed and whose
    catenary start dipped below it: :func:`catenary_start` (as MoorDyn's start) gives such a line
    its free catenary, and :func:`place_line` lifts the nodes below the seabed onto it, which leaves
    them bunched up on it, their segments slack (the lazy-wave benchmark cable's 62 m hub line
    at 15 segments: 2-11 % short). Newton cannot pull a slack run straight (no axial stiffness
    until it is), and crept at one segment per few iterations. These lines start instead on
    :func:`~moorline.quasistatic.catenary.grounded_catenary_nodes`: hanging from each end down
    to the seabed and lying straight on it between. The seabed height is that under the lifted
    nodes (their mean, for a bathymetry grid). Returns the numbers of the lines placed so."""
    lay = sys.layout
    L, E, B = lay.lines, lay.env, lay.seabed
    folded = set(sys.ic_report.get("catenary_too_long", []))
    placed = []
    for li in range(len(lay.line_N)):
        wsub = wet_weight(L, E, li)
        if wsub <= 0.0 or li + 1 in folded:
            continue
        rA, rB = end_points(lay, li, W)
        if end_on_seabed(lay, rA) or end_on_seabed(lay, rB):
            continue  # (the catenary start had its seabed)
        lifted = []
        for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
            k = 3 * int(L.node_row[n])
            zb = seabed_at(B.gx, B.gy, B.gz, E.depth, sys.y[k], sys.y[k + 1])[0]
            if sys.y[k + 2] <= zb + 1e-9 * max(1.0, abs(zb)):
                lifted.append(zb)
        if not lifted:
            continue
        N = int(lay.line_N[li])
        out = np.zeros((N + 1, 3))
        EA = float(L.seg_EA[L.seg_ptr[li]])
        H = grounded_catenary_nodes(rA, rB, float(lay.line_L[li]), N, EA, wsub, float(np.mean(lifted)), out)
        if np.isfinite(H):
            place_line(lay, li, out, sys.y)
            placed.append(li + 1)
    return placed


def folded_l_nodes(rA: np.ndarray, rB: np.ndarray, L: float, N: int, out: np.ndarray) -> None:
    """Start nodes of a line too long to lie as an "L" (the catenary's ``STATUS_TOO_LONG``): a
    vertical hang from the upper end down to the lower end's level, a straight run along the seabed
    to the lower end, and the excess length laid on the seabed as a fold that runs out beyond the
    lower end, away from the upper one, and back. The hang carries the line's weight and the
    seabed part is unstretched, so the start is close to an equilibrium (a straight chord instead
    leaves every segment slack and the whole line falls: MoorPy's case5, 890 m between points 500 m
    apart). Nodes at equal unstretched arc length; lines may overlap themselves in this model."""
    low, up = (rA, rB) if rA[2] <= rB[2] else (rB, rA)
    d = np.array([up[0] - low[0], up[1] - low[1], 0.0])
    dh = float(np.hypot(d[0], d[1]))
    u = d / dh if dh > 0.0 else np.array([1.0, 0.0, 0.0])
    h = float(up[2] - low[2])
    e = max(L - dh - h, 0.0)
    corners = [low, low - 0.5 * e * u, low + dh * u, up]
    seg = [float(np.linalg.norm(corners[k + 1] - corners[k])) for k in range(3)]
    total = sum(seg)
    for j in range(N + 1):
        s = total * j / N
        k = 0
        while k < 2 and s > seg[k]:
            s -= seg[k]
            k += 1
        f = s / seg[k] if seg[k] > 0.0 else 0.0
        out[j] = corners[k] + min(f, 1.0) * (corners[k + 1] - corners[k])
    if rA[2] > rB[2]:
        out[:] = out[::-1].copy()
    out[0] = rA
    out[N] = rB


def start_line_states(layout: Layout, li: int, nodes: np.ndarray, y: np.ndarray) -> None:
    """Line states of line ``li`` at the start (spec 6.1, MoorDyn's Line::initialize): the stretch
    state of a viscoelastic segment is its whole stretch (no initial transient from an unstretched
    static branch), that of a Syrope segment the working curve's slow strain at Tmean0 times its
    length; VIV phases are spread over 0..2 pi along the line. ``nodes``: the line's node
    positions, shape (N + 1, 3)."""
    L = layout.lines
    xo = layout.xs_offset
    s0, s1 = int(L.seg_ptr[li]), int(L.seg_ptr[li + 1])
    if L.vis[li] != VIS_ELASTIC:
        ls = np.linalg.norm(np.diff(nodes, axis=0), axis=1)
        for k, s in enumerate(range(s0, s1)):
            x = int(L.seg_xs[s])
            l0 = float(L.seg_l0[s])
            if L.vis[li] == VIS_SYROPE:
                wc = L.sy_wc[s]
                y[xo + x] = l0 * float(np.interp(L.sy_T[s, 1], wc[:, 1], wc[:, 2]))
            else:
                y[xo + x] = ls[k] - l0
    n0, n1 = int(L.node_ptr[li]), int(L.node_ptr[li + 1])
    N = n1 - n0 - 1
    for i in range(1, N):
        x = int(L.node_xs[n0 + i])
        if x >= 0:
            y[xo + x] = 2.0 * np.pi * i / N


def solve_initial_conditions(sys: System) -> None:
    """Find the initial equilibrium of ``sys`` from its catenary start with the deck's IC settings
    (spec 6): Newton statics when asked for (or by default with the implicit scheme), else, or
    when Newton fails with an explicit scheme, MoorDyn's stationary solver or dynamic relaxation.
    Fills ``sys.ic_report``."""
    L = sys.layout.lines
    # VIV is off while the initial conditions are found (as in MoorDyn); viscoelastic stretch states
    # are at rest (condensed) in the static solves, and integrated by dynamic relaxation
    L.xs_ctl[XC_VIV] = 0.0
    static = not sys.model.options.ICgenDynamic or sys.scheme == Scheme.GENALPHA or _newton_first(sys)
    if static:
        L.xs_ctl[XC_MODE] = MODE_STATIC
        L.xs_ctl[XC_HIST] = 0.0
    try:
        _solve_initial_conditions(sys)
    finally:
        if static and L.xs_s0.size > 0:
            # the line states at rest in the final positions (and the Syrope history there)
            dy = sys._S[0]
            L_, R, P, _, B, W, F, FW = sys._kernel_arrays()
            rhs(0.0, sys.y, dy, L_, R, P, sys._kernel_env_ic(), B, sys._motion, W, F, FW, 1.0, -1)
            store_line_states(sys.y, L, R, W, 0.0, True)
        end_line_states(L)
        L.xs_ctl[XC_VIV] = 1.0


def _newton_first(sys: System) -> bool:
    """Newton statics is tried first unless ``ICNewton 0`` asks for MoorDyn's methods (the implicit
    scheme always uses it)."""
    return sys.model.options.ICNewton != 0 or sys.scheme == Scheme.GENALPHA


#: a start is at rest when no free DOF accelerates by more than RESIDUAL_TOL [m/s^2] (1 mm/s^2:
#: 1e-4 g, a load error of 1e-4 of the node's weight) at zero velocity
RESIDUAL_TOL = 1e-3


def report_residual(sys: System) -> float:
    """Measure the residual of the starting state (largest acceleration [m/s^2] of a free 3-DOF row
    or 6-DOF block, translational, with every velocity at zero; the IC water kinematics) into
    ``sys.ic_report['residual']``, and say loudly when the start is not at rest."""
    lay = sys.layout
    n3, n6 = lay.n_rows, lay.n_blocks
    if n3 + n6 == 0:
        sys.ic_report["residual"] = 0.0
        return 0.0
    y = sys.y.copy()
    y[lay.u_offset:lay.z_offset] = 0.0
    dy = np.zeros_like(y)
    L, R, P, _, B, W, F, FW = sys._kernel_arrays()
    # the start is measured as it was solved: without VIV, whose lift in a current is an oscillating
    # excitation, not a static load (viv.txt: a converged start was reported 0.11 m/s^2 off)
    hist, viv = L.xs_ctl[XC_HIST], L.xs_ctl[XC_VIV]
    L.xs_ctl[XC_HIST] = 0.0
    L.xs_ctl[XC_VIV] = 0.0
    try:
        rhs(0.0, y, dy, L, R, P, sys._kernel_env_ic(), B, sys._motion, W, F, FW, 1.0, -1)
    finally:
        L.xs_ctl[XC_HIST] = hist
        L.xs_ctl[XC_VIV] = viv
    uo = lay.u_offset
    acc = dy[uo:uo + 3 * n3].reshape(-1, 3)
    blk = dy[uo + 3 * n3:uo + 3 * n3 + 6 * n6].reshape(-1, 6)[:, :3]
    a = np.linalg.norm(np.vstack([acc, blk]), axis=1)
    res = float(np.max(a)) if a.size else 0.0
    where = sys.state_rows()[int(np.argmax(a))] if a.size else ("", 0, 0)
    sys.ic_report["residual"] = res
    sys.ic_report["residual_mean"] = float(np.mean(a)) if a.size else 0.0
    sys.ic_report["residual_at"] = f"{where[0]} {where[1]}" + (f" node {where[2]}" if where[0] == "line" else "")
    if sys.ic_report.get("converged") is False or res > RESIDUAL_TOL:
        sys.ic_report["converged"] = False
        log.error("the run starts from an UNCONVERGED initial state: residual acceleration %.3g m/s^2 at %s (%s); "
                  "the results begin with a transient. Raise TmaxIC, check the model, or use ICNewton 1",
                  res, sys.ic_report["residual_at"], sys.ic_report.get("method", "catenary start"))
    return res


def _solve_initial_conditions(sys: System) -> None:
    opts = sys.model.options
    L, R, P, _, B, W, F, FW = sys._kernel_arrays()
    E = sys._kernel_env_ic()  # waves off, current on (spec 6.1)
    # Newton when asked for, and by default with the implicit scheme or floating bodies (a hull on its
    # hydrostatics is a stiff, lightly damped system that MoorDyn's pseudo-dynamics settle slowly)
    if _newton_first(sys) and newton_ic(sys, L, R, P, E, B, W, F, FW):
        return
    if opts.ICgenDynamic:
        L.xs_ctl[XC_MODE] = MODE_RATE  # dynamic relaxation integrates the line states
        L.xs_ctl[XC_HIST] = 1.0
    if sys.scheme == Scheme.GENALPHA:
        raise SimulationError("Newton statics did not find the initial equilibrium; the implicit scheme has no "
                              "explicit fallback at its step: set ICNewton 0 with an explicit tScheme, or give "
                              "a better start (line lengths, anchor positions)", time=0.0)
    if opts.ICgenDynamic:
        ok, tic, bad = dynamic_relaxation(sys.y, sys.dtM, int(sys.scheme), sys.scheme_params, opts.dtIC,
                                          opts.TmaxIC, opts.threshIC, opts.CdScaleIC, L, R, P, E, B,
                                          sys._motion, W, F, FW, sys._S, MAX_NODE_SPEED, np.zeros((11, len(sys.lines))))
        if bad >= 0:
            raise sys._instability(tic, int(bad), "during dynamic relaxation of the initial conditions")
        sys.ic_report.update(method="dynamic relaxation", converged=bool(ok), pseudo_time=float(tic))
    else:
        seg_min = float(np.min(L.seg_l0)) if L.seg_l0.size else 1.0
        cfl_ic = min(float(opts.CFL), 1.0)
        status, tic, emean, it = stationary_solve(sys.y, sys.dtM, opts.dtIC, opts.TmaxIC, opts.threshIC,
                                                  cfl_ic, seg_min, L, R, P, E, B, sys._motion, W, F, FW, sys._S)
        if status < 0 or not np.all(np.isfinite(sys.y)):
            raise SimulationError("the stationary initial-condition solver diverged (non-finite state); "
                                  "try ICgenDynamic 1 or a smaller dtM", time=0.0)
        sys.ic_report.update(method="stationary", converged=bool(status == 1), stalled=bool(status == 2),
                             pseudo_time=float(tic), iterations=int(it), mean_acceleration=float(emean))
    rep = sys.ic_report
    g = sys.layout.env.g
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


def newton_ic(sys: System, L, R, P, E, B, W, F, FW) -> bool:
    """Static equilibrium by Newton's method (pseudo-transient continuation from the catenary
    start). When that does not converge quickly, three strategies follow, each only if the one
    before failed:

    1. seabed-blend continuation (with seabed contact): Newton on a softened contact law, widths
       :data:`BLEND_WIDTHS`, then on the deck's own, from the first solve's last iterate where that
       is nearer rest than the start;
    2. implicit dynamic relaxation within the deck's TmaxIC (generalized-alpha with maximal
       numerical damping, drag scaled by CdScaleIC, steps of up to dtIC), then Newton;
    3. relaxation-Newton alternation (:data:`RELAX_CHUNK`, :data:`RELAX_STEP`,
       :data:`RELAX_BUDGET`): slack and lightly damped systems far from their start;
    4. with the implicit scheme, whose first solves are short (:data:`NEWTON_FIRST_IT`), the first
       solve and the continuation again with the explicit schemes' budgets
       (:data:`NEWTON_FIRST_IT_EXPLICIT`): the implicit scheme has no explicit start to fall back on.

    Every route ends in a Newton solve on the deck's own model to the same tolerances, so the
    answer does not depend on the route beyond those. Returns False (state restored) when none
    converges."""
    opts = sys.model.options
    A, IW = sys._implicit()
    # MoorDyn's start, which its methods get back if Newton fails, leaves a line too long for an "L"
    # on its chord; Newton's start has it folded on the seabed
    y_moordyn = sys.y.copy()
    fold_too_long_lines(sys, W)
    grounded = ground_dipping_lines(sys, W)
    if grounded:
        sys.ic_report["catenary_grounded"] = grounded
    y_start = sys.y.copy()
    t0 = time.perf_counter()
    sink_into_seabed(sys, E)
    y_sunk = sys.y.copy()  # where every Newton route starts
    first = NEWTON_FIRST_IT if sys.scheme == Scheme.GENALPHA else NEWTON_FIRST_IT_EXPLICIT

    # the compiled evaluations, looked up once for every solve below (softened seabeds included)
    ev = StaticEval(sys.y, A, IW, L, R, P, E, B, sys._motion, W, F, FW)

    def newton(env, tau0, max_it, acc_tol=NEWTON_ACC_TOL, dx_tol=NEWTON_DX_TOL):
        return newton_statics(sys.y, A, IW, L, R, P, env, B, sys._motion, W, F, FW, float(tau0),
                              acc_tol, dx_tol, max_it, NEWTON_GROWTH, ev=ev.with_env(env))

    def first_and_continuation(first):
        """Newton from the start (``y_sunk``), then (when it fails on a seabed) the seabed-blend
        continuation: (status, iterations, residual, route)."""
        sys.y[:] = y_sunk
        status, it, resid = newton(E, opts.dtIC, first)
        route = "newton"
        if status == 1 or E.kBot <= 0.0:
            return status, it, resid, route
        widths = [w for w in BLEND_WIDTHS if w > E.bed_blend]
        if not widths:
            return status, it, resid, route
        # the softened solves start from the first solve's last iterate if it is nearer rest than the
        # start (largest residual acceleration), else from the start (74 RK2 starts of the public decks
        # and ours: 22,799 -> 20,897 Jacobians, MoorDyn's complex_system.txt converging in the
        # continuation instead of after 1400 iterations and an implicit relaxation)
        y_first = sys.y.copy()
        sys.y[:] = y_sunk
        if np.isfinite(resid) and np.all(np.isfinite(y_first)) and resid < ev.residual()[0]:
            sys.y[:] = y_first
        for w in widths:
            # the softened solves need no final accuracy, only a good start for the next one; one that
            # stops short still hands on a better start than the catenary's (MoorPy's case6: the 1 m and
            # 0.1 m solves stop short, the 1 cm one converges)
            y_stage = sys.y.copy()
            st, k, _ = newton(E._replace(bed_blend=w), opts.dtIC, first, 10.0 * NEWTON_ACC_TOL, 1e-6)
            it += k
            if st < 0 or not np.all(np.isfinite(sys.y)):
                sys.y[:] = y_stage
        status, k, resid = newton(E, opts.dtIC, NEWTON_MAX_IT)
        return status, it + k, resid, "seabed-blend continuation + newton"

    status, it, resid, route = first_and_continuation(first)
    relax = 0.0
    if status != 1:
        sys.y[:] = y_start
        relax = implicit_relaxation(sys, A, IW, L, R, P, E, B, W, F, FW)
        y_relaxed = sys.y.copy()
        status, k, resid = newton(E, opts.dtIC, NEWTON_MAX_IT)
        it += k
        route = "implicit relaxation + newton"
        best, stale = np.inf, 0
        while status != 1 and relax < RELAX_BUDGET and stale < RELAX_PATIENCE:
            # on from the relaxed state, not from Newton's last iterate
            sys.y[:] = y_relaxed
            dt = implicit_relaxation(sys, A, IW, L, R, P, E, B, W, F, FW, t_max=RELAX_CHUNK, h=RELAX_STEP,
                                     window=RELAX_CHUNK, thresh=0.0)
            if dt <= 0.0 or not np.all(np.isfinite(sys.y)):
                sys.y[:] = y_relaxed
                break
            relax += dt
            y_relaxed = sys.y.copy()
            status, k, resid = newton(E, RELAX_STEP, NEWTON_FIRST_IT)
            it += k
            if resid < 0.5 * best:
                best, stale = resid, 0
            else:
                stale += 1
            route = "relaxation-newton alternation"
    if status != 1 and first < NEWTON_FIRST_IT_EXPLICIT:
        # the implicit scheme's short first solves hand over to the relaxation early, which suits slack and
        # lightly damped systems; one that needs the explicit schemes' long solves instead gets them last
        # (MoorPy's case6.dat with its segments doubled: no GenAlpha start before, 2130 iterations this way;
        # MoorDyn's BeamCantilevered.txt was such a case, 1463 iterations, until statics.STATIC_FD_REL)
        st, k, r, rt = first_and_continuation(NEWTON_FIRST_IT_EXPLICIT)
        it += k
        if st == 1:
            status, resid, route = st, r, rt + " (after the relaxation routes)"
    wall = time.perf_counter() - t0
    sys.ic_report.update(method=route, converged=bool(status == 1), iterations=int(it),
                         max_acceleration=float(resid), pseudo_time=relax, wall_time=wall)
    sys._reset_scheme()
    if status == 1:
        log.info("initial conditions: static equilibrium by %s in %d iterations%s (%.3g s), residual %.2g m/s^2",
                 route, it, f" after {relax:.3g} s of implicit relaxation" if relax else "", wall, resid)
        return True
    log.warning("Newton statics did not converge (%s after %d iterations, residual %.3g m/s^2, %.3g s of "
                "implicit relaxation)%s", "singular or non-finite" if status < 0 else "not converged", it, resid,
                relax, "" if sys.scheme == Scheme.GENALPHA else "; falling back to MoorDyn's initial-condition method")
    sys.y[:] = y_moordyn
    return False


def sink_into_seabed(sys: System, E) -> None:
    """Lower the internal line nodes the catenary start laid on the seabed to the penetration
    at which the contact law ``E`` carries the line's submerged weight. On the seabed surface
    itself the contact stiffness of the Jacobian is zero (one-sided at MoorDyn's kink, zero
    with the implicit scheme's spring blend): Newton's first step would sink them by metres
    and take dozens of damped iterations to come back (15-segment OC3 chain: 53 iterations,
    4 after sinking)."""
    L, B = sys.layout.lines, sys.layout.seabed
    if E.kBot <= 0.0:
        return
    for li in range(len(sys.layout.line_N)):
        wsub = wet_weight(L, E, li)
        if wsub <= 0.0 or L.d[li] <= 0.0:
            continue
        pen = resting_penetration(wsub / (E.kBot * L.d[li]), E.bed_blend)
        for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
            k = 3 * int(L.node_row[n])
            zb = seabed_at(B.gx, B.gy, B.gz, E.depth, sys.y[k], sys.y[k + 1])[0]
            if sys.y[k + 2] <= zb + 1e-6 * max(1.0, abs(zb)):
                sys.y[k + 2] = zb - pen


def implicit_relaxation(sys: System, A, IW, L, R, P, E, B, W, F, FW, *, t_max: float | None = None,
                        h: float | None = None, window: float | None = None, thresh: float | None = None) -> float:
    """Implicit dynamic relaxation towards equilibrium from rest (see :func:`newton_ic`): until the
    line end tensions (and the rigid blocks' poses) change by less than ``thresh`` (relative;
    default threshIC) over a ``window`` (default dtIC), or for ``t_max`` (default TmaxIC), at steps
    of ``h`` (default min(dtIC, 1 s)); the velocities are zero at the end. Returns the pseudo
    time [s] (short of ``t_max`` if a step failed)."""
    opts = sys.model.options
    t_max = float(opts.TmaxIC) if t_max is None else float(t_max)
    window = float(opts.dtIC) if window is None else float(window)
    thresh = float(opts.threshIC) if thresh is None else float(thresh)
    saved = A.par.copy()
    am, af, beta, gamma = gen_alpha_parameters(0.0)
    A.par[:4] = (am, af, beta, gamma)
    A.par[8] = opts.CdScaleIC
    st = IW.stat
    h = min(float(opts.dtIC), 1.0) if h is None else float(h)
    st[S_AVALID] = st[S_HJ] = 0.0
    st[S_H] = h
    seg = sys.layout.lines.seg_ptr
    ends = np.concatenate([seg[:-1], seg[1:] - 1]) if seg.size > 1 else np.zeros(0, dtype=np.int64)
    # the rigid blocks (free bodies and rods: position and quaternion) must settle too: a floating body
    # pulled far from its deck pose creeps towards equilibrium while the line tensions barely change
    blocks = [sys.layout.block_slices(j)[0] for j in range(sys.layout.n_blocks)]

    def rigid_state():
        return np.concatenate([sys.y[q] for q in blocks]) if blocks else np.zeros(0)

    prev = None
    prev_rigid = None
    t = 0.0
    try:
        while t < t_max:
            t_next = min(t + window, t_max)  # a window past t_max ends at t_max
            t, status, row, _ = advance_implicit(sys.y, t, t_next, h, A, IW, L, R, P, E, B, sys._motion, W, F, FW,
                                                 MAX_NODE_SPEED, True)
            if status != 0:
                break
            ten = np.linalg.norm(W.T[ends], axis=1) if ends.size else np.zeros(0)
            rig = rigid_state()
            if prev is not None and np.all(np.abs(ten - prev) <= thresh * np.maximum(np.abs(ten), 1.0)) \
                    and np.all(np.abs(rig - prev_rigid) <= thresh):
                break
            prev = ten
            prev_rigid = rig
    finally:
        A.par[:] = saved
    uoff = sys.layout.u_offset
    sys.y[uoff:] = 0.0
    return t


def quasistatic_equilibrium(sys: System, *, tol: float = 1e-7, max_outer: int = 50) -> None:
    """Equilibrium of the floating bodies on quasi-static lines: Newton statics of the bodies with
    the lines' load linearised at their pose, re-linearised until the poses change by less than
    ``tol`` [m, rad]. Fills ``sys.ic_report``."""
    L, R, P, _, B, W, F, FW = sys._kernel_arrays()
    E = sys._kernel_env_ic()
    last = None
    outer = 0
    for outer in range(1, max_outer + 1):
        sys._evaluate()
        sys._qsm.update(sys)
        if not newton_ic(sys, L, R, P, E, B, W, F, FW):
            break
        sys._evaluate()
        poses = np.concatenate([b.pose() for b in sys.bodies])
        if last is not None and np.max(np.abs(poses - last)) < tol:
            sys.ic_report.update(method="newton on quasi-static lines", outer_iterations=outer)
            log.info("initial conditions: floating bodies in equilibrium on quasi-static lines after %d "
                     "linearisations", outer)
            return
        last = poses
    sys.ic_report.update(method="newton on quasi-static lines", outer_iterations=outer, converged=False)
    raise SimulationError("the floating bodies found no equilibrium on the quasi-static lines (Newton statics of "
                          f"the linearised loads did not settle in {outer} linearisations)", time=0.0)
