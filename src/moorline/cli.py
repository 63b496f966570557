"""The ``moorline`` command.

    moorline run DECK|SYSTEM.yaml [--duration 60] [--motion motion.csv] [--out DIR] [--dt-out 0.1]
                 [--waves jonswap:Hs=3.5,Tp=7.5,heading=180,seed=1] [--current 1.0@180]
                 [--checkpoint-every S] [--resume CHECKPOINT] [--force] [--vtk]
    moorline vtk RESULT.nc [--out DIR] [--every N]
    moorline convert IN OUT [--to v1|v2]
    moorline statics DECK [--out DIR] [--quasi-static [--json] [--offset x,y,z,rx,ry,rz] [--friction CB]]
    moorline check DECK [--strict]
    moorline sweep STUDY.yaml [--workers N] [--scheduler ADDRESS] [--out DIR] [--no-resume]
    moorline fatigue RESULT.nc --do 0.040 [--di 0.020] --alpha 6.098e19 --m 6.238 [--unit 1e6]

``run`` reads a MoorDyn v2 deck, finds the initial equilibrium, imposes the coupled motion and
writes MoorDyn-style output (``<base>.out`` with the OUTPUTS channels, ``<base>_Line<n>.out`` as the
line output flags ask) plus a NetCDF file ``<base>.nc`` with everything. The files are written as
the run goes (every few seconds of wall time): a run that is killed or fails leaves them valid up to
their last write, the NetCDF file marked ``complete = 0``. ``--checkpoint-every S`` writes
``<base>.checkpoint.npz`` every S simulated seconds; ``--resume`` continues from it (same deck
and options) and appends to the files, bitwise as if the run had never stopped. The first run of
a deck of a new kind compiles the kernels (said on stderr); the compile time is kept out of the
run's wall time and real-time factor.

``--vtk`` also writes VTK files for ParaView (``<out>/<base>_vtk/<base>.pvd``, one multiblock file per
output time; see :mod:`moorline.io.vtk`); ``vtk`` writes them from the NetCDF file of an earlier run.
``convert`` rewrites a deck in MoorDyn's v2 (default) or v1 layout (see :func:`moorline.io.write_deck`).

``sweep`` runs a parametric study (see :mod:`moorline.studies`); ``fatigue`` post-processes one run
(section stress around the cable, rainflow, S-N damage; see :mod:`moorline.post`).

Exit codes: 0 success, 2 bad input (deck, motion file, study file, arguments, an output folder
that cannot be made, a checkpoint of another model), 3 the simulation or some sweep cases failed,
or the initial conditions did not converge (``run`` and ``statics``; ``--accept-unconverged-ic``
goes on); ``check --strict`` exits 1 when the check has warnings.
"""

from __future__ import annotations

import argparse
import logging
import math
import sys
import time
from pathlib import Path

import numpy as np

from . import __version__
from .errors import CheckpointError, DeckError, SimulationError
from .model import ModelError

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


def _make_out_dir(out: Path) -> Path:
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as e:
        raise _ArgumentError(f"cannot create the output folder {out}: {e.strerror or e}") from None
    return out


