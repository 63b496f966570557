"""Hard limits on input that parses but would make a run endless or meaningless.

A deck fuzzer found inputs that read without error and then ran for ever: a water density of
1e-308 kg/m^3, ``CFL 1e-308`` (a time step of 1e-311 s), ``dtIC 0`` with dynamic relaxation (a
loop that never advances). Two kinds of checks refuse them before anything is computed, with
:class:`moorline.errors.InputLimitError` (a :class:`~moorline.errors.DeckError`: bad input, exit
code 2 on the command line):

- :func:`check_model`, on every System: values outside any physical or numerical sense (densities,
  gravity, time steps and intervals that are not finite and positive or are absurdly small or
  large, more line nodes than memory holds). These are never forced.
- :func:`check_run`, before a simulation: the number of time steps it will take (dynamics and
  initial conditions). Above :data:`WARN_STEPS` it warns with a rough wall-time estimate; above
  :data:`MAX_STEPS` it refuses unless forced (``force=True``, ``--force``), as it does above
  :data:`MAX_SAMPLES` output samples (all kept in memory).
"""

from __future__ import annotations

import dataclasses
import logging
import math
from typing import TYPE_CHECKING

import numpy as np

from ..errors import InputLimitError
from ..model import Model

if TYPE_CHECKING:
    from .runtime import System

log = logging.getLogger("moorline")

#: time steps (dynamics plus initial conditions) above which a run is announced as long
WARN_STEPS = 1e8
#: time steps above which a run is refused unless forced: 1e11 steps take days even for one node
MAX_STEPS = 1e11
#: output samples above which a run is refused unless forced (every sample is kept in memory)
MAX_SAMPLES = 1e7
#: line and rod nodes above which a model is refused: the work arrays alone would take 4 GB
MAX_NODES = 1e7
#: rough cost of one node and one time step [s] (RK2; benchmarks/RESULTS.md: 4e-8 to 1e-7)
SECONDS_PER_NODE_STEP = 1e-7
#: plausible fluid densities [kg/m^3]: 0 (no fluid) or from a gas to beyond mercury
RHO_RANGE = (1e-3, 1e5)
#: plausible gravity [m/s^2]: 0 (none) up to a hundred times the Earth's
G_MAX = 1e3
#: smallest time step and interval taken seriously [s]
DT_MIN = 1e-9


def _finite(name: str, value, *, positive: bool = False, nonnegative: bool = False, what: str = "") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputLimitError(f"{name} = {value!r}: expected a number{what}") from None
    if not math.isfinite(v) or (positive and not v > 0) or (nonnegative and v < 0):
        cond = " > 0" if positive else (" >= 0" if nonnegative else "")
        raise InputLimitError(f"{name} = {value}: expected a finite number{cond}{what}")
    return v


#: largest magnitude of any number of a model, in any of its units: beyond it products overflow
MAX_MAGNITUDE = 1e30


def _walk_numbers(obj, where: str):
    """(where, value) of every number in a model object (dataclass fields, sequences, arrays)."""
    if isinstance(obj, bool) or obj is None or isinstance(obj, str):
        return
    if isinstance(obj, (int, float, np.integer, np.floating)):
        yield where, float(obj)
    elif isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fiu" and obj.size:
            bad = ~np.isfinite(obj) | (np.abs(obj) > MAX_MAGNITUDE)
            if bad.any():
                yield where, float(obj[bad].flat[0])
    elif isinstance(obj, (list, tuple)):
        for k, v in enumerate(obj):
            yield from _walk_numbers(v, f"{where}[{k}]")
    elif dataclasses.is_dataclass(obj):
        for f in dataclasses.fields(obj):
            yield from _walk_numbers(getattr(obj, f.name), f"{where} {f.name}")


