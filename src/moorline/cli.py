"""The ``moorline`` command.

    moorline run DECK|SYSTEM.yaml [--duration 60] [--motion motion.csv] [--out DIR] [--dt-out 0.1]
                 [--waves jonswap:Hs=3.5,Tp=7.5,heading=180,seed=1] [--current 1.0@180]
    moorline statics DECK [--out DIR] [--quasi-static [--json] [--offset x,y,z,rx,ry,rz] [--friction CB]]
    moorline check DECK
    moorline sweep STUDY.yaml [--workers N] [--scheduler ADDRESS] [--out DIR] [--no-resume]
    moorline fatigue RESULT.nc --do 0.040 [--di 0.020] --alpha 6.098e19 --m 6.238 [--unit 1e6]

``run`` reads a MoorDyn v2 deck, finds the initial equilibrium, imposes the coupled motion and
writes MoorDyn-style output (``<base>.out`` with the OUTPUTS channels, ``<base>_Line<n>.out`` as the
line output flags ask) plus a NetCDF file ``<base>.nc`` with everything. Files are written only
when the run succeeds, each atomically.

``sweep`` runs a parametric study (see :mod:`moorline.studies`); ``fatigue`` post-processes one run
(section stress around the cable, rainflow, S-N damage; see :mod:`moorline.post`).

Exit codes: 0 success, 2 bad input (deck, motion file, study file, arguments), 3 the simulation
or some sweep cases failed, or the initial conditions did not converge (``run`` and ``statics``;
``--accept-unconverged-ic`` goes on).
"""

from __future__ import annotations

import argparse
import logging
import sys
import time
from pathlib import Path

import numpy as np

from . import __version__
from .errors import DeckError, SimulationError

log = logging.getLogger("moorline")


def _setup_logging(verbosity: int, log_file: Path | None = None) -> None:
    level = logging.WARNING - 10 * verbosity
    root = logging.getLogger("moorline")
    root.setLevel(min(level, logging.DEBUG if log_file else level))
    handler = logging.StreamHandler(sys.stderr)
    handler.setLevel(level)
    handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
    root.handlers[:] = [handler]
    if log_file is not None:
        fh = logging.FileHandler(log_file, mode="w")
        fh.setLevel(logging.DEBUG)
        fh.setFormatter(logging.Formatter("%(asctime)s %(levelname)s %(name)s: %(message)s"))
        root.addHandler(fh)


def _read_input(path: Path):
    """The model and the run settings of a MoorDyn deck or a system file (.yaml/.yml)."""
    from .io import read_deck
    from .io.system_file import read_system_file

    if path.suffix.lower() in (".yaml", ".yml"):
        sf = read_system_file(path)
        return sf.model, sf.run
    return read_deck(path), {}


def _load(args):
    from .system import System

    model, run = _read_input(Path(args.deck))
    args.run_settings = run
    try:
        if getattr(args, "waves", None):
            model.env.waves = parse_waves(args.waves)
        if getattr(args, "current", None):
            model.env.current = parse_current(args.current)
    except ValueError as e:  # a bad --waves / --current value: bad input, exit code 2
        raise DeckError(str(e)) from None
    kwargs = {k: v for k, v in run.items() if k in ("dtM", "scheme", "mooring")}
    if getattr(args, "mooring", None):
        kwargs["mooring"] = args.mooring
    if getattr(args, "dtM", None):
        kwargs["dtM"] = args.dtM
    if getattr(args, "scheme", None):
        kwargs["scheme"] = args.scheme
    return System(model, **kwargs)


_WAVE_KINDS = ("regular", "jonswap", "pm")


