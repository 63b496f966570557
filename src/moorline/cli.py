"""The ``moorline`` command.

    moorline run DECK [--duration 60] [--motion motion.csv] [--out DIR] [--dt-out 0.1]
    moorline statics DECK [--out DIR]
    moorline check DECK

``run`` reads a MoorDyn v2 deck, finds the initial equilibrium, imposes the coupled motion and
writes MoorDyn-style output (``<base>.out`` with the OUTPUTS channels, ``<base>_Line<n>.out`` as the
line output flags ask) plus a NetCDF file ``<base>.nc`` with everything. Files are written only
when the run succeeds, each atomically.

Exit codes: 0 success, 2 bad input (deck, motion file, arguments), 3 the simulation failed.
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


def _load(args):
    from .coupling import System
    from .io import read_deck

    model = read_deck(Path(args.deck))
    kwargs = {}
    if getattr(args, "dtM", None):
        kwargs["dtM"] = args.dtM
    if getattr(args, "scheme", None):
        kwargs["scheme"] = args.scheme
    return System(model, **kwargs)


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
            recorders.append(OutputRecorder(sys_))
        recorders[0].record()

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
    for p in written:
        print(f"  wrote {p}")
    return 0


def cmd_statics(args) -> int:
    from .results import Recorder, write_netcdf

    system = _load(args)
    system.init(solve_ic=True)
    ic = system.ic_report
    print(f"initial conditions: {ic.get('method', 'catenary start only')}, "
          f"{'converged' if ic.get('converged') else 'stalled' if ic.get('stalled') else 'not converged'}")
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


def build_parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="moorline", description="Lumped-mass mooring and cable dynamics "
                                 "(MoorDyn v2 decks).")
    ap.add_argument("--version", action="version", version=f"moorline {__version__}")
    sub = ap.add_subparsers(dest="command", required=True)

    def common(p):
        p.add_argument("deck", help="MoorDyn v2 input file")
        p.add_argument("-v", "--verbose", action="count", default=0, help="more log output (-v info, -vv debug)")
        p.add_argument("--dtM", type=float, help="override the internal time step [s]")
        p.add_argument("--scheme", help="override the time scheme (Euler, RK2, RK4, BEuler<M>, Midpoint<M>)")

    p = sub.add_parser("run", help="simulate a deck with an imposed coupled motion")
    common(p)
    p.add_argument("--duration", type=float, default=60.0, help="simulated time [s] (default 60)")
    p.add_argument("--motion", help="CSV: header row, time t [s] first, one column per coupled DOF")
    p.add_argument("--interp", choices=("cubic", "linear"), default="cubic",
                   help="interpolation of the motion samples (cubic: smooth velocities; linear: as a MoorDyn "
                   "driver stepping from sample to sample)")
    p.add_argument("--out", help="output folder (default: the deck's folder)")
    p.add_argument("--dt-out", type=float, default=None, help="output interval [s] (default: dtOut or 0.1)")
    p.add_argument("--no-ic", action="store_true", help="start from the catenary profile (no IC solve)")
    p.add_argument("--no-nodes", action="store_true", help="keep node data out of the NetCDF file")
    p.add_argument("--quiet-progress", action="store_true", help="no progress bar (default: shown on a terminal)")
    p.set_defaults(func=cmd_run)

    p = sub.add_parser("statics", help="find the initial equilibrium and report it")
    common(p)
    p.add_argument("--out", help="also write <base>_statics.nc to this folder")
    p.set_defaults(func=cmd_statics)

    p = sub.add_parser("check", help="read a deck and report its size and time-step stability")
    common(p)
    p.set_defaults(func=cmd_check)
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
