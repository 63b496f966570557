"""The start shape of a line too long to lie as an "L" on the seabed (:func:`folded_l_nodes`): a
vertical hang, a run along the seabed and the excess folded back beyond the lower end."""

from __future__ import annotations

import numpy as np
import pytest

from moorline.system.initial import folded_l_nodes


@pytest.mark.parametrize("reverse", [False, True])
def test_folded_start_geometry(reverse):
    low = np.array([-400.0, 0.0, -300.0])
    up = np.array([0.0, 0.0, 0.0])
    L, N = 890.0, 40
    rA, rB = (up, low) if reverse else (low, up)
    out = np.zeros((N + 1, 3))
    folded_l_nodes(rA, rB, L, N, out)
    assert np.array_equal(out[0], rA) and np.array_equal(out[N], rB)
    seg = np.linalg.norm(np.diff(out, axis=0), axis=1)
    # every segment is unstretched, or shorter where it spans a corner (never longer: no tension)
    assert np.all(seg <= L / N + 1e-9)
    assert np.sum(np.isclose(seg, L / N)) >= N - 3
    assert np.all(out[:, 2] >= low[2] - 1e-12)
    assert np.all(out[:, 1] == 0.0)
    # from the lower end: 95 m out beyond the anchor (away from the upper end) and back
    path = out if not reverse else out[::-1]
    assert path[:, 0].min() == pytest.approx(-400.0 - 0.5 * (890.0 - 400.0 - 300.0), abs=L / N)
    # the hang is vertical under the upper end: 300 m of it
    hang = path[path[:, 2] > low[2] + 1e-9]
    assert np.allclose(hang[:, 0], 0.0)
