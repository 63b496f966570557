"""MoorDyn's local-time-step Euler (``LEuler``) in the compiled time loop.

LEuler is Euler in which a line is evaluated only when its own update interval (0.999 CFL times
its segment period) has elapsed; in between its whole derivative is reused. It runs as the time
loop's Euler step with the lines' bookkeeping before and after the one derivative evaluation
(``core.schemes.leuler_begin``/``leuler_end``). Checked here on MoorDyn's ``local_euler/hanging.txt``
(one hanging chain split at a free point into two halves of 76 and 152 segments, so the coarse
half may skip every other step):

At a quarter of the deck's own dtM (its CFL 0.1 gives 0.76 ms, at which plain Euler is unstable
on this chain), so the fine half is evaluated every 4th step and the coarse half every 8th:

1. with every line's interval set to zero, LEuler evaluates every line every step and is Euler
   bit for bit (same arithmetic, tolerance zero);
2. with the deck's intervals the lines are skipped between updates: the result differs from
   Euler (so check 1 can fail), yet stays close to it: the largest difference of the fairlead
   tension is within 3 % of its mean (measured 1.1 %: the held derivative, up to 8 steps old, lags
   the stiff chain's axial response; a line whose derivative were never refreshed would move at
   constant acceleration and leave any such bound within the second);
3. the intervals are each line's own: the coarse line's interval is twice the fine line's.

The comparison with MoorDyn itself is ``tests/conformance/test_oracle_v2_features.py``.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np
import pytest

from moorline.core.schemes import SP_LINES
from moorline.io import read_deck
from moorline.system import System

SHARED = Path(os.environ.get("MOORLINE_SHARED", Path(__file__).resolve().parents[3] / "shared"))
HANGING = SHARED / "public_decks" / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring" / "local_euler" / "hanging.txt"


def run(scheme: str, zero_intervals: bool = False, duration: float = 1.0, dt: float = 0.01):
    """Fairlead tensions of both lines at every coupling step while the vessel points surge 0.5 m,
    at a quarter of the deck's dtM."""
    if not HANGING.is_file():
        pytest.skip(f"{HANGING} not available")
    model = read_deck(HANGING)
    s = System(model, scheme=scheme, dtM=0.25 * System(model).dtM)
    nl = len(s.model.lines)
    if zero_intervals:
        s.scheme_params[SP_LINES:SP_LINES + nl] = 0.0
    x0 = s.deck_coupled_positions()
    d = np.array([1.0 if lab.endswith("_x") else 0.0 for lab in s.coupled_dof_labels])

    def X(t):
        return x0 + d * 0.5 * math.sin(math.pi * min(t / duration, 1.0)) ** 2

    s.init(X(0.0), np.zeros(x0.size))
    out = []
    for k in range(int(round(duration / dt))):
        xk = X(k * dt)
        s.step(xk, (X((k + 1) * dt) - xk) / dt, k * dt, dt)
        out.append(s.line_end_tensions()[:, 1].copy())
    return s, np.array(out)


def test_leuler_every_line_every_step_is_euler():
    _, le = run("LEuler", zero_intervals=True)
    _, ref = run("Euler")
    assert np.array_equal(ref, le), f"largest difference {np.max(np.abs(ref - le)):.3g} N"


def test_leuler_skips_lines_between_updates():
    s, le = run("LEuler")
    nl = len(s.model.lines)
    steps = s.scheme_params[SP_LINES:SP_LINES + nl] / s.dtM
    # the coarse half (76 segments of 5 m) has twice the segment period of the fine one (152 of 2.5 m)
    assert steps[0] == pytest.approx(2.0 * steps[1], rel=1e-9)
    assert steps[0] > 1.0, f"update interval of the coarse line {steps[0]:.3g} steps: nothing is skipped"
    _, eu = run("Euler")
    diff = np.max(np.abs(le - eu)) / np.mean(np.abs(eu))
    assert diff > 0.0, "LEuler with line intervals above dtM gave Euler's result: no line was skipped"
    assert diff < 3e-2, f"LEuler differs from Euler by {diff:.3g} of the mean fairlead tension"


COMPLEX = HANGING.parent / "complex_system.txt"


def test_leuler_reads_nothing_a_line_not_evaluated_leaves_behind():
    """A line not evaluated in a step keeps its loads of its last update, and the evaluation does
    not bring its interior nodes' positions and velocities up to date (Work.r, Work.v), but for the
    nodes next to its ends, from which a zero-length rod takes its axis (spec 3.14.4). Checked on
    MoorDyn's ``local_euler/complex_system.txt`` (four zero-length rods between its cables, lines
    updated every 1 to 17 steps): with every line's interior nodes set to NaN before each coupling
    step, the forces returned and the state reached are the same bit for bit (tolerance zero: no
    arithmetic differs). Were a node read that the evaluation leaves stale, the read would give NaN
    and change the results (not always into NaN: ``zero_length_axes`` keeps a rod's last axis when
    its sum is not finite): bringing none of a skipped line's nodes up to date fails this test."""
    if not COMPLEX.is_file():
        pytest.skip(f"{COMPLEX} not available")

    def run(poison: bool):
        s = System(read_deck(COMPLEX))
        x0 = s.deck_coupled_positions()
        s.init(x0, np.zeros(x0.size))
        nodes = s.layout.lines.node_ptr
        forces = []
        for k in range(20):
            if poison:
                for li in range(len(s.model.lines)):
                    s.work.r[nodes[li] + 1:nodes[li + 1] - 1] = np.nan
                    s.work.v[nodes[li] + 1:nodes[li + 1] - 1] = np.nan
            forces.append(s.step(x0 + [0.01 * k, 0.0, 0.0], [1.0, 0.0, 0.0], 0.01 * k, 0.01).copy())
        return s, np.array(forces)

    s, f = run(False)
    nl = len(s.model.lines)
    assert np.any(s.scheme_params[SP_LINES:SP_LINES + nl] > 2.0 * s.dtM), "no line is skipped between updates"
    sp, fp = run(True)
    assert np.all(np.isfinite(f))
    assert np.array_equal(f, fp), f"largest force difference {np.max(np.abs(f - fp)):.3g} N"
    assert np.array_equal(s.y, sp.y)


