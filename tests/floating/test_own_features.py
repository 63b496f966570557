"""A floating system compiled with its own features, as a user's run compiles it.

The test suite compiles every system with every feature (``MOORLINE_ALL_FEATURES=1``, see
tests/conftest.py), so a kernel argument that only a system's own feature set produces is never
compiled there. From f11472d a floating system without water kinematics passed its kernels the
small ``NoWater`` tuple, which the floating bodies' viscous loads could not take (they read the
kinematics under a run-time test of still water, outside the WATER gate): ``moorline run`` of the
README's point absorber (waves on the bodies, still water on the lines) stopped in numba's typing.
That read is now gated like every other (``when(W, WATER, ...)``). This runs the command in a
process with its own features, and in one with every feature, and compares the results bit for bit.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]


def _run(tmp_path: Path, all_features: str) -> Path:
    out = tmp_path / f"all{all_features}"
    env = dict(os.environ, MOORLINE_ALL_FEATURES=all_features)
    args = ["run", "examples/point_absorber/system.yaml", "--duration", "1", "--out", str(out)]
    code = f"import sys; from moorline.cli import main; sys.exit(main({args!r}))"
    res = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=env, capture_output=True, text=True, timeout=1800)
    assert res.returncode == 0, res.stderr[-3000:]
    assert (out / "system.nc").exists()
    return out / "system.nc"


@pytest.mark.slow
def test_point_absorber_runs_with_its_own_features(tmp_path):
    pytest.importorskip("capytaine")
    xr = pytest.importorskip("xarray")
    own = _run(tmp_path, "0")
    every = _run(tmp_path, "1")
    with xr.open_dataset(own) as a, xr.open_dataset(every) as b:
        assert sorted(a.data_vars) == sorted(b.data_vars)
        assert len(a.data_vars) > 10
        for name in a.data_vars:
            va, vb = a[name].values, b[name].values
            if np.issubdtype(va.dtype, np.number):
                assert np.array_equal(va, vb, equal_nan=True), name
