"""RAOs (single body against the 1-DOF closed form; the RM3 two-body PTO by reduced coordinates against Lagrange
multipliers) and excitation interpolation."""

from __future__ import annotations

import numpy as np
import pytest

from moorline.hydro import LinearPTO, excitation_transfer, impedance, mass_matrix, matrix, rao


def test_single_heave_rao_closed_form(rm3):
    """Heave of a body alone: X3 = F3 / (-w^2 (m + A33) - i w B33 + C33) when every other DOF is held (here the
    spar's heave with all else given a huge stiffness): agreement to 1e-6 relative at every frequency."""
    n = 12
    M = mass_matrix([725.833 * 1000, 886.687 * 1000], [[0, 0, -0.72], [0, 0, -21.29]], np.ones((2, 3)) * 1e7,
                    [[0, 0, -0.72], [0, 0, -21.29]])
    k = np.eye(n) * 1e18
    k[8, 8] = 0.0
    out = rao(rm3, M, wave_direction=0.0, stiffness=k)
    w = rm3.omega.values
    A = matrix(rm3.added_mass)[:, 8, 8]
    B = matrix(rm3.radiation_damping)[:, 8, 8]
    C = matrix(rm3.hydrostatic_stiffness)[8, 8]
    F = rm3.excitation_force.isel(wave_direction=0).values[:, 8]
    ref = F / (-w ** 2 * (M[8, 8] + A) - 1j * w * B + C)
    np.testing.assert_allclose(out.rao.values[:, 8], ref, rtol=1e-6)


def test_rm3_pto_reduced_against_lagrange(rm3):
    """RM3 float and spar, PTO 1200 kN s/m along z, other relative motions locked: the reduced-coordinate solve
    T^H Z T q = T^H F equals the Lagrange-multiplier solve [[Z, G^T], [G, 0]] [x; lambda] = [F; 0] (G the five
    locked relative motions) to 1e-8 relative; the float and spar heave differ by the PTO stroke."""
    ref = rm3.rotation_center.values
    M = mass_matrix([725.833e3, 886.687e3], ref + [[0, 0, 0], [0, 0, 0]], [[20907301, 21306090, 37085481],
                                                                       [94419615, 94407091, 28542224]], ref)
    pto = LinearPTO(body_a=0, body_b=1, axis=(0, 0, 1), damping=1.2e6)
    out = rao(rm3, M, wave_direction=0.0, pto=pto)
    w, Z = impedance(rm3, M)
    p = pto.vector(12)
    Z = Z + (-1j * w[:, None, None] * pto.damping) * np.outer(p, p)[None]
    F = excitation_transfer(rm3, w, 0.0)
    T = pto.constraint_matrix(ref, 12)
    # constraint rows: the orthogonal complement of T's range (5 locked relative motions)
    u, s, vt = np.linalg.svd(T)
    G = u[:, 7:].T
    for k in range(w.size):
        KKT = np.block([[Z[k], G.T], [G, np.zeros((5, 5))]])
        sol = np.linalg.solve(KKT, np.concatenate([F[k], np.zeros(5)]))
        np.testing.assert_allclose(out.rao.values[k], sol[:12], rtol=1e-8, atol=1e-8 * np.abs(sol[:12]).max())
    dz = out.rao.values[:, 2] - out.rao.values[:, 8]
    np.testing.assert_allclose(out.pto_displacement.values, dz, rtol=1e-12)
    assert np.all(out.pto_power.values >= 0)
    # relative rotation and horizontal relative motion locked
    np.testing.assert_allclose(out.rao.values[:, 3:6], out.rao.values[:, 9:12], atol=1e-12)


def test_excitation_interpolation_and_limits(rm3):
    """Interpolation returns the data at computed frequencies, the average half-way; an out-of-band frequency
    raises (or is zero with outside='zero'); a heading outside a non-covering set raises."""
    w = rm3.omega.values
    X = rm3.excitation_force.isel(wave_direction=0).values
    np.testing.assert_allclose(excitation_transfer(rm3, w, 0.0), X)
    mid = 0.5 * (w[10] + w[11])
    np.testing.assert_allclose(excitation_transfer(rm3, [mid], 0.0)[0], 0.5 * (X[10] + X[11]))
    with pytest.raises(ValueError, match="outside the computed band"):
        excitation_transfer(rm3, [w[-1] * 1.1], 0.0)
    z = excitation_transfer(rm3, [w[-1] * 1.1, w[5]], 0.0, outside="zero")
    assert np.all(z[0] == 0) and np.allclose(z[1], X[5])
    with pytest.raises(ValueError, match="not in the computed set"):
        excitation_transfer(rm3, w, 0.3)


def test_excitation_periodic_headings():
    """With headings covering the circle (every 10 deg from -180 to 170), 175 deg interpolates across the wrap
    between 170 and 180 = -180 deg, -185 deg gives the same, and 355 deg equals -5 deg."""
    import xarray as xr
    betas = np.radians(np.arange(-180, 180, 10.0))
    X = np.exp(1j * betas)[None, :, None] * np.ones((2, 1, 6))
    ds = xr.Dataset({"excitation_force": (("omega", "wave_direction", "influenced_dof"), X)},
                    coords={"omega": [1.0, 2.0], "wave_direction": betas,
                            "influenced_dof": ["Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw"]})
    a = excitation_transfer(ds, [1.5], np.radians(175.0))
    b = excitation_transfer(ds, [1.5], np.radians(-185.0))
    np.testing.assert_allclose(a, b)
    np.testing.assert_allclose(excitation_transfer(ds, [1.5], np.radians(355.0)),
                               excitation_transfer(ds, [1.5], np.radians(-5.0)))
    np.testing.assert_allclose(a[0, 0], 0.5 * (np.exp(1j * np.radians(170)) + np.exp(-1j * np.radians(180))))
