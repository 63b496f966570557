"""Line failures: line ends that let go of their point or rod end during a run (MoorDyn's FAILURE
section and its BreakLine call).

A failure releases some line ends from an attachment (a point, possibly on a body, or a rod end)
and joins them to one new free point that starts where the attachment was, with its velocity. The
new point has no mass, volume, drag or added mass of its own: the released end nodes carry their
half-segment masses as every line end on a free point does (MoorDyn's documented failure; with
``new_point="copy"`` it copies the old point's mass, volume, CdA and Ca as MoorDyn-C 2.7's
``BreakLine`` does). The run goes on with the new point numbered after the others.

How it meets the compiled time loop: the loop is never asked to check anything. A time-triggered
failure ends the compiled interval at its time exactly (the loop runs up to it, the system is
rewired, the loop resumes), and a tension-triggered one is checked between compiled intervals:
after every coupling step (``System.step``) or output sample, as MoorDyn checks failures after
every coupling step; ``System.failure_check_interval`` makes the checks finer during
``advance_to``. Rewiring rebuilds the layout for the new topology and carries everything over: the
state (mapped row by row: the new point's row is added), the line histories, the seabed friction
state, the water kinematics, the floating-body work; the time scheme restarts (a multi-step scheme
starts up again, the implicit solver refactors), as at any discontinuity.
"""

from __future__ import annotations

import dataclasses
import logging
import math
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from ..core.linestates import LINE_HISTORY
from ..model import Attachment, Failure, Point, PointKind
from ..model.system import check_failure
from .views import PointView

if TYPE_CHECKING:
    from .runtime import System

log = logging.getLogger("moorline")

#: what the new free point of a failure is: "massless" (MoorDyn's documented failure: no mass,
#: volume, drag or added mass of its own) or "copy" (MoorDyn-C 2.7's BreakLine: a copy of the old
#: point's mass, volume, CdA and Ca)
NEW_POINT_MODES = ("massless", "copy")


@dataclass
class FailureEvent:
    """A failure of a running system: what it is and, once it happened, when and how."""

    failure: Failure
    #: time it happened [s], None while pending
    time: float | None = None
    #: what triggered it: "time", "tension" or "call" (System.break_line)
    trigger: str = ""
    #: load through the connection when it happened [N]
    load: float = math.nan
    #: 0-based index of the new free point holding the released ends
    point: int = -1
    #: the lines released (those of ``failure.lines`` still on the attachment when it happened)
    released: list[int] = dataclasses.field(default_factory=list)
    #: what the new point was ("massless" or "copy", see :data:`NEW_POINT_MODES`)
    new_point: str = ""
    #: the new point's deck position (where the attachment was when it happened) [m]
    at: np.ndarray | None = None

    @property
    def pending(self) -> bool:
        return self.time is None


def parse_attachment(what, model) -> Attachment:
    """An :class:`Attachment` from a deck word (``'3'``, ``'P3'``, ``'R1A'``), a 1-based point number
    (int, as MoorDyn numbers points) or an Attachment."""
    if isinstance(what, Attachment):
        return what
    from ..io.columns import attachment_of

    class _Counts:
        n_points = len(model.points)
        n_rods = len(model.rods)

    try:
        return attachment_of(str(what), _Counts)
    except Exception as e:  # BadField: say what was expected
        raise ValueError(f"attachment {what!r}: expected {e}") from None


def connection_load(sys: System, att: Attachment, lines) -> float:
    """Magnitude of the vector sum of the end tensions (T + Td of the end segment) that ``lines``
    (0-based) put on attachment ``att`` [N], at the last evaluation."""
    W = sys.work
    L = sys.layout.lines
    f = np.zeros(3)
    for li in lines:
        ln = sys.model.lines[li]
        if ln.end_a == att:
            s = int(L.seg_ptr[li])
            f += W.T[s] + W.Td[s]
        if ln.end_b == att:
            s = int(L.seg_ptr[li + 1]) - 1
            f -= W.T[s] + W.Td[s]
    return float(np.linalg.norm(f))


def _kinematics(sys: System, att: Attachment) -> tuple[np.ndarray, np.ndarray]:
    W = sys.work
    if att.kind == "point":
        return W.pr[att.index].copy(), W.pv[att.index].copy()
    e = 0 if att.end == "A" else 1
    return W.rodr[att.index, e].copy(), W.rodv[att.index, e].copy()


