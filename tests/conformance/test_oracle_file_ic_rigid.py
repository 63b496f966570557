"""``fileIC`` with bodies, rods and rope states: a run starts from MoorDyn's saved state, against
MoorDyn-C 2.7.2 live (issue 18).

MoorDyn runs a deck with a free body (rotated, CG below its reference point, added mass, drag), a
coupled-pinned body carrying a rod pinned to it (the body yawed 30 deg in the deck), a free rod, a
rod pinned to the ground and viscoelastic lines of both kinds (constant and mean-load dependent
dynamic EA), for 0.5 s after its Init (so that everything moves), then saves its state and runs on.
moorline, given that file as the deck's ``fileIC`` (TmaxIC 0), must start where MoorDyn is:

- every node of every line, ends included (these follow the bodies' and rods' poses, so they check
  the quaternion convention, the rods' axes and the velocities), position and velocity to 1e-12
  (machine precision on coordinates of up to 150 m; measured 2.2e-16 m and 9e-19 m/s);
- the body poses of MoorDyn's ``GetBodyState`` (position, roll-pitch-yaw) to 1e-12.

It then runs on as MoorDyn ran on. With ``InertialLoads moordyn`` (MoorDyn-C's inertial loads,
docs/moordyn_differences.md) the whole state, read back from MoorDyn's ``SaveState`` after each of
five 0.1 s coupling steps (RK2, dtM 2e-4 s), agrees to round-off: positions within 1e-9 m,
velocities within 1e-8 m/s and rope stretches within 1e-9 m (measured 2.5e-13 m, 5.4e-11 m/s,
2e-15 m). With moorline's own inertial loads (the default) the paths differ (measured: 8e-3 m/s
after 0.5 s, mostly the free rod), which ``test_default_inertial_loads_differ`` shows with the
same file.

A Syrope line and a viscoelastic line (N rows: one per segment, the stretch of the static branch
in the last column) start from MoorDyn's stretches and run on within 1e-10 (measured 3.6e-14 m,
2e-12 m/s, 4e-15 m).
A free zero-length rod joins two lines as in MoorDyn (its axis is taken from its cables, its
three-DOF state from the file): 1e-6 m/s (measured 1.6e-7; MoorDyn takes the cables' direction
one evaluation late).
"""

from __future__ import annotations

import os
import shutil
import struct
from pathlib import Path

import numpy as np
import pytest

from moorline.errors import DeckError
from moorline.io import read_deck
from moorline.io.moordyn_state import read_moordyn_state
from moorline.model import BodyKind, RodKind
from moorline.system import System
from moorline.system.moordyn_start import start_from_moordyn_state

md = pytest.importorskip("moordyn")
pytestmark = pytest.mark.oracle

ROOT = Path(__file__).resolve().parents[2]
SHARED = Path(os.environ.get("MOORLINE_SHARED", ROOT.parent / "shared"))
OWC = SHARED / "public_decks" / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring" / "syrope" / "owc.dat"

DT = 0.1
N_BEFORE = 5  # coupling steps MoorDyn runs before saving its state
N_AFTER = 5
X_CPL = [30.0, 0.0, -10.0, 0.0, 0.0, 0.0]  # the coupled-pinned body held at its deck position

