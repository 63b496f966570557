"""Parametric sweeps end to end (moorline.studies, ``moorline sweep``), on the 5-segment test cable:

- a grid sweep over a small scatter diagram gathers into one Dataset with the parameters as
  dimensions and a summary table; the lifetime damage is the probability-weighted sum of the
  damage rates of the sea states, the zero-probability cell is skipped;
- a sweep killed (SIGKILL) after its first case is stored resumes without recomputing the stored
  cases and finishes with the same results as an uninterrupted sweep;
- a Dask LocalCluster gives the same results as local processes;
- the cases run on two local worker processes give the results of the cases run one at a time in
  this process, bit for bit, and the workers compile no kernel (they load them from the numba
  cache this process filled); the thread-count variables set for the workers take their share
  of the CPUs, keep what the user set, and leave this process's environment as it was.
"""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
import xarray as xr
import yaml

from moorline.post import SECONDS_PER_YEAR
from moorline.studies import Study, run_case, run_sweep
from moorline.studies.executors import _worker_threads, available_cpus, run_local

DECK = Path(__file__).resolve().parent / "tiny_cable.dat"

SCATTER = """# a small scatter diagram for tests (probabilities in 1e-3; the 0 cell is skipped)
Hs\\Tz,3.5,4.5
0.5,40,0
1.5,30,30
"""


def write_study(folder: Path, parameters: dict, scatter: bool = True) -> Path:
    folder.mkdir(parents=True, exist_ok=True)
    d = {"name": "tiny", "deck": str(DECK), "parameters": parameters,
         "simulation": {"settle_periods": 0.5, "samples_per_period": 20},
         "post": {"section": {"do": 0.04, "di": 0.02}, "tensile_only": True,
                  "sn": {"alpha": 6.098e19, "m": 6.238, "unit": 1.0e6},
                  "tn": {"curve": "api", "kind": "studless", "mbs": 1.0e5}, "allowable_bend_radius": 2.0}}
    if scatter:
        (folder / "scatter.csv").write_text(SCATTER)
        d["sea_states"] = {"scatter": "scatter.csv"}
    else:
        d["sea_states"] = {"Hs": 1.0, "Tz": 4.0}
    path = folder / "study.yaml"
    path.write_text(yaml.safe_dump(d, sort_keys=False))
    return path


GRID = {"mass": [2.0, 2.75, 6.0], "EI": [50.0, 350.0]}


def same(a: xr.Dataset, b: xr.Dataset) -> None:
    """Identical data, coordinates and variable attributes (the Dataset attributes hold wall times)."""
    a, b = a.copy(), b.copy()
    a.attrs, b.attrs = {}, {}
    xr.testing.assert_identical(a, b)


@pytest.fixture(scope="module")
def reference(tmp_path_factory):
    """The uninterrupted sweep, in this process."""
    study = write_study(tmp_path_factory.mktemp("ref"), GRID)
    return run_sweep(study, workers=1, progress=False)


def test_sweep_gathers_grid_and_weights_sea_states(reference):
    ds, sm = reference.dataset, reference.summary
    assert (reference.computed, reference.reused) == (6, 0)
    assert ds.damage_rate.dims == ("mass", "EI", "sea_state", "node", "theta")
    assert ds.sizes["sea_state"] == 3 and ds.sizes["node"] == 6 and ds.sizes["theta"] == 12
    np.testing.assert_allclose(ds.probability.values, np.array([40, 30, 30]) / 100.0, rtol=1e-14)
    assert ds.Hs.values.tolist() == [0.5, 1.5, 1.5] and ds.Tz.values.tolist() == [3.5, 3.5, 4.5]
    dy = (ds.damage_rate * ds.probability).sum("sea_state") * SECONDS_PER_YEAR
    np.testing.assert_allclose(ds.damage_per_year.values, dy.values, rtol=1e-12)
    np.testing.assert_allclose(ds.life_years.values, 1.0 / dy.max(("node", "theta")).values, rtol=1e-12)
    np.testing.assert_allclose(ds.damage_per_year_by_sea_state.sum("sea_state").values,
                               ds.damage_per_year_max.values, rtol=1e-12)
    assert np.all(ds.damage_rate.values >= 0) and np.all(ds.life_years.values > 0)
    assert np.all(ds.failed.values == 0)
    assert len(sm) == 6 and list(sm.columns[:3]) == ["case", "mass", "EI"]
    row = sm[(sm.mass == 6.0) & (sm.EI == 50.0)].iloc[0]
    assert row.life_years == pytest.approx(float(ds.life_years.sel(mass=6.0, EI=50.0)), rel=1e-12)
    assert (reference.out_dir / "results.nc").exists() and (reference.out_dir / "summary.csv").exists()
    same(xr.load_dataset(reference.out_dir / "results.nc", engine="h5netcdf"), ds)


