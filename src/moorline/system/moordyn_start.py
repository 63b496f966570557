"""Start a :class:`~moorline.system.System` from MoorDyn's saved state (the deck's ``fileIC``; a
MoorDyn-C ``SaveState`` file, read by :func:`moorline.io.moordyn_state.read_moordyn_state`).

What MoorDyn-C 2.7 writes for each object (decoded from its source, and checked against the live
``moordyn`` package in tests/conformance/test_oracle_file_ic.py and test_oracle_file_ic_rigid.py):

- **body** (every body, one row of 13): reference-point position (3), orientation quaternion (4, in
  Eigen's coefficient order x, y, z, w), velocity (3) and angular velocity (3, global axes). Only
  free and coupled-pinned bodies hold a state; of a coupled-pinned body the position and velocity
  are the coupling input's and are not read.
- **rod** (every rod, one row of 13): end-A position, quaternion (x, y, z, w), end-A velocity and
  angular velocity. The quaternion rotates the rod's axis as the deck gives it: in global axes for
  rods on the ground, in the body's axes for a rod pinned to a body, *without* the body's deck
  orientation (observed: MoorDyn starts such a rod along its deck axis in global axes whatever the
  body's deck angles). moorline's quaternion rotates the deck axis turned by the body's deck
  orientation Q_b0, so it is MoorDyn's times the conjugate of Q_b0. A free zero-length rod keeps
  its end-A position and velocity (its axis comes from its cables); pinned rods their quaternion
  and angular velocity (end A follows what it is pinned to; MoorDyn writes zeros for its position).
- **point** (every point, one row of 6): position and velocity (read for free points).
- **line**: one row per internal node (N - 1 rows) with the node's position and velocity, then,
  per row, the lift phase of VIV lines (Cl > 0). A viscoelastic or Syrope line has N rows (one per
  segment) and one more column, the stretch [m] of the segment's static branch (moorline's state
  too, spec 3.4); its last row's position and velocity are those of node N (not state, not read).

What MoorDyn does not save, and a run started from its file therefore starts afresh: the running
RMS of VIV motion, the Syrope history (the largest mean tension Tmax; moorline takes the deck's
Tmax0), the radiation states of floating bodies (moorline's own) and the time.
"""

from __future__ import annotations

import logging
from typing import TYPE_CHECKING

import numpy as np

from ..core.layout import quat_product
from ..core.linestates import VIS_ELASTIC
from ..errors import DeckError
from ..io.moordyn_state import read_moordyn_state
from ..model import BodyKind, RodKind

if TYPE_CHECKING:
    from .runtime import System

log = logging.getLogger("moorline")

#: columns of a body or rod row, of a point row, of a line row (before its optional columns)
RIGID_COLS = 13
POINT_COLS = 6
NODE_COLS = 6


def _quat(row: np.ndarray) -> np.ndarray:
    """moorline's (w, x, y, z) from MoorDyn's row, which holds Eigen's coefficients (x, y, z, w)."""
    return np.array([row[6], row[3], row[4], row[5]])


def _line_layout(sys: System, li: int) -> tuple[int, bool, bool]:
    """(segments N, has a stretch state, has VIV phases) of line ``li``."""
    L = sys.layout.lines
    ln = sys.model.lines[li]
    lt = sys.model.line_types[ln.line_type]
    return int(L.seg_ptr[li + 1] - L.seg_ptr[li]), int(L.vis[li]) != VIS_ELASTIC, lt.Cl > 0.0


