"""Initial equilibrium of a floating body far from its deck pose (a spar on taut lines held offset by a
constant load, as before a free-decay release) with an explicit scheme. Newton from the catenary start does
not converge; the implicit relaxation must then run until the body has settled, not only until the line
tensions stop changing (they barely change while the spar creeps), before Newton again. Before the fix the
relaxation stopped early, Newton failed again, and MoorDyn's stationary fallback left the body at its deck
pose with the lines unbalanced (a warning, no error)."""

from __future__ import annotations

import numpy as np
import pytest

import moorline
from moorline.model import Model

from .conftest import SPAR_INERTIA, SPAR_RCG

PULL = 3.0e6  # [N] surge force at the fairlead level (70 m below the reference point)


def taut_spar(ds, scheme, dtM, force):
    """The conftest spar hull (coefficients for 320 m; mass set to balance the buoyancy less 1.7 MN) on
    three taut lines (the DeepCwind OC3 test's: 450.5 m, EA 106 MN, anchors 445 m out at 200 m depth)."""
    m = Model()
    m.env.depth = 200.0
    m.options.tScheme, m.options.dtM, m.options.ICNewton = scheme, dtM, 1
    m.add_line_type("taut", d=0.09, w=13.5, EA=106.0e6, BA=-0.8, Cd=1.6, Ca=1.0, CdAx=0.1, CaAx=0.0)
    vol = float(ds["displaced_volume"].values[0])
    mass = 1025.0 * vol - 1.7e6 / 9.80665
    b = m.add_body("free", (0.0, 0.0, 0.0), m=mass, rCG=SPAR_RCG, I=SPAR_INERTIA)
    for k in range(3):
        a = np.radians(120.0 * k)
        fl = m.add_point("body", (5.2 * np.cos(a), 5.2 * np.sin(a), -70.0), body=b)
        an = m.add_point("fixed", (445.0 * np.cos(a), 445.0 * np.sin(a), -200.0))
        m.add_line("taut", an, fl, L=450.5, N=20)
    m.add_hydro([b], ds)
    m.add_floating(b, force=force)
    return m


@pytest.mark.parametrize("scheme,dtM", [("RK2", 0.004), ("GenAlpha", 0.1)])
def test_pulled_spar_on_taut_lines_finds_its_offset_equilibrium(spar, scheme, dtM):
    s = moorline.System(taut_spar(spar, scheme, dtM, [PULL, 0, 0, 0, -70.0 * PULL, 0]))
    s.init()
    assert s.ic_report["converged"], s.ic_report
    assert s.bodies[0].pose()[0] > 5.0  # the body left its deck pose (about 10 m)
    assert np.all(np.abs(s.bodies[0].acceleration()) < 1e-4)  # and is in equilibrium there