def test_interrupted_sweep_resumes_with_the_same_results(reference, tmp_path):
    study = write_study(tmp_path, GRID)
    out = tmp_path / "tiny_out"
    cases = out / "cases"
    proc = subprocess.Popen([sys.executable, "-m", "moorline.cli", "sweep", str(study), "--workers", "1",
                             "--quiet-progress"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    t0 = time.monotonic()
    try:
        while not (cases.exists() and any(cases.glob("*.nc"))):
            assert proc.poll() is None, f"the sweep ended before storing a case: {proc.stderr.read().decode()}"
            assert time.monotonic() - t0 < 180.0, "no case stored within 180 s"
            time.sleep(0.01)
    finally:
        proc.kill()
        proc.wait()
        proc.stderr.close()
    stored = {p.name: p.stat().st_mtime_ns for p in cases.glob("*.nc")}
    assert 1 <= len(stored) < 6, f"{len(stored)} cases stored: the kill came too late to test resuming"
    res = run_sweep(study, workers=1, progress=False)
    assert (res.reused, res.computed) == (len(stored), 6 - len(stored))
    assert {p.name: p.stat().st_mtime_ns for p in cases.glob("*.nc") if p.name in stored} == stored
    assert not list(cases.glob("*.part"))
    same(res.dataset, reference.dataset)
    cols = [c for c in reference.summary.columns if c != "wall_time_s"]
    assert res.summary[cols].equals(reference.summary[cols])
    # run again: everything is reused
    again = run_sweep(study, workers=1, progress=False)
    assert (again.reused, again.computed) == (6, 0)
    same(again.dataset, reference.dataset)


_COMPILES = []  # numba's compile events in this (worker) process


def _run_case_counting(spec):
    """A sweep case in a worker process, with the kernels numba compiled for it (compile events
    fire only for kernels not found in the on-disk cache) and the worker's BLAS thread setting."""
    if not _COMPILES:
        from numba.core import event

        class Counter(event.Listener):
            def on_start(self, ev):
                _COMPILES.append(ev.data["dispatcher"].py_func.__qualname__)

            def on_end(self, ev):
                pass

        _COMPILES.append(None)
        event.register("numba:compile", Counter())
    n0 = len(_COMPILES)
    ds = run_case(spec)
    return os.getpid(), _COMPILES[n0:], os.environ.get("OPENBLAS_NUM_THREADS"), ds


def test_local_workers_match_one_at_a_time_and_share_the_cache(reference):
    study = Study.from_yaml(reference.out_dir.parent / "study.yaml")
    specs = study.case_specs()
    got, errors = {}, []

    class Bar:
        def update(self, k):
            pass

    expected_threads = os.environ.get("OPENBLAS_NUM_THREADS") or str(max(1, available_cpus() // 2))
    run_local(_run_case_counting, specs, 2, lambda s, r: got.__setitem__(s.index, r),
              lambda s, e: errors.append(f"{s.label}: {e!r}"), Bar())
    assert not errors
    assert sorted(got) == [s.index for s in specs]
    for s in specs:
        pid, compiled, threads, ds = got[s.index]
        assert pid != os.getpid()
        assert compiled == [], f"a worker compiled {compiled} instead of loading them from the cache"
        assert threads == expected_threads
        same(ds, xr.load_dataset(reference.out_dir / "cases" / s.filename, engine="h5netcdf"))


def test_worker_threads_take_their_share_keep_the_users_and_are_restored(monkeypatch):
    """The thread-count variables set for starting workers: the workers' share of the CPUs where
    the user set none, the user's value where set, and this process's environment as it was after."""
    for k in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS"):
        monkeypatch.delenv(k, raising=False)
    monkeypatch.setenv("MKL_NUM_THREADS", "3")
    with _worker_threads(2):
        assert os.environ["OPENBLAS_NUM_THREADS"] == os.environ["OMP_NUM_THREADS"] == str(max(1, available_cpus() // 2))
        assert os.environ["MKL_NUM_THREADS"] == "3"
    with _worker_threads(4 * available_cpus()):
        assert os.environ["OPENBLAS_NUM_THREADS"] == "1"
    assert "OPENBLAS_NUM_THREADS" not in os.environ and "OMP_NUM_THREADS" not in os.environ
    assert os.environ["MKL_NUM_THREADS"] == "3"
    assert 1 <= available_cpus() <= (os.cpu_count() or 1)


def test_dask_cluster_matches_local_processes(tmp_path):
    distributed = pytest.importorskip("distributed")
    study = write_study(tmp_path, {"mass": [2.0, 6.0]}, scatter=False)
    local = run_sweep(study, out=tmp_path / "local", workers=2, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as c:
        dask = run_sweep(study, out=tmp_path / "dask", scheduler=c.scheduler_address, progress=False)
    assert dask.computed == 2
    same(dask.dataset, local.dataset)
    assert dask.dataset.mass.values.tolist() == [2.0, 6.0]


def test_current_and_waves_on_lines_act_on_the_cable(tmp_path):
    """One design, one sea state: with the sea's waves on the cable, then also a current, the run
    stays stable and its damage and tension change; the waves are in place only while the sea
    state runs (not during the initial equilibrium, which the three runs share)."""
    from moorline.studies import Study, run_case

    d = yaml.safe_load(write_study(tmp_path, {}, scatter=False).read_text())
    out = {}
    for label, sea, fixed in (("buoy only", {}, {}), ("waves", {"waves_on_lines": True}, {}),
                              ("waves and current", {"waves_on_lines": True},
                               {"current_speed": 0.5, "current_heading": 180.0})):
        dd = {**d, "sea_states": {**d["sea_states"], **sea}, "fixed": fixed}
        out[label] = run_case(Study.from_dict(dd, base_dir=tmp_path).case_specs()[0])
    for ds in out.values():
        assert int(ds.failed.sum()) == 0 and np.isfinite(float(ds.life_years))
    a, b, c = (float(out[k].damage_per_year_max) for k in ("buoy only", "waves", "waves and current"))
    assert a != b and b != c
    assert float(out["waves and current"].tension_max_all) != float(out["waves"].tension_max_all)
