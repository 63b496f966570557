"""Capytaine runs: Hulme's floating hemisphere, the cache, NetCDF round trip, change of reference point."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from moorline.hydro import matrix, transform_reference

cpt = pytest.importorskip("capytaine")

from moorline.hydro.bem import (  # noqa: E402
    cache_key,
    compute_coefficients,
    from_capytaine,
    mesh_cylinder,
    mesh_hemisphere,
    read_capytaine,
    write_netcdf,
)

RHO, G = 1000.0, 9.81

# Hulme, A. (1982) "The wave forces acting on a floating hemisphere undergoing forced periodic oscillations",
# J. Fluid Mech. 121, 443-463. Non-dimensional added mass A/(rho 2/3 pi a^3) and damping B/(rho 2/3 pi a^3 w)
# against K a = w^2 a / g (deep water). Heave: Table 1 as transcribed in LHEEA/Hulme_Heaving_Sphere,
# comparison/HulmeResult.dat; surge: Table 2 as transcribed in a public script citing the paper (K a 0.1-1.4).
KA_HEAVE = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.4, 1.6, 1.8, 2.0])
A_HEAVE = np.array([0.8627, 0.7938, 0.7157, 0.6452, 0.5861, 0.5381, 0.4999, 0.4698, 0.4464, 0.4284, 0.4047,
                    0.3924, 0.3871, 0.3864, 0.3884])
B_HEAVE = np.array([0.1816, 0.2793, 0.3254, 0.3410, 0.3391, 0.3271, 0.3098, 0.2899, 0.2691, 0.2484, 0.2096,
                    0.1756, 0.1469, 0.1229, 0.1031])
KA_SURGE = np.array([0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0, 1.2, 1.4])
A_SURGE = np.array([0.5223, 0.5515, 0.5848, 0.6175, 0.6439, 0.6586, 0.6682, 0.6421, 0.6127, 0.5740, 0.4860, 0.4038])
B_SURGE = np.array([0.001, 0.0082, 0.0255, 0.0557, 0.0987, 0.1516, 0.2092, 0.2653, 0.3145, 0.3535, 0.3978, 0.406])

MESH = dict(n_meridian=40, n_theta=64)  # 40 panels pole to waterline, 64 around: 2560 panels, one wedge solved


@pytest.fixture(scope="module")
def hemisphere(tmp_path_factory):
    ka = np.union1d(np.union1d(KA_HEAVE, KA_SURGE), np.linspace(0.02, 2.0, 23))
    ds = compute_coefficients(mesh_hemisphere(1.0, **MESH), omega=np.sqrt(ka * G), rho=RHO, g=G,
                              cache_dir=tmp_path_factory.mktemp("cache"))
    return ds


def _nondim(ds, dof, ka):
    m = RHO * 2 / 3 * np.pi
    w = np.sqrt(ka * G)
    a = ds.added_mass.sel(radiating_dof=dof, influenced_dof=dof).sel(omega=w, method="nearest").values / m
    b = ds.radiation_damping.sel(radiating_dof=dof, influenced_dof=dof).sel(omega=w, method="nearest").values / (m * w)
    return a, b


@pytest.mark.parametrize("dof, ka, a_ref, b_ref", [("Heave", KA_HEAVE, A_HEAVE, B_HEAVE),
                                                   ("Surge", KA_SURGE, A_SURGE, B_SURGE)])
def test_hulme_hemisphere(hemisphere, dof, ka, a_ref, b_ref):
    """Within 2 % of each tabulated curve's peak (the surge damping starts at 0.001, where a relative error means
    nothing). Measured at this mesh (2560 panels): heave A <= 1.5 %, B <= 3.9 % of the point value (K a = 2),
    surge A <= 2.2 %, B <= 3.0 % of the point value for K a >= 0.2; all <= 1.6 % of the curve peaks."""
    a, b = _nondim(hemisphere, dof, ka)
    assert np.max(np.abs(a - a_ref)) <= 0.02 * a_ref.max()
    assert np.max(np.abs(b - b_ref)) <= 0.02 * b_ref.max()


def test_hemisphere_limits_and_hydrostatics(hemisphere):
    """Infinite-frequency heave added mass of the hemisphere tends to 0.5 (Hulme) within 2 %; C33 = rho g pi a^2
    within 0.5 %; buoyancy-only roll stiffness about the centre is rho g (pi a^4/4 - 2/3 pi a^3 * 3a/8) = 0
    to 0.3 % of either cancelling term rho g pi a^4/4 (measured 0.19 %: the panel polygon); the displaced
    volume is 2/3 pi a^3 within 0.5 %."""
    m = RHO * 2 / 3 * np.pi
    a33_inf = float(hemisphere.added_mass_inf.sel(radiating_dof="Heave", influenced_dof="Heave")) / m
    assert a33_inf == pytest.approx(0.5, rel=2e-2)
    C = matrix(hemisphere.hydrostatic_stiffness)
    assert C[2, 2] == pytest.approx(RHO * G * np.pi, rel=5e-3)
    assert abs(C[3, 3]) < 3e-3 * RHO * G * np.pi / 4
    assert float(hemisphere.displaced_volume[0]) == pytest.approx(2 / 3 * np.pi, rel=5e-3)


def test_hemisphere_irf_round_trip_and_state_space(hemisphere):
    """Heave of the hemisphere, band K a = 0.02-2 (B33 at the top is 54 % of its peak, so the taper matters):
    B and A rebuilt from K (T = 100 s) within 2 % of their peaks for K a >= 0.2 (measured B 0.1 %, A 1.7 %); below,
    A is 2.1 % off at K a = 0.1 whatever T (Capytaine's low-frequency A33, with its k log k behaviour, is not
    matched by B linear between the samples), hence 2.5 % over the whole band; the state-space
    fit is stable, passive, and its kernel within 2 % (relative L2) of K. Surge is not checked here: B11 is still
    97 % of its peak at K a = 2, so this band cannot carry its impulse response (A11 rebuilt 10 % off)."""
    from moorline.hydro import coefficients_from_irf, fit_state_space, impulse_response
    t = np.arange(0.0, 100.0, 0.01)
    K = impulse_response(hemisphere, t)
    w = hemisphere.omega.values
    A, B = coefficients_from_irf(K, t, w, hemisphere.added_mass_inf)
    above = w ** 2 / G >= 0.2
    for ref, got in ((hemisphere.added_mass.values, A), (hemisphere.radiation_damping.values, B)):
        assert np.abs(got[above, 2, 2] - ref[above, 2, 2]).max() <= 0.02 * np.abs(ref[:, 2, 2]).max()
        assert np.abs(got[:, 2, 2] - ref[:, 2, 2]).max() <= 0.025 * np.abs(ref[:, 2, 2]).max()
    fit = fit_state_space(hemisphere, t=t)
    heave = [p for p in fit.pairs if p.i == p.j == 2][0]
    assert np.all(np.linalg.eigvals(heave.A).real < 0)
    assert heave.error <= 0.02
    assert fit.passivity_report.passive


def test_cache_hit_identical_and_key_changes(tmp_path, caplog):
    """The second call loads from the cache (no Capytaine run) and returns identical data; every input changes
    the key."""
    mesh = mesh_cylinder(1.0, 1.0, n_radial=3, n_vertical=4, n_theta=12)
    kw = dict(omega=np.array([0.8, 1.6, 2.4]), wave_direction=[0.0, np.pi / 2], rho=RHO, g=G, cache_dir=tmp_path)
    first = compute_coefficients(mesh, **kw)
    with caplog.at_level(logging.INFO, logger="moorline.hydro"):
        second = compute_coefficients(mesh, **kw)
    assert "cache hit" in caplog.text and "cache miss" not in caplog.text
    for var in first.data_vars:
        np.testing.assert_array_equal(second[var].values, first[var].values)
    base = dict(lids=[False], omega=kw["omega"], wave_direction=[0.0], water_depth=np.inf, rho=RHO, g=G,
                rotation_centers=[[0, 0, 0]], names=["b"])
    k0 = cache_key([mesh], **base)
    assert cache_key([mesh], **base) == k0
    changes = [dict(lids=[True]), dict(omega=kw["omega"] * 1.001), dict(wave_direction=[0.1]),
               dict(water_depth=50.0), dict(rho=1025.0), dict(g=9.8), dict(rotation_centers=[[0, 0, -0.1]]),
               dict(names=["c"])]
    for ch in changes:
        assert cache_key([mesh], **{**base, **ch}) != k0, ch
    moved = mesh_cylinder(1.0, 1.01, n_radial=3, n_vertical=4, n_theta=12)
    assert cache_key([moved], **base) != k0


def test_netcdf_round_trip_and_capytaine_layout(tmp_path):
    """A result written by Capytaine's own export (complex split along 'complex') reads back to the same
    coefficients as the in-memory conversion; moorline's writer round-trips exactly."""
    mesh = cpt.mesh_vertical_cylinder(radius=1.0, length=2.0, center=(0, 0, -0.5), resolution=(3, 12, 6))
    body = cpt.FloatingBody(mesh=mesh.immersed_part(), dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                            center_of_mass=(0, 0, -0.3), name="cyl")
    test = __import__("xarray").Dataset(coords={"omega": [0.5, 1.0, 2.0, np.inf], "wave_direction": [0.0],
                                                "radiating_dof": list(body.dofs), "rho": RHO})
    res = cpt.BEMSolver().fill_dataset(test, body)
    res["hydrostatic_stiffness"] = body.immersed_part().compute_hydrostatic_stiffness(rho=RHO)
    path = tmp_path / "cyl.nc"
    cpt.export_dataset(path, res.drop_vars([v for v in ("center_of_mass",) if v in res.coords]))
    ours = read_capytaine(path)
    mem = from_capytaine(res)
    for var in ("added_mass", "radiation_damping", "added_mass_inf", "excitation_force"):
        np.testing.assert_allclose(ours[var].values, mem[var].values, rtol=1e-12)
    # Capytaine 3 stores (omega, influenced, radiating); ours (omega, radiating, influenced): labels agree
    a_cpt = res.added_mass.sel(omega=1.0, radiating_dof="Pitch", influenced_dof="Surge").item()
    assert mem.added_mass.sel(omega=1.0, radiating_dof="Pitch", influenced_dof="Surge").item() == a_cpt
    write_netcdf(mem, tmp_path / "ours.nc")
    back = read_capytaine(tmp_path / "ours.nc")
    for var in mem.data_vars:
        np.testing.assert_array_equal(back[var].values, mem[var].values)