def parse_waves(text: str):
    """A sea from the command line: ``jonswap:Hs=3.5,Tp=7.5[,gamma=3.3][,heading=180][,seed=1]
    [,n=200][,ramp=20]``, ``pm:Hs=..,Tp=..`` (Pierson-Moskowitz) or ``regular:H=2,T=8[,heading=..]``.
    Headings in degrees, direction of travel from +x toward +y."""
    from .model.water import Waves

    kind, _, rest = text.partition(":")
    kind = kind.strip().lower()
    if kind not in _WAVE_KINDS:
        raise ValueError(f"--waves {text!r}: expected one of {', '.join(_WAVE_KINDS)} before ':', e.g. "
                         "jonswap:Hs=3.5,Tp=7.5,heading=180")
    kv = {}
    for item in filter(None, (x.strip() for x in rest.split(","))):
        key, eq, val = item.partition("=")
        try:
            kv[key.strip().lower()] = float(val)
        except ValueError:
            raise ValueError(f"--waves {text!r}: expected key=number, got {item!r}") from None
        if not eq:
            raise ValueError(f"--waves {text!r}: expected key=number, got {item!r}")
    opts = {}
    if "ramp" in kv:
        opts["ramp_time"] = kv.pop("ramp")
    heading = kv.pop("heading", 0.0)
    try:
        if kind == "regular":
            return Waves.regular(kv.pop("h"), kv.pop("t"), heading=heading, phase=kv.pop("phase", 0.0), **opts)
        Hs, Tp = kv.pop("hs"), kv.pop("tp")
        gamma = kv.pop("gamma", 3.3 if kind == "jonswap" else 1.0)
        seed = int(kv.pop("seed")) if "seed" in kv else None
        n = int(kv.pop("n")) if "n" in kv else None
        return Waves.jonswap(Hs, Tp, gamma, heading=heading, seed=seed, n_components=n, **opts)
    except KeyError as e:
        raise ValueError(f"--waves {text!r}: missing {e.args[0]}") from None
    finally:
        if kv:
            log.warning("--waves: ignored %s", ", ".join(sorted(kv)))


def parse_current(text: str):
    """A uniform current from the command line: ``SPEED@HEADING`` [m/s, deg toward], e.g. ``1.0@180``."""
    from .model.water import Current

    speed, _, heading = text.partition("@")
    try:
        return Current.uniform(float(speed), heading=float(heading or 0.0))
    except ValueError:
        raise ValueError(f"--current {text!r}: expected SPEED@HEADING, e.g. 1.0@180 (m/s toward 180 deg)") from None


def _out_dir(args) -> Path:
    return Path(args.out) if args.out else Path(args.deck).resolve().parent


def cmd_run(args) -> int:
    from .io.outputs import OutputRecorder
    from .motion import Trajectory
    from .results import write_netcdf
    from .simulate import simulate

    system = _load(args)
    out = _out_dir(args)
    base = Path(args.deck).stem
    out.mkdir(parents=True, exist_ok=True)
    if system.model.options.writeLog > 0:
        _setup_logging(args.verbose, out / f"{base}.log")
    motion = None
    if args.motion:
        motion = Trajectory.from_csv(args.motion, n_dof=system.n_coupled_dof, interpolation=args.interp)
    elif system.n_coupled_dof:
        log.info("no --motion given: the %d coupled DOF stay where the deck puts them", system.n_coupled_dof)
    t0 = time.perf_counter()
    recorders = []

    def record(sys_):
        if not recorders:
            _check_ic(sys_, args)
            recorders.append(OutputRecorder(sys_))
        recorders[0].record()

    run = args.run_settings
    if args.duration is None:
        args.duration = run.get("duration", 60.0)
    if args.dt_out is None:
        args.dt_out = run.get("dt_out")
    ds = simulate(system, args.duration, motion, dt_out=args.dt_out, solve_ic=not args.no_ic,
                  record_nodes=not args.no_nodes, progress=False if args.quiet_progress else None,
                  on_output=[record])
    wall = time.perf_counter() - t0
    written = []
    if not system.model.options.disableOutput:
        written += recorders[0].write(out, base)
    written.append(write_netcdf(ds, out / f"{base}.nc"))
    ic = system.ic_report
    print(f"moorline {__version__}: {args.deck}")
    print(f"  {len(system.lines)} lines, {len(system.points)} points, {system.layout.n_rows} free 3-DOF rows, "
          f"{system.n_coupled_dof} coupled DOF; {system.scheme_label}, dtM = {system.dtM:.4g} s")
    if ic.get("method"):
        state = "converged" if ic.get("converged") else ("stalled" if ic.get("stalled") else "NOT converged")
        print(f"  initial conditions: {ic['method']}, {state} after {ic['pseudo_time']:.4g} s pseudo time")
    print(f"  {system.stability['text']}")
    print(f"  simulated {args.duration:g} s in {wall:.3g} s wall time ({ds.attrs['real_time_factor']:.3g} x real time,"
          f" incl. initial conditions)")
    for ln in system.lines:
        tb = ds.line_tension_b.sel(line=ln.number).values
        print(f"  line {ln.number}: fairlead tension min {tb.min() / 1e3:.1f} kN, mean {tb.mean() / 1e3:.1f} kN, "
              f"max {tb.max() / 1e3:.1f} kN")
    fl = system.layout.fl
    for b in fl.body:
        pose = ds.body_pose.sel(body=int(b) + 1).values
        print(f"  floating body {int(b) + 1}: surge mean {pose[:, 0].mean():.3f} m, std heave {pose[:, 2].std():.3f} "
              f"m, pitch {np.degrees(pose[:, 4]).std():.3f} deg, yaw {np.degrees(pose[:, 5]).std():.3f} deg")
    if "pto_power" in ds:
        for j in ds.joint.values:
            P = ds.pto_power.sel(joint=j).values
            print(f"  joint {j}: mean PTO power {P.mean() / 1e3:.2f} kW, max {P.max() / 1e3:.1f} kW")
    for p in written:
        print(f"  wrote {p}")
    return 0


