"""One case of a study: build the model with the case's parameters, find its equilibrium, run
every sea state and post-process the results (:func:`run_case`)."""

from __future__ import annotations

import json
import logging
import math
import time
from pathlib import Path

import numpy as np
import xarray as xr

from .. import __version__
from ..errors import SimulationError, SweepError
from ..io import read_deck
from ..model.water import Waves
from ..motion import Trajectory
from ..post import (
    SECONDS_PER_YEAR,
    ScatterDiagram,
    SeaState,
    buoy_motion,
    critical_location,
    cross_section_stress,
    envelopes,
    fatigue_damage,
    life_years,
    section_loads,
    wave_components,
    wavenumber,
)
from ..results import write_netcdf
from ..simulate import simulate
from ..system import System
from .parameters import _apply_parameters
from .spec import CaseSpec, _curves, _section

log = logging.getLogger("moorline")


def _sea_states(settings: dict, sea_fields: dict) -> list[SeaState] | None:
    ss = settings["sea_states"] or {}
    if not ss and not sea_fields:
        return None
    kw = {k: ss[k] for k in ("heading", "gamma", "seed") if k in ss}
    kw.update({k: v for k, v in sea_fields.items() if k in ("heading", "gamma", "seed")})
    kind = ss.get("kind", "regular")
    if ss.get("scatter"):
        sc = ScatterDiagram.from_csv(ss["scatter"], normalise=bool(ss.get("normalise", True)))
        return sc.sea_states(kind=kind, min_probability=float(ss.get("min_probability", 0.0)), **kw)
    Hs = sea_fields.get("Hs", ss.get("Hs"))
    Tz = sea_fields.get("Tz", ss.get("Tz"))
    return [SeaState(float(Hs), float(Tz), kind=kind, **kw)]


def _windows(sea: SeaState | None, sim: dict) -> dict:
    """Ramp, transient, analysed duration and output interval of one run [s]."""
    if sea is None:
        dt_out = sim["dt_out"] or 0.1
        return {"ramp": 0.0, "transient": float(sim["transient"] or 0.0), "duration": float(sim["duration"]),
                "dt_out": float(dt_out), "periodic": False}
    spp = int(sim["samples_per_period"])
    if sea.kind == "regular":
        T = sea.T
        return {"ramp": sim["ramp_periods"] * T, "transient": (sim["ramp_periods"] + sim["settle_periods"]) * T,
                "duration": int(sim["analyse_periods"]) * T, "dt_out": T / spp, "periodic": True}
    Tp = sea.Tp
    ramp = sim["ramp_periods"] * Tp
    transient = sim["transient"] if sim["transient"] is not None else (sim["ramp_periods"] + sim["settle_periods"]) * Tp
    return {"ramp": ramp, "transient": float(max(transient, ramp)), "duration": float(sim["duration"] or 600.0),
            "dt_out": float(sim["dt_out"] or sea.Tz / spp), "periodic": False}


def _post_one(ds: xr.Dataset, model, line: int, post: dict, sn, tn, section, periodic: bool, duration: float):
    """Damage rates and envelopes of one run."""
    an = ds.isel(time=slice(0, -1)) if periodic else ds
    sec = section_loads(an, line, model=model, frame=post["frame"])
    st = cross_section_stress(sec, section, n_theta=int(post["n_theta"]),
                              tensile_only=bool(post["tensile_only"])) if section is not None else None
    out = {}
    if sn is not None:
        out["damage_rate"] = fatigue_damage(st, sn, periodic=periodic) / duration
    if tn is not None:
        seg = np.flatnonzero(an.segment_line.values == line)
        out["tn_damage_rate"] = fatigue_damage(an.segment_tension.isel(segment=seg), tn, periodic=periodic) / duration
    env = envelopes(an, line, sections=sec, stress=st, allowable_bend_radius=post["allowable_bend_radius"],
                    compression_strain=float(post["compression_strain"]), warn=False)
    for k in env.data_vars:
        out[k] = env[k]
    return out


