"""The quasi-static time-domain mode: the spar of test_moored.py on quasi-static lines
(System(..., mooring="quasistatic")), against the quasi-static solver's own equilibrium of the
free spar and against the dynamic lines.
"""

from __future__ import annotations

import numpy as np
import pytest

import moorline
from moorline import hydro
from moorline.quasistatic import QuasiStaticModel
from moorline.quasistatic.hydrostatics import BodyHydrostatics

from .conftest import spar_model

FORCE = np.array([1.0e6, 0.0, 0.0, 0.0, 0.0, 0.0])


def test_equilibrium_matches_the_dynamic_lines(spar):
    """Still water: the same heave within 1 mm; fairlead tensions within 1.5 % (the dynamic model
    reports the top segment's tension, half a 45 m segment below the fairlead, where the chain's
    weight makes it 1.1 % lower)."""
    m = spar_model(spar)
    dyn = moorline.System(m)
    dyn.init()
    qs = moorline.System(m, mooring="quasistatic")
    qs.init()
    assert qs.ic_report["method"] == "newton on quasi-static lines"
    assert qs.bodies[0].pose()[2] == pytest.approx(dyn.bodies[0].pose()[2], abs=1e-3)
    np.testing.assert_allclose(qs.line_end_tensions()[:, 1], dyn.line_end_tensions()[:, 1], rtol=0.015)


def test_offset_under_a_steady_force_matches_the_quasi_static_solver(spar):
    """A 1 MN surge force: the time-domain mode, started at its still-water equilibrium with heavy
    extra damping, settles where the quasi-static solver puts the free spar with the same
    hydrostatics (buoyancy at rest and the buoyancy stiffness of the coefficients) and the same
    force: surge within 0.5 %, pitch within 1 %. Both use the same line model; what differs is the
    way there (time stepping with a linearised load re-solved every 0.1 s, against Newton on the
    whole network)."""
    m = spar_model(spar, linear_damping=[4.0e6, 4.0e6, 4.0e6, 2.0e10, 2.0e10, 4.0e8])
    s = moorline.System(m, mooring="quasistatic")
    s.init()
    s.layout.fl.Fc[0] = FORCE
    for k in range(60):
        s.step(None, None, 10.0 * k, 10.0)
    x_td = s.bodies[0].pose()
    hs = BodyHydrostatics(displaced_volume=float(spar["displaced_volume"].values[0]),
                          center_of_buoyancy=spar["center_of_buoyancy"].values[0],
                          hydrostatic_stiffness=hydro.matrix(spar["hydrostatic_stiffness"]))
    m_qs = spar_model(spar)
    m_qs.floating.clear()
    m_qs.hydro.clear()
    q = QuasiStaticModel(m_qs, bodies_free=True, hydrostatics={1: hs}, external_loads={1: FORCE})
    x_qs = q.solve().bodies[0]
    assert x_td[0] == pytest.approx(x_qs[0], rel=0.005)
    assert x_td[4] == pytest.approx(x_qs[4], rel=0.01)


def test_dynamic_and_quasi_static_lines_give_similar_surge_decays(spar):
    """A 10 m surge decay in still water: quasi-static lines have no inertia and no drag, so the
    period is a little shorter (measured 107 s against 111 s) and the decay slower; both near the
    frequency of the linearised system (within 10 %)."""
    m = spar_model(spar)
    periods = {}
    for mode in ("dynamic", "quasistatic"):
        s = moorline.System(m, mooring=mode)
        s.init()
        x_eq = s.bodies[0].pose()[0]
        s.set_body_state(0, position=s.bodies[0].position() + [10.0, 0.0, 0.0])
        t = np.arange(0.0, 300.0 + 1e-9, 1.0)
        x = [10.0]
        for k in range(1, t.size):
            s.step(None, None, t[k - 1], 1.0)
            x.append(s.bodies[0].pose()[0] - x_eq)
        x = np.array(x)
        i = np.where(np.sign(x[:-1]) != np.sign(x[1:]))[0]
        zc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
        periods[mode] = 2.0 * np.mean(np.diff(zc[:4]))
    assert periods["quasistatic"] == pytest.approx(periods["dynamic"], rel=0.10)
