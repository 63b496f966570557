"""Parametric sweeps: a study file, local processes or a Dask cluster, resumable.

    moorline sweep study.yaml [--workers N] [--scheduler tcp://host:8786] [--out DIR]

or in Python::

    from moorline.studies import Study, run_sweep
    res = run_sweep(Study.from_yaml("study.yaml"))
    res.dataset           # one labelled Dataset, the parameters as dimensions/coordinates
    res.summary           # one row per case (pandas DataFrame), also written as summary.csv

A study file (YAML) names a base deck, the parameters to vary (a full-factorial grid, or an
explicit list of cases), the sea states or motion that drive the coupled points, the simulation
settings, and what to post-process (see ``docs/fatigue.md`` for every key). Each case reads the
deck, applies its parameters through the registry of named setters (:data:`PARAMETERS`), finds
the initial equilibrium once, then runs every sea state from that equilibrium and keeps its
post-processed results: damage rates along the line at points around the section, curvature,
tension and stress envelopes, compression. A finished case is written at once and atomically to
``<out>/cases/case_<key>.nc``, where the key is a hash of the case's parameters, the settings
and the contents of the deck, scatter and motion files; a sweep run again skips the cases whose
files are there, so an interrupted sweep resumes without recomputing them. The cases gather
into ``<out>/results.nc`` and ``<out>/summary.csv``.

Parameters act on the model through :func:`register_parameter` (current_speed and
current_heading make a uniform current); the sea-state parameters (Hs, Tz, wave_heading, gamma,
seed) act on the sea state, which drives the buoy motion (:mod:`moorline.post.seastate`) and,
with ``sea_states: {waves_on_lines: true}``, acts on the lines as waves in phase with it
(:func:`sea_waves`).
"""

from ..errors import StudyError, SweepError
from .parameters import PARAMETERS, Parameter, register_parameter
from .run import run_case, sea_waves
from .spec import CaseSpec, Study
from .sweep import SweepResult, gather, run_sweep

__all__ = ["PARAMETERS", "CaseSpec", "Parameter", "Study", "StudyError", "SweepError", "SweepResult", "gather",
           "register_parameter", "run_case", "run_sweep", "sea_waves"]
