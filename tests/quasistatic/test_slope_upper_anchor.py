"""Reproduction (issue 17, validation/volturnus_seabed): a chain whose anchor lies on a descending 12.5 %
slope above its other end. The VolturnUS-S upslope case: the anchor at 708.75 m depth, the chain lying
down the slope from it, lifting off towards a junction 22 m lower than the anchor but 39 m above the
seabed under it. The quasi-static line hangs through the seabed (a fully suspended catenary, 1.78 MN at
the anchor) where the dynamic model, with seabed contact, gives 340 kN at the anchor and 273 kN at the
junction; in the full system the free junction then finds no equilibrium. Marked strict xfail: it
documents the bug for the owner of moorline.quasistatic and turns red when the solver is fixed."""

from __future__ import annotations

import numpy as np
import pytest

from moorline.model import Model
from moorline.model.types import Bathymetry
from moorline.quasistatic import QuasiStaticModel

SLOPE = 0.125


def _model():
    x = np.arange(-1400.0, 1400.0 + 1e-9, 100.0)
    X, _ = np.meshgrid(x, x)
    m = Model()
    m.env.depth = 850.0
    m.env.bathymetry = Bathymetry(x, x, -(850.0 + SLOPE * X))  # rises towards -x
    m.add_line_type("chain", d=0.216, w=288.0, EA=1.2326e9, BA=-1.0, Cd=1.333, Ca=1.0, CdAx=0.639, CaAx=0.5)
    a = m.add_point("fixed", (-1130.0, 0.0, -(850.0 - SLOPE * 1130.0)))
    j = m.add_point("fixed", (-640.84, 0.0, -731.01))
    m.add_line("chain", a, j, L=500.0, N=25)
    return m


@pytest.mark.xfail(strict=True, reason="quasi-static line with its seabed end the upper one hangs through a "
                   "descending slope (issue 17 report)")
def test_chain_from_an_upper_anchor_rests_on_the_descending_slope():
    m = _model()
    qs = QuasiStaticModel(m)
    sol = qs.solve()
    _, r, _ = qs.line_profile(1, 201)
    b = m.env.bathymetry
    # the line stays on or above the seabed (1 cm), and its anchor tension is far below the suspended
    # catenary's 1.78 MN (the dynamic model: 340 kN)
    assert np.all(r[:, 2] >= b.height(r[:, 0], r[:, 1]) - 0.01)
    assert sol.tensions[0, 0] < 0.5e6