RIGID = """\
state-file test: free body, coupled-pinned body with a pinned rod, free rod, ground-pinned rod, viscoelastic lines
---------------------- LINE TYPES --------------------------------------------------
TypeName  Diam   Mass/m  EA                   BA/-zeta      EI   Cd   Ca   CdAx  CaAx
(name)    (m)    (kg/m)  (N)                  (N-s/-)       (N-m^2) (-) (-) (-)  (-)
chain     0.1    20.0    5.0e8                -0.5          0    1.2  1.0  0.2   0.0
poly      0.15   15.0    1.0e8|1.2e8|0.3      2e7|1e6       0    1.2  1.0  0.2   0.0
nylon     0.12   10.0    4.0e7|6.0e7          -0.3|2e5      0    1.2  1.0  0.2   0.0
---------------------- ROD TYPES ------------------------------------
TypeName  Diam  Mass/m  Cd   Ca   CdEnd  CaEnd
(name)    (m)   (kg/m)  (-)  (-)  (-)    (-)
rod       0.3   200     1.0  1.0  0.5    0.5
---------------------------- BODIES -----------------------------------------------------
ID  Attachment     X0    Y0   Z0    r0  p0  y0   Mass   CG*   I*      Volume  CdA*  Ca
(#)  (-)           (m)   (m)  (m)   (deg) (deg) (deg) (kg) (m) (kg-m^2) (m^3) (m^2) (-)
1   Free           0     0    -20   5   -3  10   2.0e4  0|0|-0.5  4e4|4e4|2e4  10  5  0.8
2   CoupledPinned  30    0    -10   0   0   30   1.0e3  0|0|-0.3  1e3     1.0     1     1.0
---------------------- RODS ----------------------------------------
ID  RodType  Attachment   Xa   Ya  Za   Xb   Yb  Zb   NumSegs  RodOutputs
(#) (name)   (#/key)      (m)  (m) (m)  (m)  (m) (m)  (-)      (-)
1   rod      Free         -40  5   -30  -35  5   -33  4        -
2   rod      Pinned       40   -20 -40  44   -20 -43  3        -
3   rod      Body2Pinned  1    0   0    3    0   -2   2        -
----------------------- POINTS ----------------------------------------------
ID  Attachment  X     Y    Z     M   V   CdA  CA
(#) (-)         (m)   (m)  (m)   (kg) (m^3) (m^2) (-)
1   Fixed       -150  0    -100  0   0   0    0
2   Fixed       150   0    -100  0   0   0    0
3   Fixed       0     150  -100  0   0   0    0
4   Body1       0     0    -1    0   0   0    0
5   Fixed       -100  5    -100  0   0   0    0
6   Fixed       100   -20  -100  0   0   0    0
7   Body2       0     0    0     0   0   0    0
8   Fixed       60    40   -100  0   0   0    0
---------------------- LINES --------------------------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   chain     1        4        175       10       -
2   poly      2        4        172       8        -
3   chain     3        4        170       10       -
4   chain     5        R1A      110       8        -
5   chain     R1B      4        40        6        -
6   chain     6        R2B      120       8        -
7   nylon     R2A      7        18        5        -
8   chain     7        4        35        5        -
9   chain     R3B      8        95        8        -
---------------------- OPTIONS ------------------------------------------------------
2e-4     dtM
3e6      kb
3e5      cb
10       TmaxIC
2.0      CdScaleIC
1.0      dtIC
100      WtrDpth
{extra}
--------------------- need this line ------------------------------------------------
"""

JOINT = """\
state-file test: a free zero-length rod joining a chain and a viscoelastic rope
---------------------- LINE TYPES --------------------------------------------------
TypeName  Diam   Mass/m  EA                   BA/-zeta      EI   Cd   Ca   CdAx  CaAx
(name)    (m)    (kg/m)  (N)                  (N-s/-)       (N-m^2) (-) (-) (-)  (-)
chain     0.1    20.0    5.0e8                -0.5          0    1.2  1.0  0.2   0.0
nylon     0.12   10.0    4.0e7|6.0e7          -0.3|2e5      0    1.2  1.0  0.2   0.0
---------------------- ROD TYPES ------------------------------------
TypeName  Diam  Mass/m  Cd   Ca   CdEnd  CaEnd
(name)    (m)   (kg/m)  (-)  (-)  (-)    (-)
joint     0.2   0       1.0  1.0  0.5    0.5
---------------------- RODS ----------------------------------------
ID  RodType  Attachment   Xa   Ya  Za   Xb   Yb  Zb   NumSegs  RodOutputs
(#) (name)   (#/key)      (m)  (m) (m)  (m)  (m) (m)  (-)      (-)
1   joint    Free         -60  -40 -60  -60  -40 -60  0        -
----------------------- POINTS ----------------------------------------------
ID  Attachment  X     Y    Z     M   V   CdA  CA
(#) (-)         (m)   (m)  (m)   (kg) (m^3) (m^2) (-)
1   Fixed       -100  -80  -100  0   0   0    0
2   Fixed       0     0    -21   0   0   0    0
---------------------- LINES --------------------------------------------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   chain     1        R1A      65        6        -
2   nylon     R1B      2        75        6        -
---------------------- OPTIONS ------------------------------------------------------
2e-4     dtM
3e6      kb
3e5      cb
10       TmaxIC
2.0      CdScaleIC
1.0      dtIC
100      WtrDpth
--------------------- need this line ------------------------------------------------
"""