def _copy_leading(old: np.ndarray, new: np.ndarray) -> None:
    """Copy ``old`` into ``new`` where their shapes agree, or into the leading rows of ``new`` when
    it has more rows (arrays over points, which gained one)."""
    if old.shape == new.shape:
        new[...] = old
    elif old.ndim == new.ndim and old.ndim > 0 and old.shape[1:] == new.shape[1:] and new.shape[0] > old.shape[0]:
        new[:old.shape[0]] = old


def release(sys: System, att: Attachment, lines, *, new_point: str = "massless", at=None) -> int:
    """Detach the ends of ``lines`` (0-based) on ``att`` and join them to a new free point; return its
    0-based index. The system is rebuilt for the new topology with its state carried over.
    ``at``: the new point's deck position [m] (default: where the attachment is now)."""
    if new_point not in NEW_POINT_MODES:
        raise ValueError(f"new_point must be one of {NEW_POINT_MODES}, got {new_point!r}")
    if sys._qsm is not None:
        raise NotImplementedError("line failures in the quasi-static mooring mode (mooring='quasistatic') are not "
                                  "supported: run the dynamic mooring")
    model = sys.model
    r, v = _kinematics(sys, att)
    props = {}
    if new_point == "copy" and att.kind == "point":
        old = model.points[att.index]
        props = {"m": old.m, "V": old.V, "CdA": old.CdA, "Ca": old.Ca}
    point = Point(PointKind.FREE, r if at is None else np.asarray(at, dtype=float), **props)
    k = len(model.points)
    new_att = Attachment("point", k)
    new_lines = list(model.lines)
    for li in lines:
        ln = model.lines[li]
        new_lines[li] = dataclasses.replace(ln, end_a=new_att if ln.end_a == att else ln.end_a,
                                            end_b=new_att if ln.end_b == att else ln.end_b)
    new_model = dataclasses.replace(model, points=[*model.points, point], lines=new_lines, failures=[])
    _rebuild(sys, new_model)
    # the new point starts where the attachment was, with its velocity
    lay = sys.layout
    row = int(lay.points.row[k])
    sys.y[3 * row:3 * row + 3] = r
    sys.y[lay.u_offset + 3 * row:lay.u_offset + 3 * row + 3] = v
    sys._reset_scheme()
    sys._evaluate()
    return k


def _rebuild(sys: System, model) -> None:
    """Give ``sys`` the layout of ``model`` (the same lines, rods and bodies, points added at the
    end) with its state and histories carried over."""
    old_lay, old_y, old_rows, old_work = sys.layout, sys.y, sys.state_rows(), sys.work
    fresh = type(sys)(model, dtM=sys.dtM, scheme=sys._scheme_name, loads_at=sys.loads_at, _floating=sys._floating)
    lay = fresh.layout
    # the sea, its excitation and the seabed state are those of the running system (a random sea is
    # not drawn again); external water kinematics gain the new points' rows
    env, env_ic = old_lay.env, old_lay.env_ic
    n_new = len(lay.points.kind) - len(old_lay.points.kind)
    K = env.water
    if K.U_ext.shape[0]:
        at = old_work.r.shape[0] + old_work.rn_r.shape[0] + len(old_lay.points.kind)
        K = K._replace(U_ext=np.insert(K.U_ext, at, np.zeros((n_new, 3)), axis=0),
                       Ud_ext=np.insert(K.Ud_ext, at, np.zeros((n_new, 3)), axis=0))
        env = env._replace(water=K)
    lay.env, lay.env_ic = env, env_ic
    lay.seabed = old_lay.seabed
    for name in LINE_HISTORY:
        getattr(lay.lines, name)[...] = getattr(old_lay.lines, name)
    # the state, row by row (the new points' rows stay zero here), then the radiation and line states
    new_index = {r: i for i, r in enumerate(fresh.state_rows())}
    y = fresh.y
    nr0, nr1 = old_lay.n_rows, lay.n_rows
    for i, label in enumerate(old_rows):
        j = new_index[label]
        if i < nr0:
            y[3 * j:3 * j + 3] = old_y[3 * i:3 * i + 3]
            uo, un = old_lay.u_offset + 3 * i, lay.u_offset + 3 * j
            y[un:un + 3] = old_y[uo:uo + 3]
        else:
            qo, uo = old_lay.block_slices(i - nr0)
            qn, un = lay.block_slices(j - nr1)
            y[qn] = old_y[qo]
            y[un] = old_y[uo]
    y[lay.z_offset:] = old_y[old_lay.z_offset:]
    work = fresh.work
    for name in work._fields:
        if name != "features":
            _copy_leading(getattr(old_work, name), getattr(work, name))
    sys.model = model
    sys.full_model = model
    sys.layout = lay
    sys.work = work
    sys.y = y
    sys._S = fresh._S
    sys._dy_eval = fresh._dy_eval
    sys._imp = None
    sys._features_key = None
    sys._drop_step_plan()  # (it holds the old layout, state and Work arrays)
    sys.points += [PointView(sys, i) for i in range(len(sys.points), len(model.points))]