def _check_ic(system, args) -> None:
    """Stop (exit code 3) when the initial conditions did not converge, unless
    ``--accept-unconverged-ic`` says to go on."""
    ic = system.ic_report
    if ic.get("converged", True) or getattr(args, "accept_unconverged_ic", False):
        return
    res = ic.get("residual", float("nan"))
    raise SimulationError(f"the initial conditions did not converge ({ic.get('method', 'catenary start')}: residual "
                          f"acceleration {res:.3g} m/s^2 at {ic.get('residual_at', '?')}); raise TmaxIC or fix the "
                          "model, or pass --accept-unconverged-ic to run from this state", time=0.0)


def cmd_statics(args) -> int:
    from .results import Recorder, write_netcdf

    if args.quasi_static:
        return _statics_quasi_static(args)
    for flag in ("json", "offset", "friction"):
        if getattr(args, flag) not in (None, False):
            raise DeckError(f"--{flag} needs --quasi-static")
    system = _load(args)
    system.init(solve_ic=True)
    ic = system.ic_report
    print(f"initial conditions: {ic.get('method', 'catenary start only')}, "
          f"{'converged' if ic.get('converged') else 'stalled' if ic.get('stalled') else 'NOT converged'}, "
          f"residual {ic.get('residual', 0.0):.3g} m/s^2")
    for ln in system.lines:
        r = ln.node_positions()
        print(f"  line {ln.number}: fairlead tension {ln.fairlead_tension() / 1e3:.2f} kN, anchor tension "
              f"{ln.anchor_tension() / 1e3:.2f} kN, lowest node z = {np.min(r[:, 2]):.3f} m")
    for p in system.points:
        f = p.force()
        print(f"  point {p.number} ({p.kind.name.lower()}): position {np.round(p.position(), 4).tolist()}, "
              f"force {np.round(f / 1e3, 3).tolist()} kN")
    if args.out:
        rec = Recorder(system)
        rec.record()
        path = write_netcdf(rec.to_dataset(), Path(args.out) / f"{Path(args.deck).stem}_statics.nc")
        print(f"  wrote {path}")
    if not ic.get("converged", True) and not args.accept_unconverged_ic:
        print("moorline: the initial conditions did not converge (pass --accept-unconverged-ic to exit 0)",
              file=sys.stderr)
        return 3
    return 0


