"""A whole sweep: run the pending cases on an executor, store each as it finishes, resume, and
gather the results into one Dataset and a summary table (:func:`run_sweep`)."""

from __future__ import annotations

import json
import logging
import math
import os
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from .. import __version__
from ..errors import SweepError
from ..results import write_netcdf
from .executors import available_cpus, run_dask, run_local
from .run import run_case
from .spec import CaseSpec, Study

log = logging.getLogger("moorline")


# ---------------------------------------------------------------------------------------------- sweep
@dataclass
class SweepResult:
    """What :func:`run_sweep` returns."""

    dataset: xr.Dataset
    summary: object  # pandas.DataFrame
    out_dir: Path
    wall_time: float
    computed: int
    reused: int


_SUMMARY_VARS = ("life_years", "damage_per_year_max", "critical_s", "critical_theta", "curvature_max_all",
                 "curvature_max_s", "bend_radius_min_all", "bend_radius_ok", "tension_max_all", "tension_min_all",
                 "compression_probability", "tn_life_years", "failed_probability")


def _load_case(path: Path, key: str) -> xr.Dataset | None:
    try:
        ds = xr.load_dataset(path, engine="h5netcdf")
    except Exception as e:  # a damaged file is recomputed
        log.warning("cannot read %s (%s); the case is run again", path, e)
        return None
    return ds if ds.attrs.get("case_key") == key else None


def _write_text_atomic(path: Path, text: str) -> None:
    fd, tmp = tempfile.mkstemp(prefix=path.name + ".", suffix=".part", dir=path.parent)
    try:
        with os.fdopen(fd, "w") as f:
            f.write(text)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def gather(study: Study, datasets: list[xr.Dataset], specs: list[CaseSpec]) -> tuple[xr.Dataset, object]:
    """Combine case Datasets into one (parameters as dimensions for a grid, else a ``case``
    dimension with the parameters as coordinates) and a summary table (pandas DataFrame)."""
    import pandas as pd

    names = study.parameter_names()
    rows = []
    prepared = []
    for ds, spec in zip(datasets, specs, strict=True):
        vals = {n: spec.params.get(n, np.nan) for n in names}
        row = {"case": spec.index, **vals}
        for v in _SUMMARY_VARS:
            if v in ds:
                row[v] = float(ds[v])
        row["wall_time_s"] = float(ds.attrs.get("wall_time_s", np.nan))
        rows.append(row)
        d = ds.drop_vars([n for n in names if n in ds.variables], errors="ignore")  # e.g. Hs as a parameter
        d = d.expand_dims(case=[spec.index]).assign_coords({n: ("case", [v]) for n, v in vals.items()})
        prepared.append(d)
    combined = xr.concat(prepared, dim="case", coords="different", compat="equals", join="outer",
                         combine_attrs="drop")
    if study.is_grid and len(names) == 1:
        combined = combined.swap_dims(case=names[0]).drop_vars("case")
    elif study.is_grid:
        combined = combined.set_index(case=names).unstack("case").transpose(*names, ...)
    combined.attrs.update(study=study.name, deck=str(study.deck), moorline_version=__version__,
                          parameters=json.dumps(names), settings=json.dumps(study.settings(), default=str))
    return combined, pd.DataFrame(rows)


def run_sweep(study: Study | str | os.PathLike, *, out=None, workers: int | None = None, scheduler=None,
              resume: bool = True, progress: bool | None = None) -> SweepResult:
    """Run every case of a study and gather the results.

    Parameters
    ----------
    study : Study or path
        The study (or its YAML file).
    out : path, optional
        Output folder (default: the study's ``output`` or ``<name>_out`` next to the study file).
    workers : int, optional
        Local worker processes (default: the CPUs this process may use; 1 runs the cases in this
        process).
    scheduler : str or distributed.Client, optional
        Address of a Dask scheduler (or a Client): run the cases on that cluster instead.
    resume : bool
        Reuse the stored results of cases already finished (default); False recomputes all.
    progress : bool, optional
        Progress bar over the cases (default: when the output is a terminal).

    Returns
    -------
    SweepResult

    Raises
    ------
    StudyError
        A study that cannot run (checked before any case starts).
    SweepError
        When some cases failed; the finished ones are stored.
    """
    if not isinstance(study, Study):
        study = Study.from_yaml(study)
    if out is not None:
        study.output = Path(out).resolve()
    out_dir = study.output_dir()
    cases_dir = out_dir / "cases"
    cases_dir.mkdir(parents=True, exist_ok=True)
    for stale in cases_dir.glob("*.part"):  # left by a killed run
        stale.unlink(missing_ok=True)
    specs = study.case_specs()
    wall0 = time.perf_counter()
    done: dict[int, xr.Dataset] = {}
    if resume:
        for s in specs:
            p = cases_dir / s.filename
            if p.exists():
                ds = _load_case(p, s.key)
                if ds is not None:
                    done[s.index] = ds
    pending = [s for s in specs if s.index not in done]
    reused = len(done)
    if reused:
        log.info("%s: %d of %d cases already done in %s", study.name, reused, len(specs), cases_dir)
    failures: list[str] = []

    def finished(spec: CaseSpec, ds: xr.Dataset) -> None:
        write_netcdf(ds, cases_dir / spec.filename)
        done[spec.index] = ds
        life = float(ds["life_years"]) if "life_years" in ds else math.nan
        log.info("case %d/%d (%s): life %.4g years, %.3g s", spec.index + 1, len(specs), spec.label, life,
                 ds.attrs.get("wall_time_s", math.nan))

    def failed(spec: CaseSpec, e: BaseException) -> None:
        log.error("case %d (%s) failed: %s: %s", spec.index + 1, spec.label, type(e).__name__, e)
        failures.append(f"case {spec.index + 1} ({spec.label}): {type(e).__name__}: {e}")

    bar = tqdm(total=len(specs), initial=reused, desc=study.name, unit="case",
               disable=(not progress) if progress is not None else None)
    try:
        if not pending:
            pass
        elif scheduler is not None:
            run_dask(run_case, pending, scheduler, finished, failed, bar)
        else:
            n = workers if workers is not None else available_cpus()
            if n <= 1 or len(pending) == 1:
                for s in pending:
                    try:
                        ds = run_case(s)
                    except Exception as e:  # reported per case; the others go on
                        failed(s, e)
                    else:
                        finished(s, ds)
                    bar.update(1)
            else:
                run_local(run_case, pending, n, finished, failed, bar)
    finally:
        bar.close()
    if failures:
        raise SweepError(f"{len(failures)} of {len(specs)} cases failed (the other results are stored in "
                         f"{cases_dir}; run the sweep again to retry):\n  " + "\n  ".join(failures))
    ordered = [done[s.index] for s in specs]
    dataset, summary = gather(study, ordered, specs)
    wall = time.perf_counter() - wall0
    dataset.attrs.update(sweep_wall_time_s=wall, cases_computed=len(pending), cases_reused=reused)
    write_netcdf(dataset, out_dir / "results.nc")
    _write_text_atomic(out_dir / "summary.csv", summary.to_csv(index=False))
    log.info("%s: %d cases (%d computed, %d reused) in %.1f s; results in %s", study.name, len(specs), len(pending),
             reused, wall, out_dir)
    return SweepResult(dataset, summary, out_dir, wall, len(pending), reused)
