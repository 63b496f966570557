"""The quasi-static network: stiffness and tension gradients by finite differences, the invariants
(symmetry, rotation of the whole system, A/B reversal), free bodies, input errors and the speed of
the time-domain interface."""

from __future__ import annotations

import copy
import logging
import math

import numpy as np
import pytest

from moorline.io import read_deck
from moorline.io.deck import read_deck_text
from moorline.model import rotation_xyz
from moorline.quasistatic import QuasiStaticError, QuasiStaticModel

from .conftest import DATA, SYSTEMS, deck, oc3_hydrostatics, reverse_lines, rotate_model, small_rotation_pose

ALL = [*SYSTEMS, "bridle_clump_buoy/bridle_clump_buoy.txt", "catenary_3line/lines.txt"]


def _offset_pose(qs, x0):
    """A generic pose: every coupled DOF moved a little (translations 2.3 m, rotations 0.03 rad)."""
    x = np.array(x0, dtype=float)
    for i, lab in enumerate(qs.coupled_dof_labels):
        x[i] += 0.03 * (1 + i % 3) if lab.split("_")[1] in ("roll", "pitch", "yaw") else 2.3 * (1 - 0.4 * (i % 3))
    return x


def _perturbed(qs, x, j, h):
    """x moved by h along coupled DOF j (a small rotation about a global axis for body rotations)."""
    lab = qs.coupled_dof_labels[j]
    name, c = lab.split("_")
    if c in ("roll", "pitch", "yaw"):
        i0 = qs.coupled_dof_labels.index(f"{name}_x")
        out = np.array(x, dtype=float)
        out[i0:i0 + 6] = small_rotation_pose(x[i0:i0 + 6], ("roll", "pitch", "yaw").index(c), h)
        return out
    out = np.array(x, dtype=float)
    out[j] += h
    return out


@pytest.mark.parametrize("name", ALL)
def test_stiffness_and_tension_gradients_match_finite_differences(name):
    """Central differences of the equilibrium loads and tensions (free points re-solved each time).
    Steps 1e-3 m and 1e-5 rad: truncation ~ (h/l)^2 of the curvature length l >~ 10 m, ~1e-8; the
    equilibrium is converged to 1e-10 of the force scale, so the difference quotient carries
    ~1e-10 F / h ~ 1e-4 N/m of noise on stiffnesses of 1e3..1e8 N/m: 1e-5 of the largest entry holds."""
    qs = QuasiStaticModel(deck(name))
    x = _offset_pose(qs, qs.deck_coupled_positions())
    sol = qs.solve(x, gradients=True)
    nc = qs.n_coupled_dof
    K_fd = np.zeros((nc, nc))
    G_fd = np.zeros_like(sol.tension_gradient)
    for j in range(nc):
        rot = qs.coupled_dof_labels[j].split("_")[1] in ("roll", "pitch", "yaw")
        h = 1e-5 if rot else 1e-3
        sp = qs.solve(_perturbed(qs, x, j, h), stiffness=False)
        sm = qs.solve(_perturbed(qs, x, j, -h), stiffness=False)
        K_fd[:, j] = -(sp.loads - sm.loads) / (2 * h)
        G_fd[:, :, j] = (sp.tensions - sm.tensions) / (2 * h)
    assert np.max(np.abs(K_fd - sol.stiffness)) <= 1e-5 * np.max(np.abs(sol.stiffness))
    assert np.max(np.abs(G_fd - sol.tension_gradient)) <= 1e-5 * np.max(np.abs(sol.tension_gradient))


