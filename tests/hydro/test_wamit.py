"""WAMIT reader/writer: RM3 sanity, write/read round trip, scaling exponents, conventions, error messages."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

from moorline.hydro import HydroFileError, check_coefficients, matrix, read_wamit, write_wamit

from .conftest import data_file

RHO, G = 1000.0, 9.81


def test_rm3_shapes_and_reference_points(rm3):
    assert rm3.sizes["omega"] == 260 and rm3.sizes["influenced_dof"] == 12
    assert list(rm3.body.values) == ["body1", "body2"]
    np.testing.assert_allclose(rm3.rotation_center.values[:, 2], [-0.72, -21.29])
    np.testing.assert_allclose(rm3.displaced_volume.values, [725.833, 886.688], rtol=1e-5)
    assert np.all(np.diff(rm3.omega.values) > 0)
    np.testing.assert_allclose(rm3.omega.values[[0, -1]], [0.02, 5.2], rtol=1e-5)


def test_rm3_symmetry_and_positive_damping(rm3):
    """Heave-related terms are symmetric to 1 % of sqrt(|M_ii M_jj|) (BEM precision); the file's surge-pitch and
    sway-roll couplings are not (e.g. A(1,5) = 1.312e6 vs A(5,1) = 0.899e6 kg m at 0.02 rad/s) and
    check_coefficients must say so. Diagonal damping >= -0.5 % of its peak except yaw, which is solver noise for
    these axisymmetric hulls (the data dip below zero near 5 rad/s, by at most 0.32 % of the peak, float heave)."""
    for var in ("added_mass", "radiation_damping"):
        m = matrix(rm3[var])
        peak = np.abs(np.einsum("kii->ki", m)).max(axis=0)
        for i, j in ((2, 8), (2, 3), (2, 4), (8, 9), (8, 10)):
            err = np.abs(m[:, i, j] - m[:, j, i]).max() / np.sqrt(peak[i] * peak[j])
            assert err < 1e-2, (var, i, j, err)
    b = np.einsum("kii->ki", matrix(rm3.radiation_damping))[:, [0, 1, 2, 3, 4, 6, 7, 8, 9, 10]]
    assert np.all(b >= -5e-3 * np.abs(b).max(axis=0))
    warnings = check_coefficients(rm3)
    assert any("added_mass not symmetric" in w for w in warnings)


def test_rm3_long_wave_heave_excitation_and_phase_convention(rm3):
    """Long waves: heave force -> rho g A_wp in phase with the elevation at the body centre (x = 0 here), to 0.1 %
    for the float and 1.5 % for the spar (its deep plate diffracts). Heave alone cannot tell conjugates apart
    (phase -> 0 either way); surge does: F1 = (m_d + A11) du/dt leads the elevation by 90 deg, i.e. a phase of
    -90 deg in Capytaine's exp(-i w t) (WAMIT's file says +90.03)."""
    X = rm3.excitation_force.isel(omega=0, wave_direction=0).values
    C = matrix(rm3.hydrostatic_stiffness)
    for i, tol in ((2, 1e-3), (8, 1.5e-2)):
        awp = C[i, i] / (RHO * G)
        assert abs(abs(X[i]) / (RHO * G * awp) - 1) < tol
        assert abs(np.angle(X[i], deg=True)) < 0.1
    assert np.angle(X[0], deg=True) == pytest.approx(-90.0, abs=0.1)
    assert np.angle(X[6], deg=True) == pytest.approx(-90.0, abs=0.5)


def test_rm3_waterplane_stiffness_against_geometry(rm3):
    """C33 = rho g A_wp with A_wp = -int n_z dS over the wetted part of the float STL (display mesh, outward
    normals): agreement within 0.5 % (the WAMIT panels and the STL facets approximate the same circles)."""
    pytest.importorskip("meshio")
    from moorline.hydro.bem import meshio_read

    with warnings.catch_warnings():
        # an ASCII STL: meshio's test for a binary file overflows on it, which meshio_read silences
        warnings.simplefilter("error", RuntimeWarning)
        m = meshio_read(data_file("rm3/float.stl"))
    tri = m.points[np.concatenate([c.data for c in m.cells if c.type == "triangle"])]
    area_nz = 0.0
    for p in tri:
        z = p[:, 2]
        if np.all(z >= 0):
            continue
        # clip the triangle to z <= 0 (Sutherland-Hodgman against one plane)
        poly = []
        for k in range(3):
            a, b = p[k], p[(k + 1) % 3]
            if a[2] <= 0:
                poly.append(a)
            if (a[2] < 0) != (b[2] < 0) and a[2] != b[2]:
                poly.append(a + (b - a) * (-a[2] / (b[2] - a[2])))
        poly = np.array(poly)
        for k in range(1, len(poly) - 1):
            area_nz += 0.5 * np.cross(poly[k] - poly[0], poly[k + 1] - poly[0])[2]
    awp = abs(area_nz)
    c33 = matrix(rm3.hydrostatic_stiffness)[0 + 2, 2]
    assert c33 / (RHO * G) == pytest.approx(awp, rel=5e-3)


def test_write_read_round_trip(rm3, tmp_path):
    """write_wamit then read_wamit returns the same coefficients to 1e-6 relative (7 significant digits written)."""
    write_wamit(rm3, tmp_path / "rt")
    back = read_wamit(tmp_path / "rt", rho=RHO, g=G)
    for var in ("added_mass", "radiation_damping", "added_mass_inf", "added_mass_zero", "hydrostatic_stiffness",
                "excitation_force"):
        a, b = rm3[var].values, back[var].values
        np.testing.assert_allclose(b, a, rtol=1e-6, atol=1e-6 * np.abs(a).max(), err_msg=var)
    np.testing.assert_allclose(back.omega.values, rm3.omega.values, rtol=1e-6)
    np.testing.assert_allclose(back.rotation_center.values, rm3.rotation_center.values)
    np.testing.assert_allclose(back.displaced_volume.values, rm3.displaced_volume.values, rtol=1e-6)


def _write(path, text):
    path.write_text(text)
    return path


def _small_set(tmp_path, *, per=2.0, extra1="", hst=""):
    """One body, one period, all DOFs present: Abar = 1 on the diagonal plus (1,5) = (5,1) = 0.5."""
    rows = []
    for i in range(1, 7):
        rows.append(f"{per} {i} {i} 1.0 2.0")
    rows.append(f"{per} 1 5 0.5 0.25")
    rows.append(f"{per} 5 1 0.5 0.25")
    for p in (-1.0, 0.0):
        for i in range(1, 7):
            rows.append(f"{p} {i} {i} 1.0")
    _write(tmp_path / "s.1", "header line\n" + "\n".join(rows) + extra1 + "\n")
    exc = [f"{per} 0.0 {i} 1.0 30.0 0.8660254 0.5" for i in range(1, 7)]
    _write(tmp_path / "s.3", "\n".join(exc) + "\n")
    _write(tmp_path / "s.hst", hst or "3 3 2.0\n4 4 3.0\n5 5 3.0\n3 5 1.0\n5 3 1.0\n")
    return tmp_path / "s"


def test_scaling_exponents_by_hand(tmp_path):
    """L = 2 m, rho = 1000, g = 10, w = 2 pi / 2 s: A11 = 1 rho L^3 = 8000, A15 = 0.5 rho L^4 = 8000,
    A55 = rho L^5 = 32000; B11 = 2 rho w L^3, B15 = 0.25 rho w L^4; X1 = conj(0.866 + 0.5 i) rho g L^2,
    X5 = ... L^3; C33 = 2 rho g L^2, C35 = rho g L^3, C55 = 3 rho g L^4 (hand-computed)."""
    stem = _small_set(tmp_path)
    ds = read_wamit(stem, rho=1000.0, g=10.0, length_scale=2.0, reference_point=(0, 0, 0), cog=(0, 0, 0))
    w = np.pi
    A = matrix(ds.added_mass)[0]
    B = matrix(ds.radiation_damping)[0]
    assert ds.omega.values[0] == pytest.approx(w)
    assert A[0, 0] == pytest.approx(8000.0) and A[0, 4] == pytest.approx(8000.0) and A[4, 4] == pytest.approx(32000.0)
    assert B[0, 0] == pytest.approx(2 * 1000 * w * 8) and B[0, 4] == pytest.approx(0.25 * 1000 * w * 16)
    X = ds.excitation_force.values[0, 0]
    assert X[0] == pytest.approx((0.8660254 - 0.5j) * 1000 * 10 * 4)
    assert X[4] == pytest.approx((0.8660254 - 0.5j) * 1000 * 10 * 8)
    C = matrix(ds.hydrostatic_stiffness)
    assert C[2, 2] == pytest.approx(2 * 1000 * 10 * 4)
    assert C[2, 4] == pytest.approx(1000 * 10 * 8)
    assert C[4, 4] == pytest.approx(3 * 1000 * 10 * 16)
    assert matrix(ds.added_mass_inf)[4, 4] == pytest.approx(32000.0)


def test_weight_terms_removed(tmp_path):
    """A WAMIT .hst made with a centre of gravity z_g = -2 m below the reference point holds C44 = rho g (Iwp +
    V z_b) - m g z_g; reading with that CG and mass returns the buoyancy part (difference m g z_g exactly)."""
    stem = _small_set(tmp_path)
    plain = read_wamit(stem, rho=1000.0, g=10.0, reference_point=(0, 0, -1.0), cog=(0, 0, -1.0), mass=5000.0)
    low = read_wamit(stem, rho=1000.0, g=10.0, reference_point=(0, 0, -1.0), cog=(1.0, 0.5, -3.0), mass=5000.0)
    d = matrix(low.hydrostatic_stiffness) - matrix(plain.hydrostatic_stiffness)
    mg = 5000.0 * 10.0
    assert d[3, 3] == pytest.approx(mg * -2.0) and d[4, 4] == pytest.approx(mg * -2.0)
    assert d[3, 5] == pytest.approx(-mg * 1.0) and d[4, 5] == pytest.approx(-mg * 0.5)
    assert np.count_nonzero(np.abs(d) > 1e-9) == 4


def test_error_missing_dof(tmp_path):
    stem = _small_set(tmp_path)
    text = (tmp_path / "s.1").read_text().splitlines()
    (tmp_path / "s.1").write_text("\n".join(r for r in text if not r.split()[1:3] == ["6", "6"]) + "\n")
    with pytest.raises(HydroFileError, match=r"s\.1.*DOF 6 \(body 1 Yaw\) absent"):
        read_wamit(stem, reference_point=(0, 0, 0))


def test_error_nan(tmp_path):
    stem = _small_set(tmp_path)
    text = (tmp_path / "s.1").read_text().replace("2.0 3 3 1.0 2.0", "2.0 3 3 nan 2.0")
    (tmp_path / "s.1").write_text(text)
    with pytest.raises(HydroFileError, match=r"s\.1, line 4: non-finite"):
        read_wamit(stem, reference_point=(0, 0, 0))


def test_error_non_monotonic_periods(tmp_path):
    stem = _small_set(tmp_path)
    rows = []
    for per in (3.0, 1.0, 2.0):
        rows += [f"{per} {i} {i} 1.0 2.0" for i in range(1, 7)]
    (tmp_path / "s.1").write_text("\n".join(rows) + "\n")
    with pytest.raises(HydroFileError, match=r"s\.1, line 13: periods not monotonic"):
        read_wamit(stem, reference_point=(0, 0, 0))


def test_error_malformed_row(tmp_path):
    stem = _small_set(tmp_path)
    (tmp_path / "s.hst").write_text("3 3 2.0\n4 4\n")
    with pytest.raises(HydroFileError, match=r"s\.hst, line 2: malformed row: expected I J Cbar"):
        read_wamit(stem, reference_point=(0, 0, 0))


def test_period_column_auto_frequency(tmp_path):
    """A file whose first column is frequency is recognised from the zero/infinite limits when told 'auto'."""
    stem = _small_set(tmp_path)
    ds_p = read_wamit(stem, reference_point=(0, 0, 0), period_column="period")
    ds_f = read_wamit(stem, reference_point=(0, 0, 0), period_column="frequency")
    assert ds_p.omega.values[0] == pytest.approx(np.pi) and ds_f.omega.values[0] == pytest.approx(2.0)


def test_volturnus_reads_and_hydrostatics():
    """VolturnUS-S: 36 headings (-180 and 180 merged), passes check_coefficients. Its README says the CG was put at
    the origin so the .hst holds no gravity terms: C44 must equal rho g (I_wp,yy + V z_b), buoyancy only, computed
    from the WAMIT panel mesh (IEA-15-240-RWT.gdf) by surface integrals (I_wp,yy = -int y^2 n_z dS,
    V z_b = int z^2/2 n_z dS over the wetted hull): agreement within 1 %. The platform's weight moment
    m g z_g (ElastoDyn: 1.7838e7 kg at z = -14.94 m) is 1.2 times C44, so a .hst with weight terms would fail."""
    stem = data_file("volturnus_s/IEA-15-240-RWT-UMaineSemi.1").with_suffix("")
    # no .out in this set: the volume is HydroDyn's PtfmVol0, the centre of buoyancy from the panel mesh below
    ds = read_wamit(stem, rho=1025.0, g=9.80665, cog=(0.0, 0.0, 0.0), reference_point=(0, 0, 0),
                    displaced_volume=20206.34889, center_of_buoyancy=(0.0, 0.0, -13.63))
    assert ds.sizes["wave_direction"] == 36 and ds.sizes["omega"] > 50
    check_coefficients(ds)
    assert "[[0.0, 0.0, 0.0, 0.0]]" in ds.attrs["weight_terms_removed"].replace("-0.0", "0.0")
    from moorline.hydro.bem import read_gdf
    v, f = read_gdf(data_file("volturnus_s/IEA-15-240-RWT.gdf"))
    vol = iyy = vzb = 0.0
    for q in v[f]:
        if q[:, 2].max() > 1e-6 or np.abs(q[:, 2]).max() < 1e-6:
            continue  # above water, or a panel of the interior free-surface lid (the file includes one)
        for a, b, c in (q[[0, 1, 2]], q[[0, 2, 3]]):
            nz = 0.5 * np.cross(b - a, c - a)[2]
            sq = (a ** 2 + b ** 2 + c ** 2 + a * b + b * c + c * a) / 6  # mean of x_k^2 over the triangle
            vol += nz * (a[2] + b[2] + c[2]) / 3
            iyy -= nz * sq[1]
            vzb += nz * sq[2] / 2
    sign = np.sign(vol)
    vol, iyy, vzb = sign * vol, sign * iyy, sign * vzb
    assert vol == pytest.approx(20206.3, rel=1e-2)
    assert vzb / vol == pytest.approx(-13.63, abs=0.05)
    c44 = matrix(ds.hydrostatic_stiffness)[3, 3] / (1025.0 * 9.80665)
    assert c44 == pytest.approx(iyy + vzb, rel=1e-2)
    assert 1.7838e7 * 14.94 / 1025.0 > c44
