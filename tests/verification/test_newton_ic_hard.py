"""Newton statics on the public decks it used to give up on (issue 18): slack lines, touchdowns and a
free joint, where the first pseudo-transient Newton solve from the catenary start stalls and the
continuation stages of :func:`moorline.system.initial.newton_ic` must finish the job.

1. ``lifting.txt`` (MoorDyn's tests): a 1 t point on a 100.5 m neutrally buoyant line whose deck
   start is 0.5 m slack. Analytic: the point hangs at -L (1 + m g / EA) and the top tension is
   m g plus the line's (here tiny) net weight. Tolerances: 1e-7 m and 1e-7 relative, a hundred
   times the converged residual's effect (1e-7 m/s^2 on a 1 t point against 2e8 N/m segments).
2. MoorPy's ``case2.dat`` (chain and polyester joined by a free, massless point): the joint within
   3 cm of MoorPy's analytic catenaries (measured 1.4 cm: 25 and 15 lumped-mass segments against
   exact catenaries) and the polyester's end tensions within 0.2 % (measured 0.08 %). The chain's
   tension at the joint is not compared: moorline reports the last segment's tension, MoorPy the
   end's, which differ by half a segment's weight (1.4 %).
3. MoorPy's ``case5.dat``: 890 m of chain between points 500 m apart, too long to lie as an "L".
   Started from the folded "L" (:func:`~moorline.system.initial.folded_l_nodes`), plain Newton
   converges to a vertical hang: zero tension at the anchor as in MoorPy, and the top segment's
   tension is MoorPy's fairlead tension less half a segment's submerged weight, within 0.3 %
   (measured 0.13 %: where the touchdown falls between two nodes 22 m apart, a lumped model can be
   off by up to half a segment's weight, 3.8 %).
4. ``viv.txt`` (a riser in a current with VIV lift): the start is measured as it was solved,
   without VIV, whose lift in a current is an oscillating excitation, not a static load. A
   converged start used to be reported 0.11 m/s^2 off (logged as an error; ``moorline run`` would
   exit non-zero).
5. Invariant: the equilibrium does not depend on the route. case2 solved by the seabed-blend
   continuation and, with that stage switched off, by implicit relaxation and Newton: the same
   state within 1e-6 m.
6. MoorPy's ``case6.dat`` with its segments doubled, with the implicit scheme: its short first
   solves (30 iterations) and the relaxation routes do not find the equilibrium, which RK2's long
   ones (250) do. The implicit scheme has no explicit start to fall back on, so it raised; it now
   takes the explicit schemes' budgets last. Invariant: the state is the one the implicit scheme
   reaches with those budgets from the start (the relaxation routes tried before leave nothing
   behind), within 1e-6 m, the update tolerance's thousandfold. (RK2's own start differs by mm
   on the seabed: the implicit scheme's contact law is blended, MoorDyn's is not.) MoorDyn's
   BeamCantilevered.txt was the case at its own mesh, until the static Jacobian's smaller step
   (:data:`moorline.core.statics.STATIC_FD_REL`) let its first solve converge in 6 iterations.
7. A chain hanging free: the tension near a free hanging end falls to the end node's weight, so
   its segments sit within 1e-7 m of the slack kink, which the Jacobian's finite-difference step
   must not straddle (:data:`moorline.core.statics.STATIC_FD_REL`). A 30 m chain on 60 segments,
   its free end started 6 m aside, must come to the analytic lumped hang: vertical, each segment
   stretched by the weight below it, z_k exact to 1e-9 m. MoorDyn's test_dynamic_currents.txt
   (the same chain in a current) with its segments doubled must start by Newton. With a step of
   1e-7 of the coordinate, both stayed at 0.04-38 m/s^2 and fell back on MoorDyn's unconverged
   stationary solver.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

import moorline.system.initial as initial
from moorline.io import read_deck
from moorline.model import Environment, Model, Options
from moorline.system import System

SHARED = Path(os.environ.get("MOORLINE_SHARED", Path(__file__).resolve().parents[3] / "shared"))
DECKS = SHARED / "public_decks"
LIFTING = DECKS / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring" / "lifting.txt"
CASE2 = DECKS / "NREL+MoorPy" / "tests" / "case2.dat"
CASE5 = DECKS / "NREL+MoorPy" / "tests" / "case5.dat"
CASE6 = DECKS / "NREL+MoorPy" / "tests" / "case6.dat"
CURRENTS = DECKS / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring" / "wavekin_3" / "test_dynamic_currents.txt"
VIV = DECKS / "FloatingArrayDesign+MoorDyn" / "tests" / "Mooring" / "viv" / "viv.txt"

pytestmark = pytest.mark.slow


def _need(path: Path) -> None:
    if not path.exists():
        pytest.skip(f"{path} not available")


def _started(path: Path, scheme: str | None = None, refine: int = 1) -> System:
    """The deck started, with ``scheme`` and the segments of every line multiplied by ``refine``."""
    model = read_deck(path)
    for ln in model.lines:
        ln.N *= refine
    s = System(model, scheme=scheme)
    x0 = s.deck_coupled_positions()
    s.init(x0, np.zeros_like(x0))
    return s


def _converged(path: Path, method: str) -> System:
    """The deck started (skipped if absent), its start converged by ``method`` and at rest."""
    _need(path)
    s = _started(path)
    rep = s.ic_report
    assert rep["converged"] and rep["method"] == method, rep
    assert rep["residual"] < 1e-5
    return s


def test_lifting_point_hangs_at_the_analytic_stretch():
    s = _converged(LIFTING, "relaxation-newton alternation")
    lt = s.model.line_types["main"]
    g = s.layout.env.g
    L = 100.5
    mg = 1.0e3 * g
    w_net = (lt.w - 1000.0 * np.pi / 4.0 * lt.d ** 2) * g  # N/m, -1.6e-5: neutrally buoyant to 2e-6
    z = s.points[1].position()[2]
    assert z == pytest.approx(-L * (1.0 + mg / lt.EA), abs=1e-7)
    assert s.lines[0].anchor_tension() == pytest.approx(mg + w_net * L, rel=1e-7)


def _moorpy(path):
    mp = pytest.importorskip("moorpy")
    ms = mp.System(file=str(path))
    ms.initialize()
    ms.solveEquilibrium()
    return ms


def test_moorpy_case2_free_joint_against_moorpy():
    _need(CASE2)
    ms = _moorpy(CASE2)
    s = _started(CASE2)
    rep = s.ic_report
    assert rep["converged"] and rep["method"] == "seabed-blend continuation + newton", rep
    joint = next(p for p in ms.pointList if p.type == 0)
    assert np.linalg.norm(s.points[1].position() - joint.r) < 0.03
    poly = ms.lineList[1]
    assert s.lines[1].anchor_tension() == pytest.approx(poly.TA, rel=2e-3)
    assert s.lines[1].fairlead_tension() == pytest.approx(poly.TB, rel=2e-3)
    assert s.lines[0].anchor_tension() == pytest.approx(ms.lineList[0].TA, rel=2e-3)


def test_the_equilibrium_does_not_depend_on_the_route(monkeypatch):
    _need(CASE2)
    a = _started(CASE2)
    assert a.ic_report["method"] == "seabed-blend continuation + newton"
    monkeypatch.setattr(initial, "BLEND_WIDTHS", ())
    b = _started(CASE2)
    assert b.ic_report["converged"] and "relaxation" in b.ic_report["method"], b.ic_report
    n = a.layout.u_offset
    assert np.max(np.abs(a.y[:n] - b.y[:n])) < 1e-6


def test_implicit_scheme_falls_back_on_the_explicit_budgets(monkeypatch):
    _need(CASE6)

    a = _started(CASE6, "GenAlpha", refine=2)
    rep = a.ic_report
    assert rep["converged"] and rep["method"].endswith("(after the relaxation routes)"), rep
    assert rep["residual"] < 1e-5
    monkeypatch.setattr(initial, "NEWTON_FIRST_IT", initial.NEWTON_FIRST_IT_EXPLICIT)
    b = _started(CASE6, "GenAlpha", refine=2)
    assert b.ic_report["converged"] and "relaxation" not in b.ic_report["method"], b.ic_report
    n = a.layout.u_offset
    assert np.max(np.abs(a.y[:n] - b.y[:n])) < 1e-6


def test_moorpy_case5_line_too_long_for_an_l():
    _need(CASE5)
    ms = _moorpy(CASE5)
    s = _started(CASE5)
    rep = s.ic_report
    assert rep["converged"] and rep["method"] == "newton" and rep["catenary_too_long"] == [1], rep
    ln = s.lines[0]
    assert ln.anchor_tension() == 0.0 and ms.lineList[0].TA == 0.0
    lt = s.model.line_types["main"]
    w = (lt.w - s.layout.env.rho * np.pi / 4.0 * lt.d ** 2) * s.layout.env.g
    half = 0.5 * 890.0 / 40
    assert ln.fairlead_tension() == pytest.approx(ms.lineList[0].TB - w * half, rel=3e-3)


def test_viv_start_is_measured_without_the_lift():
    s = _converged(VIV, "newton")
    assert s.layout.lines.xs_ctl[initial.XC_VIV] == 1.0  # VIV is on again for the run


def test_chain_hanging_free_comes_to_the_analytic_hang():
    g, rho, d, mass, EA, L, N = 9.80665, 1025.0, 0.01333, 1.1, 7.51e6, 30.0, 60
    m = Model(env=Environment(g=g, rho=rho, depth=400.0), options=Options(dtM=1e-4, tScheme="RK2"))
    m.add_line_type("chain", d=d, w=mass, EA=EA, BA=-0.5, EI=0.0, Cd=2.4, Ca=0.0, CdAx=0.1, CaAx=0.0)
    top = np.array([18.0, 5.0, -10.0])
    a = m.add_point("fixed", tuple(top))
    b = m.add_point("free", (24.0, 5.0, -38.0))
    m.add_line("chain", a, b, L=L, N=N)
    s = System(m)
    s.init()
    rep = s.ic_report
    assert rep["converged"] and "newton" in rep["method"], rep
    r = s.lines[0].node_positions()
    # segment j from the bottom (j = 1..N) carries the submerged weight of j - 1/2 segments
    w_sub = (mass - rho * np.pi * d * d / 4.0) * g
    l0 = L / N
    T = w_sub * l0 * (np.arange(N, 0, -1) - 0.5)  # segments from the top
    z = top[2] - np.concatenate([[0.0], np.cumsum(l0 * (1.0 + T / EA))])
    np.testing.assert_allclose(r[:, 2], z, rtol=0.0, atol=1e-9)
    np.testing.assert_allclose(r[:, :2], np.broadcast_to(top[:2], (N + 1, 2)), rtol=0.0, atol=1e-9)


def test_chain_hanging_in_a_current_on_a_doubled_mesh_starts_by_newton():
    _need(CURRENTS)
    s = _started(CURRENTS, "RK2", refine=2)  # (its ICNewton is the default, -1: Newton first)
    rep = s.ic_report
    assert rep["converged"] and "newton" in rep["method"], rep
    assert rep["residual"] < 1e-5