@pytest.mark.parametrize("name", ALL)
def test_stiffness_symmetry(name):
    """Conservative lines: the stiffness is symmetric, except the rotation block of a body, which
    differs from its transpose by S(M) for the mooring moment M about the reference point (a load
    turning with the body; MoorPy's convention too). Round-off bound: 1e-9 of the largest entry."""
    qs = QuasiStaticModel(deck(name))
    sol = qs.solve(_offset_pose(qs, qs.deck_coupled_positions()))
    K = sol.stiffness
    A = K - K.T
    expect = np.zeros_like(K)
    for i, lab in enumerate(qs.coupled_dof_labels):
        if lab.endswith("_roll"):
            M = sol.loads[i:i + 3]
            expect[i:i + 3, i:i + 3] = [[0.0, -M[2], M[1]], [M[2], 0.0, -M[0]], [-M[1], M[0], 0.0]]
    assert np.max(np.abs(A - expect)) <= 1e-9 * np.max(np.abs(K))
    if not any(lab.endswith("_roll") for lab in qs.coupled_dof_labels):
        assert np.max(np.abs(A)) <= 1e-9 * np.max(np.abs(K))


def _block_rotation(qs, Rz):
    n = qs.n_coupled_dof
    B = np.zeros((n, n))
    for i in range(0, n, 3):
        B[i:i + 3, i:i + 3] = Rz
    return B


@pytest.mark.parametrize("name", ALL)
def test_rotating_the_system_rotates_the_stiffness(name):
    """Turn anchors, points and bodies by 37 deg about z: same tensions, loads and stiffness turned
    (K' = R K R^T). Tolerance 1e-8 of the largest entry: both equilibria are converged to 1e-10 of the
    force scale."""
    m = deck(name)
    phi = math.radians(37.0)
    Rz = rotation_xyz((0.0, 0.0, phi))
    qs, qr = QuasiStaticModel(m), QuasiStaticModel(rotate_model(m, phi))
    s, r = qs.solve(gradients=True), qr.solve(gradients=True)
    B = _block_rotation(qs, Rz)
    assert np.allclose(r.tensions, s.tensions, rtol=1e-9)
    assert np.allclose(r.loads, B @ s.loads, rtol=0, atol=1e-8 * np.max(np.abs(s.loads)))
    assert np.max(np.abs(r.stiffness - B @ s.stiffness @ B.T)) <= 1e-8 * np.max(np.abs(s.stiffness))


@pytest.mark.parametrize("name", ALL)
def test_line_end_reversal_gives_mirrored_results(name):
    """Every line given from its other end: end tensions swap; loads, stiffness and free points do not
    change (1e-9 relative: the same equilibrium reached through mirrored line solves)."""
    m = deck(name)
    qs, qr = QuasiStaticModel(m), QuasiStaticModel(reverse_lines(m))
    x = _offset_pose(qs, qs.deck_coupled_positions())
    s, r = qs.solve(x), qr.solve(x)
    assert np.allclose(r.tensions, s.tensions[:, ::-1], rtol=1e-9)
    assert np.allclose(r.points, s.points, rtol=0, atol=1e-9 * qs.length_scale * 1e3)
    assert np.allclose(r.loads, s.loads, rtol=0, atol=1e-9 * np.max(np.abs(s.loads)))
    assert np.max(np.abs(r.stiffness - s.stiffness)) <= 1e-9 * np.max(np.abs(s.stiffness))


def test_warm_start_does_not_change_the_answer():
    """A solution reached through a sequence of warm-started, predicted steps equals a cold solve
    (both converged to 1e-10 of the force scale: 1e-8 relative in the tensions)."""
    qs = QuasiStaticModel(deck("oc3_bridle"))
    x0 = qs.deck_coupled_positions()
    for a in np.linspace(0.0, 25.0, 26):
        warm = qs.solve(x0 + np.r_[a, 0.3 * a, 0.0, 0.0, 0.0, 0.004 * a])
    cold = QuasiStaticModel(deck("oc3_bridle")).solve(warm.x)
    assert np.allclose(warm.tensions, cold.tensions, rtol=1e-8)
    assert np.allclose(warm.stiffness, cold.stiffness, rtol=1e-6, atol=1e-8 * np.max(np.abs(cold.stiffness)))
    assert warm.iterations <= 3  # predictor plus Newton: quadratic from a first-order start