def _statics_quasi_static(args) -> int:
    """``statics --quasi-static``: the quasi-static equilibrium, tensions and coupled stiffness."""
    import json

    from .io import read_deck
    from .quasistatic import QuasiStaticError, QuasiStaticModel
    from .quasistatic.studies import displace_coupled, solution_dataset

    model = read_deck(Path(args.deck))
    friction = 0.0 if args.friction is None else args.friction
    try:
        if friction != "deck":
            friction = float(friction)
        qs = QuasiStaticModel(model, seabed_friction=friction)
        x = None
        if args.offset:
            try:
                dq = np.array([float(v) for v in args.offset.split(",")])
            except ValueError:
                dq = np.zeros(0)
            if dq.size != 6:
                raise DeckError(f"--offset {args.offset!r}: expected six numbers x,y,z,rx,ry,rz (m, deg)")
            x = displace_coupled(qs, np.r_[dq[:3], np.radians(dq[3:])])
        sol = qs.solve(x)
        qs.check_seabed()
    except (QuasiStaticError, ValueError) as e:
        if isinstance(e, DeckError):
            raise
        print(f"moorline: quasi-static model: {e}", file=sys.stderr)
        return 2
    m = model
    if args.json:
        out = {
            "lines": {str(k + 1): {"fairlead_tension": float(sol.tensions[k, 1]),
                                   "anchor_tension": float(sol.tensions[k, 0])} for k in range(len(m.lines))},
            "points": {str(p + 1): [float(v) for v in sol.points[p]] for p, pt in enumerate(m.points)
                       if pt.kind.name == "FREE"},
            "bodies": {str(b + 1): [float(v) for v in sol.bodies[b]] for b in range(len(m.bodies))},
            "stiffness": [[float(v) for v in row] for row in sol.stiffness],
        }
        print(json.dumps(out, indent=1))
    else:
        print(f"moorline {__version__}: quasi-static equilibrium of {args.deck} ({sol.iterations} Newton iterations)")
        for k in range(len(m.lines)):
            print(f"  line {k + 1}: fairlead tension {sol.tensions[k, 1] / 1e3:.3f} kN, anchor tension "
                  f"{sol.tensions[k, 0] / 1e3:.3f} kN")
        for p, pt in enumerate(m.points):
            if pt.kind.name == "FREE":
                print(f"  point {p + 1} (free): position {np.round(sol.points[p], 4).tolist()} m")
        for b in range(len(m.bodies)):
            print(f"  body {b + 1}: position {np.round(sol.bodies[b, :3], 4).tolist()} m, rotation "
                  f"{np.round(np.degrees(sol.bodies[b, 3:]), 4).tolist()} deg")
        labels = qs.coupled_dof_labels
        if labels:
            print("  stiffness of the coupled DOFs [N/m, N/rad, N m/m, N m/rad]:")
            print("  " + " " * 10 + "".join(f"{lab:>12s}" for lab in labels))
            for i, lab in enumerate(labels):
                print(f"  {lab:>10s}" + "".join(f"{v:12.4g}" for v in sol.stiffness[i]))
    if args.out:
        from .results import write_netcdf

        path = write_netcdf(solution_dataset(qs, qs.solve(x, gradients=True)),
                            Path(args.out) / f"{Path(args.deck).stem}_quasistatic.nc")
        print(f"  wrote {path}", file=sys.stderr if args.json else sys.stdout)
    return 0


def cmd_check(args) -> int:
    system = _load(args)
    m = system.model
    print(f"{args.deck}: {len(m.line_types)} line types, {len(m.lines)} lines "
          f"({int(system.layout.line_N.sum())} segments), {len(m.points)} points, "
          f"{system.n_coupled_dof} coupled DOF ({', '.join(system.coupled_dof_labels) or 'none'})")
    from .core.stability import stability_report

    _, limit, text = stability_report(m, system.layout, system.dtM, system.scheme, label=system.scheme_label)
    print(f"  {text}")
    for key, val in m.options.not_acted_on.items():
        print(f"  option {key} = {val}: read but not acted on by this version")
    return 0 if system.dtM <= limit else 1


def cmd_sweep(args) -> int:
    from .errors import StudyError, SweepError
    from .studies import run_sweep

    try:
        res = run_sweep(args.study, out=args.out, workers=args.workers, scheduler=args.scheduler,
                        resume=not args.no_resume, progress=False if args.quiet_progress else None)
    except StudyError as e:
        print(f"moorline: study error: {e}", file=sys.stderr)
        return 2
    except SweepError as e:
        print(f"moorline: {e}", file=sys.stderr)
        return 3
    sm = res.summary
    print(f"moorline {__version__}: sweep {args.study}: {len(sm)} cases ({res.computed} computed, {res.reused} reused) "
          f"in {res.wall_time:.1f} s")
    if "life_years" in sm:
        params = [c for c in sm.columns if c not in ("case", "wall_time_s") and c in res.dataset.coords]
        for label, row in (("shortest life", sm.loc[sm.life_years.idxmin()]),
                           ("longest life", sm.loc[sm.life_years.idxmax()])):
            where = ", ".join(f"{p}={row[p]}" for p in params) or "base"
            print(f"  {label}: {row.life_years:.4g} years ({where}) at s = {row.critical_s:.2f} m, "
                  f"theta = {row.critical_theta:g} deg")
    for name in ("results.nc", "summary.csv"):
        print(f"  wrote {res.out_dir / name}")
    return 0