def cmd_run(args) -> int:
    from .io.outstream import OutStream
    from .motion import Trajectory
    from .results import NetCDFStream
    from .simulate import simulate

    if args.vtk and args.no_nodes:
        raise _ArgumentError("--vtk needs the node data: drop --no-nodes")
    system = _load(args)
    out = _make_out_dir(_out_dir(args))
    base = Path(args.deck).stem
    if system.model.options.writeLog > 0:
        _setup_logging(args.verbose, out / f"{base}.log")
    motion = None
    if args.motion:
        motion = Trajectory.from_csv(args.motion, n_dof=system.n_coupled_dof, interpolation=args.interp)
    elif system.n_coupled_dof:
        log.info("no --motion given: the %d coupled DOF stay where the deck puts them", system.n_coupled_dof)
    checked = []

    def check_ic_once(sys_):
        """Stop on an unconverged start (at the first output, right after the initial conditions)."""
        if not checked:
            checked.append(True)
            if not args.resume:
                _check_ic(sys_, args)

    run = args.run_settings
    if args.duration is None:
        args.duration = run.get("duration", 60.0)
    if args.dt_out is None:
        args.dt_out = run.get("dt_out")
    cursors = {}
    if args.resume:
        cursors = system.load(args.resume).get("outputs", {})
        if system.t >= args.duration - 1e-9:
            raise _ArgumentError(f"--resume {args.resume}: the checkpoint is at t = {system.t:g} s, not before "
                                 f"--duration {args.duration:g} s: nothing to continue")
    t_resumed = system.t
    writers = [] if system.model.options.disableOutput else [OutStream(out, base, resume=cursors.get("out"))]
    nc = NetCDFStream(out / f"{base}.nc", resume=cursors.get("netcdf"))
    writers.append(nc)
    checkpoint = out / f"{base}.checkpoint.npz" if args.checkpoint_every else None
    t0 = time.perf_counter()
    try:
        ds = simulate(system, args.duration - system.t, motion, dt_out=args.dt_out, solve_ic=not args.no_ic,
                      record_nodes=not args.no_nodes, progress=False if args.quiet_progress else None,
                      writers=writers, on_output=[check_ic_once], checkpoint=checkpoint,
                      checkpoint_every=args.checkpoint_every,
                      force=args.force, compile_notice=True)
    except SimulationError as e:
        files = [str(p) for w in writers for p in w.paths if p.exists()]
        kept = (f"Partial results up to t = {system.t:.6g} s are in {', '.join(files)} (the NetCDF file is marked "
                "complete = 0)." if files else "No result files were written.")
        raise SimulationError(f"{e}\n{kept}") from None
    total = time.perf_counter() - t0
    written = [p for w in writers for p in w.paths]
    if checkpoint is not None and checkpoint.exists():
        written.append(checkpoint)
    ic = system.ic_report
    print(f"moorline {__version__}: {args.deck}")
    print(f"  {len(system.lines)} lines, {len(system.points)} points, {system.layout.n_rows} free 3-DOF rows, "
          f"{system.n_coupled_dof} coupled DOF; {system.scheme_label}, dtM = {system.dtM:.4g} s")
    if args.resume:
        print(f"  resumed from {args.resume} at t = {t_resumed:.6g} s")
    elif ic.get("method"):
        state = "converged" if ic.get("converged") else ("stalled" if ic.get("stalled") else "NOT converged")
        print(f"  initial conditions: {ic['method']}, {state} after {ic['pseudo_time']:.4g} s pseudo time "
              f"({ds.attrs['init_time_s']:.3g} s wall time)")
    print(f"  {system.stability['text']}")
    if ds.attrs["compile_time_s"] > 0.05:
        print(f"  compiled kernels for this machine in {ds.attrs['compile_time_s']:.3g} s (first run of this kind "
              "of deck only: they are cached)")
    print(f"  simulated {args.duration - t_resumed:g} s in {ds.attrs['wall_time_s']:.3g} s wall time "
          f"({ds.attrs['real_time_factor']:.3g} x real time); {total:.3g} s in all")
    full_ds = ds
    if args.resume:  # the summary covers the whole run, from the file the resumed run appended to
        import xarray as xr

        with xr.open_dataset(nc.path, engine="h5netcdf") as full:
            full_ds = full.load()
    tb = full_ds.line_tension_b
    for ln in system.lines:
        t = tb.sel(line=ln.number).values
        print(f"  line {ln.number}: fairlead tension min {t.min() / 1e3:.1f} kN, mean {t.mean() / 1e3:.1f} kN, "
              f"max {t.max() / 1e3:.1f} kN")
    fl = system.layout.fl
    for b in fl.body:
        pose = full_ds.body_pose.sel(body=int(b) + 1).values
        print(f"  floating body {int(b) + 1}: surge mean {pose[:, 0].mean():.3f} m, std heave {pose[:, 2].std():.3f} "
              f"m, pitch {np.degrees(pose[:, 4]).std():.3f} deg, yaw {np.degrees(pose[:, 5]).std():.3f} deg")
    if "pto_power" in full_ds:
        for j in full_ds.joint.values:
            P = full_ds.pto_power.sel(joint=j).values
            print(f"  joint {j}: mean PTO power {P.mean() / 1e3:.2f} kW, max {P.max() / 1e3:.1f} kW")
    if args.vtk:
        from .io.vtk import write_vtk

        written.append(write_vtk(full_ds, out / f"{base}_vtk", base=base))
    for p in written:
        print(f"  wrote {p}")
    return 0


def cmd_vtk(args) -> int:
    from .io.vtk import write_vtk

    src = Path(args.results)
    if not src.is_file():
        raise _ArgumentError(f"no such results file: {src}")
    out = Path(args.out) if args.out else src.with_name(f"{src.stem}_vtk")
    try:
        pvd = write_vtk(src, out, base=src.stem, every=args.every)
    except (OSError, KeyError) as e:
        raise DeckError(f"cannot read results: {e}", file=src) from None
    print(f"moorline {__version__}: wrote {pvd} (open it in ParaView)")
    return 0


def cmd_convert(args) -> int:
    from .io import read_deck, write_deck

    src, dst = Path(args.input), Path(args.output)
    if dst.resolve() == src.resolve():
        raise _ArgumentError(f"OUT must differ from IN ({src}): converting in place would lose the original")
    model = read_deck(src)
    try:
        path = write_deck(model, dst, version=args.to)
    except ValueError as e:
        print(f"moorline convert: {src} cannot be written as a MoorDyn {args.to} deck: {e}", file=sys.stderr)
        return 2
    print(f"moorline {__version__}: wrote {path} (MoorDyn {args.to} layout)")
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
    from .progress import CompileWatch
    from .results import Recorder, write_netcdf

    if args.quasi_static:
        return _statics_quasi_static(args)
    for flag in ("json", "offset", "friction"):
        if getattr(args, flag) not in (None, False):
            raise DeckError(f"--{flag} needs --quasi-static")
    system = _load(args)
    with CompileWatch(announce=True):
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
    warnings = []
    if system.dtM > limit:
        warnings.append(f"dtM = {system.dtM:.4g} s is above the estimated stability limit {limit:.3g} s of "
                        f"{system.scheme_label}: the run may go unstable (the estimate is conservative; see the "
                        "governing mode above)")
    for w in warnings:
        print(f"moorline: warning: {w}", file=sys.stderr)
    return 1 if warnings and args.strict else 0


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
    if ds.attrs.get("complete", 1) == 0:
        log.warning("%s holds an incomplete run (it stopped at t = %s s: %s)", args.results,
                    ds.attrs.get("simulated_until"), ds.attrs.get("status", "killed or still running"))
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