def test_free_body_equilibrium_balances_every_load():
    """OC3-Hywind free under its hydrostatics, weight and a mean rotor thrust: at the equilibrium the
    mooring loads (the same pose solved as a coupled body) plus weight, buoyancy, waterplane restoring
    and thrust sum to zero (1e-6 of the weight: the solve's tolerance is 1e-10 of it)."""
    hs = oc3_hydrostatics()
    thrust = np.array([8.0e5, 0.0, 0.0, 0.0, 8.0e5 * 90.0, 0.0])
    mfree = read_deck(DATA / "oc3_spar_free.dat")
    qs = QuasiStaticModel(mfree, hydrostatics={1: hs}, external_loads={1: thrust})
    sol = qs.solve()
    pose = sol.bodies[0]
    assert qs.n_coupled_dof == 0
    assert 20.0 < pose[0] < 40.0 and 0.05 < pose[4] < 0.15  # surge downwind, pitched by the thrust
    # the same pose as a coupled body
    mc = read_deck(DATA / "oc3_spar.dat")
    moor = QuasiStaticModel(mc).solve(pose).loads
    body = mfree.bodies[0]
    R = rotation_xyz(pose[3:])
    g, rho = mfree.env.g, mfree.env.rho
    f = np.zeros(6)
    for arm, fz in ((R @ body.rCG, -body.m * g), (R @ hs.center_of_buoyancy, rho * g * hs.displaced_volume)):
        f[2] += fz
        f[3:] += np.cross(arm, [0.0, 0.0, fz])
    f -= hs.waterplane_stiffness(rho, g) @ (pose - np.zeros(6))
    total = moor + f + thrust
    assert np.max(np.abs(total)) <= 1e-6 * body.m * g


def test_coupled_pinned_body_rotations_are_free():
    """A COUPLEDPINNED body: translations given (3 coupled DOFs), rotations in equilibrium."""
    text = (deck_text := (SYSTEMS["oc3_spar"][0]).read_text()).replace(
        "1     coupled      0.00   0.00   0.00   0.00   0.00   0.00     0.0    0.0   0.0       0.0     0.00   0.00",
        "1     coupledpinned 0.00  0.00   0.00   0.00   0.00   0.00     1.0e6  0|0|-20  1e9       0.0     0.00   0.00")
    assert text != deck_text
    qs = QuasiStaticModel(read_deck_text(text))
    assert qs.coupled_dof_labels == ["B1_x", "B1_y", "B1_z"]
    assert qs.free_dof_labels == ["B1_roll", "B1_pitch", "B1_yaw"]
    sol = qs.solve(np.array([10.0, 0.0, 0.0]))
    assert sol.bodies[0, 4] > 0.0  # the offset mooring tilts the body, its weight below resists
    K = sol.stiffness
    assert K.shape == (3, 3) and K[0, 0] > 0


def test_rods_are_an_error_and_bending_stiffness_a_warning(caplog):
    path = SYSTEMS["oc3_spar"][0]
    text = path.read_text()
    bent = text.replace("main       0.09    77.7066    384.243E6  -0.8        0 ",
                        "main       0.09    77.7066    384.243E6  -0.8        1.0e5")
    assert bent != text
    with caplog.at_level(logging.WARNING, logger="moorline.quasistatic"):
        QuasiStaticModel(read_deck_text(bent))
    assert any("ignores" in r.getMessage() and "EI" in r.getMessage() for r in caplog.records)
    m = read_deck_text(text)
    m.add_rod_type("can", d=2.0, w=100.0)
    m.add_rod("can", "fixed", (0.0, 0.0, -10.0), (0.0, 0.0, -20.0), N=2)
    with pytest.raises(QuasiStaticError, match="cannot represent rods"):
        QuasiStaticModel(m)


