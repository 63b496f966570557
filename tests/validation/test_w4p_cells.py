"""The W4P study's cell store (validation/w4p_cable/cells.py): the buoy's yaw damping is a study
parameter, so it must be part of a cell's key (another value never reads a cell made with the
study's), and the committed single-condition cells must be those of the model as it stands."""

from __future__ import annotations

import dataclasses
import importlib.util
import sys
from pathlib import Path

import pytest

HERE = Path(__file__).resolve().parents[2] / "validation" / "w4p_cable"
sys.path.insert(0, str(HERE.parent))
sys.path.insert(0, str(HERE))

cells = pytest.importorskip("cells")
w4p = pytest.importorskip("w4p")
# run.py by path and under its own name: other studies have a run.py too
_spec_run = importlib.util.spec_from_file_location("w4p_cable_run", HERE / "run.py")
run = importlib.util.module_from_spec(_spec_run)
_spec_run.loader.exec_module(run)

SINGLE = (3.5, 7.5)


def _spec(name: str, **kw):
    return run.spec_for(w4p.DESIGNS[name], *SINGLE, quick=False, paper=False, coeffs=None,
                        dims=w4p.hull_dimensions(), **kw)


def test_yaw_damping_is_in_the_key():
    fp = cells.model_fingerprint()
    base = _spec("initial")
    assert base.yaw_damping == w4p.YAW_DAMPING > 0
    other = dataclasses.replace(base, yaw_damping=0.0)
    assert cells.inputs(base, *SINGLE)["yaw_damping"] == w4p.YAW_DAMPING
    assert cells.key(base, *SINGLE, fp) != cells.key(other, *SINGLE, fp)
    assert cells.read(other, *SINGLE, fp) is None  # the committed cell is the study's buoy, not this one


@pytest.mark.parametrize("name", ["initial", "improved"])
def test_committed_single_condition_cell_is_the_current_model(name):
    """The single condition is re-run first whenever w4p.py changes; a committed cell that no
    longer matches the model would silently make every assembly skip it."""
    spec = _spec(name)
    out = cells.read(spec, *SINGLE, cells.model_fingerprint())
    assert out is not None, f"{cells.path(spec.design, *SINGLE)} was made from another model or inputs: re-run"
    assert out["yaw_range"] < 1e-5  # rad: the buoy at rest in yaw, as the study assumes
    assert out["periodicity"] < 0.05
