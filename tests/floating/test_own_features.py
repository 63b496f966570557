"""A floating system compiled with its own features, as a user's run compiles it.

The test suite compiles every system with every feature (``MOORLINE_ALL_FEATURES=1``, see
tests/conftest.py), so a kernel argument that only a system's own feature set produces is never
compiled there. From f11472d a floating system without water kinematics passed its kernels the
small ``NoWater`` tuple, which the floating bodies' viscous loads cannot take (they read the
kinematics under a run-time test of still water): ``moorline run`` of the README's point absorber
stopped in numba's typing. This runs that command in a process with its own features.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_point_absorber_runs_with_its_own_features(tmp_path):
    pytest.importorskip("capytaine")
    env = dict(os.environ, MOORLINE_ALL_FEATURES="0")
    args = ["run", "examples/point_absorber/system.yaml", "--duration", "1", "--out", str(tmp_path)]
    code = f"import sys; from moorline.cli import main; sys.exit(main({args!r}))"
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=1800)
    assert res.returncode == 0, res.stderr[-3000:]
    assert (tmp_path / "system.nc").exists()