def test_bad_inputs_name_what_is_wrong():
    qs = QuasiStaticModel(deck("oc3_spar"))
    with pytest.raises(QuasiStaticError, match="x has 5 values; the system has 6 coupled DOFs"):
        qs.solve(np.zeros(5))
    with pytest.raises(QuasiStaticError, match=r"line \d .*no quasi-static solution"):
        qs.solve(np.array([0.0, 0.0, -400.0, 0.0, 0.0, 0.0]))  # fairleads pushed below the seabed
    qs.solve()  # and the model still works after the failure
    with pytest.raises(QuasiStaticError, match="no body 2"):
        QuasiStaticModel(deck("oc3_spar"), hydrostatics={2: oc3_hydrostatics()})


def test_clump_on_the_seabed_is_explained():
    """A clump weight that would rest on the seabed (points have no seabed contact here)."""
    text = SYSTEMS["clump_line"][0].read_text().replace("350.0     70", "400.0     70").replace(
        "300.0     60", "280.0     60")
    with pytest.raises(QuasiStaticError, match="no seabed contact for points"):
        QuasiStaticModel(read_deck_text(text)).solve()


def test_time_domain_interface_warm_starts():
    """Solve + stiffness at a moving pose, as a time-domain host calls it: the spar on three
    catenaries has no network to solve (0 iterations), the 3-bridle system (9 lines, 3 junctions)
    warm-starts from the last solution and needs at most 3 Newton iterations per call of 400 along
    a smooth motion (7 from the deck's start). Counted, not timed: the speed (typically 20 and
    60 us per call) is in benchmarks/bench_quasistatic.py."""
    for name, first_max, warm_max in (("oc3_spar", 0, 0), ("oc3_bridle", 10, 3)):
        qs = QuasiStaticModel(deck(name))
        x0 = qs.deck_coupled_positions()
        assert qs.solve(x0).iterations <= first_max
        worst = 0
        for k in range(1, 401):
            a = 0.01 * k
            sol = qs.solve(x0 + np.r_[3.0 * math.sin(a), 1.0 * math.cos(a), 0.2 * math.sin(2 * a), 0.0,
                                      0.02 * math.sin(a), 0.01 * math.cos(a)])
            worst = max(worst, sol.iterations)
        assert worst <= warm_max, name


def test_euler_stiffness_linearises_the_pose_vector():
    """stiffness_euler predicts loads(x0 + dx) for Euler-angle increments at a rolled and pitched pose
    to second order: the error of the linear prediction shrinks 4x when dx halves (within 10 %)."""
    qs = QuasiStaticModel(deck("oc3_spar"))
    x0 = qs.deck_coupled_positions() + np.r_[5.0, -3.0, 0.5, 0.1, -0.15, 0.2]
    s0 = qs.solve(x0)
    dx = np.r_[0.0, 0.0, 0.0, 0.01, 0.01, 0.01]
    errs = []
    for f in (1.0, 0.5):
        s1 = qs.solve(x0 + f * dx, stiffness=False)
        errs.append(np.linalg.norm(s1.loads - (s0.loads - s0.stiffness_euler @ (f * dx))))
    assert errs[0] / errs[1] == pytest.approx(4.0, rel=0.1)
    wrong = np.linalg.norm(qs.solve(x0 + dx, stiffness=False).loads - (s0.loads - s0.stiffness @ dx))
    assert wrong > 10 * errs[0]  # the small-rotation stiffness is not the Euler one at this pose


def test_model_is_not_modified():
    m = deck("oc3_bridle")
    before = copy.deepcopy(m)
    QuasiStaticModel(m).solve()
    assert all(np.array_equal(a.r, b.r) for a, b in zip(m.points, before.points, strict=True))


