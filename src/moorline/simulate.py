"""Run a simulation: the output-interval loop, progress bar and results.

    ds = moorline.simulate(sys, duration=60.0, motion=Trajectory.from_csv("motion.csv"))

Python sees the system once per output interval; everything in between runs in the compiled
time loop (:func:`moorline.core.integrate.advance`).
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

from .model import Model
from .motion import Trajectory
from .results import Recorder
from .system import System

log = logging.getLogger("moorline")


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


def simulate(system, duration: float, motion=None, *, dt_out: float | None = None, solve_ic: bool = True,
             record_nodes: bool = True, water_probes=None, progress: bool | None = None,
             on_output: Iterable[Callable[[System], None]] = ()) -> xr.Dataset:
    """Simulate ``duration`` seconds and return the results.

    Parameters
    ----------
    system : System, Model or path
        What to simulate. A System that is not yet initialised is initialised here with the
        coupled DOFs at the motion's position and velocity at t = 0.
    duration : float
        Simulated time [s].
    motion : Trajectory, CSV path, (t, X) tuple or None
        Imposed coupled-DOF motion; None holds the coupled objects where the deck puts them.
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
        Show a progress bar (default: when the output is a terminal).
    on_output : callables
        Called with the system after initialisation and at every output time.

    Returns
    -------
    xarray.Dataset
        See :mod:`moorline.results`.

    Raises
    ------
    SimulationError
        When the run goes unstable (time, line, node and a suggested dtM in the message).
    """
    sys = _as_system(system)
    if not duration > 0:
        raise ValueError(f"duration must be > 0, got {duration}")
    traj = _as_trajectory(sys, motion)
    if sys.n_coupled_dof and duration > traj.t_end + 1e-9 and motion is not None:
        log.warning("the motion ends at t = %.6g s; the coupled DOFs hold still after that", traj.t_end)
    if dt_out is None:
        dt_out = sys.model.options.dtOut if sys.model.options.dtOut > 0 else 0.1
    if not dt_out > 0:
        raise ValueError(f"dt_out must be > 0, got {dt_out}")
    if not sys.initialized:
        t0 = _time.perf_counter()
        sys.init(traj.position(0.0), traj.velocity(0.0), solve_ic=solve_ic)
        log.info("initialisation took %.3g s", _time.perf_counter() - t0)
    rec = Recorder(sys, nodes=record_nodes, probes=water_probes)
    callbacks = list(on_output)
    rec.record()
    for cb in callbacks:
        cb(sys)
    n_out = int(math.floor(duration / dt_out + 1e-9))
    times = list(np.arange(1, n_out + 1) * dt_out)
    if duration - n_out * dt_out > 1e-9 * dt_out:
        times.append(duration)
    t_start = sys.t
    wall = _time.perf_counter()
    with tqdm(total=round(duration, 6), unit="s", unit_scale=False, disable=(not progress) if progress is not None
              else None, desc="simulated", bar_format="{l_bar}{bar}| {n:.1f}/{total:.1f} s "
              "[{elapsed}<{remaining}, {rate_fmt}]") as bar:
        motion_k = traj.as_motion()
        for tk in times:
            sys.advance_to(t_start + tk, motion_k)
            rec.record()
            for cb in callbacks:
                cb(sys)
            bar.update(round(tk - bar.n, 6))
    wall = _time.perf_counter() - wall
    ds = rec.to_dataset()
    ds.attrs["wall_time_s"] = wall
    ds.attrs["real_time_factor"] = duration / wall if wall > 0 else math.inf
    log.info("simulated %.6g s in %.3g s wall time (%.3g x real time)", duration, wall,
             ds.attrs["real_time_factor"])
    return ds
