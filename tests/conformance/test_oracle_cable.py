"""A power cable with bending stiffness, clamped at the seabed and joined through a zero-length
rod, side by side with MoorDyn-C (``moordyn`` 2.7.2) as a live oracle.

Our own deck: a fixed rod on the seabed is the hub connector; a cable with EI is clamped to its
end B; a FREE zero-length rod joins it to a light section with EI (the lazy-wave joint: the rod
takes its axis from the EI-weighted end segments of both cables and clamps both ends to it); the
light section ends at a coupled point near the surface. Both sections hang in slack catenaries:
a taut stiff segment would turn 1e-6 m of round-off into tens of newtons of tension and hide
what is compared. RK4, dtM = 0.5 ms, TmaxIC = 0 (both
codes start from the same catenary start, away from equilibrium), then 12 s of imposed heave
(1 m, 6 s period). Every outer sample (0.1 s) compares node positions and node tensions of both
cables, the curvature of the nodes next to the joint, the joint's position, and the coupled force.

Tolerances: the two codes integrate the same equations with the same scheme and step, so what is
left is the order of floating-point operations carried over 24 000 steps of a system with
undamped bending modes (spec 3.10); measured differences are stated next to each constant.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

md = pytest.importorskip("moordyn")

from moorline.io import read_deck  # noqa: E402
from moorline.system import System  # noqa: E402

pytestmark = pytest.mark.oracle

#: node and joint positions [m] (measured 5e-5 m)
TOL_POS = 2e-3
#: node tensions: relative to the largest tension of the line, plus absolute [N]
TOL_TEN_REL, TOL_TEN_ABS = 5e-3, 5.0
#: curvature next to the joint [1/m]
TOL_CURV = 2e-3
#: coupled force [N] (measured 0.04 N)
TOL_F_REL, TOL_F_ABS = 5e-3, 5.0

DT = 0.1
DURATION = 12.0
X0 = np.array([30.0, 0.0, -8.0])

DECK = """\
--------------------- MoorDyn Input File ------------------------------------
moorline oracle test: cable with EI clamped to a seabed connector, zero-length rod joint, light section
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA          BA/-zeta    EI      Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)         (N-s/-)     (N-m^2) (-)    (-)    (-)     (-)
cable      0.10    18.0       4.0e7       -0.5        2.0e3   1.2    1.0    0.01    0.0
light      0.15    20.0       4.0e7       -0.5        2.0e3   1.2    1.0    0.01    0.0
---------------------- ROD TYPES ------------------------------------
TypeName      Diam     Mass/m    Cd     Ca      CdEnd    CaEnd
(name)        (m)      (kg/m)    (-)    (-)     (-)      (-)
hub           0.5      100       1.0    1.0     0.0      0.0
joint         0.1      0         0.0    0.0     0.0      0.0
---------------------- RODS ----------------------------------------
ID   RodType  Attachment  Xa    Ya    Za    Xb    Yb    Zb   NumSegs  RodOutputs
(#)  (name)    (#/key)    (m)   (m)   (m)   (m)   (m)   (m)  (-)       (-)
1    hub       Fixed      -2     0    -40    0     0    -40   2         -
2    joint     Free       12     0    -30    12    0    -30   0         -
---------------------- POINTS --------------------------------
ID    Attachment  X       Y      Z       Mass    Volume  CdA    Ca
(#)   (-)         (m)     (m)    (m)     (kg)    (m^3)   (m^2)  (-)
1     Coupled     30.0    0.0    -8.0    0       0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    cable      R1B      R2A      24.0      12       -
2    light      R2B      1        36.0      18       -
---------------------- OPTIONS -----------------------------------------
0             writeLog
0.0005        dtM
RK4           tScheme
50            WtrDpth
3.0e6         kBot
3.0e5         cBot
0             TmaxIC
1             disableOutTime
---------------------- OUTPUTS -----------------------------------------
FairTen1
------------------------- need this line --------------------------------------
"""


def X(t):
    return X0 + np.array([0.0, 0.0, 1.0 * math.sin(2.0 * math.pi * t / 6.0) * min(t / 3.0, 1.0)])


def md_sample(s, f):
    lines = [md.GetLine(s, i) for i in (1, 2)]
    pos, ten, curv = [], [], []
    for L in lines:
        N = md.GetLineN(L)
        pos.append(np.array([md.GetLineNodePos(L, j) for j in range(N + 1)]))
        ten.append(np.array([np.linalg.norm(md.GetLineNodeTen(L, j)) for j in range(N + 1)]))
        curv.append(np.array([md.GetLineNodeCurv(L, j) for j in range(N + 1)]))
    return {"pos": pos, "ten": ten, "curv": curv, "joint": np.array(md.GetRodNodePos(md.GetRod(s, 2), 0)),
            "f": np.array(f)}


def ml_sample(s: System, f):
    def node_ten(ln):
        sv = ln.segment_tension_vectors()
        return np.linalg.norm(np.vstack([sv[:1], 0.5 * (sv[:-1] + sv[1:]), sv[-1:]]), axis=1)

    return {"pos": [ln.node_positions() for ln in s.lines], "ten": [node_ten(ln) for ln in s.lines],
            "curv": [ln.node_curvatures() for ln in s.lines], "joint": s.rods[1].node_positions()[0],
            "f": np.array(f)}


def run(sample, create, init, step, n_steps):
    out = []
    s = create()
    f = init(s)
    out.append(sample(s, f))
    for k in range(n_steps):
        t = k * DT
        xk = X(t)
        vk = (X(t + DT) - xk) / DT
        f = step(s, xk, vk, t)
        out.append(sample(s, f))
    return s, out


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    folder = tmp_path_factory.mktemp("oracle_cable")
    deck = folder / "cable.txt"
    deck.write_text(DECK)
    n = int(round(DURATION / DT))

    def md_init(s):
        md.Init(s, X0.tolist(), [0.0, 0.0, 0.0])
        return md.Step(s, X0.tolist(), [0.0, 0.0, 0.0], 0.0, 0.0)

    mds, ref = run(md_sample, lambda: md.Create(str(deck)), md_init,
                   lambda s, x, v, t: md.Step(s, x.tolist(), v.tolist(), t, DT), n)
    md.Close(mds)
    ours_sys, ours = run(ml_sample, lambda: System(read_deck(deck), loads_at="last_stage"),
                         lambda s: s.init(X0, np.zeros(3)), lambda s, x, v, t: s.step(x, v, t, DT), n)
    return ref, ours


def test_start_profile(runs):
    ref, ours = runs
    for i in range(2):
        err = np.abs(ours[0]["pos"][i] - ref[0]["pos"][i]).max()
        assert err <= TOL_POS, f"line {i + 1}: start profile differs by {err:.3g} m"


def test_positions_and_joint(runs):
    ref, ours = runs
    err = max(np.abs(o["pos"][i] - r["pos"][i]).max() for o, r in zip(ours, ref, strict=True) for i in range(2))
    assert err <= TOL_POS, f"node positions differ by {err:.3g} m"
    err = max(np.abs(o["joint"] - r["joint"]).max() for o, r in zip(ours, ref, strict=True))
    assert err <= TOL_POS, f"joint position differs by {err:.3g} m"


def test_node_tensions(runs):
    ref, ours = runs
    for i in range(2):
        big = max(r["ten"][i].max() for r in ref)
        err = max(np.abs(o["ten"][i] - r["ten"][i]).max() for o, r in zip(ours[1:], ref[1:], strict=True))
        assert err <= TOL_TEN_REL * big + TOL_TEN_ABS, f"line {i + 1}: node tensions differ by {err:.3g} N"


def test_curvature_at_the_joint(runs):
    """Interior curvatures next to the joint (the end nodes of a clamped cable are reported by
    MoorDyn from one segment length, spec 3.10; we compare the interior nodes one away)."""
    ref, ours = runs
    err = max(max(abs(o["curv"][0][-2] - r["curv"][0][-2]), abs(o["curv"][1][1] - r["curv"][1][1]))
              for o, r in zip(ours[1:], ref[1:], strict=True))
    assert err <= TOL_CURV, f"curvature next to the joint differs by {err:.3g} 1/m"


def test_coupled_force(runs):
    ref, ours = runs
    big = max(np.abs(r["f"]).max() for r in ref)
    err = max(np.abs(o["f"] - r["f"]).max() for o, r in zip(ours[1:], ref[1:], strict=True))
    assert err <= TOL_F_REL * big + TOL_F_ABS, f"coupled force differs by {err:.3g} N"


def test_guard_the_cable_bends_and_moves(runs):
    """The comparison means something: the joint moves, the cable is bent and tensioned."""
    ref, _ = runs
    joint_moves = np.ptp([r["joint"][2] for r in ref])
    assert joint_moves > 0.05
    assert max(r["curv"][1].max() for r in ref) > 0.01
    assert max(r["ten"][1].max() for r in ref) > 100.0
