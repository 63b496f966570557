"""Invariants of the line and point physics (DESIGN.md, tests/kernels).

* Newton's third law and momentum balance of the derivative kernel, for arbitrary states: the
  internal (tension and damping) forces of a line sum to zero over its nodes; what a line end puts
  on its point is the end node's net force; summed over the whole system, mass times acceleration
  of the free DOFs plus the loads on the fixed and coupled points equals the external loads.
* A/B reversal: a line defined from B to A gives the same physics, mirrored in node order.
* Rotation about z, horizontal translation and the mirror y -> -y leave tensions unchanged and
  transform positions and coupled forces accordingly, after the initial-condition solve and after
  20 s of dynamics with an imposed fairlead motion.

Tolerances of the transformed runs are 1e-6 relative, not exact: the transformed system is
computed with different floating-point operands (rotated coordinates are rounded, sums run in a
different order after A/B reversal: tangents r[i+1] - r[i-1] become r[i-1] - r[i+1], segment
strains are formed from the other end, the point sums its lines' end forces in the same order but
with rounded operands), and these last-bit differences are carried by an iterative
initial-condition solve and thousands of time steps. Any physics error (a sign, a wrong end, a
direction-dependent term) is orders of magnitude larger.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from moorline.model import Curve, Environment, Model, Options
from moorline.system import System

#: Newton's third law / momentum balance in one evaluation (brief: 1e-9 relative to the loads)
RTOL_BALANCE = 1e-9
#: transformed systems after IC and dynamics (see module docstring)
RTOL_INVARIANT = 1e-6

DT_OUT = 0.1  # outer coupling step [s]
T_DYN = 20.0  # dynamics after the initial-condition solve [s]


# ---------------------------------------------------------------------------------- models
def add_types(m: Model):
    m.add_line_type("chain", d=0.1, w=100.0, EA=8.0e8, BA=-0.8, Cd=1.2, Ca=1.0, CdAx=0.2, CaAx=0.5)
    m.add_line_type("poly", d=0.15, w=20.0, EA=Curve([0.0, 0.01, 0.02, 0.05], [0.0, 8.0e5, 2.0e6, 6.0e6]),
                    BA=-0.6, Cd=1.3, Ca=0.9, CdAx=0.01, CaAx=0.1)


def env():
    return Environment(depth=100.0, mu=0.5, fric_damp=200.0, stat_dyn=1.3)


def opts():
    return Options(dtM=0.002, TmaxIC=60.0, threshIC=1e-4, dtIC=0.5)


def three_line_model(angle=0.0, shift=(0.0, 0.0), mirror_y=False) -> Model:
    """Three chains from anchors at radius 380 m to coupled fairleads; rotated by ``angle`` [rad]
    about z, then mirrored y -> -y if asked, then shifted horizontally by ``shift`` [m]."""
    m = Model(env=env(), options=opts())
    add_types(m)
    for k in range(3):
        psi = math.radians(10.0 + 120.0 * k)
        a = transform(np.array([380.0 * math.cos(psi), 380.0 * math.sin(psi), -100.0]), angle, shift, mirror_y)
        f = transform(np.array([8.0 * math.cos(psi), 8.0 * math.sin(psi), -12.0]), angle, shift, mirror_y)
        pa = m.add_point("fixed", a)
        pf = m.add_point("coupled", f)
        m.add_line("chain", pa, pf, L=400.0 + 5.0 * k, N=20)
    return m


def clump_model(reverse: bool) -> Model:
    """Anchor -> chain -> free clump weight -> polyester -> coupled fairlead; ``reverse`` defines
    both lines from B to A."""
    # the legacy dynamic relaxation converges here (the stationary solver stalls on the stiff chain)
    m = Model(env=env(), options=Options(dtM=0.002, ICgenDynamic=1, TmaxIC=200.0, threshIC=1e-4, dtIC=2.0))
    add_types(m)
    anchor = m.add_point("fixed", (-260.0, 20.0, -100.0))
    clump = m.add_point("free", (-110.0, 8.0, -70.0), m=3000.0, V=0.4, CdA=1.0, Ca=0.8)
    fair = m.add_point("coupled", (0.0, 0.0, -10.0))
    for lt, a, b, L, N in (("chain", anchor, clump, 170.0, 19), ("poly", clump, fair, 125.0, 12)):
        if reverse:
            a, b = b, a
        m.add_line(lt, a, b, L=L, N=N)
    return m


def transform(r, angle, shift, mirror_y):
    c, s = math.cos(angle), math.sin(angle)
    out = np.array([c * r[0] - s * r[1], s * r[0] + c * r[1], r[2]])
    if mirror_y:
        out[1] = -out[1]
    out[0] += shift[0]
    out[1] += shift[1]
    return out


def surge(t, direction):
    """Fairlead offset [m]: a 2 m, 12 s surge ramped in over 5 s, along ``direction``."""
    ramp = min(t / 5.0, 1.0)
    return 2.0 * ramp * math.sin(2.0 * math.pi * t / 12.0) * np.asarray(direction, dtype=float)


def snapshot(sys: System) -> dict:
    return {"ic": dict(sys.ic_report),
            "r": [ln.node_positions() for ln in sys.lines],
            "T": [ln.segment_tensions() for ln in sys.lines],
            "p": np.array([p.position() for p in sys.points]),
            "f": sys.coupled_forces().reshape(-1, 3)}


def run(model: Model, direction) -> tuple[dict, dict]:
    """IC solve, then T_DYN seconds of surge along ``direction`` driven as MoorDyn's coupling
    interface is (x_k, v_k = (X(t_{k+1}) - X(t_k))/dt). Returns snapshots after IC and at the end."""
    sys = System(model)
    x0 = sys.deck_coupled_positions()
    sys.init(x0, np.zeros_like(x0))
    after_ic = snapshot(sys)
    n = x0.size // 3

    def X(t):
        return x0 + np.tile(surge(t, direction), n)

    nsteps = int(round(T_DYN / DT_OUT))
    for k in range(nsteps):
        t = k * DT_OUT
        sys.step(X(t), (X(t + DT_OUT) - X(t)) / DT_OUT, t, DT_OUT)
    return after_ic, snapshot(sys)


def assert_same_physics(a: dict, b: dict, pos_map, vec_map, *, reverse=False, what=""):
    """``b`` is ``a`` transformed: positions by ``pos_map``, force vectors by ``vec_map``; with
    ``reverse`` the lines of ``b`` run B -> A."""
    worst = {"T": 0.0, "r": 0.0, "f": 0.0}
    for ra, rb, Ta, Tb in zip(a["r"], b["r"], a["T"], b["T"], strict=True):
        if reverse:
            rb, Tb = rb[::-1], Tb[::-1]
        tscale = np.max(Ta)
        worst["T"] = max(worst["T"], float(np.max(np.abs(Tb - Ta)) / tscale))
        span = float(np.max(np.ptp(ra, axis=0)))
        want = np.array([pos_map(r) for r in ra])
        worst["r"] = max(worst["r"], float(np.max(np.linalg.norm(rb - want, axis=1)) / span))
    if a["f"].size:
        fscale = np.max(np.linalg.norm(a["f"], axis=1))
        want = np.array([vec_map(f) for f in a["f"]])
        worst["f"] = float(np.max(np.linalg.norm(b["f"] - want, axis=1)) / fscale)
    for k, v in worst.items():
        assert v <= RTOL_INVARIANT, f"{what}: {k} differs by {v:.3g} relative ({worst})"
    return worst


# ---------------------------------------------------------------------------------- Newton's third law
def perturbed_system(seed: int) -> System:
    """The clump system on its catenary start, every free DOF moved and set in motion at random,
    with random water velocity and acceleration at every node and point."""
    rng = np.random.default_rng(seed)
    sys = System(clump_model(reverse=bool(seed % 2)))
    x0 = sys.deck_coupled_positions()
    sys.init(x0, rng.normal(scale=0.5, size=x0.size), solve_ic=False)
    lp = [ln.node_positions() + rng.normal(scale=0.3, size=(ln.n_segments + 1, 3)) for ln in sys.lines]
    lv = [rng.normal(scale=0.5, size=(ln.n_segments + 1, 3)) for ln in sys.lines]
    for r, v in zip(lp, lv, strict=True):
        # a few nodes pushed onto / into the seabed, slowly sliding
        low = r[:, 2] < -97.0
        r[low, 2] = -100.0 - rng.uniform(-2e-3, 2e-3, size=low.sum())
        v[low, 2] *= 1e-3
    pp = np.array([p.position() for p in sys.points]) + rng.normal(scale=0.5, size=(3, 3))
    pv = rng.normal(scale=0.4, size=(3, 3))
    W = sys.work
    W.U[...] = rng.normal(scale=0.6, size=W.U.shape)
    W.Ud[...] = rng.normal(scale=0.3, size=W.Ud.shape)
    W.pU[...] = rng.normal(scale=0.6, size=W.pU.shape)
    sys.set_state(lp, lv, pp, pv)  # re-evaluates every load
    return sys


def point_own_loads(sys: System, p: int) -> np.ndarray:
    """External load of a point itself (spec 3.13): constant force, buoyancy - weight, drag."""
    pt = sys.model.points[p]
    E = sys.model.env
    u = sys.work.pU[p] - sys.work.pv[p]
    return pt.F_ext + np.array([0.0, 0.0, E.g * (E.rho * pt.V - pt.m)]) \
        + 0.5 * E.rho * pt.CdA * np.linalg.norm(u) * u


@pytest.mark.parametrize("seed", [11, 12, 13, 14])
def test_internal_forces_cancel_over_each_line(seed):
    sys = perturbed_system(seed)
    W = sys.work
    n_contact = 0
    ptr = sys.layout.lines.node_ptr
    for li, ln in enumerate(sys.lines):
        n = slice(int(ptr[li]), int(ptr[li + 1]))
        external = W.W[n] + W.Fhyd[n] + W.Fbed[n]
        internal = W.F[n] - external
        n_contact += int(np.count_nonzero(W.Fbed[n][:, 2]))
        seg = ln.segment_tension_vectors()
        scale = 2.0 * np.sum(np.linalg.norm(seg, axis=1))
        # internal force of each node is the difference of its two segments' T + Td
        expect = np.zeros_like(internal)
        expect[:-1] += seg
        expect[1:] -= seg
        assert np.max(np.abs(internal - expect)) <= RTOL_BALANCE * scale
        assert np.max(np.abs(internal.sum(axis=0))) <= RTOL_BALANCE * scale, "internal forces do not cancel"
        # sum of node forces over the whole line = sum of the external loads on its nodes
        total = W.F[n].sum(axis=0)
        ext_scale = scale + np.sum(np.abs(external))
        assert np.max(np.abs(total - external.sum(axis=0))) <= RTOL_BALANCE * ext_scale
    assert n_contact > 0, "the perturbed state should put some nodes on the seabed"


@pytest.mark.parametrize("seed", [11, 12])
def test_point_receives_end_node_forces(seed):
    sys = perturbed_system(seed)
    W = sys.work
    for p in range(len(sys.points)):
        ends = np.zeros(3)
        scale = 0.0
        for ln in sys.lines:
            for end, att in (("A", sys.model.lines[ln.index].end_a), ("B", sys.model.lines[ln.index].end_b)):
                if att.index == p:
                    f = ln.end_force(end)
                    ends += f
                    scale += np.linalg.norm(f)
        own = point_own_loads(sys, p)
        scale += np.linalg.norm(own)
        err = np.max(np.abs(W.pF[p] - own - ends))
        assert err <= RTOL_BALANCE * scale, f"point {p + 1}: force {W.pF[p]} != own {own} + line ends {ends}"


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_momentum_balance_of_the_whole_system(seed):
    """sum(M a) over free DOFs + loads on fixed/coupled points = sum of all external loads."""
    sys = perturbed_system(seed)
    W = sys.work
    L = sys.layout.lines
    lhs = np.zeros(3)
    rhs_ = np.zeros(3)
    scale = 0.0
    for li, ln in enumerate(sys.lines):
        n0, n1 = int(L.node_ptr[li]), int(L.node_ptr[li + 1])
        for n in range(n0 + 1, n1 - 1):
            m, ma, mq = W.mass[n]
            q = W.q[n]
            M = m * np.eye(3) + ma * (np.eye(3) - np.outer(q, q)) + mq * np.outer(q, q)
            lhs += M @ W.acc[n]
        ext = W.W[n0:n1] + W.Fhyd[n0:n1] + W.Fbed[n0:n1]
        rhs_ += ext.sum(axis=0)
        scale += np.sum(np.abs(ext)) + 2.0 * np.sum(ln.segment_tensions())
    for p, pt in enumerate(sys.model.points):
        if pt.kind.name == "FREE":
            lhs += W.pM[p] @ W.pa[p]
        else:
            lhs += W.pF[p]
        own = point_own_loads(sys, p)
        rhs_ += own
        scale += np.sum(np.abs(own))
    err = np.max(np.abs(lhs - rhs_))
    assert err <= RTOL_BALANCE * scale, f"momentum balance off by {err:.3g} N (scale {scale:.3g} N)"


# ---------------------------------------------------------------------------------- symmetries
@pytest.fixture(scope="module")
def three_line_base():
    return run(three_line_model(), (1.0, 0.0, 0.0))


@pytest.fixture(scope="module")
def clump_runs():
    return run(clump_model(reverse=False), (1.0, 0.0, 0.0)), run(clump_model(reverse=True), (1.0, 0.0, 0.0))


def test_ab_reversal(clump_runs):
    (ic_ab, dyn_ab), (ic_ba, dyn_ba) = clump_runs
    assert ic_ab["ic"]["converged"] and ic_ba["ic"]["converged"], (ic_ab["ic"], ic_ba["ic"])
    for a, b, what in ((ic_ab, ic_ba, "after IC"), (dyn_ab, dyn_ba, f"after {T_DYN:g} s")):
        assert_same_physics(a, b, lambda r: r, lambda f: f, reverse=True, what=f"A/B reversal {what}")
        np.testing.assert_allclose(b["p"], a["p"], rtol=0, atol=RTOL_INVARIANT * 260.0)


def test_ab_reversal_moves_something(clump_runs):
    """Guard: the dynamics really change the tensions (the comparison is not of two rests)."""
    (ic_ab, dyn_ab), _ = clump_runs
    change = max(np.max(np.abs(d - i)) / np.max(i) for d, i in zip(dyn_ab["T"], ic_ab["T"], strict=True))
    assert change > 0.02


@pytest.mark.parametrize("deg", [37.0, 180.0])
def test_rotation_about_z(three_line_base, deg):
    ang = math.radians(deg)
    R = np.array([[math.cos(ang), -math.sin(ang), 0.0], [math.sin(ang), math.cos(ang), 0.0], [0.0, 0.0, 1.0]])
    rot = run(three_line_model(angle=ang), R @ np.array([1.0, 0.0, 0.0]))
    for a, b, what in zip(three_line_base, rot, ("after IC", f"after {T_DYN:g} s"), strict=True):
        assert_same_physics(a, b, lambda r: R @ r, lambda f: R @ f, what=f"rotation {deg:g} deg {what}")


def test_horizontal_translation(three_line_base):
    shift = np.array([1234.5, -678.25, 0.0])
    moved = run(three_line_model(shift=shift[:2]), (1.0, 0.0, 0.0))
    for a, b, what in zip(three_line_base, moved, ("after IC", f"after {T_DYN:g} s"), strict=True):
        assert_same_physics(a, b, lambda r: r + shift, lambda f: f, what=f"translation {what}")


def test_mirror_y(three_line_base):
    S = np.diag([1.0, -1.0, 1.0])
    mirrored = run(three_line_model(mirror_y=True), (1.0, 0.0, 0.0))
    for a, b, what in zip(three_line_base, mirrored, ("after IC", f"after {T_DYN:g} s"), strict=True):
        assert_same_physics(a, b, lambda r: S @ r, lambda f: S @ f, what=f"mirror y {what}")


def test_mirror_with_lateral_motion():
    """Mirror of a motion with a y component: the mirrored run sees the mirrored motion."""
    S = np.diag([1.0, -1.0, 1.0])
    d = np.array([0.6, 0.8, 0.0])
    base = run(three_line_model(), d)
    mirrored = run(three_line_model(mirror_y=True), S @ d)
    for a, b, what in zip(base, mirrored, ("after IC", f"after {T_DYN:g} s"), strict=True):
        assert_same_physics(a, b, lambda r: S @ r, lambda f: S @ f, what=f"mirror y, oblique surge {what}")
