"""A line hanging from two ends above the seabed and lying on it between them
(:func:`moorline.quasistatic.catenary.grounded_catenary_nodes`), Newton statics' start for such lines
(:func:`moorline.system.initial.ground_dipping_lines`)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from moorline.quasistatic.catenary import STATUS_OK, catenary_nodes, grounded_catenary_nodes

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.parametrize("reverse", [False, True])
def test_inextensible_limit_is_the_seabed_catenary_through_a_grounded_end(reverse):
    """With one end on the seabed the shape is the one of :func:`catenary_nodes` with its seabed
    through the lower end: an independent solver (Newton on the elastic catenary's two end
    conditions). EA 1e15 N makes both inextensible; 1e-8 m covers both solvers' tolerances
    (1e-12 relative) on a 330 m line, measured 1.6e-10 m."""
    low = np.array([0.0, 0.0, -50.0])
    up = np.array([300.0, 20.0, 0.0])
    rA, rB = (up, low) if reverse else (low, up)
    ours = np.zeros((41, 3))
    ref = np.zeros((41, 3))
    H = grounded_catenary_nodes(rA, rB, 330.0, 40, 1e15, 100.0, -50.0, ours)
    status, HF, _ = catenary_nodes(rA, rB, 330.0, 40, 1e15, 100.0, True, 1e-12, ref)
    assert status == STATUS_OK
    assert H == pytest.approx(HF, rel=1e-9)
    assert np.abs(ours - ref).max() < 1e-8


def _shape(N=4000, EA=1e15, reverse=False):
    rA = np.array([10.0, -5.0, -30.0])  # 20 m above the seabed
    rB = np.array([10.0 + 0.6 * 250.0, -5.0 + 0.8 * 250.0, -42.0])  # 250 m away, 8 m above it
    if reverse:
        rA, rB = rB, rA
    out = np.zeros((N + 1, 3))
    H = grounded_catenary_nodes(rA, rB, 260.0, N, EA, 80.0, -50.0, out)
    return rA, rB, H, out


def test_shape_is_two_catenaries_and_a_straight_run_on_the_seabed():
    """Analytic checks of the inextensible shape: it spans the ends, its arc length is the line's
    (chords of 4000 segments: their sum falls short of the arc by l^3 / (24 a^2) per segment of
    length l on the curved parts, about 2e-5 m in all here), it lies in the
    vertical plane of the ends, never below the seabed, and each hanging part is the catenary
    z - zb = a (cosh(x / a) - 1) of a = H / W about its touchdown (1e-9 m)."""
    rA, rB, H, out = _shape()
    assert math.isfinite(H) and H > 0.0
    assert np.array_equal(out[0], rA) and np.array_equal(out[-1], rB)
    seg = np.linalg.norm(np.diff(out, axis=0), axis=1)
    assert seg.sum() == pytest.approx(260.0, abs=1e-4)
    assert seg.max() <= 260.0 / 4000 + 1e-12
    u = (rB[:2] - rA[:2]) / np.linalg.norm(rB[:2] - rA[:2])
    rel = out[:, :2] - rA[:2]
    assert np.abs(rel[:, 0] * u[1] - rel[:, 1] * u[0]).max() < 1e-9  # in the plane of the ends
    x = rel @ u
    z = out[:, 2]
    assert z.min() >= -50.0 - 1e-12
    ground = np.flatnonzero(z <= -50.0 + 1e-12)
    assert ground.size > 3000  # about 200 m of 260 on the seabed
    a = H / 80.0
    # touchdowns: where a catenary of parameter a, horizontal there, reaches each end's height
    tdA = a * math.acosh(1.0 + 20.0 / a)
    tdB = 250.0 - a * math.acosh(1.0 + 8.0 / a)
    assert tdA < x[ground[0]] < x[ground[-1]] < tdB
    hangA = slice(0, ground[0])
    hangB = slice(ground[-1] + 1, None)
    assert np.allclose(z[hangA] + 50.0, a * (np.cosh((x[hangA] - tdA) / a) - 1.0), atol=1e-9, rtol=0)
    assert np.allclose(z[hangB] + 50.0, a * (np.cosh((x[hangB] - tdB) / a) - 1.0), atol=1e-9, rtol=0)


def test_end_reversal_gives_the_same_nodes_in_reverse():
    _, _, H, out = _shape(N=60, EA=5e8)
    _, _, Hr, outr = _shape(N=60, EA=5e8, reverse=True)
    assert Hr == pytest.approx(H, rel=1e-12)
    assert np.abs(outr[::-1] - out).max() < 1e-9


def test_stretch_by_the_seabed_tension():
    """The elastic shape is the inextensible one of the stretched length L (1 + H / EA) (one
    fixed-point pass: H of the unstretched shape; the run on the seabed is then stretched by
    H / EA to that pass's accuracy, 1e-3 of H / EA here)."""
    _, _, H0, stiff = _shape(N=300)
    _, _, H, soft = _shape(N=300, EA=2e6)
    on = np.flatnonzero(soft[:, 2] <= -50.0 + 1e-12)
    run = np.linalg.norm(np.diff(soft[on], axis=0), axis=1)
    strain = run / (260.0 / 300) - 1.0
    assert np.allclose(strain, H0 / 2e6, rtol=1e-3)
    assert np.abs(stiff - soft).max() > 1e-3


@pytest.mark.parametrize("case, args", [
    ("buoyant", dict(W=-10.0)),
    ("weightless", dict(W=0.0)),
    ("too short to reach the seabed", dict(L=252.0)),
    ("too long for a double L", dict(L=250.0 + 20.0 + 8.0 + 1.0)),
    ("no longer than the span", dict(L=250.0)),
    ("vertical", dict(rB=np.array([10.0, -5.0, -42.0]))),
])
def test_no_grounded_shape(case, args):
    kw = dict(rA=np.array([10.0, -5.0, -30.0]), rB=np.array([160.0, 195.0, -42.0]), L=260.0, N=20, EA=1e9,
              W=80.0, zb=-50.0)
    kw.update(args)
    out = np.full((21, 3), 7.0)
    assert math.isnan(grounded_catenary_nodes(out=out, **kw)), case
    assert np.all(out == 7.0)


def test_lazy_wave_cable_starts_grounded_and_reaches_the_same_equilibrium(monkeypatch):
    """The lazy-wave benchmark cable's hub line hangs from a connector 2 m above the seabed: its
    catenary start ran through the seabed and, lifted onto it, left its segments 2-11 % slack, and
    its RK2 start took 1352 Newton iterations (seabed-blend continuation). Started grounded, the
    first Newton solve gets within the residual tolerance in 37 iterations; a touchdown node then
    cycles across the contact law's kink and Newton stops on :data:`STALL_ITERS` (41 in all).
    The equilibrium is the one of the old route, catenary start and no stall test (1352 iterations,
    464 since the static Jacobian's smaller finite-difference step, :data:`STATIC_FD_REL`; more than
    five times the new route's in both cases; converged to 1e-9 m position updates), to 1e-5 m: the
    stalled iterate meets the residual tolerance (1e-5 m/s^2; 2.6e-6 reached), not the update one,
    and the buoyant arch's vertical mode is soft (measured: line 2's nodes 5.5e-6 m higher, the rest within 1e-8 m)."""
    from moorline import System
    from moorline.core import statics
    from moorline.system import initial

    deck = ROOT / "benchmarks" / "decks" / "lazy_wave_cable.dat"

    def start():
        s = System.from_file(deck)
        x0 = s.deck_coupled_positions()
        s.init(x0, np.zeros_like(x0))
        assert s.ic_report["converged"]
        return s.y.copy(), s.ic_report

    y_new, new = start()
    monkeypatch.setattr(initial, "ground_dipping_lines", lambda sys, W: [])
    monkeypatch.setattr(statics, "STALL_ITERS", 10**9)
    y_old, old = start()
    assert new["catenary_grounded"] == [1]
    assert new["method"] == "newton" and new["iterations"] < 100, new
    assert "catenary_grounded" not in old and old["iterations"] > 5 * new["iterations"], old
    assert np.abs(y_new - y_old).max() < 1e-5
