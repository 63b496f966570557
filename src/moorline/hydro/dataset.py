"""The coefficient Dataset: its schema, builder, checks and the rigid-body change of reference point.

Schema (names and meanings are Capytaine's, so a Capytaine result passes straight in; see docs/hydro.md):

======================  ==============================================  =====================================
variable                dims                                            units
======================  ==============================================  =====================================
added_mass              (omega, radiating_dof, influenced_dof)          kg, kg m, kg m^2
radiation_damping       (omega, radiating_dof, influenced_dof)          kg/s, kg m/s, kg m^2/s
added_mass_inf          (radiating_dof, influenced_dof)                 as added_mass (omega -> infinity)
added_mass_zero         (radiating_dof, influenced_dof), optional       as added_mass (omega -> 0)
excitation_force        (omega, wave_direction, influenced_dof)         N, N m per m of wave amplitude
Froude_Krylov_force     same, optional                                  same
diffraction_force       same, optional                                  same
hydrostatic_stiffness   (influenced_dof, radiating_dof)                 N/m, N/rad, N m/m, N m/rad
displaced_volume        (body,)                                         m^3
center_of_buoyancy      (body, space_coordinate)                        m, global frame
rotation_center         coordinate (body, space_coordinate)             m, global frame
======================  ==============================================  =====================================

``added_mass.sel(radiating_dof=j, influenced_dof=i)`` is A_ij: the force (or moment) on DOF ``i`` per unit
acceleration of DOF ``j``, so the matrix in ``F = -A a`` is ``added_mass.transpose(..., "influenced_dof",
"radiating_dof")``. Capytaine 3.0 stores the same labels in the order (omega, influenced_dof, radiating_dof);
the labels, not the axis order, carry the meaning. ``hydrostatic_stiffness`` is the buoyancy/waterplane part
only: no weight terms (moorline applies each body's weight at its centre of gravity).

Complex amplitudes follow Capytaine: a quantity ``X`` means ``Re{X exp(-i omega t)}``; WAMIT's is the
conjugate. ``rho`` [kg/m^3], ``g`` [m/s^2] and ``water_depth`` [m, inf allowed] are scalar coordinates.
"""

from __future__ import annotations

import hashlib
import logging
from pathlib import Path

import numpy as np
import xarray as xr

log = logging.getLogger("moorline.hydro")

RIGID_DOFS = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")
SPACE = ("x", "y", "z")
REQUIRED = ("added_mass", "radiation_damping", "added_mass_inf", "excitation_force", "hydrostatic_stiffness",
            "displaced_volume", "center_of_buoyancy")
CONVENTION = "Re{X exp(-i omega t)} (Capytaine); WAMIT's complex amplitudes are the conjugate"


class HydroFileError(ValueError):
    """A malformed or inconsistent coefficient file.

    The message names the file, the 1-based line number where known, and what was expected.
    """

    def __init__(self, message: str, *, file=None, line: int | None = None, row: str | None = None):
        self.file = str(file) if file is not None else None
        self.line = line
        where = ", ".join(w for w in (self.file, f"line {line}" if line is not None else None) if w)
        text = f"{where}: {message}" if where else message
        if row is not None:
            text += f"\n    {row.strip()}"
        super().__init__(text)


def dof_labels(body_names) -> list[str]:
    """DOF labels in moorline's order (body-major, six per body).

    One body gives ``Surge ... Yaw``; several give Capytaine's ``<body>__Surge`` style.
    """
    names = list(body_names)
    if len(names) == 1:
        return list(RIGID_DOFS)
    return [f"{b}__{d}" for b in names for d in RIGID_DOFS]


def dof_body_index(ds: xr.Dataset) -> np.ndarray:
    """Body index (into ``ds.body``) of each influenced DOF, shape (n_dof,)."""
    bodies = [str(b) for b in ds["body"].values]
    out = []
    for lab in ds["influenced_dof"].values:
        lab = str(lab)
        if "__" in lab:
            out.append(bodies.index(lab.rsplit("__", 1)[0]))
        else:
            out.append(0)
    return np.asarray(out, dtype=np.int64)


