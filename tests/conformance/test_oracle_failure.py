"""Line failures (MoorDyn's FAILURE section and BreakLine; issue 18), against MoorDyn-C 2.7.2 as a
live oracle where it is right, and against Newton's second law and the statics of a hanging line.

Decks of our own:

* VEE: a 2 t clump held by two symmetric lines from two fixed points (RK4, dtM 0.5 ms, TmaxIC 0:
  both codes start from the same catenary start). Line 1 lets go of the clump at t = 1 s.
  MoorDyn-C's BreakLine puts the released end on a copy of the clump (its 2 t mass, drag, added
  mass): with ``new_point="copy"`` moorline must reproduce every node of both lines and the clump
  (measured: tensions 5.2e-5 of the largest tension, positions 9e-7 m). With moorline's default
  (a massless new point, MoorDyn's documented failure) the released line differs, but the clump and
  line 2 cannot tell: they must still agree with MoorDyn.
* DROP: a 5 t clump (no drag, so its fall is analytic) hanging from a fixed point on one vertical
  line, released by the FAILURE section at t = 0.5 s: the clump falls with
  a = g (m - rho V) / (m + Ca rho V) from the moment of the failure, and the released line, solved
  for statics, hangs with its end segment holding only the end node's submerged weight.

MoorDyn-C 2.7.2's FAILURE section itself is not an oracle: it fires at the first coupling step
whatever FailTime says (an inverted comparison) and leaves the new point where it was (the point is
not integrated); both are documented in docs/moordyn_differences.md.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from moorline.io import read_deck_text
from moorline.model import Attachment, PointKind
from moorline.system import System

VEE = """\
--------------------- MoorDyn Input File ------------------------------------
moorline failure test: a clump held by two lines from fixed points
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
main       0.05    20.0       1.0E8      -0.8        0          1.2    1.0    0.2     0.0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     -40     0       -10     0      0       0      0
2     Fixed     40      0       -10     0      0       0      0
3     Free      0       0       -50     2000   0       1.0    1.0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     main       1        3         58.0      10      -
2     main       2        3         58.0      10      -
{failure}---------------------- OPTIONS -----------------------------------------
0.0005        dtM
RK4           tScheme
1025.0        WtrDnsty
100           WtrDpth
0             TmaxIC
------------------------- need this line --------------------------------------
"""

DROP = """\
--------------------- MoorDyn Input File ------------------------------------
moorline failure test: a clump on one vertical line lets go
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta    EI         Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)        (N-s/-)     (N-m^2)    (-)    (-)    (-)     (-)
main       0.05    20.0       1.0E8      -0.8        0          1.2    1.0    0.2     0.0
---------------------- POINT PROPERTIES --------------------------------
ID    Type      X       Y       Z       Mass   Volume  CdA    Ca
(#)   (-)       (m)     (m)     (m)     (kg)   (m^3)   (m^2)  (-)
1     Fixed     0       0       -5      0      0       0      0
2     Free      0       0       -45     5000   0.5     0      0.8
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)   (name)     (#)      (#)       (m)       (-)     (-)
1     main       1        2         40.0      8       -
---------------------- FAILURE ----------------------------------------
FailureID  Point  Lines  FailTime  FailTen
(#)        (-)    (-)    (s)       (N)
1          2      1      0.5       0
---------------------- OPTIONS -----------------------------------------
0.0005        dtM
RK4           tScheme
1025.0        WtrDnsty
100           WtrDpth
60            TmaxIC
------------------------- need this line --------------------------------------
"""

RHO, G = 1025.0, 9.80665
DT = 0.1
#: node tensions against MoorDyn, relative to the largest tension (measured 5.2e-5: the two codes
#: sum the same forces in different orders over 8000 RK4 steps)
TOL_TEN_REL = 1e-3
#: node and point positions against MoorDyn [m] (measured 9e-7 m)
TOL_POS = 1e-4


def _vee(failure: str = "") -> System:
    s = System(read_deck_text(VEE.format(failure=failure)))
    s.init()
    return s


def _run_pair(mode: str, t_break: float = 1.0, t_end: float = 4.0):
    """Step MoorDyn and moorline side by side; break line 1 at the clump at ``t_break``; return the
    largest differences seen (tensions relative to 17 kN, positions [m])."""
    md = pytest.importorskip("moordyn")
    import tempfile
    from pathlib import Path

    with tempfile.TemporaryDirectory() as d:
        deck = Path(d) / "vee.txt"
        deck.write_text(VEE.format(failure=""))
        m = md.Create(str(deck))
        md.SetVerbosity(m, md.LEVEL_ERR)
        md.Init(m, [], [])
        s = _vee()
        worst = dict.fromkeys(("T1", "T2", "P1", "P2", "clump"), 0.0)
        t = 0.0
        for k in range(round(t_end / DT)):
            if k == round(t_break / DT):
                md.BreakLine(m, md.GetPoint(m, 3), md.GetLine(m, 1))
                s.break_line(0, "B", new_point=mode)
            md.Step(m, [], [], t, DT)
            s.step(None, None, t, DT)
            t += DT
            for li in (1, 2):
                ln = md.GetLine(m, li)
                view = s.lines[li - 1]
                ten = np.array([np.linalg.norm(md.GetLineNodeTen(ln, i)) for i in range(11)])
                pos = np.array([md.GetLineNodePos(ln, i) for i in range(11)])
                worst[f"T{li}"] = max(worst[f"T{li}"], float(np.max(np.abs(ten - view.node_tensions())) / 17e3))
                worst[f"P{li}"] = max(worst[f"P{li}"], float(np.max(np.abs(pos - view.node_positions()))))
            clump = np.array(md.GetPointPos(md.GetPoint(m, 3)))
            worst["clump"] = max(worst["clump"], float(np.max(np.abs(clump - s.points[2].position()))))
        n_points = md.GetNumberPoints(m)
        md.Close(m)
    return s, worst, n_points


@pytest.mark.oracle
def test_break_line_as_moordyn_breakline():
    """new_point='copy' is MoorDyn-C's BreakLine: both lines and the clump agree node by node."""
    s, worst, n_md = _run_pair("copy")
    assert n_md == len(s.points) == 4
    assert max(worst["T1"], worst["T2"]) < TOL_TEN_REL, worst
    assert max(worst["P1"], worst["P2"], worst["clump"]) < TOL_POS, worst
    # the copy is a free point with the clump's mass; by symmetry the released line mirrors line 2
    assert s.model.points[3].m == 2000.0
    assert np.allclose(s.points[3].position() * [-1, 1, 1], s.points[2].position(), atol=1e-6)


@pytest.mark.oracle
def test_massless_release_leaves_the_rest_as_moordyn():
    """The default (massless) new point changes only the released line: the clump and line 2 are
    those of MoorDyn, the released line is not (it falls on its own now)."""
    s, worst, _ = _run_pair("massless")
    assert worst["T2"] < TOL_TEN_REL and max(worst["P2"], worst["clump"]) < TOL_POS, worst
    assert worst["P1"] > 0.5  # a 2 t copy and a massless end do not move alike (measured 3.9 m)
    assert s.model.points[3].m == 0.0 and s.model.points[3].V == 0.0
    ev = s.failures[-1]
    assert ev.trigger == "call" and ev.point == 3 and ev.released == [0]
    assert abs(ev.time - 1.0) < 1e-9


def test_failure_section_time_trigger_is_exact_and_equals_break_line():
    """A FAILURE row at 1.05 s (inside a coupling step) happens at 1.05 s exactly: the same run as
    break_line() called at 1.05 s (bitwise: the same steps in the same order)."""
    a = _vee("---------------------- FAILURE ----\nID Point Lines Time Ten\n(#) (-) (-) (s) (N)\n1 3 1 1.05 0\n")
    assert len(a.failures) == 1 and a.failures[0].pending
    b = _vee()
    for k in range(15):
        a.step(None, None, k * DT, DT)
        if k == 10:
            b.step(None, None, b.t, 0.05)
            b.break_line(0, "B")
            b.step(None, None, b.t, 0.05)
        else:
            b.step(None, None, k * DT, DT)
    ev = a.failures[0]
    assert ev.trigger == "time" and abs(ev.time - 1.05) < 1e-9 and ev.point == 3
    assert np.array_equal(a.y, b.y)
    assert np.array_equal(a.lines[0].node_tensions(), b.lines[0].node_tensions())


def test_tension_trigger():
    """A tension-triggered failure happens at the first check where the load through the
    connection (the end tension of line 1 at the clump) reaches the threshold, not before."""
    s = _vee()
    loads = []
    for k in range(8):
        s.step(None, None, k * DT, DT)
        loads.append(s.lines[0].fairlead_tension())
    threshold = 0.5 * (min(loads) + max(loads))
    s = _vee()
    ev = s.add_failure(3, [0], tension=threshold)
    for k in range(8):
        s.step(None, None, k * DT, DT)
        if ev.pending:
            assert loads[k] < threshold
    first = next(k for k, v in enumerate(loads) if v >= threshold)
    assert ev.trigger == "tension" and abs(ev.time - (first + 1) * DT) < 1e-9
    assert ev.load == pytest.approx(loads[first], rel=1e-12)
    # the released end: its tension now only holds the end node (far below the 17 kN it carried)
    assert s.lines[0].fairlead_tension() < 0.1 * threshold


def test_dropped_clump_falls_as_newton_says_and_the_line_hangs():
    """DROP: before 0.5 s the clump hangs at rest (Newton start); from the failure on it falls with
    a = g (m - rho V) / (m + Ca rho V) (no drag, no line: to 1e-6 m); the released line, solved for
    statics, hangs straight down with its end segment holding the end node's submerged weight
    w l / 2 and its top segment the weight of the rest, w (L - l / 2) (to 1e-6)."""
    s = System(read_deck_text(DROP))
    s.init()
    z0 = s.points[1].position()[2]
    for k in range(20):
        s.step(None, None, k * DT, DT)
    ev = s.failures[0]
    assert ev.trigger == "time" and abs(ev.time - 0.5) < 1e-9
    m, V, Ca = 5000.0, 0.5, 0.8
    a = G * (m - RHO * V) / (m + Ca * RHO * V)
    t = s.t - 0.5
    z = s.points[1].position()[2]
    assert z == pytest.approx(z0 - 0.5 * a * t * t, abs=1e-6)
    assert np.allclose(s.points[1].velocity(), [0.0, 0.0, -a * t], atol=1e-8)
    # the rewired model: line 1 now ends on a new massless free point 3; its statics (the falling
    # clump held fixed, it has no equilibrium of its own) are those of a line hanging free
    assert s.model.lines[0].end_b == Attachment("point", 2)
    hang = dataclasses.replace(s.model, points=[s.model.points[0], dataclasses.replace(
        s.model.points[1], kind=PointKind.FIXED), s.model.points[2]])
    h = System(hang)
    h.init()
    assert h.ic_report["converged"]
    w = (20.0 - RHO * math.pi * 0.05 ** 2 / 4) * G
    ten = h.lines[0].segment_tensions()
    assert ten[-1] == pytest.approx(w * 5.0 / 2, rel=1e-6)
    assert ten[0] == pytest.approx(w * (40.0 - 2.5), rel=1e-6)
    assert np.allclose(h.lines[0].node_positions()[:, :2], 0.0, atol=1e-6)


def test_checkpoint_across_a_failure(tmp_path):
    """A checkpoint written after a failure restores into a system built from the deck (the line
    end is released again) and continues bitwise."""
    a = System(read_deck_text(DROP))
    a.init()
    for k in range(8):
        a.step(None, None, k * DT, DT)
    a.save(tmp_path / "c.npz")
    b = System(read_deck_text(DROP))
    b.init()
    b.load(tmp_path / "c.npz")
    assert len(b.points) == 3 and not b.failures[0].pending
    for k in range(8, 12):
        a.step(None, None, k * DT, DT)
        b.step(None, None, k * DT, DT)
    assert np.array_equal(a.y, b.y)


def test_failure_errors():
    s = _vee()
    with pytest.raises(ValueError, match="line 2 is not attached to P1"):
        s.add_failure(1, [1], time=1.0)
    with pytest.raises(ValueError, match="end must be 'A' or 'B'"):
        s.break_line(0, "C")
    with pytest.raises(ValueError, match="time and tension must be > 0"):
        s.add_failure("P3", [0], time=-1.0)


def test_failure_with_the_implicit_scheme():
    """GenAlpha: the failure time is reached exactly and the dropped clump falls as Newton says
    (a constant acceleration is integrated exactly by the scheme; to 1e-6 m)."""
    s = System(read_deck_text(DROP.replace("RK4           tScheme", "GenAlpha      tScheme")
                              .replace("0.0005        dtM", "0.01          dtM")))
    s.init()
    z0 = s.points[1].position()[2]
    for k in range(10):
        s.step(None, None, k * DT, DT)
    ev = s.failures[0]
    assert ev.trigger == "time" and abs(ev.time - 0.5) < 1e-9 and s.solver_stats["steps"] > 0
    a = G * (5000.0 - RHO * 0.5) / (5000.0 + 0.8 * RHO * 0.5)
    assert s.points[1].position()[2] == pytest.approx(z0 - 0.5 * a * (s.t - 0.5) ** 2, abs=1e-6)


def test_failure_in_simulate_and_on_a_body_point():
    """simulate() with a FAILURE section (time series keep the deck's points), and a line released
    from a point on a coupled body: its new point starts at the body point's global position."""
    import moorline

    ds = moorline.simulate(System(read_deck_text(DROP)), duration=1.0, dt_out=0.25, progress=False)
    assert ds.sizes["point"] == 2
    ten = ds.line_tension_b.sel(line=1).values
    assert ten[0] > 20e3 and ten[-1] < 1e3  # the clump's weight, then only the end node's
    deck = VEE.format(failure="").replace(
        "3     Free      0       0       -50     2000   0       1.0    1.0",
        "3     Body1     0       0       -5      0      0       0      0").replace(
        "---------------------- POINT PROPERTIES",
        "---------------------- BODIES ----\nID Attachment X0 Y0 Z0 r0 p0 y0 Mass CG* I* Volume CdA* Ca\n"
        "(#) (-) (m) (m) (m) (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)\n"
        "1 Coupled 0 0 -45 0 0 30 0 0 0 0 0 0\n---------------------- POINT PROPERTIES")
    s = System(read_deck_text(deck))
    x = np.array([0.0, 0.0, -45.0, 0.0, 0.0, math.radians(30.0)])
    s.init(x, np.zeros(6))
    where = s.points[2].position()
    assert np.allclose(where, [0.0, 0.0, -50.0])
    k = s.break_line(0, "B")
    assert k == 3 and np.allclose(s.points[3].position(), where, atol=1e-12)
    for k in range(3):
        s.step(x, np.zeros(6), k * DT, DT)
    # the released end falls away from the body point; line 2 stays on it
    assert np.linalg.norm(s.lines[0].node_positions()[-1] - s.points[2].position()) > 0.01
    assert np.allclose(s.lines[1].node_positions()[-1], s.points[2].position(), atol=1e-12)
    assert np.allclose(s.lines[0].node_positions()[-1], s.points[3].position(), atol=1e-12)


def test_tension_checks_inside_a_long_step():
    """failure_check_interval: within one long step the load is checked every 0.05 s, and the
    failure happens at the first check where it is reached (the same as stepping 0.05 s at a time)."""
    s = _vee()
    loads = []
    for k in range(16):
        s.step(None, None, k * 0.05, 0.05)
        loads.append(s.lines[0].fairlead_tension())
    threshold = 0.5 * (min(loads) + max(loads))
    first = next(k for k, v in enumerate(loads) if v >= threshold)
    s = _vee()
    s.failure_check_interval = 0.05
    ev = s.add_failure("P3", [0], tension=threshold)
    s.step(None, None, 0.0, 0.8)
    assert ev.trigger == "tension" and abs(ev.time - 0.05 * (first + 1)) < 1e-9
    assert ev.load == pytest.approx(loads[first], rel=1e-12)