def fire(sys: System, ev: FailureEvent, trigger: str, *, new_point: str) -> None:
    """Let failure ``ev`` happen now: release its lines that are still on its attachment."""
    f = ev.failure
    att = f.attachment
    lines = [li for li in f.lines if att in (sys.model.lines[li].end_a, sys.model.lines[li].end_b)]
    ev.load = connection_load(sys, att, lines) if lines else 0.0
    ev.time = sys.t
    ev.trigger = trigger
    ev.released = lines
    ev.new_point = new_point
    sys._drop_step_plan()  # (one pending failure fewer: step() may take its fast path again)
    if not lines:
        log.warning("failure at %s at t = %.6g s: lines %s are no longer attached there; nothing to release", att,
                    sys.t, ", ".join(str(li + 1) for li in f.lines))
        return
    ev.point = release(sys, att, lines, new_point=new_point)
    ev.at = sys.model.points[ev.point].r
    log.info("line failure at t = %.6g s (%s): line%s %s let go of %s (load %.6g N); their ends are free point %d",
             sys.t, trigger, "s" if len(lines) > 1 else "", ", ".join(str(li + 1) for li in lines), att, ev.load,
             ev.point + 1)


def new_event(sys: System, att, lines, time: float, tension: float) -> FailureEvent:
    """A checked :class:`FailureEvent` for ``lines`` (0-based) on ``att`` (see :func:`parse_attachment`)."""
    f = Failure(parse_attachment(att, sys.model), [int(i) for i in np.atleast_1d(lines)], float(time),
                float(tension))
    check_failure(sys.model, f, "failure")
    return FailureEvent(f)


def to_record(ev: FailureEvent) -> dict:
    """A JSON-ready record of ``ev`` (for checkpoints)."""
    f = ev.failure
    return {"attachment": [f.attachment.kind, f.attachment.index, f.attachment.end], "lines": f.lines,
            "time": f.time if math.isfinite(f.time) else None,
            "tension": f.tension if math.isfinite(f.tension) else None, "happened": ev.time, "trigger": ev.trigger,
            "load": ev.load if math.isfinite(ev.load) else None, "point": ev.point, "released": ev.released,
            "new_point": ev.new_point,
            "at": None if ev.point < 0 else [float(v) for v in ev.at]}


def replay(sys: System, records: list[dict]) -> None:
    """Give ``sys`` (built from the deck of a checkpoint) the failures of ``records``: the ones that
    had happened are applied again (the topology only: the checkpoint's state follows)."""
    events = []
    for r in records:
        att = Attachment(r["attachment"][0], int(r["attachment"][1]), r["attachment"][2])
        f = Failure(att, list(r["lines"]), math.inf if r["time"] is None else r["time"],
                    math.inf if r["tension"] is None else r["tension"])
        ev = FailureEvent(f, r["happened"], r["trigger"], math.nan if r["load"] is None else r["load"], r["point"],
                          list(r["released"]), r["new_point"], None if r["at"] is None else np.array(r["at"]))
        if ev.time is not None and ev.released and len(sys.model.points) <= ev.point:
            release(sys, att, ev.released, new_point=ev.new_point, at=r["at"])
        events.append(ev)
    sys.failures = events
    sys._drop_step_plan()