def is_rotation(labels) -> np.ndarray:
    """True for roll/pitch/yaw labels, shape (n_dof,)."""
    return np.array([str(lab).rsplit("__", 1)[-1] in ("Roll", "Pitch", "Yaw") for lab in labels])


def matrix(da: xr.DataArray) -> np.ndarray:
    """The (..., influenced, radiating) numpy array of a radiation or stiffness DataArray, i.e. the matrix
    M with ``F_i = -M_ij x_j``."""
    dims = [d for d in da.dims if d not in ("influenced_dof", "radiating_dof")] + ["influenced_dof", "radiating_dof"]
    return da.transpose(*dims).values


def file_digest(paths) -> str:
    """SHA-256 of the concatenated bytes of existing files (provenance)."""
    h = hashlib.sha256()
    for p in paths:
        p = Path(p)
        if p.is_file():
            h.update(p.read_bytes())
    return h.hexdigest()


def _version() -> str:
    try:
        from moorline import __version__
        return __version__
    except Exception:  # pragma: no cover - only during a broken install
        return "unknown"


def build_dataset(*, omega, wave_direction, body_names, added_mass, radiation_damping, added_mass_inf,
                  excitation_force, hydrostatic_stiffness, displaced_volume, center_of_buoyancy, rotation_center,
                  rho, g, water_depth, added_mass_zero=None, froude_krylov_force=None, diffraction_force=None,
                  attrs=None) -> xr.Dataset:
    """Assemble a coefficient Dataset from plain arrays.

    Parameters
    ----------
    omega : array, shape (n_w,)
        Circular frequencies [rad/s], finite, > 0, strictly increasing.
    wave_direction : array, shape (n_b,)
        Directions the waves travel toward [rad], from +x toward +y.
    body_names : sequence of str, length n_body
    added_mass, radiation_damping : arrays, shape (n_w, n_dof, n_dof)
        Matrices in ``[k, i, j]`` = force i per motion j (influenced, radiating) order.
    added_mass_inf : array, shape (n_dof, n_dof), same [i, j] order.
    excitation_force : complex array, shape (n_w, n_b, n_dof)
        Per unit wave amplitude, Capytaine's exp(-i omega t) convention.
    hydrostatic_stiffness : array, shape (n_dof, n_dof), [i, j] = force i per displacement j, buoyancy only.
    displaced_volume : array, shape (n_body,) [m^3]
    center_of_buoyancy, rotation_center : arrays, shape (n_body, 3) [m], global frame.
    rho, g, water_depth : float
    added_mass_zero : array (n_dof, n_dof), optional
    froude_krylov_force, diffraction_force : complex arrays like excitation_force, optional
    attrs : dict, optional
        Provenance and notes.

    Returns
    -------
    xarray.Dataset
    """
    labels = dof_labels(body_names)
    n = len(labels)

    def rad(a):  # [.., i, j] -> dims (.., radiating j, influenced i)
        return np.swapaxes(np.asarray(a, dtype=float), -1, -2)

    coords = {
        "omega": ("omega", np.asarray(omega, dtype=float), {"units": "rad/s"}),
        "wave_direction": ("wave_direction", np.asarray(wave_direction, dtype=float),
                           {"units": "rad", "long_name": "direction the waves travel toward, from +x toward +y"}),
        "radiating_dof": ("radiating_dof", labels),
        "influenced_dof": ("influenced_dof", labels),
        "body": ("body", [str(b) for b in body_names]),
        "space_coordinate": ("space_coordinate", list(SPACE)),
        "rotation_center": (("body", "space_coordinate"), np.asarray(rotation_center, dtype=float).reshape(-1, 3),
                            {"units": "m", "long_name": "reference point the coefficients are about"}),
        "rho": ((), float(rho), {"units": "kg/m^3"}),
        "g": ((), float(g), {"units": "m/s^2"}),
        "water_depth": ((), float(water_depth), {"units": "m"}),
    }
    rad_dims = ("omega", "radiating_dof", "influenced_dof")
    mat_dims = ("radiating_dof", "influenced_dof")
    exc_dims = ("omega", "wave_direction", "influenced_dof")
    data = {
        "added_mass": (rad_dims, rad(added_mass)),
        "radiation_damping": (rad_dims, rad(radiation_damping)),
        "added_mass_inf": (mat_dims, rad(added_mass_inf)),
        "excitation_force": (exc_dims, np.asarray(excitation_force, dtype=complex)),
        "hydrostatic_stiffness": (("influenced_dof", "radiating_dof"), np.asarray(hydrostatic_stiffness, dtype=float)),
        "displaced_volume": (("body",), np.asarray(displaced_volume, dtype=float).reshape(-1)),
        "center_of_buoyancy": (("body", "space_coordinate"),
                               np.asarray(center_of_buoyancy, dtype=float).reshape(-1, 3)),
    }
    if added_mass_zero is not None:
        data["added_mass_zero"] = (mat_dims, rad(added_mass_zero))
    if froude_krylov_force is not None:
        data["Froude_Krylov_force"] = (exc_dims, np.asarray(froude_krylov_force, dtype=complex))
    if diffraction_force is not None:
        data["diffraction_force"] = (exc_dims, np.asarray(diffraction_force, dtype=complex))
    ds = xr.Dataset(data, coords=coords)
    if ds.sizes["influenced_dof"] != n:
        raise ValueError(f"expected {n} DOFs for bodies {list(body_names)}, got {ds.sizes['influenced_dof']}")
    units = {"added_mass": "kg (translation), kg m (coupling), kg m^2 (rotation)",
             "radiation_damping": "kg/s, kg m/s, kg m^2/s", "added_mass_inf": "as added_mass",
             "added_mass_zero": "as added_mass", "excitation_force": "N or N m per m of wave amplitude",
             "Froude_Krylov_force": "N or N m per m", "diffraction_force": "N or N m per m",
             "hydrostatic_stiffness": "N/m, N/rad, N m/m, N m/rad (buoyancy and waterplane only)",
             "displaced_volume": "m^3", "center_of_buoyancy": "m"}
    for k, u in units.items():
        if k in ds:
            ds[k].attrs["units"] = u
    ds.attrs.update({"convention": CONVENTION,
                     "hydrostatics": "buoyancy and waterplane terms only; weight terms excluded",
                     "moorline_version": _version()})
    if attrs:
        ds.attrs.update({k: v for k, v in attrs.items() if v is not None})
    return ds


