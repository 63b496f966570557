"""The validation gallery (validation/<study>/run.py --quick): each study runs in a subprocess into a
temporary folder, must exit 0 (all its own checks passed) and write a results.json with the
headline numbers of issue 16 in SI units, finite and in physically sensible ranges.

These are slow (minutes each on a shared 2-core machine). A study is skipped when what it needs
is absent: ../shared/data (the RM3 studies: the public RM3 set; W4P: the scatter diagram) or
Capytaine (fps and W4P compute their hull's coefficients).
"""

from __future__ import annotations

import json
import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared" / "data"

pytestmark = pytest.mark.slow


#: what each study reads from ../shared/data, and whether it runs Capytaine
NEEDS = {"fps": ((), True), "rm3": (("rm3/rm3.1", "rm3/rm3_moorings_moordyn.txt"), False),
         "rm3_umbilical": (("rm3/rm3.1", "rm3/rm3_moorings_moordyn.txt"), False),
         "w4p_cable": (("w4p_scatter.csv",), True)}


def _start(study: str, tmp_path: Path, *extra: str) -> subprocess.CompletedProcess:
    files, bem = NEEDS[study]
    missing = [f for f in files if not (SHARED / f).exists()]
    if missing:
        pytest.skip(f"../shared/data/{missing[0]} is not present (public reference data beside the repository)")
    if bem:
        pytest.importorskip("capytaine")
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT / "src") + os.pathsep + env.get("PYTHONPATH", "")
    env.setdefault("MPLBACKEND", "Agg")
    return subprocess.run([sys.executable, str(ROOT / "validation" / study / "run.py"), "--quick", "--out",
                           str(tmp_path), *extra], capture_output=True, text=True, env=env, timeout=1800)


def _run(study: str, tmp_path: Path, *extra: str) -> dict:
    proc = _start(study, tmp_path, *extra)
    assert proc.returncode == 0, f"{study} --quick failed:\n{proc.stdout[-4000:]}\n{proc.stderr[-4000:]}"
    res = json.loads((tmp_path / "results.json").read_text())
    assert res["mode"] == "quick"
    assert res["passed"] is True
    assert all(c["passed"] for c in res["checks"])
    assert list(tmp_path.glob("*.png")), "no figure written"
    return res


def _finite(*values):
    return all(isinstance(v, (int, float)) and math.isfinite(v) for v in values)


def test_fps(tmp_path):
    res = _run("fps", tmp_path)
    for case in ("regular", "irregular"):
        mean, std = res[case]["fairlead_tension_mean_n"], res[case]["fairlead_tension_std_n"]
        assert len(mean) == len(std) == 3 and _finite(*mean, *std)
        # 45.5 g/m chain hanging about 1 m: a fraction of a newton; M1 and M3 mirror each other
        assert all(0.2 < m < 1.0 for m in mean)
        assert mean[0] == pytest.approx(mean[2], rel=1e-3)
        assert all(s > 0 for s in std)
    # the waves make the tension fluctuate more in the 40 mm regular wave than in the 20 mm sea
    assert min(res["regular"]["fairlead_tension_std_n"]) > max(res["irregular"]["fairlead_tension_std_n"])
    assert 0.004 < res["heave_equilibrium_sink_m"] < 0.007


def test_rm3(tmp_path):
    res = _run("rm3", tmp_path)
    for key in ("relative_motion_std_m", "mean_pto_power_w"):
        assert set(res[key]) == {"moored", "free"} and _finite(*res[key].values())
        assert res[key]["moored"] == pytest.approx(res[key]["free"], rel=0.05)
    assert 0.3 < res["regular_relative_motion_amplitude_m"] < 1.5
    assert 1e5 < res["regular_mean_pto_power_w"] < 5e5
    fd = res["regular_frequency_domain"]
    assert res["regular_free"]["relative"] == pytest.approx(fd["relative"], rel=0.03)


def test_rm3_umbilical(tmp_path):
    # in two sessions: the first stops at its first checkpoint (20 s of 60), the second resumes
    first = _start("rm3_umbilical", tmp_path, "--chunk", "20", "--stop-after", "1")
    assert first.returncode == 3, f"expected a stop at the first checkpoint:\n{first.stdout[-4000:]}\n" \
                                  f"{first.stderr[-4000:]}"
    assert "stopped at t = 20 s of 60 s" in first.stdout
    assert not (tmp_path / "results.json").exists()  # nothing written as if complete
    res = _run("rm3_umbilical", tmp_path, "--chunk", "20", "--resume")
    # the resumed record is whole: every output time once, from 0 to 60 s
    import xarray as xr

    with xr.open_dataset(tmp_path / "out" / "quick" / "coupled.nc", engine="h5netcdf") as ds:
        t = ds.time.values
        assert int(ds.attrs["complete"]) == 1
    assert t[0] == 0.0 and t[-1] == pytest.approx(60.0) and len(t) == 301
    assert (t[1:] - t[:-1]).min() > 0.19
    assert _finite(res["top_tension_mean_n"], res["top_tension_max_n"], res["max_curvature_per_m"])
    assert 0 < res["top_tension_mean_n"] < res["top_tension_max_n"]
    # the cable hangs about 60 m of 77.3 kg/m line (wet 52 kg/m): tens of kN at the top
    assert 5e3 < res["top_tension_mean_n"] < 2e5
    assert 0 < res["max_curvature_per_m"] < 2.0


def test_w4p_cable(tmp_path):
    res = _run("w4p_cable", tmp_path, "--workers", "1")
    for key in ("life_years", "single_condition_life_years"):
        assert set(res[key]) == {"initial", "improved"} and _finite(*res[key].values())
        assert all(v > 0 for v in res[key].values())
    assert res["partial"] is True
    assert 0 <= res["critical_location_s_m"] <= 70
    assert _finite(res["min_clearance_to_buoy_m"])
