"""Initial velocities, ``init(x, xd)`` with xd != 0 (issue 18), against MoorDyn-C 2.7.2 live.

What MoorDyn does (measured here, spec 3.17): its initial-condition solver moves the coupled objects
with xd while it iterates, so after ``Init`` they sit at x + xd * t_IC, t_IC being the pseudo-time
the solver ran (one dtIC window on catenary_3line: 1 s with dtIC 1, 0.5 s with dtIC 0.5), the lines
in equilibrium with them there; the first ``Step`` then starts from x again, a jump back of
xd * t_IC. The starting loads therefore depend on dtIC and on how fast the solver converged (the
issue's 576 vs 309 kN on MoorDyn's bench deck).

What moorline does: the initial conditions are solved with the coupled objects at x, at rest; xd
is their velocity from t = 0 (the lines at rest, their end nodes moving with the coupled objects).
The start is then the same as with xd = 0 except for the internal damping of the end segments,
which feel the end's velocity: |Td| = BA (xd . e) / l0 on the fairlead segment. This is the
documented difference (docs/moordyn_differences.md); with xd = 0 both codes agree.
"""

from __future__ import annotations

import numpy as np
import pytest

from moorline.io import read_deck
from moorline.system import System

from .driver import SHARED

md = pytest.importorskip("moordyn")
pytestmark = pytest.mark.oracle

DECK = SHARED / "conformance" / "inputs" / "catenary_3line" / "lines.txt"
X0 = np.array([5.2, 0.0, -70.0, -2.6, 4.5, -70.0, -2.6, -4.5, -70.0])
XD = np.array([1.0, 0.0, 0.5] * 3)


@pytest.fixture(scope="module")
def deck():
    if not DECK.is_file():
        pytest.skip(f"{DECK} not found (../shared absent)")
    return DECK


def _md_init(path, xd):
    m = md.Create(str(path))
    md.SetVerbosity(m, md.LEVEL_ERR)
    md.Init(m, X0.tolist(), list(xd))
    out = (np.array(md.GetPointPos(md.GetPoint(m, 4))), md.GetLineFairTen(md.GetLine(m, 1)))
    md.Close(m)
    return out


@pytest.mark.parametrize("dtIC", [1.0, 0.5])
def test_moordyn_moves_coupled_points_with_xd_during_its_ic(deck, tmp_path, dtIC):
    text = deck.read_text().replace("1.0           dtIC", f"{dtIC:<14}dtIC")
    path = tmp_path / "lines.txt"
    path.write_text(text)
    pos, _ = _md_init(path, XD)
    assert np.allclose(pos, X0[:3] + XD[:3] * dtIC, atol=1e-9)
    s = System(read_deck(path))
    s.init(X0, XD)
    assert np.allclose(s.points[3].position(), X0[:3], atol=1e-12)
    assert np.allclose(s.points[3].velocity(), XD[:3], atol=1e-12)


def test_moorline_start_with_xd(deck):
    """xd = 0: both codes start alike (1.4e-4, their IC solvers stop at different residuals).
    xd != 0: moorline's lines start where they start with xd = 0, and the fairlead segment's
    damping force is BA (xd . e) / l0 (to 1e-9)."""
    _, ten_md = _md_init(deck, np.zeros(9))
    a = System(read_deck(deck))
    a.init(X0, np.zeros(9))
    assert a.lines[0].fairlead_tension() == pytest.approx(ten_md, rel=1e-3)
    b = System(read_deck(deck))
    b.init(X0, XD)
    for la, lb in zip(a.lines, b.lines, strict=True):
        assert np.array_equal(la.node_positions(), lb.node_positions())
        assert np.array_equal(lb.node_velocities()[:-1], np.zeros_like(lb.node_velocities()[:-1]))
    L = b.layout.lines
    for li, ln in enumerate(b.lines):
        s = int(L.seg_ptr[li + 1]) - 1
        r = ln.node_positions()
        e = (r[-1] - r[-2]) / np.linalg.norm(r[-1] - r[-2])
        want = L.seg_BA[s] * abs(XD[3 * li:3 * li + 3] @ e) / L.seg_l0[s]
        assert want > 1e3  # the fairlead segments are damped (BA -0.8: a damping ratio)
        assert np.linalg.norm(ln.segment_damping_forces()[-1]) == pytest.approx(want, rel=1e-9)
        assert np.allclose(ln.segment_damping_forces()[:-1], 0.0, atol=1e-9)