def check_coefficients(ds: xr.Dataset, *, sym_rtol: float = 1e-2, psd_rtol: float = 1e-3) -> list[str]:
    """Validate a coefficient Dataset.

    Hard errors (a ValueError listing every problem): missing variables or dims, non-finite values,
    frequencies not finite, not > 0 or not strictly increasing, wrong shapes.
    Warnings (logged, and returned): asymmetry of A(w), B(w), A_inf beyond ``sym_rtol`` times the largest
    diagonal-scaled entry, and negative eigenvalues of B(w) below ``-psd_rtol`` times its largest eigenvalue
    (small BEM noise is expected; large ones point at a wrong file or convention).

    Parameters
    ----------
    ds : xarray.Dataset
    sym_rtol : float
        Tolerance on ``|M_ij - M_ji| / sqrt(|M_ii| |M_jj|)`` [-].
    psd_rtol : float
        Tolerance on ``-lambda_min(B) / lambda_max(B)`` at each frequency [-].

    Returns
    -------
    list of str
        The warnings issued.
    """
    errors: list[str] = []
    warnings: list[str] = []
    for dim in ("omega", "wave_direction", "radiating_dof", "influenced_dof", "body"):
        if dim not in ds.dims:
            errors.append(f"dimension '{dim}' missing")
    for var in REQUIRED:
        if var not in ds:
            errors.append(f"variable '{var}' missing")
    for c in ("rho", "g", "water_depth", "rotation_center"):
        if c not in ds.coords:
            errors.append(f"coordinate '{c}' missing")
    if errors:
        raise ValueError("coefficient Dataset invalid:\n  " + "\n  ".join(errors))
    w = ds["omega"].values
    if not np.all(np.isfinite(w)) or np.any(w <= 0):
        errors.append("omega must be finite and > 0 (zero and infinite limits go to added_mass_zero/_inf)")
    elif np.any(np.diff(w) <= 0):
        k = int(np.argmax(np.diff(w) <= 0))
        errors.append(f"omega not strictly increasing at index {k + 1}: {w[k]} then {w[k + 1]} rad/s")
    if list(ds["radiating_dof"].values) != list(ds["influenced_dof"].values):
        errors.append("radiating_dof and influenced_dof labels differ")
    for var in list(REQUIRED) + ["added_mass_zero", "Froude_Krylov_force", "diffraction_force", "rotation_center"]:
        if var in ds and not np.all(np.isfinite(ds[var].values)):
            bad = np.argwhere(~np.isfinite(np.asarray(ds[var].values)))[0]
            errors.append(f"'{var}' has non-finite values (first at index {tuple(int(b) for b in bad)})")
    if not (np.isfinite(float(ds["rho"])) and float(ds["rho"]) > 0 and float(ds["g"]) > 0):
        errors.append("rho and g must be finite and > 0")
    if float(ds["water_depth"]) <= 0 or np.isnan(float(ds["water_depth"])):
        errors.append("water_depth must be > 0 (inf for deep water)")
    if errors:
        raise ValueError("coefficient Dataset invalid:\n  " + "\n  ".join(errors))

    labels = list(ds["influenced_dof"].values)
    for var in ("added_mass", "radiation_damping", "added_mass_inf"):
        m = matrix(ds[var]).reshape(-1, len(labels), len(labels))
        d = np.sqrt(np.abs(np.einsum("kii->ki", m)))
        scale = np.maximum(d[:, :, None] * d[:, None, :], 1e-300)
        asym = np.abs(m - np.swapaxes(m, 1, 2)) / scale
        # entries whose diagonals are pure noise (e.g. yaw of an axisymmetric body) are judged on the max scale
        big = scale >= 1e-9 * scale.max(axis=(1, 2), keepdims=True)
        asym = np.where(big, asym, 0.0)
        worst = float(asym.max()) if asym.size else 0.0
        if worst > sym_rtol:
            k, i, j = np.unravel_index(int(np.argmax(asym)), asym.shape)
            where = f" at omega = {ds['omega'].values[k]:.4g} rad/s" if var != "added_mass_inf" else ""
            warnings.append(f"{var} not symmetric{where}: ({labels[i]}, {labels[j]}) differs from its transpose by "
                            f"{worst:.3g} of sqrt(|M_ii M_jj|) (tolerance {sym_rtol})")
    bmat = matrix(ds["radiation_damping"])
    bsym = 0.5 * (bmat + np.swapaxes(bmat, 1, 2))
    eig = np.linalg.eigvalsh(bsym)
    lmax = np.maximum(eig[:, -1], 1e-300)
    ratio = -eig[:, 0] / lmax
    if ratio.max() > psd_rtol:
        k = int(np.argmax(ratio))
        warnings.append(f"radiation_damping not positive semi-definite at omega = {ds['omega'].values[k]:.4g} rad/s: "
                        f"lambda_min = {eig[k, 0]:.3g}, {ratio[k]:.3g} of lambda_max (tolerance {psd_rtol})")
    diag_b = np.einsum("kii->ki", bmat)
    if np.any(diag_b < -psd_rtol * np.abs(diag_b).max(axis=0, initial=0.0)):
        k, i = np.unravel_index(int(np.argmin(diag_b)), diag_b.shape)
        warnings.append(f"negative diagonal damping {labels[i]} = {diag_b[k, i]:.3g} at omega = "
                        f"{ds['omega'].values[k]:.4g} rad/s")
    for msg in warnings:
        log.warning("check_coefficients: %s", msg)
    return warnings