def test_capytaine_weight_terms_removed():
    """A Capytaine stiffness computed with the centre of mass 0.3 m below the rotation centre (so it holds
    -m g (z_g - z_c) in C44/C55) comes out equal to the buoyancy-only one (centre of mass at the rotation centre)
    to 1e-9 rho g."""
    mesh = cpt.mesh_vertical_cylinder(radius=1.0, length=2.0, center=(0, 0, -0.5), resolution=(3, 12, 6))
    hull = mesh.immersed_part()
    res = {}
    for zg in (-0.3, 0.0):
        body = cpt.FloatingBody(mesh=hull, dofs=cpt.rigid_body_dofs(rotation_center=(0, 0, 0)),
                                center_of_mass=(0.1, 0, zg), name="cyl")
        test = __import__("xarray").Dataset(coords={"omega": [1.0, np.inf], "wave_direction": [0.0],
                                                    "radiating_dof": list(body.dofs), "rho": RHO})
        ds = cpt.BEMSolver().fill_dataset(test, body, hydrostatics=False)
        ds["hydrostatic_stiffness"] = body.compute_hydrostatic_stiffness(rho=RHO, g=G)
        ds["disp_mass"] = RHO * body.disp_volume
        ds["center_of_buoyancy"] = (("space_coordinate",), body.center_of_buoyancy)
        ds = ds.assign_coords(center_of_mass=(("space_coordinate",), [0.1, 0.0, zg]))
        res[zg] = ds
    assert not np.allclose(res[-0.3].hydrostatic_stiffness.values, res[0.0].hydrostatic_stiffness.values)
    a, b = from_capytaine(res[-0.3]), from_capytaine(res[0.0])
    np.testing.assert_allclose(a.hydrostatic_stiffness.values, b.hydrostatic_stiffness.values, atol=1e-9 * RHO * G)
    c = matrix(b.hydrostatic_stiffness)
    assert c[3, 5] == pytest.approx(0.0, abs=1e-9 * RHO * G)  # x_g - x_c weight term in C46 removed too