ROPES = """\
state-file test: a Syrope line and a viscoelastic line
------------------------- LINE TYPES --------------------------------------------------
LineType  Diam    MassDenInAir    EA                        BA/-zeta       EI     Cd   Ca  CdAx   CaAx
(-)       (m)       (kg/m)        (-)                       (Pa-s/-)      (n-m^2) (-)   (-)  (-)   (-)
poly      0.203     40      SYROPE:syrope.dat|1.53e8|23.12  5.0e10|1.0e5   0.0    1.0   1.0  0.1   0.0
vpoly     0.1       15      1.0e8|1.2e8                     -0.5|1e5       0.0    1.2   1.0  0.1   0.0
----------------------- POINTS ----------------------------------------------
Node      Type      X          Y         Z        M        V         CdA   CA
(-)       (-)      (m)        (m)       (m)      (kg)     (m^3)     (m^2)  (-)
1         Fixed    0.0         0       -50.0      0        0          0     0
2         Coupled  40.6        0       -50.0      0        0          0     0
3         Fixed    0.0        10       -50.0      0        0          0     0
4         Coupled  30.0       10       -20.0      0        0          0     0
-------------------------- LINES -------------------------------------------------
Line     LineType NodeA     NodeB  UnstrLen   NumSegs     Flags/Outputs
(-)      (-)       (-)       (-)    (m)         (-)          (-)
1        poly       2         1     40.0         4           -
2        vpoly      3         4     45.0         6           -
-------------------------- SYROPE IC -------------------------------------------------------
Line(s)   Tmax0    Tmean0
(-)        (N)      (N)
1       1.3886e6  4.339e5
-------------------------- SOLVER OPTIONS---------------------------------------------------
2e-4     dtM
3.0e6    kb
3.0e5    cb
70       WtrDpth
2.0      TmaxIC
0.5      dtIC
--------------------------- need this line -------------------------------------------------
"""
SYROPE_CFG = """owc.dat  OWC     original working curve
LINEAR      WCType  working curve formula
1.25e8      k1      first parameter
0.0         k2      second parameter
"""


def _moordyn_run(deck: Path, x, n_before=N_BEFORE, n_after=N_AFTER):
    """Run MoorDyn: Init, ``n_before`` coupling steps, SaveState (``<deck>.s0``), then
    ``n_after`` more steps, each followed by SaveState (``<deck>.s<k>``). Returns the body states
    and line node positions and velocities at the save, and the state files after it."""
    m = md.Create(str(deck))
    md.SetVerbosity(m, md.LEVEL_ERR)
    n = md.NCoupledDOF(m)
    x = list(x)[:n]
    v = [0.0] * n
    md.Init(m, x, v)
    for k in range(n_before):
        md.Step(m, x, v, k * DT, DT)
    md.SaveState(m, f"{deck}.s0")
    bodies = [np.array(md.GetBodyState(md.GetBody(m, i))) for i in range(1, md.GetNumberBodies(m) + 1)]
    nodes = []
    for i in range(1, md.GetNumberLines(m) + 1):
        ln = md.GetLine(m, i)
        N = md.GetLineN(ln)
        nodes.append((np.array([md.GetLineNodePos(ln, j) for j in range(N + 1)]),
                      np.array([md.GetLineNodeVel(ln, j) for j in range(N + 1)])))
    after = []
    for k in range(n_before, n_before + n_after):
        md.Step(m, x, v, k * DT, DT)
        md.SaveState(m, f"{deck}.s{k - n_before + 1}")
        after.append(Path(f"{deck}.s{k - n_before + 1}"))
    md.Close(m)
    return bodies, nodes, after


