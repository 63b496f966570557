"""Sea states, scatter diagrams and envelopes (moorline.post.seastate, moorline.post.envelopes):

- the W4P scatter diagram: 82 non-zero cells of 13 x 14, probabilities normalised, zero cells
  skipped, regular-wave equivalent H = Hs/sqrt(2), T = Tz;
- the buoy motion of a regular wave: heave (H/2) sin(2 pi t/T) after the ramp, surge coth(kh) H/2
  a quarter period behind, along the heading; the dispersion relation;
- a JONSWAP record: reproducible from its seed, 4 std(heave) = Hs; Tp/Tz of DNV-RP-C205;
- probability-weighted lifetime damage;
- envelopes: bend radius against an allowable, tension extremes, compressed segments.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
from scipy.integrate import trapezoid

from moorline.post import (
    SECONDS_PER_YEAR,
    ScatterDiagram,
    SeaState,
    buoy_motion,
    envelopes,
    jonswap_spectrum,
    lifetime_damage,
    to_scatter_grid,
    tp_from_tz,
    wavenumber,
)

SCATTER = Path(__file__).resolve().parents[2] / "examples" / "w4p_study" / "w4p_scatter.csv"


def test_w4p_scatter_diagram():
    sc = ScatterDiagram.from_csv(SCATTER)
    assert sc.P.shape == (13, 14)
    assert sc.P.sum() == pytest.approx(1.0, rel=1e-14)
    seas = sc.sea_states()
    assert len(seas) == 82 and all(s.probability > 0 for s in seas)
    assert sum(s.probability for s in seas) == pytest.approx(1.0, rel=1e-14)
    # the table's largest cell: Hs 1.5 m, Tz 5.5 s, 1014 of 10002
    big = max(seas, key=lambda s: s.probability)
    assert (big.Hs, big.Tz) == (1.5, 5.5) and big.probability == pytest.approx(1014 / 10002, rel=1e-14)
    assert big.H == pytest.approx(1.5 / math.sqrt(2)) and big.T == 5.5
    assert len(sc.sea_states(min_probability=1e-3)) < 82
    # back onto the grid
    p = xr.DataArray([s.probability for s in seas], dims="sea_state",
                     coords={"Hs": ("sea_state", [s.Hs for s in seas]), "Tz": ("sea_state", [s.Tz for s in seas])})
    g = to_scatter_grid(p)
    assert g.sel(Hs=1.5, Tz=5.5).item() == pytest.approx(big.probability)
    assert np.isnan(g.sel(Hs=12.5, Tz=2.5).item())


def test_scatter_errors(tmp_path):
    f = tmp_path / "bad.csv"
    f.write_text("Hs\\Tz,4,6\n1,0.5\n")
    with pytest.raises(ValueError, match="2 probabilities"):
        ScatterDiagram.from_csv(f)
    with pytest.raises(ValueError):
        ScatterDiagram([1.0], [4.0], [[-1.0]])


def test_dispersion_relation():
    w = np.array([0.3, 0.8, 2.0])
    for h in (5.0, 50.0, 500.0):
        k = wavenumber(w, h)
        np.testing.assert_allclose(9.80665 * k * np.tanh(k * h), w * w, rtol=1e-12)
    np.testing.assert_allclose(wavenumber(w, 0.0), w * w / 9.80665)


def test_regular_buoy_motion():
    sea = SeaState(3.0, 8.0, heading=90.0)
    x0 = np.array([0.0, 0.0, -2.0])
    t, X = buoy_motion(sea, x0, duration=40.0, dt=0.05, depth=50.0, ramp=8.0)
    a = 0.5 * 3.0 / math.sqrt(2)
    w = 2 * math.pi / 8.0
    k = wavenumber(w, 50.0)[0]
    after = t >= 8.0
    np.testing.assert_allclose(X[after, 2], -2.0 + a * np.sin(w * t[after]), atol=1e-12)
    # heading 90 deg: surge along +y, a quarter period behind the heave, amplitude coth(kh) a
    np.testing.assert_allclose(X[after, 1], -a / math.tanh(k * 50.0) * np.cos(w * t[after]), atol=1e-12)
    np.testing.assert_allclose(X[:, 0], 0.0, atol=1e-12)
    np.testing.assert_allclose(X[0], x0)  # starts at rest at the deck position
    assert abs(X[1, 2] - X[0, 2]) / 0.05 < 1e-4  # from rest
    # a coupled body (6 DOF) and a point: both translate, the angles stay
    labels = ["B1_x", "B1_y", "B1_z", "B1_roll", "B1_pitch", "B1_yaw", "P2_x", "P2_y", "P2_z"]
    xb = np.array([1.0, 2.0, 3.0, 0.1, 0.2, 0.3, 4.0, 5.0, -6.0])
    _, XB = buoy_motion(sea, xb, duration=40.0, dt=0.05, depth=50.0, ramp=8.0, labels=labels)
    np.testing.assert_allclose(XB[:, 3:6], np.tile([0.1, 0.2, 0.3], (len(t), 1)))
    np.testing.assert_allclose(XB[:, [0, 1, 2]] - xb[:3], X - x0, atol=1e-12)
    np.testing.assert_allclose(XB[:, [6, 7, 8]] - xb[6:], X - x0, atol=1e-12)


def test_jonswap_record():
    sea = SeaState(2.5, 6.5, kind="jonswap", seed=7)
    assert tp_from_tz(6.5, 3.3) == pytest.approx(6.5 / 0.7776, rel=1e-3)
    assert tp_from_tz(1.0, 1.0) == pytest.approx(1.0 / 0.7117, rel=1e-3)  # Pierson-Moskowitz
    w = np.linspace(0.01, 6.0, 20000)
    m0 = trapezoid(jonswap_spectrum(w, 2.5, sea.Tp), w)
    assert 4 * math.sqrt(m0) == pytest.approx(2.5, rel=0.03)  # DNV's A_gamma normalisation
    x0 = np.zeros(3)
    # the record is one repeat period of the components (dw = 2 pi / duration), so its variance is
    # their sum a^2/2 = m0 whatever the phases: 4 std = Hs
    t, X = buoy_motion(sea, x0, duration=600.0, dt=0.5, depth=50.0, ramp=0.0)
    assert 4 * X[:-1, 2].std() == pytest.approx(2.5, rel=1e-3)
    _, X2 = buoy_motion(sea, x0, duration=600.0, dt=0.5, depth=50.0, ramp=0.0)
    np.testing.assert_array_equal(X, X2)
    _, X3 = buoy_motion(SeaState(2.5, 6.5, kind="jonswap", seed=8), x0, duration=600.0, dt=0.5, depth=50.0,
                        ramp=0.0)
    assert not np.allclose(X, X3)


def test_lifetime_damage_weighting():
    rate = xr.DataArray([[1e-12, 2e-12], [4e-12, 1e-12]], dims=("sea_state", "node"))
    d = lifetime_damage(rate, [0.75, 0.25])
    np.testing.assert_allclose(d.values, [(0.75e-12 + 1e-12) * SECONDS_PER_YEAR,
                                          (1.5e-12 + 0.25e-12) * SECONDS_PER_YEAR], rtol=1e-14)


def _results(strain, tension, curvature):
    """A results-like Dataset of one 3-segment line."""
    nt = len(strain)
    return xr.Dataset(
        {"node_curvature": (("time", "node"), np.asarray(curvature, float)),
         "node_tension": (("time", "node"), np.asarray(tension, float)),
         "segment_tension": (("time", "segment"), np.clip(np.asarray(strain, float), 0, None) * 1e5),
         "segment_strain": (("time", "segment"), np.asarray(strain, float))},
        coords={"time": np.arange(nt) * 0.5, "node_line": ("node", [1, 1, 1, 1]), "node_index": ("node", range(4)),
                "node_s": ("node", [0.0, 1.0, 2.0, 3.0]), "segment_line": ("segment", [1, 1, 1]),
                "segment_s": ("segment", [0.5, 1.5, 2.5])})


def test_envelopes_bend_radius_tension_compression(caplog):
    ds = _results(strain=[[1e-3, 2e-3, 1e-3], [1e-3, -1e-4, 5e-4], [2e-3, 1e-3, 1e-3]],
                  tension=[[100, 150, 120, 90], [80, 40, 10, 70], [200, 160, 110, 100]],
                  curvature=[[0.0, 0.2, 0.1, 0.0], [0.0, 0.6, 0.3, 0.0], [0.0, 0.1, 0.9, 0.0]])
    with caplog.at_level(logging.WARNING, logger="moorline"):
        env = envelopes(ds, allowable_bend_radius=2.0)
    np.testing.assert_allclose(env.curvature_max.values, [0.0, 0.6, 0.9, 0.0])
    np.testing.assert_allclose(env.bend_radius_min.values, [np.inf, 1 / 0.6, 1 / 0.9, np.inf])
    assert env.bend_radius_ok.values.tolist() == [True, False, False, True]
    assert env.attrs["curvature_max_s"] == 2.0 and env.attrs["bend_radius_utilisation"] == pytest.approx(1.8)
    np.testing.assert_allclose(env.tension_max.values, [200, 160, 120, 100])
    np.testing.assert_allclose(env.tension_min.values, [80, 40, 10, 70])
    np.testing.assert_allclose(env.compressed_fraction.values, [0.0, 1 / 3, 0.0])
    assert env.attrs["compressed_segments"] == 1
    assert "bend radius below the allowable" in caplog.text
    assert "1 segments in compression" in caplog.text and "t = 0.5 s" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="moorline"):
        envelopes(ds, allowable_bend_radius=2.0, warn=False)
    assert caplog.text == ""
