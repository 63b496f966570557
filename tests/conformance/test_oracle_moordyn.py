"""moorline side by side with MoorDyn-C (the ``moordyn`` 2.7.2 Python wrapper) as a live oracle.

Our own deck (not one of the conformance corpus): a chain and a polyester rope with a tabulated
EA curve file, joined by a free clump weight (mass, volume, CdA, Ca), from an anchor on the seabed
to a coupled fairlead, in 150 m of water with seabed contact and friction; dtM = 1 ms, RK2.

* statics: the same deck with MoorDyn's stationary initial-condition solver (TmaxIC = 100 s;
  moorline's default is a Newton start, so the moorline side sets ICNewton 0);
  node positions, node tensions, clump position and fairlead force after Init;
* dynamics: TmaxIC = 0, so both codes start from the same catenary start (compared first), with
  the clump away from equilibrium; then 40 s of imposed fairlead surge (a 4 m ramp over 30 s plus a
  0.8 m, 9 s oscillation), driven as a MoorDyn coupling program does (outer dt = 0.1 s,
  x_k = X(t_k), v_k = (X(t_{k+1}) - X(t_k))/dt); every outer sample compares fairlead and anchor
  tensions of both lines, every node position, the clump position and the coupled force.
  moorline runs with ``loads_at="last_stage"`` because MoorDyn reports the loads of the last RK
  stage of its last step.

Tolerances (named constants below) are an order of magnitude or more above the differences
measured with moordyn 2.7.2 (stated next to each), and far below what any modelling difference
produces (a missing drag term, a wrong reference area, a wrong damping conversion or a wrong
seabed law changes tensions by per cents and positions by decimetres over 40 s). What remains is
floating-point order of operations and the catenary-start Newton iterate, carried by 40 000
time steps; for the statics, MoorDyn's stationary solver does not reach its threshold on this
deck in either code (both stop at TmaxIC with a mean residual of about 0.9 m/s^2 of the stiffest
mode cycling at its stability limit), so the comparison there is of the same iterate of the same
algorithm and gets a looser position tolerance.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

md = pytest.importorskip("moordyn")

from moorline.io import read_deck  # noqa: E402
from moorline.system import System  # noqa: E402

pytestmark = pytest.mark.oracle

# ---------------------------------------------------------------------------------- tolerances
#: catenary-start node positions [m] (measured 1.4e-5 m: Newton iterate of the same algorithm)
TOL_POS_START = 1e-3
#: node and clump positions during the dynamics [m] (measured 1.4e-5 m)
TOL_POS_DYN = 5e-3
#: tensions during the dynamics: relative to the largest tension of that channel, plus absolute
#: [N] (measured 7.4 N on 2.0e5 N, 3.6e-5 relative)
TOL_TEN_REL, TOL_TEN_ABS = 2e-3, 50.0
#: coupled force components, relative to the largest |component| plus absolute [N] (measured 1.8 N)
TOL_F_REL, TOL_F_ABS = 2e-3, 50.0
#: statics after the stationary IC solver: positions [m] (measured 1.2e-4 m) and node tensions /
#: coupled force, relative to the line's largest tension plus absolute [N] (measured 2.8 N)
TOL_POS_IC = 1e-2
TOL_TEN_IC_REL, TOL_TEN_IC_ABS = 2e-3, 50.0

DT = 0.1  # outer coupling step [s]
DURATION = 40.0
X0 = np.array([0.0, 0.0, -15.0])  # fairlead

DECK = """\
--------------------- MoorDyn Input File ------------------------------------
moorline oracle test: chain + polyester joined by a clump weight, coupled fairlead
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA          BA/-zeta    EI      Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)         (N-s/-)     (N-m^2) (-)    (-)    (-)     (-)
chain      0.14    120.0      5.8e8       -0.8        0       2.4    1.0    1.15    0.5
poly       0.16    25.0       poly_ea.txt -0.6        0       1.2    0.9    0.008   0.1
---------------------- POINTS --------------------------------
ID    Attachment  X       Y      Z       Mass    Volume  CdA    Ca
(#)   (-)         (m)     (m)    (m)     (kg)    (m^3)   (m^2)  (-)
1     Fixed       -420.0  30.0   -150.0  0       0       0      0
2     Free        -160.0  10.0   -118.0  6000    1.2     2.0    0.8
3     Coupled     0.0     0.0    -15.0   0       0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    chain      1        2        285.0     20       -
2    poly       2        3        188.0     15       -
---------------------- OPTIONS -----------------------------------------
0             writeLog
0.001         dtM
RK2           tScheme
150           WtrDpth
3.0e6         kBot
3.0e5         cBot
0.4           FrictionCoefficient
1.0           dtIC
{tmax_ic}     TmaxIC
1e-5          threshIC
1             disableOutTime
---------------------- OUTPUTS -----------------------------------------
FairTen1
FairTen2
------------------------- need this line --------------------------------------
"""

# polyester working curve: three header lines, then strain / tension [N]; no trailing newline
# (MoorDyn-C reads the empty record after a final newline as a bad curve point)
EA_CURVE = "\n".join(["polyester working curve", "strain  tension", "(-)     (N)",
                      "0.0 0.0", "0.01 6.0e5", "0.02 1.6e6", "0.03 2.9e6", "0.05 6.0e6"])


def smoothstep5(s):
    s = min(max(s, 0.0), 1.0)
    return s * s * s * (6.0 * s * s - 15.0 * s + 10.0)


def X(t):
    """Imposed fairlead position [m]."""
    surge = 4.0 * smoothstep5(t / 30.0) + 0.8 * math.sin(2.0 * math.pi * t / 9.0) * min(t / 5.0, 1.0)
    return X0 + np.array([surge, 0.0, 0.0])


def write_deck(folder, tmax_ic):
    (folder / "poly_ea.txt").write_text(EA_CURVE)
    path = folder / "oracle.txt"
    path.write_text(DECK.format(tmax_ic=tmax_ic))
    return path


# ---------------------------------------------------------------------------------- sampling
def md_sample(s, f):
    lines = [md.GetLine(s, i) for i in (1, 2)]
    ten, pos, node_ten = [], [], []
    for L in lines:
        N = md.GetLineN(L)
        ten += [np.linalg.norm(md.GetLineNodeTen(L, 0)), md.GetLineFairTen(L)]
        pos.append(np.array([md.GetLineNodePos(L, j) for j in range(N + 1)]))
        node_ten.append(np.array([np.linalg.norm(md.GetLineNodeTen(L, j)) for j in range(N + 1)]))
    return {"ten": np.array(ten), "pos": pos, "node_ten": node_ten, "f": np.array(f, dtype=float),
            "clump": np.array(md.GetPointPos(md.GetPoint(s, 2)))}


def ml_sample(s: System, f):
    ten = []
    for ln in s.lines:
        ten += [ln.anchor_tension(), ln.fairlead_tension()]
    return {"ten": np.array(ten), "pos": [ln.node_positions() for ln in s.lines],
            "node_ten": [ln.node_tensions() for ln in s.lines], "f": np.array(f, dtype=float),
            "clump": s.points[1].position()}


def run_moordyn(deck, n_steps):
    s = md.Create(str(deck))
    try:
        assert md.NCoupledDOF(s) == 3
        md.Init(s, X0.tolist(), [0.0, 0.0, 0.0])
        f = md.Step(s, X0.tolist(), [0.0, 0.0, 0.0], 0.0, 0.0)
        out = [md_sample(s, f)]
        for k in range(n_steps):
            t = k * DT
            xk = X(t)
            vk = (X(t + DT) - xk) / DT
            f = md.Step(s, xk.tolist(), vk.tolist(), t, DT)
            out.append(md_sample(s, f))
    finally:
        md.Close(s)
    return out


def run_moorline(deck, n_steps):
    model = read_deck(deck)
    # the statics compare MoorDyn's stationary solver with moorline's implementation of it (both
    # stop at TmaxIC unconverged here); moorline's default Newton start would go to equilibrium
    model.options.ICNewton = 0
    s = System(model, loads_at="last_stage")
    f = s.init(X0, np.zeros(3))
    out = [ml_sample(s, f)]
    for k in range(n_steps):
        t = k * DT
        xk = X(t)
        vk = (X(t + DT) - xk) / DT
        f = s.step(xk, vk, t, DT)
        out.append(ml_sample(s, f))
    return out, s


# ---------------------------------------------------------------------------------- statics
@pytest.fixture(scope="module")
def statics(tmp_path_factory):
    folder = tmp_path_factory.mktemp("oracle_ic")
    deck = write_deck(folder, tmax_ic="100.0")
    ref = run_moordyn(deck, 0)[0]
    got, sys = run_moorline(deck, 0)
    return ref, got[0], sys


def test_statics_node_positions(statics):
    ref, got, _ = statics
    for i in range(2):
        err = np.max(np.abs(got["pos"][i] - ref["pos"][i]))
        assert err <= TOL_POS_IC, f"line {i + 1}: node positions after Init differ by {err:.3g} m"
    err = np.max(np.abs(got["clump"] - ref["clump"]))
    assert err <= TOL_POS_IC, f"clump position after Init differs by {err:.3g} m"


def test_statics_tensions_and_fairlead_force(statics):
    ref, got, _ = statics
    for i in range(2):
        tmax = np.max(ref["node_ten"][i])
        err = np.max(np.abs(got["node_ten"][i] - ref["node_ten"][i]))
        assert err <= TOL_TEN_IC_ABS + TOL_TEN_IC_REL * tmax, f"line {i + 1}: node tensions differ by {err:.3g} N"
    fmax = np.max(np.abs(ref["f"]))
    err = np.max(np.abs(got["f"] - ref["f"]))
    assert err <= TOL_TEN_IC_ABS + TOL_TEN_IC_REL * fmax, f"fairlead force {got['f']} vs MoorDyn {ref['f']}"


def test_statics_guard(statics):
    """The IC solver moved the system: the clump settled away from its deck position and the
    polyester carries its pretension."""
    ref, got, _ = statics
    assert np.max(np.abs(ref["clump"] - np.array([-160.0, 10.0, -118.0]))) > 1.0
    assert np.max(ref["node_ten"][1]) > 2.0e4


# ---------------------------------------------------------------------------------- dynamics
@pytest.fixture(scope="module")
def dynamics(tmp_path_factory):
    folder = tmp_path_factory.mktemp("oracle_dyn")
    deck = write_deck(folder, tmax_ic="0")
    n = int(round(DURATION / DT))
    ref = run_moordyn(deck, n)
    got, _ = run_moorline(deck, n)
    return ref, got


def test_catenary_start_profile(dynamics):
    ref, got = dynamics
    for i in range(2):
        err = np.max(np.abs(got[0]["pos"][i] - ref[0]["pos"][i]))
        assert err <= TOL_POS_START, f"line {i + 1}: catenary start differs by {err:.3g} m"
    np.testing.assert_allclose(got[0]["clump"], ref[0]["clump"], rtol=0, atol=TOL_POS_START)


def test_dynamics_end_tensions(dynamics):
    """Anchor and fairlead tension of both lines at every outer step. The t = 0 sample is not
    compared: with TmaxIC = 0 MoorDyn has evaluated no loads before its first step (it reports 0)."""
    ref, got = dynamics
    A = np.array([r["ten"] for r in ref[1:]])
    B = np.array([g["ten"] for g in got[1:]])
    names = ["line 1 anchor", "line 1 fairlead", "line 2 anchor", "line 2 fairlead"]
    for c, name in enumerate(names):
        tmax = np.max(A[:, c])
        err = np.abs(B[:, c] - A[:, c])
        k = int(np.argmax(err))
        assert err[k] <= TOL_TEN_ABS + TOL_TEN_REL * tmax, \
            f"{name} tension: {B[k, c]:.6g} N vs MoorDyn {A[k, c]:.6g} N at t = {(k + 1) * DT:.1f} s"


def test_dynamics_node_and_clump_positions(dynamics):
    ref, got = dynamics
    worst = 0.0
    for r, g in zip(ref, got, strict=True):
        for i in range(2):
            worst = max(worst, float(np.max(np.abs(g["pos"][i] - r["pos"][i]))))
        worst = max(worst, float(np.max(np.abs(g["clump"] - r["clump"]))))
    assert worst <= TOL_POS_DYN, f"node/clump positions differ by up to {worst:.3g} m"


def test_dynamics_coupled_force(dynamics):
    ref, got = dynamics
    A = np.array([r["f"] for r in ref[1:]])
    B = np.array([g["f"] for g in got[1:]])
    allow = TOL_F_ABS + TOL_F_REL * np.max(np.abs(A))
    err = np.max(np.abs(B - A), axis=0)
    assert np.all(err <= allow), f"coupled force components differ by {err} N (allowed {allow:.3g} N)"


def test_dynamics_guard(dynamics):
    """The run is dynamic: fairlead tension of the polyester varies by more than 20 %, the clump
    moves by more than 1 m."""
    ref, _ = dynamics
    T = np.array([r["ten"][3] for r in ref[1:]])
    assert (T.max() - T.min()) > 0.2 * T.max()
    clump = np.array([r["clump"] for r in ref])
    assert np.max(np.ptp(clump, axis=0)) > 1.0


# ---------------------------------------------------------------------------------- still-water level
SURFACE_DECK = """\
--------------------- MoorDyn Input File ------------------------------------
moorline oracle test: a line rising to a coupled point at or near the still-water level
----------------------- LINE TYPES ------------------------------------------
TypeName   Diam    Mass/m     EA          BA/-zeta    EI      Cd     Ca     CdAx    CaAx
(name)     (m)     (kg/m)     (N)         (N-s/-)     (N-m^2) (-)    (-)    (-)     (-)
hose       0.5     300.0      1.0e8       -0.8        0       1.2    1.0    0.0     0.0
---------------------- POINTS --------------------------------
ID    Attachment  X       Y      Z       Mass    Volume  CdA    Ca
(#)   (-)         (m)     (m)    (m)     (kg)    (m^3)   (m^2)  (-)
1     Fixed       -50.0   0.0    -40.0   0       0       0      0
2     Coupled     0.0     0.0    {z}     0       0       0      0
---------------------- LINES ----------------------------------------
ID   LineType   AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#)  (name)     (#)      (#)      (m)       (-)      (-)
1    hose       1        2        64.0      8        -
---------------------- OPTIONS -----------------------------------------
0             writeLog
0.001         dtM
60            WtrDpth
0             TmaxIC
1             disableOutTime
---------------------- OUTPUTS -----------------------------------------
------------------------- need this line --------------------------------------
"""
#: weight - buoyancy of the two nodes of the top segment after one 1 ms step from the same
#: catenary start, relative to the dry weight of the node (measured 0 at z = -0.3 m, 9e-8 at +0.3 m)
TOL_NODE_WEIGHT_REL = 1e-4


@pytest.mark.parametrize("z", [-0.3, 0.0, 0.3])
def test_node_weight_with_fairlead_at_still_water_level(tmp_path, z):
    """Net weight (weight - buoyancy) of the top two nodes of a line whose end B is at z = -0.3,
    exactly 0 (a deck value of 0.0) or +0.3 m. The top segment's submerged fraction decides it
    (spec 3.6: fully wet only if z_a <= 0 and z_b < 0); MoorDyn 2.7.2 gives 0.969 at z = 0."""
    deck = tmp_path / "surface.txt"
    deck.write_text(SURFACE_DECK.format(z=repr(z)))
    x = [0.0, 0.0, z]
    s = md.Create(str(deck))
    try:
        md.Init(s, x, [0.0, 0.0, 0.0])
        md.Step(s, x, [0.0, 0.0, 0.0], 0.0, 0.001)
        L = md.GetLine(s, 1)
        ref = np.array([md.GetLineNodeWeight(L, j) for j in (7, 8)])
    finally:
        md.Close(s)
    sys = System(read_deck(deck), loads_at="last_stage")
    sys.init(np.array(x), np.zeros(3))
    sys.step(np.array(x), np.zeros(3), 0.0, 0.001)
    got = sys.work.W[int(sys.layout.lines.node_ptr[1]) - 2:int(sys.layout.lines.node_ptr[1])]
    dry = 300.0 * 8.0 * 9.80665  # dry weight of an internal node [N]
    err = np.max(np.abs(got - ref))
    assert err <= TOL_NODE_WEIGHT_REL * dry, \
        f"fairlead at z = {z:g}: node net weights {got[:, 2]} N vs MoorDyn {ref[:, 2]} N"