def check_model(model: Model) -> None:
    """Refuse a model whose values make no physical or numerical sense (see the module docstring).

    Raises
    ------
    InputLimitError
    """
    groups = [(f"line type {k!r}", v) for k, v in model.line_types.items()]
    groups += [(f"rod type {k!r}", v) for k, v in model.rod_types.items()]
    for name, seq in (("point", model.points), ("line", model.lines), ("rod", model.rods), ("body", model.bodies)):
        groups += [(f"{name} {k}", v) for k, v in enumerate(seq, 1)]
    for what, obj in groups:
        for where, v in _walk_numbers(obj, what):
            if not math.isfinite(v) or abs(v) > MAX_MAGNITUDE:
                raise InputLimitError(f"{where} = {v:g}: expected a finite number of magnitude below "
                                      f"{MAX_MAGNITUDE:g} (no mooring property is larger in SI units)")
    env, opts = model.env, model.options
    rho = _finite("water density rho", env.rho, nonnegative=True, what=" [kg/m^3]")
    if rho != 0.0 and not RHO_RANGE[0] <= rho <= RHO_RANGE[1]:
        raise InputLimitError(f"water density rho = {rho:.3g} kg/m^3 is not the density of any fluid: expected 0 "
                              f"(no fluid) or {RHO_RANGE[0]:g} to {RHO_RANGE[1]:g} kg/m^3 (sea water: 1025)")
    g = _finite("gravity g", env.g, nonnegative=True, what=" [m/s^2]")
    if g > G_MAX:
        raise InputLimitError(f"gravity g = {g:.3g} m/s^2: expected 0 to {G_MAX:g} m/s^2 (Earth: 9.81)")
    _finite("water depth WtrDpth", env.depth, what=" [m]")
    _finite("seabed stiffness kBot", env.kBot, nonnegative=True, what=" [Pa/m]")
    _finite("seabed damping cBot", env.cBot, nonnegative=True, what=" [Pa s/m]")
    if opts.dtM is not None and opts.dtM > 0:
        dtM = _finite("time step dtM", opts.dtM, positive=True, what=" [s]")
        if dtM < DT_MIN:
            raise InputLimitError(f"time step dtM = {dtM:.3g} s is below {DT_MIN:g} s: no mooring needs it; "
                                  "see 'moorline check DECK' for the largest stable dtM")
    else:
        cfl = _finite("CFL", opts.CFL, positive=True, what=" (time step as a fraction of the shortest segment "
                      "period, e.g. 0.5)")
        if cfl < 1e-6:
            raise InputLimitError(f"CFL = {cfl:.3g}: the time step would be {cfl:.3g} times the shortest segment "
                                  "period; expected about 0.1 to 1")
    tmax = _finite("TmaxIC", opts.TmaxIC, nonnegative=True, what=" [s]")
    if tmax > 0:
        dtic = _finite("dtIC", opts.dtIC, positive=True, what=" [s] (the initial-condition convergence interval)")
        if tmax / dtic > MAX_SAMPLES:
            raise InputLimitError(f"dtIC = {dtic:.3g} s with TmaxIC = {tmax:.3g} s: {tmax / dtic:.3g} convergence "
                                  "checks; expected dtIC of about 0.1 to 1 s")
        _finite("threshIC", opts.threshIC, positive=True)
    _finite("dtOut", opts.dtOut, nonnegative=True, what=" [s]")
    nodes = sum(int(ln.N) + 1 for ln in model.lines) + sum(int(rod.N) + 1 for rod in model.rods)
    if nodes > MAX_NODES:
        raise InputLimitError(f"{nodes:.3g} line and rod nodes: more than {MAX_NODES:g}, beyond the memory of any "
                              "machine this runs on; check NumSegs")
    for k, ln in enumerate(model.lines, 1):
        _finite(f"line {k} UnstrLen", ln.L, what=" [m]")


def estimated_steps(system: System, duration: float, *, solve_ic: bool) -> tuple[float, float]:
    """(time steps of the dynamics, pseudo-time steps of the initial conditions) a run takes, at
    most: ``duration / dtM`` and ``TmaxIC / dtM`` (Newton statics takes far fewer)."""
    dyn = duration / system.dtM
    ic = system.model.options.TmaxIC / system.dtM if solve_ic else 0.0
    return dyn, ic


def check_run(system: System, duration: float, *, solve_ic: bool, dt_out: float | None = None,
              force: bool = False) -> float:
    """Refuse (unless ``force``) or announce a run of ``duration`` seconds of ``system`` that takes
    an astronomical or a very large number of time steps; returns the estimated steps.

    Raises
    ------
    InputLimitError
        More than :data:`MAX_STEPS` steps, or more than :data:`MAX_SAMPLES` output samples.
    """
    dyn, ic = estimated_steps(system, duration, solve_ic=solve_ic)
    total = dyn + ic
    nodes = max(int(system.work.r.shape[0]) + int(system.work.rn_r.shape[0]), 1)
    hours = total * nodes * SECONDS_PER_NODE_STEP / 3600.0
    if total > MAX_STEPS and not force:
        raise InputLimitError(f"this run would take {total:.3g} time steps ({dyn:.3g} for {duration:g} s of dynamics "
                              f"and {ic:.3g} for the initial conditions, at dtM = {system.dtM:.3g} s), about "
                              f"{hours:.3g} hours: use a larger dtM or CFL, or a shorter duration or TmaxIC (force it "
                              "with --force, or force=True)")
    if dt_out is not None and duration / dt_out > MAX_SAMPLES and not force:
        raise InputLimitError(f"{duration / dt_out:.3g} output samples (duration {duration:g} s, output interval "
                              f"{dt_out:.3g} s): more than {MAX_SAMPLES:g}, which memory would not hold; use a larger "
                              "output interval (force it with --force, or force=True)")
    if total > WARN_STEPS:
        log.warning("this run takes about %.3g time steps at dtM = %.3g s: roughly %.3g hours of wall time for %d "
                    "nodes", total, system.dtM, hours, nodes)
    return total