def test_several_lines_between_the_same_points():
    """Two identical lines side by side between the same points act as one line of twice the wet
    weight and twice the EA (the same shape at twice the tension): the free clump finds the same
    place and the coupled stiffness is the same (1e-9: two equal equilibria)."""
    text = SYSTEMS["clump_line"][0].read_text()
    double = text.replace("2     main       2        3         300.0     60      -",
                          "2     main       2        3         300.0     60      -\n"
                          "3     main       2        3         300.0     60      -")
    rho = 1025.0
    area = math.pi * 0.09 ** 2 / 4
    heavy = text.replace("2     main       2        3", "2     twin       2        3").replace(
        "---------------------- POINTS", f"twin       0.09    {2 * 77.7066 - rho * area:.10f}    768.486E6  -0.8  0  "
        "1.6  1.0  0.1  0.0\n---------------------- POINTS")
    assert double != text and heavy != text
    s2 = QuasiStaticModel(read_deck_text(double)).solve()
    sh = QuasiStaticModel(read_deck_text(heavy)).solve()
    assert np.allclose(s2.points, sh.points, atol=1e-7)
    assert np.allclose(s2.tensions[1], s2.tensions[2], rtol=1e-12)  # the line type twin: 2 W, 2 EA
    assert np.allclose(2 * s2.tensions[1], sh.tensions[1], rtol=1e-9)
    assert np.allclose(s2.stiffness, sh.stiffness, rtol=1e-8, atol=1e-9 * np.max(np.abs(sh.stiffness)))


def test_bodies_free_false_gives_every_body_coupled():
    """The time-domain coupling: a deck whose body is FREE (the dynamic model moves it) solved with
    the body given. Same coupled DOFs, loads and stiffness as the deck with a COUPLED body (the
    body's own mass is not a mooring load); an (nB, 6) pose array is accepted."""
    qf = QuasiStaticModel(read_deck(DATA / "oc3_spar_free.dat"), bodies_free=False)
    qc = QuasiStaticModel(deck("oc3_spar"))
    assert qf.coupled_dof_labels == qc.coupled_dof_labels == [f"B1_{c}" for c in
                                                               ("x", "y", "z", "roll", "pitch", "yaw")]
    pose = np.array([[3.0, -1.0, 0.2, 0.01, 0.02, 0.05]])
    sf, sc = qf.solve(pose), qc.solve(pose.ravel())
    assert np.array_equal(sf.loads, sc.loads) and np.array_equal(sf.stiffness, sc.stiffness)
    qt = QuasiStaticModel(deck("oc3_spar"), bodies_free=True, hydrostatics={1: oc3_hydrostatics()})
    assert qt.n_coupled_dof == 0 and qt.free_dof_labels[:3] == ["B1_x", "B1_y", "B1_z"]


def test_check_seabed_reports_what_the_model_cannot_see(caplog):
    """In 50 m of water: a chain hanging between two coupled points sags below the seabed (a line not
    anchored on the seabed is kept suspended), and a clump hung from a coupled point on a 60 m chain
    lies below it (points have no seabed contact); check_seabed names both and logs them."""
    from moorline.model import Environment, Model

    m = Model(env=Environment(depth=50.0))
    m.add_line_type("chain", d=0.09, w=77.7, EA=3.8e8)
    a = m.add_point("coupled", (0.0, 0.0, -20.0))
    b = m.add_point("coupled", (100.0, 0.0, -20.0))
    c = m.add_point("free", (0.0, 30.0, -60.0), m=1000.0)
    m.add_line("chain", a, b, L=200.0, N=20)
    m.add_line("chain", a, c, L=60.0, N=10)
    qs = QuasiStaticModel(m)
    sol = qs.solve()
    assert sol.points[2, 2] < -50.0
    with caplog.at_level(logging.WARNING, logger="moorline.quasistatic"):
        msgs = qs.check_seabed()
    assert any(s.startswith("point 3 lies") for s in msgs)
    assert any(s.startswith("line 1 sags") for s in msgs)
    assert len(caplog.records) == len(msgs)
    qs2 = QuasiStaticModel(deck("clump_line"))
    qs2.solve()
    assert qs2.check_seabed() == []
