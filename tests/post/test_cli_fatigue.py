"""``moorline fatigue``: one run's NetCDF results to section stress, damage, critical location and
life, agreeing with the Python API it wraps."""

from __future__ import annotations

from pathlib import Path

import pytest
import xarray as xr

import moorline
from moorline.cli import main
from moorline.io import read_deck
from moorline.post import (
    SECONDS_PER_YEAR,
    SeaState,
    SNCurve,
    TubeSection,
    buoy_motion,
    critical_location,
    cross_section_stress,
    fatigue_damage,
    section_loads,
)
from moorline.results import write_netcdf

TINY = Path(__file__).resolve().parents[1] / "studies" / "tiny_cable.dat"


def test_cli_fatigue_matches_api(tmp_path, capsys):
    model = read_deck(TINY)
    sys_ = moorline.System(model)
    t, X = buoy_motion(SeaState(1.0, 4.0), sys_.deck_coupled_positions(), duration=12.0, dt=0.05, depth=15.0,
                       ramp=4.0)
    ds = moorline.simulate(sys_, 12.0, (t, X), dt_out=0.1, progress=False)
    path = write_netcdf(ds, tmp_path / "tiny.nc")
    out = tmp_path / "tiny_fatigue.nc"
    rc = main(["fatigue", str(path), "--do", "0.04", "--di", "0.02", "--alpha", "6.098e19", "--m", "6.238",
               "--tensile-only", "--start", "4", "--allowable-bend-radius", "0.5", "--out", str(out)])
    assert rc == 0
    text = capsys.readouterr().out
    part = ds.sel(time=slice(4.0, None))
    st = cross_section_stress(section_loads(part, model=model), TubeSection(0.04, 0.02), tensile_only=True)
    d = fatigue_damage(st, SNCurve.one_slope(6.098e19, 6.238, unit=1e6))
    crit = critical_location(d)
    assert f"s = {crit['s']:.3f} m from end A, theta = {crit['theta']:g} deg" in text
    saved = xr.load_dataset(out, engine="h5netcdf")
    xr.testing.assert_allclose(saved.damage, d, rtol=1e-12)
    assert float(saved.damage_per_year.max()) == pytest.approx(crit["damage"] / 8.0 * SECONDS_PER_YEAR, rel=1e-9)
    assert "curvature_max" in saved and "stress_max" in saved
    # no deck and no EI: an input error
    bare = ds.copy()
    bare.attrs["source"] = ""
    p2 = write_netcdf(bare, tmp_path / "bare.nc")
    assert main(["fatigue", str(p2), "--do", "0.04", "--alpha", "1e10", "--m", "3"]) == 2
