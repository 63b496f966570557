"""Cross-section stress, rainflow counting, S-N curves and Miner's sum (issue "Cable fatigue and
design studies", "Verified by"):

- section properties and the stress formula against values worked out by hand;
- rainflow counts of the ASTM E1049-85 example history against the ``rainflow`` library and the
  standard's own table; the periodic option against the same signal repeated;
- Miner's damage of a constant-amplitude signal is n S^m / alpha exactly; two-slope curves are
  continuous at the knee; an endurance limit removes the damage below it; T-N curves;
- the compression cut-off sets compressive stress to zero before counting.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import rainflow
import xarray as xr

from moorline.post import (
    SNCurve,
    TubeSection,
    api_chain_tn_curve,
    critical_location,
    cross_section_stress,
    dnv_chain_sn_curve,
    fatigue_damage,
    life_years,
    miner_sum,
    rainflow_cycles,
    theta_points,
)

#: the study's copper-conductor S-N curve (S in MPa)
ALPHA, M = 6.098e19, 6.238

#: ASTM E1049-85 (2011) Fig. 6 load history and its rainflow count (Table, section 5.4.4):
#: range -> cycles
ASTM_HISTORY = [-2.0, 1.0, -3.0, 5.0, -1.0, 3.0, -4.0, 4.0, -2.0]
ASTM_COUNT = {3.0: 0.5, 4.0: 1.5, 6.0: 0.5, 8.0: 1.0, 9.0: 0.5}


# ------------------------------------------------------------------------------------------ stress
def test_tube_section_properties_by_hand():
    """do = 40 mm, di = 20 mm: A = pi/4 (1.6e-3 - 4e-4) = 3e-4 pi m^2, I = pi/64 (2.56e-6 - 1.6e-7)
    = 3.75e-8 pi m^4; a solid bar of 40 mm: I = pi d^4/64 = 4e-8 pi m^4."""
    s = TubeSection(0.040, 0.020)
    assert s.A == pytest.approx(3.0e-4 * math.pi, rel=1e-14)
    assert s.I == pytest.approx(3.75e-8 * math.pi, rel=1e-14)
    assert s.c == 0.020
    assert TubeSection(0.040).I == pytest.approx(4.0e-8 * math.pi, rel=1e-14)
    with pytest.raises(ValueError):
        TubeSection(0.02, 0.03)


def test_stress_formula_by_hand():
    """N = 1 kN, My = 100 N m, Mz = 50 N m on the 40/20 mm tube: N/A = 1000/(3e-4 pi) = 1.0610 MPa;
    My c / I = 100 * 0.02 / (3.75e-8 pi) = 16.977 MPa, Mz c / I = 8.4883 MPa. At theta = 0:
    N/A - Mz c/I; 90: N/A + My c/I; 180: N/A + Mz c/I; 270: N/A - My c/I."""
    s = TubeSection(0.040, 0.020)
    na = 1000.0 / (3e-4 * math.pi)
    my = 100.0 * 0.02 / (3.75e-8 * math.pi)
    mz = 50.0 * 0.02 / (3.75e-8 * math.pi)
    assert na == pytest.approx(1.0610330e6, rel=1e-7)
    assert my == pytest.approx(16.976527e6, rel=1e-7)
    sig = s.stress(1000.0, 100.0, 50.0, np.deg2rad([0.0, 90.0, 180.0, 270.0, 30.0]))
    expected = [na - mz, na + my, na + mz, na - my, na + my * 0.5 - mz * math.sqrt(3) / 2]
    np.testing.assert_allclose(sig, expected, rtol=1e-12, atol=1e-6)


def _sections(N, My, Mz):
    """A minimal section-loads Dataset (time, node)."""
    N, My, Mz = (np.atleast_2d(np.asarray(v, dtype=float)) for v in (N, My, Mz))
    t = np.arange(N.shape[0], dtype=float)
    return xr.Dataset({k: (("time", "node"), v) for k, v in (("tension", N), ("My", My), ("Mz", Mz))},
                      coords={"time": t, "node_s": ("node", np.arange(N.shape[1], dtype=float))})


def test_cross_section_stress_points_and_cutoff():
    """12 points 30 deg apart by default; tensile_only sets exactly the negative values to zero."""
    assert theta_points().tolist() == [0.0, 30.0, 60.0, 90.0, 120.0, 150.0, 180.0, 210.0, 240.0, 270.0, 300.0, 330.0]
    sec = _sections([[1000.0, 10.0]], [[100.0, 300.0]], [[50.0, 0.0]])
    s = TubeSection(0.040, 0.020)
    full = cross_section_stress(sec, s)
    cut = cross_section_stress(sec, s, tensile_only=True)
    assert full.dims == ("time", "node", "theta") and full.sizes["theta"] == 12
    assert full.attrs["units"] == "Pa"
    np.testing.assert_allclose(full.sel(theta=90.0).values, s.stress(sec.tension, sec.My, sec.Mz, math.pi / 2))
    assert np.any(full.values < 0)
    np.testing.assert_array_equal(cut.values, np.where(full.values > 0, full.values, 0.0))


# ------------------------------------------------------------------------------------------ rainflow
def test_rainflow_astm_example_matches_library_and_standard():
    ranges, means, counts = rainflow_cycles(ASTM_HISTORY)
    mine: dict[float, float] = {}
    for r, c in zip(ranges, counts, strict=True):
        mine[r] = mine.get(r, 0.0) + c
    assert mine == dict(rainflow.count_cycles(ASTM_HISTORY))
    assert mine == ASTM_COUNT
    lib = list(rainflow.extract_cycles(ASTM_HISTORY))
    np.testing.assert_array_equal(means, [c[1] for c in lib])


def test_rainflow_periodic_equals_repeated_signal():
    """A periodic record counted with periodic=True: every cycle closed (the largest, max to min,
    as the standard's two half cycles), and k times its damage is the damage of the signal
    repeated k times to within the open cycles of the ends (at most one half cycle of the largest
    range at each end)."""
    t = np.arange(200) / 200.0
    x = 40.0 * np.sin(2 * np.pi * t + 0.3) + 15.0 * np.sin(6 * np.pi * t) + 5.0 * np.cos(14 * np.pi * t)
    r, _, c = rainflow_cycles(x, periodic=True)
    assert np.all(r[c == 0.5] == x.max() - x.min()) and np.sum(c == 0.5) == 2
    curve = SNCurve.one_slope(ALPHA, M)
    d1 = curve.damage(r, c)
    k = 25
    dk = miner_sum(np.tile(x, k), curve)
    big = curve.damage([x.max() - x.min()])
    assert abs(dk - k * d1) <= big * 1.0000001
    # the rotation makes the count independent of where the period starts
    d_shift = miner_sum(np.roll(x, 77), curve, periodic=True)
    assert d_shift == pytest.approx(d1, rel=1e-12)


def test_rainflow_plateaus_and_short_series():
    r, _, c = rainflow_cycles([0.0, 1.0, 1.0, 1.0, -1.0, -1.0, 2.0])
    assert dict(rainflow.count_cycles([0.0, 1.0, 1.0, 1.0, -1.0, -1.0, 2.0])) == {
        k: sum(cc for rr, cc in zip(r, c, strict=True) if rr == k) for k in set(r)}
    assert rainflow_cycles([3.0])[0].size == 0
    with pytest.raises(ValueError):
        rainflow_cycles([0.0, np.nan, 1.0])


# ------------------------------------------------------------------------------------------ S-N, Miner
@pytest.mark.parametrize("n", [1, 7, 1000])
def test_miner_constant_amplitude_is_n_S_m_over_alpha(n):
    """A constant-amplitude history of n cycles of range S (stress in Pa, curve in MPa)."""
    S = 23.7e6
    x = np.tile([S, 0.0], n + 1)[: 2 * n + 1] + 1.5e6  # n cycles, peak to peak S, mean offset
    r, _, c = rainflow_cycles(x)
    assert np.sum(c) == n
    curve = SNCurve.one_slope(ALPHA, M, unit=1e6)
    assert miner_sum(x, curve) == pytest.approx(n * (S / 1e6) ** M / ALPHA, rel=1e-13)
    # the same through the periodic path of one cycle
    assert miner_sum([S, 0.0], curve, periodic=True) * n == pytest.approx(n * (S / 1e6) ** M / ALPHA, rel=1e-13)


def test_two_slope_curve_and_endurance_limit():
    """DNV-RP-C203-like curve: log a1 = 12.164, m1 = 3, m2 = 5, knee at 1e7 cycles."""
    a1 = 10**12.164
    c = SNCurve.two_slope(a1, 3.0, 5.0, knee_cycles=1e7)
    Sk = (a1 / 1e7) ** (1 / 3)
    assert c.knee == pytest.approx(Sk, rel=1e-14)
    assert c.cycles_to_failure(Sk) == pytest.approx(1e7, rel=1e-12)
    assert c.cycles_to_failure(Sk * (1 - 1e-12)) == pytest.approx(1e7, rel=1e-9)  # continuous
    assert c.cycles_to_failure(2 * Sk) == pytest.approx(a1 * (2 * Sk) ** -3, rel=1e-12)
    assert c.cycles_to_failure(0.5 * Sk) == pytest.approx(1e7 * 2.0**5, rel=1e-12)
    assert c.damage([2 * Sk, 0.5 * Sk], [3.0, 4.0]) == pytest.approx(
        3 / (a1 * (2 * Sk) ** -3) + 4 / (1e7 * 32), rel=1e-12)
    same = SNCurve.two_slope(a1, 3.0, 5.0, knee=Sk)
    assert same.cycles_to_failure(0.3 * Sk) == pytest.approx(c.cycles_to_failure(0.3 * Sk), rel=1e-12)
    e = SNCurve.one_slope(ALPHA, M, endurance=10.0)
    assert e.damage([9.999, 0.0]) == 0.0
    assert e.damage([10.0]) == pytest.approx(10.0**M / ALPHA, rel=1e-14)
    e2 = SNCurve.two_slope(a1, 3.0, 5.0, knee_cycles=1e7, endurance=0.8 * Sk)
    assert e2.damage([0.7 * Sk]) == 0.0 and e2.damage([0.9 * Sk]) > 0.0
    with pytest.raises(ValueError):
        SNCurve.two_slope(a1, 3.0, 5.0)


def test_tn_curves():
    """API RP 2SK studless chain N R^3.36 = 370 with R = range / MBS; DNV-OS-E301 studless chain
    N = 6e10 S^-3 with S the range over 2 pi d^2/4 in MPa."""
    mbs = 5.0e6
    api = api_chain_tn_curve("studless", mbs)
    assert api.damage([0.1 * mbs], [1000.0]) == pytest.approx(1000 * 0.1**3.36 / 370.0, rel=1e-13)
    d = 0.076
    dnv = dnv_chain_sn_curve("studless", d)
    dT = 2.0e5
    S = dT / (2 * math.pi * d * d / 4) / 1e6
    assert dnv.damage([dT]) == pytest.approx(S**3 / 6e10, rel=1e-13)
    with pytest.raises(ValueError):
        api_chain_tn_curve("wire", mbs)


def test_compression_cutoff_before_counting():
    """Tensile-only counting: a history swinging between -10 and +10 MPa counts as 0..10 MPa;
    a history that stays compressive does no damage; a tensile one is unchanged."""
    curve = SNCurve.one_slope(ALPHA, M, unit=1e6)
    n = 50
    sw = np.tile([10e6, -10e6], n)
    # stress = N/A + bending: build sections whose theta = 90 deg stress is the history
    s = TubeSection(0.040, 0.020)
    my = sw * s.I / s.c
    sec = _sections(np.zeros((2 * n, 1)), my[:, None], np.zeros((2 * n, 1)))
    cut = cross_section_stress(sec, s, theta=[90.0, 270.0], tensile_only=True)
    d = fatigue_damage(cut, curve)
    full = fatigue_damage(cross_section_stress(sec, s, theta=[90.0, 270.0]), curve)
    assert d.sel(theta=90.0).item() == pytest.approx(miner_sum(np.clip(sw, 0, None), curve), rel=1e-12)
    assert d.sel(theta=90.0).item() == pytest.approx(full.sel(theta=90.0).item() / 2.0**M, rel=1e-6)
    comp = cross_section_stress(_sections(np.zeros((4, 1)), -np.array([[1.0], [5.0], [2.0], [7.0]]) * 1e3,
                                          np.zeros((4, 1))), s, theta=[90.0], tensile_only=True)
    assert np.all(comp.values == 0.0) and fatigue_damage(comp, curve).item() == 0.0


def test_damage_along_line_and_critical_location():
    """fatigue_damage keeps the other dimensions and coordinates; the critical location is the
    node and theta of the largest damage; life = 1 / annual damage."""
    t = np.arange(40) * 0.25
    rng = np.random.default_rng(3)
    base = rng.normal(size=(t.size, 4, 3)) * 1e6
    base[:, 2, 1] *= 3.0
    da = xr.DataArray(base, dims=("time", "node", "theta"),
                      coords={"time": t, "node_s": ("node", [0.0, 1.5, 3.0, 4.5]), "theta": [0.0, 120.0, 240.0]})
    curve = SNCurve.one_slope(ALPHA, M, unit=1e6)
    d = fatigue_damage(da, curve)
    assert d.dims == ("node", "theta") and d.attrs["duration"] == pytest.approx(t[-1])
    assert d.sel(theta=120.0).isel(node=2).item() == pytest.approx(miner_sum(base[:, 2, 1], curve), rel=1e-14)
    crit = critical_location(d)
    assert (crit["node"], crit["s"], crit["theta"]) == (2, 3.0, 120.0)
    assert life_years(0.01) == pytest.approx(100.0) and life_years(0.0) == math.inf