def run_case(spec: CaseSpec) -> xr.Dataset:
    """Run one case: build the model, find its equilibrium, run every sea state, post-process.

    Returns
    -------
    xarray.Dataset
        Dimensions ``sea_state``, ``node``, ``theta``, ``segment`` (of the post-processed line);
        see ``docs/fatigue.md`` for the variables.
    """
    wall0 = time.perf_counter()
    st = spec.settings
    sim, post = st["simulation"], st["post"]
    model = read_deck(Path(st["deck"]))
    sea_fields = _apply_parameters(model, {**st["fixed"], **spec.params})
    line = int(st["line"] or 1)
    sn, tn = _curves(post)
    section = _section(post)
    seas = _sea_states(st, sea_fields)
    kw = {k: sim[k] for k in ("dtM", "scheme") if sim[k] is not None}
    waves_on_lines = bool((st["sea_states"] or {}).get("waves_on_lines", False)) and seas is not None
    if waves_on_lines:
        model.env.waves = None  # the sea states bring their own
    elif seas is not None and model.env.waves is not None:
        log.warning("the deck's waves act on the lines while the buoy follows the study's sea states")
    base = System(model, **kw)
    x0 = base.deck_coupled_positions()
    zero = np.zeros_like(x0)
    labels = base.coupled_dof_labels
    base.init(x0, zero, solve_ic=bool(sim["solve_ic"]))
    ic = dict(base.ic_report)
    y_ic = base.y.copy()  # the equilibrium: every sea state starts from it
    runs_dir = Path(st["output"]) / "runs" / spec.key[:16] if st["record"]["runs"] else None

    entries = seas if seas is not None else [None]
    results, failed, notes = [], [], []
    for k, sea in enumerate(entries):
        w = _windows(sea, sim)
        t_total = w["transient"] + w["duration"]
        system = base
        if sea is not None:
            motion = Trajectory.from_samples(*buoy_motion(sea, x0, duration=t_total + w["dt_out"],
                                                          dt=0.5 * w["dt_out"], depth=model.env.depth,
                                                          ramp=w["ramp"], g=model.env.g, labels=labels))
            if waves_on_lines:
                model.env.waves = sea_waves(sea, x0, labels, depth=model.env.depth, g=model.env.g, ramp=w["ramp"],
                                            duration=t_total + w["dt_out"])
                system = System(model, **kw)
        elif st["motion"] and st["motion"].get("csv"):
            motion = Trajectory.from_csv(st["motion"]["csv"], n_dof=system.n_coupled_dof,
                                         interpolation=st["motion"].get("interpolation", "cubic"))
        else:
            motion = None
        system.init(x0, zero, solve_ic=False)  # time 0, the motion at rest
        if system.y.shape != y_ic.shape:
            raise RuntimeError("the state vector changed size with the sea state")
        system.y[:] = y_ic
        system.set_state()  # re-evaluates the loads, clears the scheme history, relaxes friction springs
        try:
            if w["transient"] > 0:
                simulate(system, w["transient"], motion, dt_out=w["transient"], progress=False)
            ds = simulate(system, w["duration"], motion, dt_out=w["dt_out"], progress=False)
        except SimulationError as e:
            what = f"sea state Hs = {sea.Hs} m, Tz = {sea.Tz} s" if sea is not None else "the run"
            log.warning("case %s: %s failed: %s", spec.label, what, e)
            failed.append(1)
            notes.append(f"{what}: {e}")
            results.append(None)
            continue
        if w["periodic"]:
            dt = np.diff(ds.time.values)
            if not np.allclose(dt, w["dt_out"], rtol=1e-6, atol=1e-9):
                raise RuntimeError(f"the analysis window of case {spec.label} is not sampled uniformly")
        if runs_dir is not None:
            write_netcdf(ds, runs_dir / f"sea_state_{k:03d}.nc")
        results.append(_post_one(ds, model, line, post, sn, tn, section, w["periodic"], w["duration"]))
        failed.append(0)

    out = _assemble(results, entries, failed)
    _summarise(out, post)
    out.attrs.update(case_key=spec.key, case_index=spec.index, parameters=json.dumps(spec.params),
                     ic=json.dumps(ic, default=str), failures=json.dumps(notes),
                     wall_time_s=time.perf_counter() - wall0, moorline_version=__version__, line=line)
    return out


def sea_waves(sea: SeaState, x0, labels, *, depth: float, g: float, ramp: float, duration: float):
    """The waves of a sea state acting on the lines, in phase with :func:`~moorline.post.buoy_motion`:
    the components of :func:`~moorline.post.wave_components` with their phases moved from the
    buoy to the origin (arg A_j = phi_j + k_j (x_b cos(beta) + y_b sin(beta)), x_b, y_b the first
    coupled object's horizontal position), so the elevation at the buoy is the buoy's heave; the
    same ramp.

    Returns
    -------
    moorline.model.water.Waves
    """
    a, w, phi = wave_components(sea, duration)
    x0 = np.asarray(x0, dtype=float)
    pos = {lab[-2:]: x0[i] for i, lab in reversed(list(enumerate(labels)))}  # the first object's
    b = math.radians(sea.heading)
    lb = pos.get("_x", 0.0) * math.cos(b) + pos.get("_y", 0.0) * math.sin(b)
    A = a * np.exp(1j * (phi + wavenumber(w, depth, g) * lb))
    return Waves.from_components(w, A, sea.heading, ramp_time=ramp,
                                 source=f"{sea.kind} sea Hs={sea.Hs:g} m Tz={sea.Tz:g} s (moorline.batch)")