def test_transform_reference_against_capytaine(tmp_path):
    """Coefficients computed about (0,0,0) and moved to (0.3,-0.2,-0.4) equal those Capytaine computes about that
    point (radiation 1e-6 of the largest entry, excitation likewise, buoyancy stiffness 1e-9 rho g), and moving
    back is the identity to 1e-12."""
    mesh = mesh_cylinder(1.0, 1.5, n_radial=3, n_vertical=5, n_theta=12)
    kw = dict(omega=np.array([1.0, 2.0]), wave_direction=[0.3], rho=RHO, g=G, cache_dir=tmp_path)
    p = np.array([0.3, -0.2, -0.4])
    about_o = compute_coefficients(mesh, rotation_center=(0, 0, 0), **kw)
    about_p = compute_coefficients(mesh, rotation_center=p, **kw)
    moved = transform_reference(about_o, p)
    for var in ("added_mass", "radiation_damping", "added_mass_inf", "excitation_force"):
        scale = np.abs(about_p[var].values).max()
        np.testing.assert_allclose(moved[var].values, about_p[var].values, atol=1e-6 * scale, err_msg=var)
    np.testing.assert_allclose(moved.hydrostatic_stiffness.values, about_p.hydrostatic_stiffness.values,
                               atol=1e-9 * RHO * G)
    back = transform_reference(moved, (0, 0, 0))
    for var in ("added_mass", "excitation_force", "hydrostatic_stiffness"):
        np.testing.assert_allclose(back[var].values, about_o[var].values, atol=1e-12 * np.abs(about_o[var]).max())


