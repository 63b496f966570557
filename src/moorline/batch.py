"""Old home of the parametric sweeps, kept so that ``from moorline.batch import Study, run_sweep``
goes on working; they now live in :mod:`moorline.studies`."""

from .studies import (
    PARAMETERS,
    CaseSpec,
    Parameter,
    Study,
    StudyError,
    SweepError,
    SweepResult,
    gather,
    register_parameter,
    run_case,
    run_sweep,
    sea_waves,
)

__all__ = ["PARAMETERS", "CaseSpec", "Parameter", "Study", "StudyError", "SweepError", "SweepResult", "gather",
           "register_parameter", "run_case", "run_sweep", "sea_waves"]
