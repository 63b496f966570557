"""Section loads from node positions (moorline.post.sections):

- nodes on a circular arc: the kernel's discrete curvature (4/(l1+l2)) sin(theta/2) is exactly
  1/R there, the bending axis is normal to the arc's plane, and the signs of My and of the
  stress follow the documented frame (a sagging arc stretches its lower fibre);
- the curvature magnitudes recomputed from positions equal the recorded ``node_curvature`` of a
  simulated cable, clamped end included, also for out-of-plane motion (then Mz != 0);
- the reference frame does not flip when the tangent passes through the vertical (the
  instantaneous horizontal frame does);
- cantilever (issue "Verified by"): the curvature-derived moment EI kappa at the static
  equilibrium of a tip-loaded cantilever matches the analytic beam M(x) = P (L - x) + q (L - x)^2/2.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

import moorline
from moorline.io import read_deck
from moorline.post import SeaState, TubeSection, buoy_motion, cross_section_stress, section_loads
from moorline.results import Recorder

TINY = Path(__file__).resolve().parents[1] / "studies" / "tiny_cable.dat"


def make_ds(r, tension=None, curvature=None):
    """A results-like Dataset of one line from node positions r (time, node, 3)."""
    r = np.asarray(r, dtype=float)
    nt, n, _ = r.shape
    tension = np.ones((nt, n)) if tension is None else tension
    v = {"node_position": (("time", "node", "xyz"), r), "node_tension": (("time", "node"), tension)}
    if curvature is not None:
        v["node_curvature"] = (("time", "node"), curvature)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(r[0], axis=0), axis=1))])
    return xr.Dataset(v, coords={"time": np.arange(nt, dtype=float), "node_line": ("node", np.ones(n, dtype=int)),
                                 "node_index": ("node", np.arange(n)), "node_s": ("node", s)})


def test_circular_arc_curvature_frame_and_sign():
    """A sagging arc (centre above, concave up) in the x-z plane, from left to right."""
    R, n = 12.0, 9
    phi = np.linspace(-0.6, 0.6, n)
    r = np.stack([R * np.sin(phi), np.zeros(n), R - R * np.cos(phi)], axis=-1)[None]
    EI = 350.0
    sec = section_loads(make_ds(r), EI=EI)
    k = sec.curvature.values[0]
    assert k[0] == 0.0 and k[-1] == 0.0  # pinned ends
    np.testing.assert_allclose(k[1:-1], 1.0 / R, rtol=1e-12)
    # frame: tangent along +x at the bottom, y horizontal (e_z x t = +y), z = t x y up
    mid = n // 2
    np.testing.assert_allclose(sec.tangent.values[0, mid], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(sec.axis_y.values[0, mid], [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(sec.axis_z.values[0, mid], [0, 0, 1], atol=1e-12)
    # e_a x e_b = -y for a tangent turning upward: My = -EI/R, Mz = 0
    np.testing.assert_allclose(sec.My.values[0, 1:-1], -EI / R, rtol=1e-12)
    np.testing.assert_allclose(sec.Mz.values[0], 0.0, atol=1e-12)
    np.testing.assert_allclose(sec.kappa_y.values[0, 1:-1], -1.0 / R, rtol=1e-12)
    # the lower fibre (theta = 270 deg, -z) is stretched, the upper one compressed
    s = cross_section_stress(sec.assign(tension=sec.tension * 0.0), TubeSection(0.04, 0.02), n_theta=4)
    sig = s.isel(time=0, node=mid)
    c, I = 0.02, TubeSection(0.04, 0.02).I
    assert sig.sel(theta=270.0).item() == pytest.approx(EI / R * c / I, rel=1e-12)
    assert sig.sel(theta=90.0).item() == pytest.approx(-EI / R * c / I, rel=1e-12)
    # a right-handed orthonormal frame at every node
    t, y, z = (sec[v].values for v in ("tangent", "axis_y", "axis_z"))
    np.testing.assert_allclose(np.einsum("...k,...k", t, y), 0.0, atol=1e-14)
    np.testing.assert_allclose(np.cross(t, y), z, atol=1e-14)


def test_clamp_direction_follows_a_moving_rod():
    """A straight cable along +x clamped at end A to end B of a rod that pitches: the clamp
    direction is read from the recorded rod end positions at each time, so the end curvature is
    (4/l) sin(phi/2) for a rod axis phi off the cable. Without recorded rod positions a moving
    (here pinned) rod gives no clamp direction: only fixed rods take theirs from the model."""
    from moorline.model import Model

    m = Model()
    m.add_line_type("c", d=0.04, w=2.0, EA=1e5, EI=10.0)
    m.add_rod_type("r", d=0.3, w=10.0)
    _, rb = m.add_rod("r", "pinned", (-1.0, 0.0, 0.0), (0.0, 0.0, 0.0), N=1)
    tip = m.add_point("free", (4.0, 0.0, 0.0))
    m.add_line("c", rb, tip, L=4.0, N=4)
    phis = np.array([0.0, 0.1, -0.2])
    r = np.repeat(np.stack([np.arange(5.0), np.zeros(5), np.zeros(5)], axis=-1)[None], 3, axis=0)
    ds = make_ds(r)
    ends = np.zeros((3, 2, 3))
    ends[:, 0] = -np.stack([np.cos(phis), np.zeros(3), np.sin(phis)], axis=-1)  # rod end A; end B at the origin
    ds["rod_end_position"] = (("time", "rod", "rod_end", "xyz"), ends[:, None])
    sec = section_loads(ds, model=m)
    np.testing.assert_allclose(sec.curvature.values[:, 0], 4.0 * np.abs(np.sin(phis / 2)), rtol=1e-12)
    assert sec.My.values[1, 0] * sec.My.values[2, 0] < 0  # the rod pitched both ways
    assert sec.attrs["clamped_ends"] == "A"
    static = section_loads(ds.drop_vars("rod_end_position"), model=m)
    assert static.attrs["clamped_ends"] == ""


def test_moment_table_and_missing_EI():
    """An EI table gives M = table(kappa) (clamped as the kernel does); without EI or a model
    the moments cannot be formed."""
    R, n = 5.0, 5
    phi = np.linspace(-0.5, 0.5, n)
    r = np.stack([R * np.sin(phi), np.zeros(n), R - R * np.cos(phi)], axis=-1)[None]
    ds = make_ds(r)
    table = moorline.model.Curve([0.0, 0.1, 1.0], [0.0, 30.0, 40.0])
    sec = section_loads(ds, EI=table)
    np.testing.assert_allclose(sec.bending_moment.values[0, 1:-1], 30.0 + 10.0 * (0.2 - 0.1) / 0.9, rtol=1e-12)
    with pytest.raises(ValueError, match="EI"):
        section_loads(ds)


def test_reference_frame_does_not_flip_through_vertical():
    """Three nodes of a hanging cable whose middle tangent swings through the vertical while the
    cable keeps bending the same way: My keeps its sign in the reference frame; in the
    instantaneous horizontal frame y = unit(e_z x t) turns over with the tangent and My flips."""
    frames = []
    for a in np.linspace(-0.2, 0.2, 9):  # tilt of the middle tangent from the vertical [rad]
        t = np.array([math.sin(a), 0.0, -math.cos(a)])
        n = np.array([math.cos(a), 0.0, math.sin(a)])  # in-plane normal
        ea = t - 0.1 * n
        eb = t + 0.1 * n
        frames.append([-ea, [0.0, 0.0, 0.0], eb])
    r = np.array(frames)
    ref = section_loads(make_ds(r), EI=1.0)
    hor = section_loads(make_ds(r), EI=1.0, frame="horizontal")
    my_ref = ref.My.values[:, 1]
    my_hor = hor.My.values[:, 1]
    assert np.all(my_ref > 0) or np.all(my_ref < 0)
    assert np.all(np.isfinite(my_hor)) and np.any(my_hor > 0) and np.any(my_hor < 0)
    np.testing.assert_allclose(np.abs(my_ref), ref.bending_moment.values[:, 1], rtol=1e-12)
    # at the vertical instant the horizontal frame falls back to y = e_y, still orthonormal
    np.testing.assert_allclose(np.linalg.norm(hor.axis_y.values, axis=-1), 1.0, rtol=1e-12)


@pytest.fixture(scope="module")
def tiny_run():
    """The 5-segment test cable (clamped at a rod at end A) under a buoy in an oblique regular
    wave (heading 30 deg), so it bends in and out of its plane."""
    model = read_deck(TINY)
    sys = moorline.System(model)
    sea = SeaState(1.5, 4.0, heading=30.0)
    t, X = buoy_motion(sea, sys.deck_coupled_positions(), duration=10.0, dt=0.05, depth=15.0, ramp=4.0)
    ds = moorline.simulate(sys, 10.0, (t, X), dt_out=0.1, progress=False)
    return model, ds


def test_curvature_magnitude_matches_recorded(tiny_run):
    model, ds = tiny_run
    sec = section_loads(ds, model=model)
    assert sec.attrs["clamped_ends"] == "A"
    np.testing.assert_allclose(sec.curvature.values, ds.node_curvature.values, rtol=1e-10, atol=1e-13)
    assert ds.node_curvature.values[:, 0].max() > 0.01  # the clamp bends
    np.testing.assert_allclose(np.hypot(sec.kappa_y, sec.kappa_z), sec.curvature, rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(np.hypot(sec.My, sec.Mz), 350.0 * sec.curvature, rtol=1e-10, atol=1e-10)
    assert float(abs(sec.Mz).max()) > 0.05 * float(abs(sec.My).max())  # out of plane
    # y horizontal at the first output time (the equilibrium), right-handed frame throughout
    np.testing.assert_allclose(sec.axis_y.values[0, :, 2], 0.0, atol=1e-14)
    t, y, z = (sec[v].values for v in ("tangent", "axis_y", "axis_z"))
    np.testing.assert_allclose(np.einsum("...k,...k", t, y), 0.0, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(y, axis=-1), 1.0, rtol=1e-12)
    np.testing.assert_allclose(np.cross(t, y), z, atol=1e-12)


def test_clamp_without_model_borrows_the_neighbours_axis(tiny_run, caplog):
    model, ds = tiny_run
    with caplog.at_level(logging.WARNING, logger="moorline"):
        sec = section_loads(ds, EI=350.0)
    assert "no clamp direction" in caplog.text
    np.testing.assert_allclose(sec.curvature.values[:, 0], ds.node_curvature.values[:, 0])
    with pytest.raises(ValueError, match="no line 2"):
        section_loads(ds, 2, EI=1.0)


def test_cantilever_moment_matches_analytic_beam():
    """The verification suite's cantilever (10 m, EI = 2 MN m^2, clamped horizontally at a fixed
    rod, 100 kg at the free tip; P L^2 / EI = 0.05, small deflection) brought to rest by kinetic
    damping (residual force < 1e-3 N). The beam's moment is M(s) = P (L - s) + q (L - s)^2 / 2 with
    q the net weight per length (-0.3 N/m, a slightly buoyant cable); EI kappa at every node is
    within 5e-4 of the root moment of it (the remaining 1.6e-4 is the large-deflection shortening
    of the lever arms, independent of N). The upper fibre at the root is in tension."""
    from tests.verification.test_bending import CANT_EI, CANT_L, G, cantilever, net_q, relax

    s = cantilever(8, 100.0)
    assert relax(s, 1e-3, t_max=200.0) < 1e-3
    rec = Recorder(s)
    rec.record()
    ds = rec.to_dataset()
    sec = section_loads(ds, model=s.model)
    x = ds.node_s.values
    M = 100.0 * G * (CANT_L - x) + net_q() * (CANT_L - x) ** 2 / 2
    np.testing.assert_allclose(sec.My.values[0], M, atol=5e-4 * M[0])
    # two computations of the same curvature from the same positions: each takes 1 - cos of an
    # angle of about 1e-3 between unit vectors, so their rounding differs by eps / (1 - cos) ~ 1e-10
    np.testing.assert_allclose(sec.bending_moment.values[0], CANT_EI * ds.node_curvature.values[0], rtol=1e-8)
    assert float(abs(sec.Mz).max()) < 1e-9 * M[0]
    sig = cross_section_stress(sec, TubeSection(0.3525), n_theta=4).isel(time=0, node=0)
    assert sig.sel(theta=90.0).item() > 0 > sig.sel(theta=270.0).item()