class _ArgumentError(Exception):
    """A bad command-line value found after parsing (exit code 2)."""


class _Parser(argparse.ArgumentParser):
    """argparse with one-line errors: ``moorline run: argument --duration: ...`` and exit code 2."""

    def error(self, message):
        self.exit(2, f"{self.prog}: {message} (see {self.prog} --help)\n")


def _positive(text: str) -> float:
    """A finite number > 0 (a duration, time step or interval)."""
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not (math.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"expected a finite number > 0, got {text!r}")
    return v


def build_parser() -> argparse.ArgumentParser:
    ap = _Parser(prog="moorline", description="Lumped-mass mooring and cable dynamics (MoorDyn v2 decks).")
    ap.add_argument("--version", action="version", version=f"moorline {__version__}")
    sub = ap.add_subparsers(dest="command", required=True, parser_class=_Parser)

    def common(p):
        p.add_argument("deck", help="MoorDyn v2 input file, or a system file (.yaml) naming one")
        p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
        p.add_argument("--dtM", type=_positive, help="override the internal time step [s]")
        p.add_argument("--scheme", help="override the time scheme (Euler, LEuler, Heun, RK2, RK4, AB2-4, BEuler<M>, "
                       "Midpoint<M>, ACA<M>, Wilson<M>, GenAlpha[rho_inf])")

    p = sub.add_parser("run", help="simulate a deck with an imposed coupled motion")
    common(p)
    p.add_argument("--duration", type=_positive, default=None,
                   help="simulated time [s] (default: the system file's, else 60)")
    p.add_argument("--motion", help="CSV: header row, time t [s] first, one column per coupled DOF")
    p.add_argument("--interp", choices=("cubic", "linear"), default="cubic",
                   help="interpolation of the motion samples (cubic: smooth velocities; linear: as a MoorDyn "
                   "driver stepping from sample to sample)")
    p.add_argument("--out", help="output folder (default: the deck's folder)")
    p.add_argument("--dt-out", type=_positive, default=None, help="output interval [s] (default: dtOut or 0.1)")
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
    p.add_argument("--checkpoint-every", type=_positive, metavar="SECONDS",
                   help="write <out>/<base>.checkpoint.npz every SECONDS of simulated time (for --resume)")
    p.add_argument("--resume", metavar="CHECKPOINT", help="continue an interrupted run from its checkpoint (same "
                   "deck, options and --out), appending to its output files")
    p.add_argument("--force", action="store_true", help="run even when the number of time steps is astronomical")
    p.add_argument("--vtk", action="store_true", help="also write VTK files for ParaView to <out>/<base>_vtk/ "
                   "(<base>.pvd: every output time)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("vtk", help="write VTK files for ParaView from the NetCDF results of a run")
    p.add_argument("results", help="NetCDF results of 'moorline run' (with node data)")
    p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
    p.add_argument("--out", help="output folder (default: <results stem>_vtk beside the results)")
    p.add_argument("--every", type=int, default=1, help="write every N-th output time (default 1: all)")
    p.set_defaults(func=cmd_vtk)

    p = sub.add_parser("convert", help="rewrite a deck in MoorDyn's v2 or v1 layout")
    p.add_argument("input", metavar="IN", help="MoorDyn deck (v1 or v2)")
    p.add_argument("output", metavar="OUT", help="deck to write (curve and settings files go beside it)")
    p.add_argument("--to", choices=("v1", "v2"), default="v2", help="layout to write (default v2)")
    p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
    p.set_defaults(func=cmd_convert)

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
    p.add_argument("--strict", action="store_true", help="exit 1 when the check has warnings (stability advice)")
    p.set_defaults(func=cmd_check)

    p = sub.add_parser("sweep", help="run a parametric study (YAML study file); resumes an interrupted sweep")
    p.add_argument("study", help="study file (YAML)")
    p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
    p.add_argument("--out", help="output folder (default: the study's 'output' or <name>_out beside it)")
    p.add_argument("--workers", type=int, help="local worker processes (default: the CPUs this process may use)")
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
    except (DeckError, ModelError, CheckpointError) as e:
        print(f"moorline: input error: {e}", file=sys.stderr)
        return 2
    except _ArgumentError as e:
        print(f"moorline {args.command}: {e}", file=sys.stderr)
        return 2
    except SimulationError as e:
        print(f"moorline: simulation failed: {e}", file=sys.stderr)
        return 3
    except (ValueError, OSError) as e:  # a motion file, an output folder, a value out of range
        print(f"moorline {args.command}: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