VISCO_DECK = """two viscoelastic ropes of different segment lengths (moorline test deck)
---------------------- LINE TYPES ----------------------
TypeName  Diam    Mass/m  EA                     BA/-zeta  EI  Cd   Ca   CdAx  CaAx
(name)    (m)     (kg/m)  (N)                    (N-s/-)   (-) (-)  (-)  (-)   (-)
rope      0.1438  22.42   1.424e+08|1.586e+08|0.4  5E4|1E6   0   1.2  1.0  0.2   0.0
---------------------- POINTS ----------------------
ID  Attachment  X     Y    Z      Mass  Volume  CdA  Ca
(#) (-)         (m)   (m)  (m)    (kg)  (m^3)   (m^2) (-)
1   Fixed       0.0   0.0  -50.0  0     0       0    0
2   Coupled     10.05 0.0  -50.0  0     0       0    0
3   Fixed       0.0   5.0  -50.0  0     0       0    0
4   Coupled     20.1  5.0  -50.0  0     0       0    0
---------------------- LINES ----------------------
ID  LineType  AttachA  AttachB  UnstrLen  NumSegs  LineOutputs
(#) (name)    (#)      (#)      (m)       (-)      (-)
1   rope      1        2        10.0      4        -
2   rope      3        4        20.0      4        -
---------------------- OPTIONS ----------------------
0.0              g
100              WtrDpth
1025             rho
0                TmaxIC
0.05             CFL
LEuler           tScheme
--------------------- need this line ----------------------
"""


def test_leuler_keeps_a_skipped_lines_derivative_rows(tmp_path):
    """Local Euler evaluates into the derivative it carries between steps, and the derivative
    leaves there the rows of a line not evaluated now: its interior nodes' velocities and
    accelerations and its line states (here the viscoelastic segments' stretch rates) stay those
    of its last update (MoorDyn-C's LEuler). Checked step by step on two stretched viscoelastic
    ropes whose segments differ in length by 2x, at a tenth of the deck's dtM so that both are
    skipped between updates: on every step, a line not due leaves its rows unchanged bit for bit,
    and a line due changes them (the fairleads surge, so the derivative moves)."""
    path = tmp_path / "visco2.txt"
    path.write_text(VISCO_DECK)
    model = read_deck(path)
    s = System(model, scheme="LEuler", dtM=2e-5)
    x0 = s.deck_coupled_positions()
    d = np.array([1.0 if lab.endswith("_x") else 0.0 for lab in s.coupled_dof_labels])
    s.init(x0, np.zeros(x0.size))
    La = s.layout.lines
    dims = s.layout.rigid.dims
    n3, n6 = int(dims[0]), int(dims[1])
    uoff = 3 * n3 + 7 * n6
    xo = 6 * n3 + 13 * n6 + int(dims[2])
    nl = len(s.model.lines)
    rows = []
    for li in range(nl):
        r = [3 * La.node_row[n] + c for n in range(La.node_ptr[li] + 1, La.node_ptr[li + 1] - 1) for c in range(3)]
        r = r + [uoff + i for i in r]
        xs = [xo + x for x in La.seg_xs[La.seg_ptr[li]:La.seg_ptr[li + 1]] if x >= 0]
        assert xs, f"line {li + 1} has no viscoelastic states"
        rows.append(np.array(r + xs))
    steps = s.scheme_params[SP_LINES:SP_LINES + nl] / s.dtM
    assert np.all(steps > 2.0) and not np.isclose(steps[0], steps[1]), steps
    skipped = due = 0
    for k in range(400):
        before = s._S[0].copy()
        s.step(x0 + 0.2 * d * s.t, 0.2 * d, s.t, s.dtM)
        since = s.scheme_params[SP_LINES + nl:SP_LINES + 2 * nl]
        for li in range(nl):
            if since[li] > 1.0001 * s.dtM:
                skipped += 1
                assert np.array_equal(s._S[0][rows[li]], before[rows[li]]), f"step {k}: line {li + 1} not kept"
            else:
                due += 1
                if k > 0:
                    assert not np.array_equal(s._S[0][rows[li]], before[rows[li]]), f"step {k}: line {li + 1}"
    assert np.all(np.isfinite(s.y))
    assert skipped > 300 and due > 20, (skipped, due)