def cmd_fatigue(args) -> int:
    import xarray as xr

    from .io import read_deck
    from .post import (
        SECONDS_PER_YEAR,
        SNCurve,
        TubeSection,
        critical_location,
        cross_section_stress,
        envelopes,
        fatigue_damage,
        life_years,
        section_loads,
    )
    from .results import write_netcdf

    try:
        ds = xr.load_dataset(args.results, engine="h5netcdf")
    except (OSError, ValueError) as e:
        raise DeckError(f"cannot read results: {e}", file=Path(args.results)) from None
    deck = args.deck or ds.attrs.get("source")
    model = read_deck(Path(deck)) if deck else None
    if model is None and args.EI is None:
        raise DeckError("the results name no deck: give --deck (or --EI)", file=Path(args.results))
    if args.start is not None:
        ds = ds.sel(time=slice(args.start, None))
    sec = section_loads(ds, args.line, model=model, EI=args.EI)
    stress = cross_section_stress(sec, TubeSection(args.do, args.di), n_theta=args.n_theta,
                                  tensile_only=args.tensile_only)
    curve = SNCurve.one_slope(args.alpha, args.m, endurance=args.endurance, unit=args.unit)
    dmg = fatigue_damage(stress, curve)
    dur = dmg.attrs["duration"]
    crit = critical_location(dmg)
    env = envelopes(ds, args.line, sections=sec, stress=stress, allowable_bend_radius=args.allowable_bend_radius)
    per_year = crit["damage"] / dur * SECONDS_PER_YEAR
    print(f"moorline {__version__}: fatigue of line {sec.attrs['line']} in {args.results} over {dur:.6g} s")
    print(f"  section do = {args.do} m, di = {args.di} m; {curve.describe()}"
          f"{'; tensile stress only' if args.tensile_only else ''}")
    print(f"  critical location: s = {crit['s']:.3f} m from end A, theta = {crit['theta']:g} deg; damage "
          f"{crit['damage']:.4g} over the record, {per_year:.4g} per year if the record repeats: life "
          f"{life_years(per_year):.4g} years")
    print(f"  largest curvature {env.attrs['curvature_max']:.4g} 1/m (bend radius {env.attrs['bend_radius_min']:.4g} m)"
          f" at s = {env.attrs['curvature_max_s']:.3f} m; tension {env.attrs['tension_min']:.4g} to "
          f"{env.attrs['tension_max']:.4g} N")
    if args.out:
        out = xr.Dataset({"damage": dmg, "damage_per_year": dmg / dur * SECONDS_PER_YEAR, **env.data_vars})
        path = write_netcdf(out, Path(args.out))
        print(f"  wrote {path}")
    return 0


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="moorline", description="Lumped-mass mooring and cable dynamics "
                                 "(MoorDyn v2 decks).")
    ap.add_argument("--version", action="version", version=f"moorline {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("deck", help="MoorDyn v2 input file, or a system file (.yaml) naming one")
        p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
        p.add_argument("--dtM", type=float, help="override the internal time step [s]")
        p.add_argument("--scheme", help="override the time scheme (Euler, LEuler, Heun, RK2, RK4, AB2-4, BEuler<M>, "
                       "Midpoint<M>, ACA<M>, Wilson<M>, GenAlpha[rho_inf])")

    p = sub.add_parser("run", help="simulate a deck with an imposed coupled motion")
    common(p)
    p.add_argument("--duration", type=float, default=None,
                   help="simulated time [s] (default: the system file's, else 60)")
    p.add_argument("--motion", help="CSV: header row, time t [s] first, one column per coupled DOF")
    p.add_argument("--interp", choices=("cubic", "linear"), default="cubic",
                   help="interpolation of the motion samples (cubic: smooth velocities; linear: as a MoorDyn "
                   "driver stepping from sample to sample)")
    p.add_argument("--out", help="output folder (default: the deck's folder)")
    p.add_argument("--dt-out", type=float, default=None, help="output interval [s] (default: dtOut or 0.1)")
    p.add_argument("--waves", help="a sea instead of the deck's WaveKin: jonswap:Hs=3.5,Tp=7.5[,gamma=3.3]"
                   "[,heading=180][,seed=1][,n=200][,ramp=20], pm:Hs=..,Tp=.. or regular:H=2,T=8[,heading=..]")
    p.add_argument("--current", help="a uniform current instead of the deck's Currents: SPEED@HEADING, e.g. 1.0@180")
    p.add_argument("--mooring", choices=("dynamic", "quasistatic"),
                   help="lines as dynamic lumped masses (default) or quasi-static catenaries re-solved every step "
                   "(floating bodies only)")
    p.add_argument("--no-ic", action="store_true", help="start from the catenary profile (no IC solve)")
    p.add_argument("--accept-unconverged-ic", action="store_true",
                   help="run even when the initial conditions did not converge (default: stop, exit code 3)")
    p.add_argument("--no-nodes", action="store_true", help="keep node data out of the NetCDF file")
    p.add_argument("--quiet-progress", action="store_true", help="no progress bar (default: shown on a terminal)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("statics", help="find the initial equilibrium and report it")
    common(p)
    p.add_argument("--out", help="also write <base>_statics.nc (<base>_quasistatic.nc) to this folder")
    p.add_argument("--quasi-static", action="store_true",
                   help="the quasi-static model (catenary lines): equilibrium, tensions and coupled stiffness")
    p.add_argument("--json", action="store_true", help="with --quasi-static: print the results as JSON")
    p.add_argument("--offset", help="with --quasi-static: rigid offset of the coupled body (coupled points) from the "
                   "deck pose: x,y,z,rx,ry,rz (m, deg)")
    p.add_argument("--friction", help="with --quasi-static: seabed friction coefficient CB of the lines (default 0), "
                   "or 'deck' for the deck's axial friction coefficient")
    p.add_argument("--accept-unconverged-ic", action="store_true",
                   help="exit 0 even when the initial conditions did not converge (default: exit code 3)")
    p.set_defaults(func=cmd_statics)

    p = sub.add_parser("check", help="read a deck and report its size and time-step stability")
    common(p)
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("sweep", help="run a parametric study (YAML study file); resumes an interrupted sweep")
    p.add_argument("study", help="study file (YAML)")
    p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
    p.add_argument("--out", help="output folder (default: the study's 'output' or <name>_out beside it)")
    p.add_argument("--workers", type=int, help="local worker processes (default: number of CPUs)")
    p.add_argument("--scheduler", help="Dask scheduler address: run the cases on that cluster")
    p.add_argument("--no-resume", action="store_true", help="recompute cases already stored")
    p.add_argument("--quiet-progress", action="store_true", help="no progress bar (default: shown on a terminal)")
    p.set_defaults(func=cmd_sweep)

    p = sub.add_parser("fatigue", help="cross-section stress, rainflow and S-N damage of one run's results")
    p.add_argument("results", help="NetCDF results of 'moorline run' (with node data)")
    p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
    p.add_argument("--deck", help="the deck (default: the one named in the results) for EI and clamps")
    p.add_argument("--line", type=int, help="line number (default: the only line)")
    p.add_argument("--EI", type=float, help="bending stiffness [N m^2] (default: the deck's)")
    p.add_argument("--do", type=float, required=True, help="outer diameter of the stress section [m]")
    p.add_argument("--di", type=float, default=0.0, help="inner diameter [m] (default 0)")
    p.add_argument("--n-theta", type=int, default=12, help="points around the section (default 12)")
    p.add_argument("--alpha", type=float, required=True, help="S-N intercept: N = alpha S^-m")
    p.add_argument("--m", type=float, required=True, help="S-N inverse slope")
    p.add_argument("--unit", type=float, default=1e6, help="S-N stress unit in Pa (default 1e6: MPa)")
    p.add_argument("--endurance", type=float, help="endurance limit [S-N units]")
    p.add_argument("--tensile-only", action="store_true", help="set compressive stresses to zero before counting")
    p.add_argument("--start", type=float, help="skip the record before this time [s] (transient)")
    p.add_argument("--allowable-bend-radius", type=float, help="minimum allowable bend radius [m]")
    p.add_argument("--out", help="write damage and envelopes to this NetCDF file")
    p.set_defaults(func=cmd_fatigue)
    return ap


def main(argv=None) -> int:
    args = build_parser().parse_args(argv)
    _setup_logging(args.verbose)
    try:
        return args.func(args)
    except DeckError as e:
        print(f"moorline: input error: {e}", file=sys.stderr)
        return 2
    except SimulationError as e:
        print(f"moorline: simulation failed: {e}\nNo result files were written.", file=sys.stderr)
        return 3



if __name__ == "__main__":
    sys.exit(main())