def _assemble(results: list, entries: list, failed: list) -> xr.Dataset:
    """Stack the per-run results along ``sea_state`` (NaN for failed runs)."""
    ok = [r for r in results if r is not None]
    if not ok:
        raise SweepError("every run of the case failed")
    names = list(ok[0])
    stacked = {}
    for name in names:
        tmpl = ok[0][name]
        arrs = [(r[name] if r is not None else xr.full_like(tmpl, np.nan, dtype=float)) for r in results]
        da = xr.concat([a.drop_vars([c for c in a.coords if c not in a.dims and c not in ("node_s", "segment_s")],
                                    errors="ignore") for a in arrs], dim="sea_state", coords="minimal",
                       compat="override", join="override")
        stacked[name] = da.assign_attrs(tmpl.attrs)
    ds = xr.Dataset(stacked)
    n = len(entries)
    sea_coords = {"sea_state": np.arange(n), "failed": ("sea_state", np.asarray(failed, dtype=np.int8))}
    if entries[0] is not None:
        sea_coords.update(
            Hs=("sea_state", [s.Hs for s in entries], {"units": "m"}),
            Tz=("sea_state", [s.Tz for s in entries], {"units": "s"}),
            H=("sea_state", [s.H if s.kind == "regular" else np.nan for s in entries], {"units": "m"}),
            T=("sea_state", [s.T if s.kind == "regular" else np.nan for s in entries], {"units": "s"}),
            probability=("sea_state", [s.probability for s in entries]))
    else:
        sea_coords["probability"] = ("sea_state", [1.0])
    ds = ds.assign_coords(sea_coords)
    for dim in ("node", "segment"):
        if dim in ds.dims:
            ds = ds.assign_coords({dim: np.arange(ds.sizes[dim])})
    return ds


def _summarise(ds: xr.Dataset, post: dict) -> None:
    """Add the lifetime results of a case as 0-d variables (in place)."""
    p = ds.probability
    ok = ds.failed == 0
    ds["failed_probability"] = p.where(~ok, 0.0).sum()
    if "damage_rate" in ds:
        dy = (ds.damage_rate * p).sum("sea_state", skipna=True) * SECONDS_PER_YEAR
        ds["damage_per_year"] = dy.assign_attrs(units="1/year", long_name="probability-weighted damage per year")
        crit = critical_location(dy)
        ds["damage_per_year_max"] = crit["damage"]
        ds["life_years"] = life_years(crit["damage"])
        ds["critical_s"] = crit["s"]
        ds["critical_node"] = crit["node"]
        ds["critical_theta"] = crit["theta"]
        at = ds.damage_rate.isel(node=crit["node"]).sel(theta=crit["theta"])
        ds["damage_per_year_by_sea_state"] = (at * p * SECONDS_PER_YEAR).assign_attrs(
            units="1/year", long_name="contribution of each sea state to the damage at the critical location")
        ds["damage_per_year_max"].attrs.update(units="1/year")
        ds["life_years"].attrs.update(units="year")
        ds["critical_s"].attrs.update(units="m", long_name="arc length of the critical location from end A")
        ds["critical_theta"].attrs.update(units="deg")
    if "tn_damage_rate" in ds:
        ty = (ds.tn_damage_rate * p).sum("sea_state", skipna=True) * SECONDS_PER_YEAR
        ds["tn_damage_per_year"] = ty.assign_attrs(units="1/year")
        ds["tn_life_years"] = life_years(float(ty.max()))
    kmax = ds.curvature_max.max("sea_state")
    i = int(np.argmax(kmax.values))
    ds["curvature_max_all"] = float(kmax[i])
    ds["curvature_max_s"] = float(ds.node_s.values[i]) if "node_s" in ds.coords else np.nan
    ds["bend_radius_min_all"] = 1.0 / float(kmax[i]) if kmax[i] > 0 else np.inf
    ds["tension_max_all"] = float(ds.tension_max.max())
    ds["tension_min_all"] = float(ds.tension_min.min())
    if "compressed_fraction" in ds:
        comp = (ds.compressed_fraction > 0).any("segment")
        ds["compression_probability"] = float(p.where(comp, 0.0).sum())
    if post.get("allowable_bend_radius"):
        ds["bend_radius_ok"] = int(ds["bend_radius_min_all"] >= post["allowable_bend_radius"])
