"""Run a simulation: the output-interval loop, progress bar, streamed outputs, checkpoints and results.

    ds = moorline.simulate(sys, duration=60.0, motion=Trajectory.from_csv("motion.csv"))

Python sees the system once per output interval; everything in between runs in the compiled
time loop (:func:`moorline.core.integrate.advance`). Before the loop the kernels are compiled (or
loaded from numba's cache): the time that takes is measured apart and kept out of the run's wall
time and real-time factor.
"""

from __future__ import annotations

import logging
import math
import time as _time
from collections.abc import Callable, Iterable
from pathlib import Path

import numpy as np
import xarray as xr
from tqdm.auto import tqdm

from .errors import CheckpointError
from .model import Model
from .motion import Trajectory
from .progress import CompileWatch
from .results import Recorder
from .system import System
from .system.limits import check_run

log = logging.getLogger("moorline")

#: default wall time between two flushes of the streamed outputs [s]
FLUSH_EVERY = 2.0


def _as_system(system) -> System:
    if isinstance(system, System):
        return system
    if isinstance(system, Model):
        return System(system)
    if isinstance(system, (str, Path)):
        return System.from_file(system)
    raise TypeError(f"expected a System, Model or deck path, got {type(system).__name__}")


def _as_trajectory(sys: System, motion) -> Trajectory:
    if motion is None:
        return Trajectory.hold(sys.deck_coupled_positions())
    if isinstance(motion, Trajectory):
        traj = motion
    elif isinstance(motion, (str, Path)):
        traj = Trajectory.from_csv(motion, n_dof=sys.n_coupled_dof)
    elif isinstance(motion, tuple) and len(motion) == 2:
        traj = Trajectory.from_samples(*motion)
    else:
        raise TypeError("motion must be None, a Trajectory, a CSV path or a (t, X) tuple")
    if traj.n_dof != sys.n_coupled_dof:
        raise ValueError(f"the motion has {traj.n_dof} DOF, the system {sys.n_coupled_dof} "
                         f"({', '.join(sys.coupled_dof_labels) or 'none'})")
    return traj


def output_times(t_start: float, duration: float, dt_out: float) -> np.ndarray:
    """Output times after ``t_start`` up to ``t_start + duration`` [s]: ``t_start + k dt_out``, and
    the end time when it is not one of them. When ``t_start`` is itself a multiple ``k0 dt_out``
    (a run started at 0, or resumed from a checkpoint taken at an output time) the times are
    computed as ``k dt_out``, the same floating-point numbers an uninterrupted run uses."""
    k0 = round(t_start / dt_out)
    on_grid = float(np.float64(k0) * dt_out) == t_start
    t_end = t_start + duration
    if on_grid:
        k_end = round(t_end / dt_out)
        if abs(t_end - k_end * dt_out) <= 1e-9 * dt_out:
            t_end = float(np.float64(k_end) * dt_out)  # a resumed run ends where the uninterrupted one does
        n_out = int(math.floor(t_end / dt_out + 1e-9)) - k0
        times = list(np.arange(k0 + 1, k0 + n_out + 1) * dt_out)
    else:
        n_out = int(math.floor(duration / dt_out + 1e-9))
        times = list(t_start + np.arange(1, n_out + 1) * dt_out)
    if not times or t_end - times[-1] > 1e-9 * dt_out:
        times.append(t_end)
    return np.array([t for t in times if t > t_start])