def skew(r) -> np.ndarray:
    """Cross-product matrix [r]x with [r]x v = r x v, shape (3, 3)."""
    x, y, z = r
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


def reference_transform(old_points, new_points) -> np.ndarray:
    """Motion transformation T with x_old = T x_new for rigid bodies, block diagonal, shape (6N, 6N).

    Translation at the old point u_O = u_P + r x theta with r = P - O; forces transform with T^T
    (f_P = T^T f_O: the moment about P is M_O - r x F).
    """
    old = np.asarray(old_points, dtype=float).reshape(-1, 3)
    new = np.asarray(new_points, dtype=float).reshape(-1, 3)
    n = old.shape[0]
    t = np.eye(6 * n)
    for b in range(n):
        t[6 * b:6 * b + 3, 6 * b + 3:6 * b + 6] = skew(new[b] - old[b])
    return t


def transform_reference(ds: xr.Dataset, new_points) -> xr.Dataset:
    """Rigid-body transformation of all coefficients to new reference points (one per body).

    Radiation matrices and the excitation vector transform by congruence (A_P = T^T A_O T, X_P = T^T X_O,
    see :func:`reference_transform`); phases stay relative to the incident wave at the global origin.
    The buoyancy stiffness is congruent in its waterplane part but its static-buoyancy part depends on the
    point (the moment arm of rho g V turns with the body): C_P = T^T C_O T + rho g V D, with
    D_44 = D_55 = -(z_P - z_O), D_46 = x_P - x_O, D_56 = y_P - y_O (rows influenced, columns radiating),
    which reproduces rho g (V (z_b - z_P) + waterplane moments about P) and -rho g V (x_b - x_P).

    Parameters
    ----------
    ds : xarray.Dataset
    new_points : array, shape (3,) or (n_body, 3)
        New reference points [m], global frame.

    Returns
    -------
    xarray.Dataset
        A copy about the new points (``rotation_center`` updated).
    """
    old = ds["rotation_center"].values.reshape(-1, 3)
    new = np.broadcast_to(np.asarray(new_points, dtype=float).reshape(-1, 3), old.shape).copy()
    t = reference_transform(old, new)
    out = ds.copy(deep=True)

    def cong(da):
        m = matrix(da)
        m2 = np.einsum("ki,...kl,lj->...ij", t, m, t)
        dims = [d for d in da.dims if d not in ("influenced_dof", "radiating_dof")]
        res = xr.DataArray(m2, dims=dims + ["influenced_dof", "radiating_dof"],
                           coords={d: da[d] for d in da.dims})
        return res.transpose(*da.dims)

    for var in ("added_mass", "radiation_damping", "added_mass_inf", "added_mass_zero"):
        if var in ds:
            out[var] = cong(ds[var]).assign_attrs(ds[var].attrs)
    for var in ("excitation_force", "Froude_Krylov_force", "diffraction_force"):
        if var in ds:
            v = ds[var].transpose(..., "influenced_dof")
            out[var] = v.copy(data=np.einsum("ki,...k->...i", t, v.values)).transpose(*ds[var].dims)
    if "hydrostatic_stiffness" in ds:
        c = cong(ds["hydrostatic_stiffness"]).values
        rho_g = float(ds["rho"]) * float(ds["g"])
        vol = ds["displaced_volume"].values
        for b in range(old.shape[0]):
            dx, dy, dz = new[b] - old[b]
            o = 6 * b
            c[o + 3, o + 3] -= rho_g * vol[b] * dz
            c[o + 4, o + 4] -= rho_g * vol[b] * dz
            c[o + 3, o + 5] += rho_g * vol[b] * dx
            c[o + 4, o + 5] += rho_g * vol[b] * dy
        out["hydrostatic_stiffness"] = ds["hydrostatic_stiffness"].copy(data=c)
    out = out.assign_coords(rotation_center=(("body", "space_coordinate"), new))
    out["rotation_center"].attrs.update(ds["rotation_center"].attrs)
    return out