def test_two_body_set(tmp_path):
    """Two cylinders (12-gons) side by side: 12 x 12 matrices with body-major Capytaine labels, non-zero coupling
    between the bodies, hydrostatics block diagonal with each body's waterplane, volumes of the 12-gon prisms
    (3.0 and 1.5 m^3, exact for the polygons)."""
    a = mesh_cylinder(1.0, 1.0, n_radial=3, n_vertical=4, n_theta=12)
    b = mesh_cylinder(0.5, 2.0, n_radial=3, n_vertical=6, n_theta=12).translated((3.0, 0, 0))
    ds = compute_coefficients([a, b], omega=[0.5, 1.0, 2.0], rho=RHO, g=G, rotation_center=[[0, 0, 0], [3, 0, 0]],
                              cache_dir=tmp_path)
    labels = list(ds.influenced_dof.values)
    assert labels[:2] == ["body1__Surge", "body1__Sway"] and labels[8] == "body2__Heave"
    A = matrix(ds.added_mass)
    assert np.all(np.abs(A[:, 2, 8]) > 1e-3 * np.sqrt(A[:, 2, 2] * A[:, 8, 8]))
    C = matrix(ds.hydrostatic_stiffness)
    assert np.all(C[:6, 6:] == 0) and np.all(C[6:, :6] == 0)
    assert C[2, 2] == pytest.approx(RHO * G * 3.0, rel=1e-9) and C[8, 8] == pytest.approx(RHO * G * 0.75, rel=1e-9)
    np.testing.assert_allclose(ds.displaced_volume.values, [3.0, 1.5], rtol=1e-9)
    np.testing.assert_allclose(ds.center_of_buoyancy.values[1], [3.0, 0.0, -1.0], atol=1e-9)