def _start(deck: Path, x, extra: str = "") -> System:
    model = read_deck(deck)
    model.options.fileIC = f"{deck}.s0"
    model.options.TmaxIC = 0.0
    if extra:
        model.options.InertialLoads = extra
    s = System(model, loads_at="last_stage")
    xm = np.asarray(x, dtype=float)[:s.n_coupled_dof]
    s.init(xm, np.zeros_like(xm))
    return s


def _state_gap(s: System, files, x) -> list[tuple[float, float, float]]:
    """Run ``s`` on a coupling step at a time and compare its whole state with MoorDyn's after
    each step, put into a second system by the same reader: (largest position [m] (and quaternion)
    difference, largest velocity difference [m/s, rad/s], largest line-state difference [m, rad])
    per step. The translational slots of pinned objects (not state) are left out."""
    ref = System(s.model, loads_at="last_stage")
    lay = s.layout
    used = np.ones(s.y.size, dtype=bool)
    R = lay.rigid
    for blk, free in ([(int(R.rod_blk[k]), R.rod_kind[k] == RodKind.FREE) for k in range(len(R.rod_kind))]
                      + [(int(R.body_blk[i]), R.body_kind[i] == BodyKind.FREE) for i in range(len(R.body_kind))]):
        if blk >= 0 and not free:
            q, u = lay.block_slices(blk)
            used[q.start:q.start + 3] = False
            used[u.start:u.start + 3] = False
    nq = lay.u_offset
    nu = 3 * lay.n_rows + 6 * lay.n_blocks
    xm = np.asarray(x, dtype=float)[:s.n_coupled_dof]
    out = []
    for k, f in enumerate(files):
        s.step(xm, np.zeros_like(xm), k * DT, DT)
        ref.y[:] = 0.0
        start_from_moordyn_state(ref, f)
        d = np.where(used, np.abs(s.y - ref.y), 0.0)
        out.append((float(d[:nq].max()), float(d[nq:nq + nu].max()), float(d[nq + nu:].max(initial=0.0))))
    return out


@pytest.fixture(scope="module")
def rigid(tmp_path_factory):
    d = tmp_path_factory.mktemp("file_ic_rigid")
    decks = {}
    for name, extra in (("full", ""), ("moordyn", "moordyn  InertialLoads")):
        p = d / f"rigid_{name}.txt"
        p.write_text(RIGID.format(extra=extra))
        decks[name] = (p, *_moordyn_run(p, X_CPL))
    return decks


def test_start_is_moordyns_state(rigid):
    deck, bodies, nodes, _ = rigid["moordyn"]
    s = _start(deck, X_CPL)
    for ln, (pos, vel) in zip(s.lines, nodes, strict=True):
        assert np.max(np.abs(ln.node_positions() - pos)) < 1e-12
        assert np.max(np.abs(ln.node_velocities() - vel)) < 1e-12
    for b, (pose, vel) in zip(s.bodies, bodies, strict=True):
        assert np.max(np.abs(b.pose() - pose)) < 1e-12
        assert np.max(np.abs(np.concatenate([b.velocity(), b.angular_velocity()]) - vel)) < 1e-12
    assert s.ic_report["file_ic"].endswith(".s0")
    # the viscoelastic stretches are MoorDyn's (moorline's state holds the same quantity)
    objs = read_moordyn_state(f"{deck}.s0")[1]
    L = s.layout.lines
    nb, nr, npnt = len(s.bodies), len(s.rods), len(s.points)
    for li in (1, 6):  # poly (mean-load EA_d) and nylon (constant EA_d)
        a = objs[nb + nr + npnt + li]
        x = s.layout.xs_offset + L.seg_xs[L.seg_ptr[li]:L.seg_ptr[li + 1]]
        assert a.shape == (L.seg_ptr[li + 1] - L.seg_ptr[li], 7)
        assert np.array_equal(s.y[x], a[:, 6])


def test_runs_on_as_moordyn(rigid):
    deck, _, _, files = rigid["moordyn"]
    gaps = _state_gap(_start(deck, X_CPL), files, X_CPL)
    for dq, du, dx in gaps:
        assert dq < 1e-9 and du < 1e-8 and dx < 1e-9, gaps


