"""Free decays of a floating vertical cylinder (radius 5 m, draft 10 m, centre of gravity 7 m below
the waterline) with Capytaine coefficients: the damped period and the logarithmic decrement of the
time-domain decay against the mode of the frequency-domain equations at the mode's own frequency,
(-w^2 (M + A(w)) + i w B(w) + C) x = 0 solved for the complex eigenvalue with A and B evaluated at
|Im lambda| (a fixed point): heave alone, pitch together with the surge it drags along (surge has no
stiffness, so the pitch mode of the free body is the coupled one; about the CG the pitch-only
formula sqrt(C55 / (I + A55)) misses the coupling by 3 %).

Tolerances: the period within 1 % (the issue's), the decrement within 10 %: the time-domain decay
is not a pure mode (the radiation memory follows A(w), B(w) over the whole band while the formula
freezes them at w_n), which changes the decay rate by a few per cent.
"""

from __future__ import annotations

import numpy as np
import pytest

import moorline
from moorline import hydro
from moorline.model import Model

pytest.importorskip("capytaine")

RADIUS, DRAFT, ZG = 5.0, 10.0, -7.0


@pytest.fixture(scope="module")
def cylinder(tmp_path_factory):
    w = np.linspace(0.05, 4.0, 60)
    mesh = hydro.mesh_cylinder(RADIUS, DRAFT, n_theta=24, n_radial=6, n_vertical=10)
    return hydro.compute_coefficients(mesh, omega=w, rho=1025.0, g=9.80665, rotation_center=[0.0, 0.0, ZG],
                                      cache_dir=tmp_path_factory.mktemp("hydro"))


def _mass(ds):
    m = 1025.0 * float(ds["displaced_volume"].values[0])
    inertia = (0.8 * m * (3 * RADIUS**2 + DRAFT**2) / 12,) * 2 + (m * RADIUS**2 / 2,)
    return m, inertia


def _decay(ds, dof, x0, scheme="RK4", dtM=0.01):
    m, inertia = _mass(ds)
    M = Model()
    M.env.depth = 200.0
    M.options.tScheme = scheme
    M.options.dtM = dtM
    b = M.add_body("free", (0.0, 0.0, ZG), m=m, I=inertia)
    M.add_hydro([b], ds)
    s = moorline.System(M)
    s.init()
    if dof == 2:
        s.set_body_state(0, position=(0.0, 0.0, ZG + x0))
    else:
        s.set_body_state(0, angles=(0.0, x0, 0.0))
    t = np.arange(0.0, 45.0, 0.01)
    x = [x0]
    for k in range(1, t.size):
        s.step(None, None, t[k - 1], t[k] - t[k - 1])
        x.append(s.bodies[0].pose()[dof] - (ZG if dof == 2 else 0.0))
    return t, np.array(x)


def _measured(t, x):
    """Damped period from zero crossings (linear interpolation) and the mean logarithmic decrement
    of successive peaks of the same sign, over the first three cycles."""
    i = np.where(np.sign(x[:-1]) != np.sign(x[1:]))[0]
    zc = t[i] - x[i] * (t[i + 1] - t[i]) / (x[i + 1] - x[i])
    Td = 2.0 * np.mean(np.diff(zc[:7]))
    peaks = np.array([np.max(np.abs(x[(t >= zc[k]) & (t < zc[k + 1])])) for k in range(7)])
    return Td, float(np.mean(np.log(peaks[:-2] / peaks[2:])))


def _mode(ds, dofs, w0):
    """Damped period and logarithmic decrement of the frequency-domain mode (see the module
    docstring)."""
    m, inertia = _mass(ds)
    Mfull = hydro.mass_matrix(m, [0.0, 0.0, ZG], inertia, [0.0, 0.0, ZG])[np.ix_(dofs, dofs)]
    w_data = ds["omega"].values
    Ad = hydro.matrix(ds["added_mass"])[:, dofs][:, :, dofs]
    Bd = hydro.matrix(ds["radiation_damping"])[:, dofs][:, :, dofs]
    C = hydro.matrix(ds["hydrostatic_stiffness"])[np.ix_(dofs, dofs)]
    n = len(dofs)
    w = w0
    for _ in range(100):
        A = np.array([[np.interp(w, w_data, Ad[:, i, j]) for j in range(n)] for i in range(n)])
        B = np.array([[np.interp(w, w_data, Bd[:, i, j]) for j in range(n)] for i in range(n)])
        Mm = Mfull + A
        S = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(Mm, C), -np.linalg.solve(Mm, B)]])
        lam = np.linalg.eigvals(S)
        lam = lam[np.argmax(np.abs(lam.imag))]
        w_new = abs(lam.imag)
        if abs(w_new - w) < 1e-12 * w:
            break
        w = w_new
    return 2 * np.pi / abs(lam.imag), 2 * np.pi * (-lam.real) / abs(lam.imag)


@pytest.mark.parametrize("dof, x0, dofs, w0", [(2, 0.5, [2], 0.9), (4, 0.05, [0, 4], 1.1)], ids=["heave", "pitch"])
def test_free_decay_period_and_decrement(cylinder, dof, x0, dofs, w0):
    t, x = _decay(cylinder, dof, x0)
    Td, delta = _measured(t, x)
    Tf, delta_f = _mode(cylinder, dofs, w0)
    assert Td == pytest.approx(Tf, rel=0.01)
    assert delta == pytest.approx(delta_f, rel=0.10)


def test_implicit_scheme_decay_matches_rk4(cylinder):
    """Generalized-alpha at 0.05 s (1/140 of the heave period) against RK4 at 0.01 s: heave decay
    within 1 % of the initial displacement over 45 s."""
    _, x_rk = _decay(cylinder, 2, 0.5)
    _, x_ga = _decay(cylinder, 2, 0.5, scheme="GenAlpha", dtM=0.05)
    assert np.max(np.abs(x_ga - x_rk)) < 0.01 * 0.5