def simulate(system, duration: float, motion=None, *, dt_out: float | None = None, solve_ic: bool = True,
             record_nodes: bool = True, water_probes=None, progress: bool | None = None,
             on_output: Iterable[Callable[[System], None]] = (), writers: Iterable = (),
             flush_every: float = FLUSH_EVERY, checkpoint=None, checkpoint_every: float | None = None,
             force: bool = False, compile_notice: bool | None = None) -> xr.Dataset:
    """Simulate ``duration`` seconds and return the results.

    Parameters
    ----------
    system : System, Model or path
        What to simulate. A System that is not yet initialised is initialised here with the
        coupled DOFs at the motion's position and velocity at t = 0. One that is (for instance
        restored from a checkpoint by :meth:`System.load`) continues from its time.
    duration : float
        Simulated time [s] from the system's current time.
    motion : Trajectory, CSV path, (t, X) tuple or None
        Imposed coupled-DOF motion (absolute time); None holds the coupled objects where the deck
        puts them.
    dt_out : float, optional
        Output interval [s]; default the deck's ``dtOut`` or 0.1 s.
    solve_ic : bool
        Find the initial equilibrium (MoorDyn's IC solver) before the dynamics.
    record_nodes : bool
        Keep node positions, velocities, tensions and curvatures (the bulk of the data).
    water_probes : array_like (n, 3), optional
        Points [m] where the wave elevation, water velocity, acceleration and dynamic pressure are
        recorded (``probe_*`` variables).
    progress : bool, optional
        Show a progress bar, and a notice while kernels are compiled (default: when stderr is a
        terminal).
    on_output : callables
        Called with the system after initialisation and at every output time.
    writers : iterable
        Streamed outputs (:class:`moorline.results.NetCDFStream`,
        :class:`moorline.io.outstream.OutStream`): started with the system and the run's
        Recorder, given each output sample, flushed every ``flush_every`` seconds of wall time,
        at every checkpoint and at the end, and finished (marked complete, or incomplete with
        the reason when the run fails).
    flush_every : float
        Wall time between flushes of the writers [s].
    checkpoint : path, optional
        Checkpoint file (:meth:`System.save`), rewritten every ``checkpoint_every`` simulated
        seconds (at the first output time at or after each multiple) with the writers' cursors,
        so :meth:`System.load` and writers opened with ``resume=`` continue the run.
    checkpoint_every : float, optional
        Simulated time between checkpoints [s].
    force : bool
        Run even when the number of time steps is astronomical (see
        :func:`moorline.system.limits.check_run`).
    compile_notice : bool, optional
        Say on stderr when kernels are being compiled (default: as ``progress``).

    Returns
    -------
    xarray.Dataset
        See :mod:`moorline.results`. Attributes ``wall_time_s`` (the time loop, compilation
        excluded), ``real_time_factor`` (simulated time over that), ``compile_time_s`` and
        ``init_time_s`` (initial conditions, compilation excluded).

    Raises
    ------
    SimulationError
        When the run goes unstable (time, line, node and a suggested dtM in the message).
    InputLimitError
        When the run would take an astronomical number of steps (unless ``force``).
    """
    sys = _as_system(system)
    if not (math.isfinite(duration) and duration > 0):
        raise ValueError(f"duration must be a finite number > 0, got {duration}")
    traj = _as_trajectory(sys, motion)
    if dt_out is None:
        dt_out = sys.model.options.dtOut if sys.model.options.dtOut > 0 else 0.1
    if not (math.isfinite(dt_out) and dt_out > 0):
        raise ValueError(f"dt_out must be a finite number > 0, got {dt_out}")
    if checkpoint_every is not None and not (math.isfinite(checkpoint_every) and checkpoint_every > 0):
        raise ValueError(f"checkpoint_every must be a finite number > 0, got {checkpoint_every}")
    if checkpoint is not None and getattr(sys, "_qsm", None) is not None:
        raise CheckpointError("checkpoints of the quasi-static mooring mode (mooring='quasistatic') are not "
                              "supported: its quasi-static line solver keeps a warm start that a checkpoint does "
                              "not hold; run it without checkpoints")
    check_run(sys, duration, solve_ic=solve_ic and not sys.initialized, dt_out=dt_out, force=force)
    t_start = sys.t
    if sys.n_coupled_dof and t_start + duration > traj.t_end + 1e-9 and motion is not None:
        log.warning("the motion ends at t = %.6g s; the coupled DOFs hold still after that", traj.t_end)
    writers = list(writers)
    callbacks = list(on_output)
    watch = CompileWatch(announce=progress if compile_notice is None else compile_notice)
    with watch:
        init_wall = 0.0
        if not sys.initialized:
            t0 = _time.perf_counter()
            sys.init(traj.position(0.0), traj.velocity(0.0), solve_ic=solve_ic)
            init_wall = _time.perf_counter() - t0
        c_init = watch.seconds
        rec = Recorder(sys, nodes=record_nodes, probes=water_probes)
        motion_k = traj.as_motion()
        sys.warm_up(motion_k)
        for w in writers:
            w.start(sys, rec)

        def sample():
            rec.record()
            for w in writers:
                w.record(sys)
            for cb in callbacks:
                cb(sys)

        sample()
        c_loop = watch.seconds
        times = output_times(t_start, duration, dt_out)
        next_ckpt = t_start + checkpoint_every if checkpoint is not None and checkpoint_every else math.inf
        wall = _time.perf_counter()
        last_flush = wall - 2 * flush_every  # the first sample is written at once
        try:
            with tqdm(total=round(duration, 6), unit="s", unit_scale=False,
                      disable=(not progress) if progress is not None else None, desc="simulated",
                      bar_format="{l_bar}{bar}| {n:.1f}/{total:.1f} s [{elapsed}<{remaining}, {rate_fmt}]") as bar:
                for tk in times:
                    now = _time.perf_counter()
                    if now - last_flush >= flush_every:
                        for w in writers:
                            w.flush()
                        last_flush = now
                    sys.advance_to(tk, motion_k)
                    sample()
                    if tk >= next_ckpt - 1e-9 * dt_out:
                        for w in writers:
                            w.flush()
                        last_flush = _time.perf_counter()
                        sys.save(checkpoint, meta={"outputs": {w.name: w.cursor() for w in writers}})
                        while next_ckpt <= tk + 1e-9 * dt_out:
                            next_ckpt += checkpoint_every
                    bar.update(round(tk - t_start - bar.n, 6))
        except BaseException as e:
            for w in writers:
                w.finish(e)
            raise
    wall = _time.perf_counter() - wall - (watch.seconds - c_loop)
    attrs = {"wall_time_s": wall, "real_time_factor": duration / wall if wall > 0 else math.inf,
             "compile_time_s": watch.seconds, "init_time_s": max(init_wall - c_init, 0.0)}
    for w in writers:
        w.finish(None, attrs)
    ds = rec.to_dataset()
    ds.attrs.update(attrs)
    if watch.seconds > 0:
        log.info("compiling kernels took %.3g s (%d functions; cached for the next runs)", watch.seconds,
                 watch.functions)
    log.info("simulated %.6g s in %.3g s wall time (%.3g x real time)", duration, wall, ds.attrs["real_time_factor"])
    return ds
