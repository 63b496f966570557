"""The coupling step's fast path (:mod:`moorline.system.stepplan`) against its general path.

``System.step`` keeps the compiled call of its time loop, the argument tuple and the force gather
ready between calls and makes them again only when something they hold is replaced. Every test
drives two systems built alike through the same calls: ``ref`` through ``_step_general`` (the path
``step`` takes where the fast path does not apply, main's code before the fast path existed) and
``sys`` through ``step``, and requires the same forces, state and time bit for bit (``==``, not a
tolerance: the two paths must run the same arithmetic), with each event that replaces or changes
what the plan holds in between: the layout's arrays or ``work`` replaced, failures added, pending,
fired, a line broken, ``set_state``, a checkpoint load, ``advance_to`` on another trajectory,
changes of ``dt``, ``dtM`` and ``loads_at`` (both of whose values have a fast path), inputs of
other types and sizes. Not timed (the cost of a call is in benchmarks/bench_step_call.py).
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from moorline.core.features import STICKSLIP, Features
from moorline.core.integrate import FINAL_END, FINAL_LAST_STAGE, FINAL_NONE
from moorline.core.layout import step_motion
from moorline.errors import SimulationError
from moorline.io import read_deck_text
from moorline.system import System, runtime
from moorline.system.stepplan import ForceGather, make_plan

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "catenary_3line" / "catenary_3line.dat"
DT = 0.01


def _pair(**kw) -> tuple[System, System]:
    ref = System.from_file(EXAMPLE, **kw)
    sys_ = System.from_file(EXAMPLE, **kw)
    ref.init()
    sys_.init()
    return ref, sys_


def _x(s: System, k: int) -> tuple[np.ndarray, np.ndarray]:
    """The coupled DOFs at call ``k``: the fairleads surging 1 m (10 s period) and heaving a little."""
    x0 = s.deck_coupled_positions()
    d = np.tile([1.0, 0.0, 0.2], 3)
    x = x0 + d * math.sin(2 * math.pi * k * DT / 10.0)
    xd = d * (2 * math.pi / 10.0) * math.cos(2 * math.pi * k * DT / 10.0)
    return x, xd


def _same(ref: System, sys_: System, fr, fs, what: str) -> None:
    assert np.array_equal(fr, fs), f"{what}: forces differ"
    assert np.array_equal(ref.y, sys_.y), f"{what}: state differs"
    assert ref.t == sys_.t, f"{what}: time differs"
    # and everything the views and outputs read (tensions, node forces, curvatures, ...)
    for name in ref.work._fields:
        a, b = getattr(ref.work, name), getattr(sys_.work, name)
        if isinstance(a, np.ndarray):
            assert np.array_equal(a, b, equal_nan=True), f"{what}: Work.{name} differs"


def _both(ref: System, sys_: System, x, xd, t, dt, what: str, out_ref=None, out_sys=None):
    fr = ref._step_general(x, xd, t, dt, out_ref)
    fs = sys_.step(x, xd, t, dt, out=out_sys)
    _same(ref, sys_, fr, fs, what)
    return fs


def _count_general(s: System) -> list:
    """Count the calls of ``s.step`` that take the general path (appended to the list returned)."""
    calls = []
    general = s._step_general

    def counted(*args):
        calls.append(args[2])
        return general(*args)

    s._step_general = counted
    return calls


def _run(ref, sys_, k0, n, t0=None, what=""):
    out_r, out_s = np.empty(ref.n_coupled_dof), np.empty(sys_.n_coupled_dof)
    t = ref.t if t0 is None else t0
    for k in range(k0, k0 + n):
        x, xd = _x(ref, k)
        _both(ref, sys_, x, xd, t, DT, f"{what} call {k}", out_r, out_s)
        t += DT
    return t


def test_fast_path_bitwise_over_many_calls_and_inputs():
    ref, sys_ = _pair()
    general = _count_general(sys_)
    t = _run(ref, sys_, 0, 150, 0.0, "surge")
    p = sys_._plan
    assert p is not None and p.fn is not None, "the fast path did not apply to a plain RK2 system"
    assert general == [], "step() took the general path"
    # the plan was made once and kept for all those calls
    t = _run(ref, sys_, 150, 20, t, "again")
    assert sys_._plan is p
    # inputs the fast path hands to the general checks: lists, integer arrays, (1, n) arrays, None
    x, xd = _x(ref, 170)
    cases = [(list(x), list(xd)), (x.astype(np.int64), np.zeros(9, dtype=np.int64)), (x[None, :], xd[None, :]),
             (None, xd), (x, None), (None, None), (x.astype(np.float32), xd)]
    for i, (a, b) in enumerate(cases):
        _both(ref, sys_, a, b, t, DT, f"input case {i}")
        t += DT
    assert general == []
    # out=None allocates; an out of another size or type is the general path's business
    _both(ref, sys_, x, xd, t, DT, "out None")
    t += DT
    big_r, big_s = np.full(12, 7.0), np.full(12, 7.0)
    _both(ref, sys_, x, xd, t, DT, "out of 12 values", big_r, big_s)
    assert np.array_equal(big_r, big_s) and big_s[-1] == 7.0
    assert len(general) == 1
    t += DT
    # a strided view of 9 values is an out of the fast path's kind (take writes through a copy)
    wide_r, wide_s = np.full(18, 7.0), np.full(18, 7.0)
    fs = _both(ref, sys_, x, xd, t, DT, "strided out", wide_r[::2], wide_s[::2])
    assert np.array_equal(wide_r, wide_s) and np.all(wide_s[1::2] == 7.0) and fs.base is wide_s
    t += DT
    # other steps: longer, shorter, not a multiple of dtM, zero (evaluation only), negative
    for dt in (0.013, 0.002, 0.0005, 0.05, 0.0, -1.0, 1e-310, DT):
        fr = ref._step_general(x, xd, t, dt, None)
        fs = sys_.step(x, xd, t, dt)
        _same(ref, sys_, fr, fs, f"dt {dt}")
        t += max(dt, 0.0)
    assert sys_._plan is p  # none of this replaced what the plan holds
    assert len(general) == 1 + 3  # (dt 0, -1 and 1e-310)


def test_wrong_sizes_raise_the_same_error():
    ref, sys_ = _pair()
    x, xd = _x(ref, 0)
    _both(ref, sys_, x, xd, 0.0, DT, "first")
    for bad_x, bad_xd, name in ((x[:8], xd, "x"), (x, np.zeros(10), "xd"), (np.zeros((3, 4)), xd, "x"),
                                (1.0, xd, "x")):
        msgs = []
        for path in (lambda a, b: ref._step_general(a, b, DT, DT, None), lambda a, b: sys_.step(a, b, DT, DT)):
            with pytest.raises(ValueError, match=f"^{name} has .* values; the system has 9 coupled DOF") as e:
                path(bad_x, bad_xd)
            msgs.append(str(e.value))
        assert msgs[0] == msgs[1]
    # after the errors both go on alike (the fast path's plan is still the one made first)
    p = sys_._plan
    _run(ref, sys_, 1, 5, DT, "after errors")
    assert sys_._plan is p


def test_replaced_arrays_make_the_plan_again(monkeypatch):
    ref, sys_ = _pair()
    t = _run(ref, sys_, 0, 10, 0.0)
    p0 = sys_._plan
    # a kernel array of the layout replaced (same values, a new object): the plan must not keep the old
    for s in (ref, sys_):
        s.layout.env = s.layout.env._replace()
    t = _run(ref, sys_, 10, 5, t, "env replaced")
    p1 = sys_._plan
    assert p1 is not p0 and p1.E is sys_.layout.env and p1.fn is not None
    # work replaced
    for s in (ref, sys_):
        s.work = s.work._replace()
    t = _run(ref, sys_, 15, 5, t, "work replaced")
    p2 = sys_._plan
    assert p2 is not p1 and p2.work is sys_.work
    # the state vector replaced (a copy)
    for s in (ref, sys_):
        s.y = s.y.copy()
    t = _run(ref, sys_, 20, 5, t, "y replaced")
    assert sys_._plan is not p2 and sys_._plan.y is sys_.y
    # dtM changed: the plan calls the time loop with the new step
    p3 = sys_._plan
    for s in (ref, sys_):
        s.dtM = 0.001
    t = _run(ref, sys_, 25, 5, t, "dtM changed")
    assert sys_._plan is not p3 and sys_._plan.tail[0] == 0.001
    # work given other features by _kernel_arrays: the plan is dropped there (features_of is made to
    # answer otherwise once, then the system's own features come back; nothing of the kind is stepped,
    # which would compile the time loop for it)
    p4 = sys_._plan
    own = sys_.work.features
    monkeypatch.setattr(runtime, "features_of", lambda lay, scheme: Features.of(STICKSLIP))
    sys_._features_key = None
    sys_._kernel_arrays()
    assert sys_._plan is None and sys_.work.features == Features.of(STICKSLIP)
    monkeypatch.undo()
    sys_._plan = p4
    sys_._features_key = None
    sys_._kernel_arrays()
    assert sys_._plan is None and sys_.work.features == own
    _run(ref, sys_, 30, 5, t, "features")
    assert sys_._plan is not p4 and sys_._plan.fn is not None and sys_._plan.work is sys_.work


def test_loads_at_last_stage_and_the_modes_without_a_fast_path():
    ref, sys_ = _pair(loads_at="last_stage")  # MoorDyn's convention (and moorline.moordyn's)
    general = _count_general(sys_)
    t = _run(ref, sys_, 0, 30, 0.0, "last_stage")
    assert general == []
    p = sys_._plan
    assert p.fn is not None and p.tail[-1] == FINAL_LAST_STAGE
    # the loads are the last stage's, the positions those reached: not those of an evaluation there
    end = System.from_file(EXAMPLE)
    end.init()
    te = 0.0
    for k in range(30):
        end.step(*_x(end, k), te, DT)
        te += DT  # (as _run counts time)
    assert np.array_equal(end.y, sys_.y) and not np.array_equal(end.work.T, sys_.work.T)
    # a step too short to take one: no stage, the loads of the evaluation at the state
    _both(ref, sys_, *_x(ref, 30), t, 1e-14, "no step taken")
    t += 1e-14
    # loads_at changed on a running system: the plan follows
    for s in (ref, sys_):
        s.loads_at = "end"
    t = _run(ref, sys_, 31, 5, t, "end")
    assert sys_._plan is not p and sys_._plan.tail[-1] == FINAL_END
    for s in (ref, sys_):
        s.loads_at = "last_stage"
    _run(ref, sys_, 36, 5, t, "last_stage again")
    assert sys_._plan.tail[-1] == FINAL_LAST_STAGE
    # quasi-static lines: no plan (nothing compiled to find that out)
    qs = System.from_file(EXAMPLE)
    qs._qsm = object()  # (what mooring="quasistatic" sets; this deck has no line left dynamic for that mode)
    assert make_plan(qs).fn is None


def test_set_state_advance_to_and_checkpoint(tmp_path):
    ref, sys_ = _pair()
    t = _run(ref, sys_, 0, 20, 0.0)
    p = sys_._plan
    # set_state writes in place: the plan stays
    lines = [ln.node_positions() + np.array([0.0, 0.0, 0.01]) for ln in ref.lines]
    for s in (ref, sys_):
        s.set_state(line_positions=lines)
    t = _run(ref, sys_, 20, 10, t, "after set_state")
    assert sys_._plan is p
    # advance_to on a trajectory of its own, then steps again
    x, xd = _x(ref, 30)
    mo = step_motion(x, xd, t, 1.0)
    for s in (ref, sys_):
        s.advance_to(t + 0.1, mo)
    t += 0.1
    _same(ref, sys_, ref.coupled_forces(), sys_.coupled_forces(), "advance_to")
    t = _run(ref, sys_, 31, 10, t, "after advance_to")
    assert sys_._plan is p
    # a checkpoint: the system that loads it continues as the one that went on, bit for bit
    sys_.save(tmp_path / "c.npz")
    t_save = t
    t = _run(ref, sys_, 41, 10, t, "past the checkpoint")
    f_ref, y_ref = ref.coupled_forces(), ref.y.copy()
    sys_.load(tmp_path / "c.npz")
    assert sys_._plan is None and sys_.t == t_save
    out = np.empty(9)
    for k in range(41, 51):
        x, xd = _x(ref, k)
        sys_.step(x, xd, t_save + (k - 41) * DT, DT, out=out)
    assert np.array_equal(out, f_ref) and np.array_equal(sys_.y, y_ref)
    assert sys_._plan.fn is not None
    # and into a fresh system of the same deck
    fresh = System.from_file(EXAMPLE)
    fresh.load(tmp_path / "c.npz")
    for k in range(41, 51):
        x, xd = _x(ref, k)
        fresh.step(x, xd, t_save + (k - 41) * DT, DT, out=out)
    assert np.array_equal(out, f_ref) and np.array_equal(fresh.y, y_ref)


def test_failures_pending_fired_and_broken_lines():
    ref, sys_ = _pair()
    t = _run(ref, sys_, 0, 10, 0.0)
    assert sys_._plan.fn is not None
    # a failure at the fairlead of line 1 inside the step from 0.15 to 0.16: pending on a time, so
    # the calls before it keep the fast path, and the one it happens in is the general path's
    for s in (ref, sys_):
        s.add_failure(4, [0], time=0.155)
    assert sys_._plan is None
    general = _count_general(sys_)
    t = _run(ref, sys_, 10, 5, t, "pending")
    assert general == []
    p = sys_._plan
    assert p.fn is not None and len(p.pending) == 1
    assert not sys_._none_due(p, t, DT) and sys_._none_due(p, t - DT, DT)
    assert not sys_._none_due(p, 0.0, 1e-13)  # (no step taken: _advance would not call the loop at all)
    t = _run(ref, sys_, 15, 2, t, "fired")
    assert len(general) == 1  # the call it happened in
    assert [ev.pending for ev in sys_.failures] == [False]
    assert len(sys_.points) == 7 and sys_._plan.layout is sys_.layout
    t = _run(ref, sys_, 17, 20, t, "line 1 free at its fairlead")
    assert sys_._plan.fn is not None
    assert sys_.coupled_forces()[:3].tolist() == [0.0, 0.0, 0.0]  # nothing holds point 4 any more
    # a tension trigger that is never reached: pending all along, the general path all along
    for s in (ref, sys_):
        s.add_failure(5, [1], tension=1e12)
    t = _run(ref, sys_, 37, 5, t, "tension pending")
    assert sys_._plan.fn is None
    # break_line (MoorDyn's BreakLine) on top of the pending one
    for s in (ref, sys_):
        s.break_line(2, "A")
    assert sys_._plan is None
    t = _run(ref, sys_, 42, 5, t, "after break_line")
    assert len(sys_.points) == 8
    # failures replaced by a list without pending ones: the fast path again
    for s in (ref, sys_):
        s.failures = [ev for ev in s.failures if not ev.pending]
    _run(ref, sys_, 47, 5, t, "no pending")
    assert sys_._plan.fn is not None and sys_._plan.layout is sys_.layout


def test_instability_raises_the_same_error():
    ref, sys_ = _pair()
    t = _run(ref, sys_, 0, 3, 0.0)
    for s in (ref, sys_):
        s.dtM = 0.5  # far beyond the axial stability limit (about 3 ms)
    errs = []
    for f in (lambda: ref._step_general(*_x(ref, 3), t, 2.0, None), lambda: sys_.step(*_x(ref, 3), t, 2.0)):
        with pytest.raises(SimulationError, match="simulation unstable at t = ") as e:
            f()
        errs.append(str(e.value))
    assert errs[0] == errs[1]
    assert sys_._plan.fn is not None  # it was the fast path that stopped
    assert ref.t == sys_.t and np.array_equal(ref.y, sys_.y, equal_nan=True)


BODY_AND_POINT = """\
--------------------- MoorDyn Input File ------------------------------------
fast path test: a coupled body, a coupled pinned rod and a coupled point, each moored
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
main       0.05    20.0       1.0E7      -0.8        0          1.2    1.0    0.2     0.0
---------------------- ROD TYPES ------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
pole          0.3      50.0      0.8    1.0     0.0      0.0
----------------------- BODIES ------------------------------------------------------
ID   Attachment    X0     Y0     Z0     r0      p0     y0     Mass   CG*     I*      Volume   CdA*   Ca*
(#)     (-)        (m)    (m)    (m)   (deg)   (deg)  (deg)   (kg)   (m)   (kg-m^2)  (m^3)   (m^2)  (-)
1     coupled      0.00   0.00   0.00   0.00   0.00   0.00     0.0    0.0   0.0       0.0     0.00   0.00
---------------------- RODS ----------------------------------------
ID   RodType  Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs  RodOutputs
(#)  (name)   (#/key)     (m)   (m)   (m)   (m)   (m)   (m)  (-)      (-)
1    pole     CoupledPinned  30.0  0.0   -2.0  30.0  0.0   -8.0  3   -
---------------------- POINTS --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -60     0       -40     0      0       0      0
2     Fixed     60      20      -40     0      0       0      0
3     Fixed     0       -60     -40     0      0       0      0
4     Body1     -2      0       -5      0      0       0      0
5     Coupled   0       -20     -5      0      0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     main       1        4        70.0      8       -
2     main       2        R1B      45.0      8       -
3     main       3        5        50.0      8       -
---------------------- OPTIONS -----------------------------------------
0.001         dtM
RK2           tScheme
1025.0        WtrDnsty
40            WtrDpth
0             TmaxIC
------------------------- need this line --------------------------------------
"""


def test_body_rod_and_point_gathered_in_coupled_order():
    model = read_deck_text(BODY_AND_POINT)
    ref, sys_ = System(model), System(read_deck_text(BODY_AND_POINT))
    ref.init()
    sys_.init()
    assert [sl[0] for sl in sys_.coupled_slots] == ["body", "rod", "point"]
    n = sys_.n_coupled_dof
    assert n == 6 + 3 + 3
    x0 = sys_.deck_coupled_positions()
    d = np.zeros(n)
    d[[0, 6, 9]] = 1.0  # every object surges
    t = 0.0
    out_r, out_s = np.empty(n), np.empty(n)
    for k in range(40):
        x = x0 + 0.5 * math.sin(0.5 * k * DT) * d
        _both(ref, sys_, x, 0.25 * math.cos(0.5 * k * DT) * d, t, DT, f"call {k}", out_r, out_s)
        t += DT
    p = sys_._plan
    assert p.fn is not None and p.take is None and len(p.gather.segments) == 3
    assert np.all(out_s[[0, 6, 9]] != 0.0)


def test_force_gather_matches_the_loop():
    """Every kind, pinned (3 of 6 columns) and full objects, against coupled_forces' loop."""
    rng = np.random.default_rng(1)

    @dataclasses.dataclass
    class W:
        b6F: np.ndarray
        rod6F: np.ndarray
        pF: np.ndarray

    w = W(rng.normal(size=(4, 6)), rng.normal(size=(3, 6)), rng.normal(size=(5, 3)))
    slots = [("body", 3, 6, 0), ("body", 1, 3, 6), ("rod", 2, 3, 9), ("rod", 0, 6, 12), ("point", 4, 3, 18),
             ("point", 0, 3, 21)]
    want = np.concatenate([getattr(w, System._FORCE_FIELD[kind])[i, :k] for kind, i, k, _ in slots])
    g = ForceGather(slots, w, 24)
    got = np.full(24, np.nan)
    assert g(got) is got and np.array_equal(got, want)
    only_points = ForceGather([("point", 2, 3, 0), ("point", 1, 3, 3)], w, 6)
    assert only_points.whole
    assert np.array_equal(only_points(np.empty(6)), np.concatenate([w.pF[2], w.pF[1]]))
    with pytest.raises(ValueError, match="consecutive"):
        ForceGather([("point", 0, 3, 0), ("body", 0, 6, 3), ("point", 1, 3, 9)], w, 12)


VIV = Path(__file__).resolve().parents[3] / "shared" / "public_decks" / "FloatingArrayDesign+MoorDyn" / "tests" / \
    "Mooring" / "viv" / "viv.txt"


#: the loads MoorDyn's convention keeps from a step's last stage (core.integrate._keep_stage_loads)
STAGE_LOADS = ("T", "Td", "seg_len", "seg_ldot", "F", "Fhyd", "Fbed", "W", "kurv", "pF", "pa")


def test_last_stage_is_the_last_stages_loads_with_the_rest_at_the_end():
    """What loads_at='last_stage' means, checked against the two evaluations it combines rather
    than against the general path (which runs the same kernel): after the same calls, its state
    is that of loads_at='end' bit for bit; its stage loads are those the step's last stage left
    (a system whose time loop ends with no evaluation, FINAL_NONE); everything else in Work
    (positions, velocities, accelerations, water kinematics, mass matrices, ...) is that of the
    evaluation at the state reached (loads_at='end')."""
    last = System.from_file(EXAMPLE, loads_at="last_stage")
    end = System.from_file(EXAMPLE)
    none = System.from_file(EXAMPLE)
    for s in (last, end, none):
        s.init()
    t = 0.0
    for k in range(12):
        for s in (last, end, none):
            s.step(*_x(s, k), t, DT)
            if s is none and k == 0:  # the kept call, made to end without an evaluation
                p = s._plan
                assert p.tail[-1] == FINAL_END
                p.tail = p.tail[:-1] + (FINAL_NONE,)
        t += DT
    assert np.array_equal(last.y, end.y) and np.array_equal(last.y, none.y)
    assert not np.array_equal(end.work.T, none.work.T)  # (so that the comparisons below can fail)
    for name in last.work._fields:
        a = getattr(last.work, name)
        if not isinstance(a, np.ndarray) or name == "kept":
            continue
        ref = getattr(none.work if name in STAGE_LOADS else end.work, name)
        assert np.array_equal(a, ref), f"Work.{name}"


def test_last_stage_with_viv_keeps_the_remembered_accelerations():
    """MoorDyn's viv.txt (a riser in a current with VIV, RK4 at 0.1 ms): with loads_at='last_stage'
    the evaluation at the state reached must leave VIV's remembered accelerations and the line
    states' history as the step left them, as the general path does."""
    if not VIV.is_file():
        pytest.skip(f"public deck {VIV} not available")
    from moorline.io import read_deck

    pair = []
    for _ in range(2):
        model = read_deck(VIV)
        model.options.TmaxIC = 0.0
        s = System(model, loads_at="last_stage")
        s.init()
        pair.append(s)
    ref, sys_ = pair
    assert sys_.work.features.line_states and np.any(sys_.layout.lines.viv[:, 0] > 0)
    x = ref.deck_coupled_positions() if ref.n_coupled_dof else None
    general = _count_general(sys_)
    t = 0.0
    for k in range(6):
        _both(ref, sys_, x, None, t, DT, f"viv call {k}")
        t += DT
    assert sys_._plan.fn is not None and general == []


@pytest.mark.parametrize("loads_at", ["end", "last_stage"])
def test_genalpha(loads_at):
    """The implicit scheme (one generalized-alpha step per call at dtM 0.1 s, steps cut where
    Newton struggles): its own kept call, the solver's structure held and checked."""
    ref, sys_ = _pair(scheme="GenAlpha", dtM=0.1, loads_at=loads_at)
    general = _count_general(sys_)
    t = _run(ref, sys_, 0, 40, 0.0, "GenAlpha")
    assert general == []
    p = sys_._plan
    assert p.fn is not None and p.implicit and p.imp is sys_._imp
    # the solver's work replaced (a line failure does this, rebuilding it on its next use)
    for s in (ref, sys_):
        s._imp = None
    _run(ref, sys_, 40, 10, t, "GenAlpha, solver rebuilt")
    assert sys_._plan is not p and sys_._plan.imp is sys_._imp is not None
    assert ref.solver_stats == sys_.solver_stats


def test_genalpha_failure_raises_the_same_error():
    """A fairlead thrown at 1e5 m/s: the implicit step gives up (the speed limit or Newton), with the
    same error through both paths."""
    ref, sys_ = _pair(scheme="GenAlpha", dtM=0.1)
    t = _run(ref, sys_, 0, 3, 0.0)
    x, xd = _x(ref, 3)
    xd = xd + np.tile([1e5, 0.0, 0.0], 3)
    errs = []
    for path in (lambda: ref._step_general(x, xd, t, DT, None), lambda: sys_.step(x, xd, t, DT)):
        with pytest.raises(SimulationError) as e:
            path()
        errs.append(str(e.value))
    assert errs[0] == errs[1], errs
    assert sys_._plan.fn is not None and sys_._plan.implicit
    assert ref.t == sys_.t and np.array_equal(ref.y, sys_.y, equal_nan=True)