def start_from_moordyn_state(sys: System, path) -> None:
    """Put MoorDyn's saved state ``path`` into the state of ``sys``: the internal nodes of every
    line, the free points, the free and coupled-pinned bodies, the free and pinned rods (positions
    and velocities), the stretch of viscoelastic and Syrope segments and the lift phases of VIV
    lines (see the module docstring for MoorDyn's layout). Every object is checked before any is
    written; a file that does not fit the deck raises :class:`~moorline.errors.DeckError` naming the
    file and the object."""
    version, objs = read_moordyn_state(path)
    m = sys.model
    nb, nr, npnt, nl = len(m.bodies), len(m.rods), len(m.points), len(m.lines)

    def bad(msg):
        return DeckError(msg, file=str(path), field="fileIC")

    if len(objs) != nb + nr + npnt + nl:
        raise bad(f"MoorDyn {version[0]}.{version[1]} state file with {len(objs)} objects; this deck has {nb} bodies, "
                  f"{nr} rods, {npnt} points and {nl} lines ({nb + nr + npnt + nl} objects). Was it saved from "
                  f"this deck, with a single-step time scheme?")
    rigid = ([("body", i + 1, objs[i], RIGID_COLS) for i in range(nb)]
             + [("rod", k + 1, objs[nb + k], RIGID_COLS) for k in range(nr)]
             + [("point", p + 1, objs[nb + nr + p], POINT_COLS) for p in range(npnt)])
    for what, num, a, cols in rigid:
        if a.shape != (1, cols):
            exp = "position, velocity" if what == "point" else "position, quaternion, velocity, angular velocity"
            raise bad(f"{what} {num}: expected 1 x {cols} values ({exp}), got {a.shape[0]} x {a.shape[1]}")
        if not np.all(np.isfinite(a)):
            raise bad(f"{what} {num}: the state holds a NaN or an infinity")
    lay = sys.layout
    R = lay.rigid
    y = sys.y
    uoff = lay.u_offset
    writes: list[tuple[slice, np.ndarray]] = []  # (where in the state, what): written once all is checked
    for i, body in enumerate(m.bodies):
        j = int(R.body_blk[i])
        if j < 0:
            continue  # fixed and coupled bodies hold no state
        a = objs[i][0]
        Q = _quat(a)
        if not np.linalg.norm(Q) > 0.5:
            raise bad(f"body {i + 1}: the orientation quaternion {Q.tolist()} is not a rotation")
        q, u = lay.block_slices(j)
        if body.kind == BodyKind.FREE:
            writes += [(slice(q.start, q.start + 3), a[:3]), (slice(u.start, u.start + 3), a[7:10])]
        writes += [(slice(q.start + 3, q.stop), Q), (slice(u.start + 3, u.stop), a[10:13])]
    for k, rod in enumerate(m.rods):
        a = objs[nb + k][0]
        if R.rod_row[k] >= 0:  # free zero-length rod: 3 DOF
            o = 3 * int(R.rod_row[k])
            writes += [(slice(o, o + 3), a[:3]), (slice(uoff + o, uoff + o + 3), a[7:10])]
        j = int(R.rod_blk[k])
        if j < 0:
            continue
        Q = _quat(a)
        if not np.linalg.norm(Q) > 0.5:
            raise bad(f"rod {k + 1}: the orientation quaternion {Q.tolist()} is not a rotation")
        if rod.kind == RodKind.BODY_PINNED:
            Qb = R.body_Q0[int(R.rod_body[k])]
            Q = quat_product(Q, np.array([Qb[0], -Qb[1], -Qb[2], -Qb[3]]) / float(np.dot(Qb, Qb)))
        q, u = lay.block_slices(j)
        if rod.kind == RodKind.FREE:
            writes += [(slice(q.start, q.start + 3), a[:3]), (slice(u.start, u.start + 3), a[7:10])]
        writes += [(slice(q.start + 3, q.stop), Q), (slice(u.start + 3, u.stop), a[10:13])]
    points = np.vstack([objs[nb + nr + p] for p in range(npnt)]) if npnt else np.zeros((0, 6))
    L = lay.lines
    xo = lay.xs_offset
    lines = []
    for li in range(nl):
        a = objs[nb + nr + npnt + li]
        N, stretch, viv = _line_layout(sys, li)
        rows = N if stretch else N - 1
        cols = NODE_COLS + int(viv) + int(stretch)
        if a.shape != (rows, cols) and not (rows == 0 and a.size == 0):
            extra = ", then the lift phase" if viv else ""
            extra += ", then the stretch of each segment's static branch (one row a segment)" if stretch else ""
            raise bad(f"line {li + 1}: expected {rows} x {cols} values (position and velocity of each internal "
                      f"node{extra}), got {a.shape[0]} x {a.shape[1]}")
        if not np.all(np.isfinite(a)):
            raise bad(f"line {li + 1}: the state holds a NaN or an infinity")
        n0 = int(L.node_ptr[li])
        if viv:
            for i in range(1, N):
                writes.append((slice(xo + int(L.node_xs[n0 + i]), xo + int(L.node_xs[n0 + i]) + 1), a[i - 1, 6:7]))
        if stretch:
            c = NODE_COLS + int(viv)
            for s in range(N):
                x = xo + int(L.seg_xs[int(L.seg_ptr[li]) + s])
                writes.append((slice(x, x + 1), a[s, c:c + 1]))
        # MoorDyn saves the internal nodes: the ends are not state
        lines.append(np.pad(a[:N - 1, :NODE_COLS], ((1, 1), (0, 0))))
    sys._put_state([a[:, :3] for a in lines], [a[:, 3:] for a in lines], points[:, :3], points[:, 3:])
    for where, v in writes:
        y[where] = v
    sys.ic_report["file_ic"] = str(path)
    log.info("started from MoorDyn's saved state %s (MoorDyn %d.%d)", path, *version)
