"""moorline against MoorDyn's own results (../shared/conformance), judged by the corpus' own
``gen_reference.py`` with the tolerances its ``cases.yaml`` states.

Two checks per case:

* dynamics: start from MoorDyn's initial state (``reference/<case>_initial.csv``), drive the case
  exactly as MoorDyn's driver did, and compare every ``compare`` group of ``cases.yaml``. The
  system reports loads as MoorDyn does (``loads_at='last_stage'``), so this compares the physics
  and the time integration sample by sample.
* statics: moorline's own initial-condition solver against MoorDyn's initial state
  (``compare_initial``), and the dynamics that follow from it.

The pendulum's initial state is not an equilibrium: both solvers stop on a stalled error with the
mass still swinging (MoorDyn's README of the corpus says so), so its own-IC check is not made.
The cases with rods, bodies, bending stiffness, waves, currents and bathymetry belong to later
work and are not run here.
"""

from __future__ import annotations

import pytest

from .driver import CONF, compare, run_case

pytestmark = [pytest.mark.conformance,
              pytest.mark.skipif(not (CONF / "cases.yaml").exists(), reason="../shared/conformance is absent")]

LINE_POINT_CASES = [
    "catenary_3line_static",
    "catenary_3line_surge",
    "chain_wd0050_heave",
    "pendulum_point_mass",
    "bridle_clump_buoy_surge",
    "polyester_motion_csv",
    "seabed_friction_drag",
]

OWN_IC_CASES = [c for c in LINE_POINT_CASES if c != "pendulum_point_mass"]


def _check(results):
    failed = [r for r in results if not r["pass"]]
    report = "\n".join(f"{r.get('group', r.get('check'))}: worst {r.get('column', r.get('where'))} "
                       f"err {r.get('max_abs_err')} allowed {r.get('allowed')}" for r in results)
    assert not failed, report


@pytest.mark.parametrize("case", LINE_POINT_CASES)
def test_dynamics_from_moordyn_initial_state(case, tmp_path):
    pytest.importorskip("yaml")
    res = run_case(case, own_ic=False, out_dir=tmp_path)
    _check(compare(case, res, initial=False))


@pytest.mark.parametrize("case", OWN_IC_CASES)
def test_own_initial_conditions(case, tmp_path):
    pytest.importorskip("yaml")
    res = run_case(case, own_ic=True, out_dir=tmp_path)
    _check(compare(case, res, initial=True))