def test_default_inertial_loads_differ(rigid):
    """moorline's own inertial loads (the centripetal and gyroscopic loads of the free rod, which
    MoorDyn-C leaves out) take the same start elsewhere: the switch is what makes the two agree."""
    deck, _, _, files = rigid["full"]
    gaps = _state_gap(_start(deck, X_CPL), files, X_CPL)
    assert gaps[-1][1] > 1e-4, gaps
    gaps_m = _state_gap(_start(deck, X_CPL, extra="moordyn"), files, X_CPL)
    assert gaps_m[-1][1] < 1e-8, gaps_m


def test_zero_length_rod_joint(tmp_path):
    deck = tmp_path / "joint.txt"
    deck.write_text(JOINT)
    _, nodes, files = _moordyn_run(deck, [])
    s = _start(deck, [])
    for ln, (pos, vel) in zip(s.lines, nodes, strict=True):
        assert np.max(np.abs(ln.node_positions() - pos)) < 1e-12
        assert np.max(np.abs(ln.node_velocities() - vel)) < 1e-12
    gaps = _state_gap(s, files, [])
    assert max(g[0] for g in gaps) < 1e-7 and max(g[1] for g in gaps) < 1e-6 and max(g[2] for g in gaps) < 1e-7, gaps


def test_syrope_and_viscoelastic_states(tmp_path):
    if not OWC.is_file():
        pytest.skip(f"{OWC} not found (../shared is absent)")
    case = tmp_path / "case"
    case.mkdir()
    shutil.copy(OWC, case / "owc.dat")
    (case / "syrope.dat").write_text(SYROPE_CFG)
    deck = case / "ropes.txt"
    deck.write_text(ROPES)
    x = [40.6, 0.0, -50.0, 30.0, 10.0, -20.0]
    _, nodes, files = _moordyn_run(deck, x, n_before=3)
    s = _start(deck, x)
    for ln, (pos, vel) in zip(s.lines, nodes, strict=True):
        assert np.max(np.abs(ln.node_positions() - pos)) < 1e-12
        assert np.max(np.abs(ln.node_velocities() - vel)) < 1e-12
    gaps = _state_gap(s, files, x)
    for dq, du, dx in gaps:
        assert dq < 1e-10 and du < 1e-10 and dx < 1e-10, gaps


def _rewrite(src: Path, dst: Path, obj: int, rows: int, cols: int, fill: float = 0.0) -> None:
    """Copy MoorDyn state file ``src`` to ``dst`` with object ``obj`` replaced by a rows x cols
    array of ``fill`` (the header's word count adjusted)."""
    b = src.read_bytes()
    count = struct.unpack_from("<Q", b, 17)[0]
    o = 25
    parts = []
    for k in range(count):
        r, c = struct.unpack_from("<QQ", b, o)
        blob = b[o:o + 16 + 8 * r * c]
        if k == obj:
            blob = struct.pack("<QQ", rows, cols) + np.full(rows * cols, fill, "<f8").tobytes()
        parts.append(blob)
        o += 16 + 8 * r * c
    body = struct.pack("<Q", count) + b"".join(parts)
    dst.write_bytes(b[:9] + struct.pack("<Q", len(body) // 8) + body)


def test_bad_rigid_and_rope_rows(rigid, tmp_path):
    deck, _, _, _ = rigid["moordyn"]
    src = Path(f"{deck}.s0")
    # a body row of the wrong width, a zero quaternion, a NaN, a rope line without its stretch column
    cases = ((0, 1, 12, 0.0, "body 1: expected 1 x 13 values"),
             (0, 1, 13, 0.0, "body 1: the orientation quaternion"),
             (2, 1, 13, np.nan, "rod 1: the state holds a NaN"),
             (2 + 3 + 8 + 1, 7, 6, 0.0, "line 2: expected 8 x 7 values"))
    for obj, rows, cols, fill, msg in cases:
        bad = tmp_path / f"bad{obj}_{cols}.state"
        _rewrite(src, bad, obj, rows, cols, fill)
        model = read_deck(deck)
        model.options.fileIC = str(bad)
        model.options.TmaxIC = 0.0
        with pytest.raises(DeckError, match=msg) as e:
            System(model).init(np.array(X_CPL[:3]), np.zeros(3))
        assert str(bad) in str(e.value)
