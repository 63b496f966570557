"""Capytaine: reading its NetCDF/Datasets, simple hull meshes, and running it with an on-disk cache.

Capytaine is an optional dependency (``pip install "moorline[hydro]"``), imported only inside the functions that
need it. Results are turned into the moorline coefficient Dataset (:mod:`moorline.hydro.dataset`):
``omega = inf`` -> ``added_mass_inf``, ``omega = 0`` -> ``added_mass_zero``; hydrostatics are the buoyancy part
only (the body's centre of mass is put at its rotation centre, which zeroes Capytaine's weight terms
-m g (z_g - z_c) etc.; a Capytaine result computed with another centre of mass has those terms removed).
"""

from __future__ import annotations

import hashlib
import json
import logging
import os
import time
import warnings
from pathlib import Path

import numpy as np
import xarray as xr

from .dataset import build_dataset, dof_labels, file_digest

log = logging.getLogger("moorline.hydro")

_CACHE_FORMAT = 1


def _cpt():
    try:
        import capytaine
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError('Capytaine is needed for this: pip install "moorline[hydro]"') from e
    return capytaine


def _merge_complex(ds: xr.Dataset) -> xr.Dataset:
    if "complex" not in ds.dims:
        return ds
    ds = ds.copy()
    for v in list(ds.data_vars):
        if "complex" in ds[v].dims:
            da = ds[v]
            ds[v] = da.sel(complex="re", drop=True) + 1j * da.sel(complex="im", drop=True)
    return ds.drop_vars("complex")


def write_netcdf(ds: xr.Dataset, path) -> Path:
    """Write a coefficient Dataset to NetCDF, complex values split along a ``complex`` dim (Capytaine's layout)."""
    path = Path(path)
    out = ds.copy()
    for v in list(out.data_vars):
        if np.iscomplexobj(out[v].values):
            da = out[v]
            out[v] = xr.concat([da.real, da.imag], dim=xr.DataArray(["re", "im"], dims="complex", name="complex"))
    for c in ("radiating_dof", "influenced_dof", "body", "space_coordinate"):
        if c in out.coords:
            out = out.assign_coords({c: out[c].values.astype(str)})
    tmp = path.with_suffix(path.suffix + f".tmp{os.getpid()}")
    out.to_netcdf(tmp, engine="h5netcdf")
    os.replace(tmp, path)
    return path


def read_capytaine(path) -> xr.Dataset:
    """Read a NetCDF written by Capytaine (``cpt.export_dataset`` / ``separate_complex_values`` + ``to_netcdf``)
    or by :func:`write_netcdf`, and convert it with :func:`from_capytaine`."""
    path = Path(path)
    with xr.open_dataset(path) as raw:
        ds = _merge_complex(raw.load())
    out = from_capytaine(ds)
    out.attrs.setdefault("source_files", str(path))
    out.attrs["source_sha256"] = file_digest([path])
    return out


def _scalar(ds, name, default=None):
    if name not in ds.coords and name not in ds:
        if default is None:
            raise ValueError(f"Capytaine Dataset has no '{name}'")
        return default
    v = np.atleast_1d(ds[name].values)
    if v.size != 1:
        raise ValueError(f"'{name}' has {v.size} values: select one first (ds.sel({name}=...))")
    return float(v[0])


def from_capytaine(ds: xr.Dataset) -> xr.Dataset:
    """Convert a Capytaine result Dataset (in memory) to the moorline coefficient Dataset.

    Accepts Capytaine's layouts (3.x: added_mass (omega, influenced_dof, radiating_dof); 2.x: (omega,
    radiating_dof, influenced_dof)) and frequency dims omega or period. A Dataset already in moorline's form is
    returned as a copy.
    """
    if "added_mass_inf" in ds and "omega" in ds.dims and "body" in ds.dims:
        return ds.copy()
    ds = _merge_complex(ds)
    if "omega" not in ds.dims:
        for alt in ("period", "freq", "wavenumber", "wavelength"):
            if alt in ds.dims and "omega" in ds.coords:
                ds = ds.swap_dims({alt: "omega"})
                break
        else:
            raise ValueError("Capytaine Dataset has no omega dimension or coordinate")
    if "forward_speed" in ds.coords and np.any(np.atleast_1d(ds["forward_speed"].values) != 0):
        raise ValueError("forward speed must be zero")
    rho, g = _scalar(ds, "rho"), _scalar(ds, "g")
    depth = _scalar(ds, "water_depth", np.inf)
    for c in ("rho", "g", "water_depth", "forward_speed"):
        if c in ds.dims:
            ds = ds.squeeze(c)
    ds = ds.sortby("omega")
    labels = [str(x) for x in ds["influenced_dof"].values]
    if "body" in ds.coords and np.atleast_1d(ds["body"].values).size > 1:
        bodies = [str(b) for b in np.atleast_1d(ds["body"].values)]
    elif "__" in labels[0]:
        bodies = list(dict.fromkeys(lab.rsplit("__", 1)[0] for lab in labels))
    else:
        bodies = [str(np.atleast_1d(ds["body"].values)[0])] if "body" in ds.coords else ["body"]
    expect = dof_labels(bodies)
    if sorted(labels) != sorted(expect):
        raise ValueError(f"expected the six rigid-body DOFs per body {expect}, got {labels}")
    ds = ds.sel(influenced_dof=expect, radiating_dof=expect)
    w = ds["omega"].values
    finite = np.isfinite(w) & (w > 0)

    def mat(var, sel):
        return ds[var].sel(omega=sel).transpose(..., "influenced_dof", "radiating_dof").values

    A = mat("added_mass", w[finite])
    B = mat("radiation_damping", w[finite])
    a_inf = mat("added_mass", np.inf) if np.any(np.isinf(w)) else None
    a_zero = mat("added_mass", 0.0) if np.any(w == 0) else None
    if a_inf is None:
        from .irf import estimate_added_mass_inf
        log.warning("from_capytaine: no omega = inf result: added_mass_inf estimated by Ogilvie's relation")
        a_inf = estimate_added_mass_inf(w[finite], A, B)

    def exc(var):
        if var not in ds:
            return None
        return ds[var].sel(omega=w[finite]).transpose("omega", "wave_direction", "influenced_dof").values

    n_body = len(bodies)
    rc = ds["rotation_center"].values.reshape(-1, 3) if "rotation_center" in ds.coords else np.zeros((n_body, 3))
    if "hydrostatic_stiffness" in ds:
        C = ds["hydrostatic_stiffness"].transpose("influenced_dof", "radiating_dof").values.copy()
        vol = (np.atleast_1d(ds["disp_mass"].values).reshape(-1) / rho if "disp_mass" in ds
               else np.full(n_body, np.nan))
        cob = ds["center_of_buoyancy"].values.reshape(-1, 3) if "center_of_buoyancy" in ds else np.full((n_body, 3),
                                                                                                      np.nan)
        if "center_of_mass" in ds.coords:
            cog = ds["center_of_mass"].values.reshape(-1, 3)
            if "inertia_matrix" in ds:
                im = ds["inertia_matrix"].transpose("influenced_dof", "radiating_dof").values
                mass = np.array([im[6 * b, 6 * b] for b in range(n_body)])
            else:
                mass = rho * vol
            for b in range(n_body):
                rel = cog[b] - rc[b]
                mg = mass[b] * g
                o = 6 * b
                # Capytaine: C44, C55 include -m g (zg - zc); C46 +m g (xg - xc); C56 +m g (yg - yc) -> undo
                C[o + 3, o + 3] += mg * rel[2]
                C[o + 4, o + 4] += mg * rel[2]
                C[o + 3, o + 5] -= mg * rel[0]
                C[o + 4, o + 5] -= mg * rel[1]
    else:
        log.warning("from_capytaine: no hydrostatics in the Dataset: hydrostatic_stiffness, displaced_volume and "
                    "center_of_buoyancy set to NaN")
        C = np.full((6 * n_body, 6 * n_body), np.nan)
        vol = np.full(n_body, np.nan)
        cob = np.full((n_body, 3), np.nan)
    return build_dataset(
        omega=w[finite], wave_direction=ds["wave_direction"].values, body_names=bodies, added_mass=A,
        radiation_damping=B, added_mass_inf=a_inf, excitation_force=exc("excitation_force"),
        hydrostatic_stiffness=C, displaced_volume=vol, center_of_buoyancy=cob, rotation_center=rc, rho=rho, g=g,
        water_depth=depth, added_mass_zero=a_zero, froude_krylov_force=exc("Froude_Krylov_force"),
        diffraction_force=exc("diffraction_force"),
        attrs={"source": "Capytaine", "capytaine_version": ds.attrs.get("capytaine_version"),
               "added_mass_inf_source": "Capytaine omega = inf" if np.any(np.isinf(w)) else "Ogilvie estimate"})


# ------------------------------------------------------------------------------------------------ meshes
def mesh_axisymmetric(profile_r_z, *, n_theta: int = 24, name=None, symmetric: bool = True):
    """Axisymmetric hull from a meridian profile, as a Capytaine rotation-symmetric mesh.

    Parameters
    ----------
    profile_r_z : array (n, 2)
        (r, z) points [m] of the meridian, from the keel (r = 0 closes the bottom) up to the waterline or above.
    n_theta : int
        Panels around the axis.
    symmetric : bool
        Keep Capytaine's rotation symmetry (one wedge solved, the others by symmetry: a spar takes seconds).

    Returns
    -------
    capytaine mesh (clipped to z <= 0 later by :func:`compute_coefficients`).
    """
    cpt = _cpt()
    prof = np.asarray(profile_r_z, dtype=float)
    pts = np.column_stack([prof[:, 0], np.zeros(len(prof)), prof[:, 1]])
    mesh = cpt.RotationSymmetricMesh.from_profile_points(pts, n=n_theta, name=name)
    return mesh if symmetric else mesh.merged()


def mesh_hemisphere(radius: float = 1.0, *, n_meridian: int = 12, n_theta: int = 24, name="hemisphere"):
    """Floating hemisphere (centre on the still water line), rotation-symmetric panels."""
    th = np.linspace(0.0, np.pi / 2, n_meridian + 1)
    return mesh_axisymmetric(np.column_stack([radius * np.sin(th), -radius * np.cos(th)]), n_theta=n_theta, name=name)


def mesh_cylinder(radius: float, draft: float, *, n_radial: int = 6, n_vertical: int = 10, n_theta: int = 24,
                  freeboard: float = 0.0, name="cylinder"):
    """Vertical circular cylinder of given draft [m] (bottom disc plus wall up to ``freeboard`` [m])."""
    r = np.linspace(0.0, radius, n_radial + 1)
    z = np.linspace(-draft, freeboard, n_vertical + 1)
    prof = np.concatenate([np.column_stack([r, np.full_like(r, -draft)]),
                           np.column_stack([np.full(n_vertical, radius), z[1:]])])
    return mesh_axisymmetric(prof, n_theta=n_theta, name=name)


def load_mesh(path, *, name=None):
    """Read a hull mesh with meshio (STL, OBJ, VTK, MSH, ...) or WAMIT .gdf (moorline's reader).

    Returns a Capytaine ``Mesh`` [m], global frame (z up, still water line z = 0).
    """
    cpt = _cpt()
    path = Path(path)
    if path.suffix.lower() == ".gdf":
        verts, faces = read_gdf(path)
    else:
        m = meshio_read(path)
        verts = np.asarray(m.points, dtype=float)[:, :3]
        cells = [c.data for c in m.cells if c.type in ("triangle", "quad")]
        if not cells:
            raise ValueError(f"{path}: no triangle or quad cells")
        faces = [list(f) for c in cells for f in c]
    return cpt.Mesh(vertices=verts, faces=faces, name=name or path.stem)


def meshio_read(path):
    """``meshio.read(path)``, without the RuntimeWarning ("overflow encountered in scalar multiply")
    that meshio's STL reader gives on every ASCII STL. It tells a binary file from a text one by
    taking bytes 80-83 as a uint32 triangle count n and comparing 84 + 50 n with the file's size;
    on text that product overflows, the sizes differ, and it reads the file as text, correctly."""
    import meshio

    with warnings.catch_warnings():
        if Path(path).suffix.lower() == ".stl":
            warnings.filterwarnings("ignore", "overflow encountered in scalar multiply", RuntimeWarning)
        return meshio.read(path)


def read_gdf(path):
    """WAMIT low-order geometry (.gdf): header, ULEN GRAV, ISX ISY, NPAN, then 4 vertices per panel.

    Symmetry planes (ISX = 1: x = 0, ISY = 1: y = 0) are unfolded. A 4th number on a vertex line (a panel
    label, as some exporters write) is ignored.

    Returns
    -------
    vertices : array (4 n_panels', 3) [m] (times ULEN), faces : array (n_panels', 4)
    """
    path = Path(path)
    lines = path.read_text(errors="replace").splitlines()
    try:
        ulen = float(lines[1].split()[0])
        isx, isy = (int(float(v)) for v in lines[2].split()[:2])
        npan = int(float(lines[3].split()[0]))
    except (IndexError, ValueError) as e:
        from .dataset import HydroFileError
        raise HydroFileError(f"malformed GDF header ({e})", file=path) from None
    nums = []
    for n, ln in enumerate(lines[4:], start=5):
        if len(nums) >= 4 * npan:
            break
        toks = ln.split()
        if not toks:
            continue
        try:
            vals = [float(t) for t in toks]
        except ValueError:
            vals = []
        if len(vals) in (3, 4):
            nums.append(vals[:3])
        elif len(vals) % 3 == 0:
            nums.extend(np.reshape(vals, (-1, 3)).tolist())
        else:
            from .dataset import HydroFileError
            raise HydroFileError("expected vertex coordinates (3 numbers, optionally a label)", file=path, line=n,
                                 row=ln)
    v = np.asarray(nums, dtype=float)[: 4 * npan] * ulen
    if v.shape[0] != 4 * npan:
        from .dataset import HydroFileError
        raise HydroFileError(f"expected {npan} panels (4 vertices each), found {v.shape[0] / 4:g}", file=path)
    quads = v.reshape(npan, 4, 3)
    parts = [quads]
    if isx:
        parts += [q[:, ::-1] * np.array([-1, 1, 1]) for q in parts]
    if isy:
        parts += [q[:, ::-1] * np.array([1, -1, 1]) for q in parts]
    quads = np.concatenate(parts)
    return quads.reshape(-1, 3), np.arange(quads.shape[0] * 4).reshape(-1, 4)


# ------------------------------------------------------------------------------------------------ compute
def default_cache_dir() -> Path:
    """``$MOORLINE_CACHE`` if set, else ``~/.cache/moorline/hydro``."""
    env = os.environ.get("MOORLINE_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "moorline" / "hydro"


def _mesh_arrays(mesh):
    return np.asarray(mesh.vertices, dtype=float), np.asarray(mesh.faces, dtype=np.int64)


def cache_key(meshes, *, lids, omega, wave_direction, water_depth, rho, g, rotation_centers, names) -> str:
    """SHA-256 over everything that changes the answer (mesh vertices and faces, lids, frequencies, headings,
    depth, rho, g, rotation centres, body names, Capytaine version, cache format)."""
    cpt = _cpt()
    h = hashlib.sha256()
    for mesh, lid in zip(meshes, lids, strict=True):
        v, f = _mesh_arrays(mesh)
        h.update(np.round(v, 12).tobytes())
        h.update(f.tobytes())
        h.update(type(mesh).__name__.encode())
        h.update(repr(getattr(mesh, "n", None)).encode())
        h.update(repr(lid).encode())
    meta = {"omega": np.asarray(omega, float).tolist(), "beta": np.asarray(wave_direction, float).tolist(),
            "depth": float(water_depth), "rho": float(rho), "g": float(g),
            "rc": np.asarray(rotation_centers, float).tolist(), "names": list(names),
            "capytaine": cpt.__version__, "format": _CACHE_FORMAT}
    h.update(json.dumps(meta, sort_keys=True).encode())
    return h.hexdigest()


def compute_coefficients(meshes, *, omega, wave_direction=(0.0,), water_depth=np.inf, rho: float = 1025.0,
                         g: float = 9.81, rotation_center=None, names=None, lid=False, infinite_frequency=True,
                         cache_dir=None, use_cache: bool = True, n_jobs: int = 1) -> xr.Dataset:
    """Run Capytaine on one or several rigid hulls and return the coefficient Dataset (cached on disk).

    Parameters
    ----------
    meshes : mesh, path, or list of them
        Capytaine meshes (e.g. from :func:`mesh_axisymmetric`) or files for :func:`load_mesh`; clipped at z = 0
        (and the sea bed) here.
    omega : array
        Frequencies [rad/s] (finite, > 0).
    wave_direction : array
        Headings [rad].
    water_depth : float
        [m], inf for deep water.
    rho, g : float
    rotation_center : array (3,) or (n_body, 3), optional
        Reference points [m]; default the origin.
    names : list of str, optional
        Body names (default ``body1``...; one body keeps plain DOF labels).
    lid : bool or float or list
        Lid against irregular frequencies: False, True (at z = 0) or the z [m] of the lid (just below 0 is
        common), per body or for all. A rotation-symmetric hull is merged first (Capytaine 3.0.0 ignores a lid on
        a RotationSymmetricMesh without a word), so a lid costs the symmetry speed-up.
    infinite_frequency : bool
        Also solve omega = inf for added_mass_inf (Capytaine supports it in deep water; in finite depth the
        attempt is made and, if refused, A_inf is estimated by Ogilvie's relation with a warning).
    cache_dir : path, optional
        Default :func:`default_cache_dir`.
    use_cache : bool
    n_jobs : int
        Passed to Capytaine's ``fill_dataset``.

    Returns
    -------
    xarray.Dataset
    """
    cpt = _cpt()
    if not isinstance(meshes, (list, tuple)):
        meshes = [meshes]
    meshes = [load_mesh(m) if isinstance(m, (str, Path)) else m for m in meshes]
    n_body = len(meshes)
    names = list(names) if names is not None else ([getattr(meshes[0], "name", None) or "body1"] if n_body == 1
                                                   else [f"body{b + 1}" for b in range(n_body)])
    rc = np.zeros((n_body, 3)) if rotation_center is None else np.broadcast_to(
        np.asarray(rotation_center, dtype=float).reshape(-1, 3), (n_body, 3)).copy()
    lids = list(lid) if isinstance(lid, (list, tuple)) else [lid] * n_body
    omega = np.asarray(omega, dtype=float)
    if np.any(~np.isfinite(omega)) or np.any(omega <= 0):
        raise ValueError("omega must be finite and > 0 (the infinite-frequency solve is added by the function)")
    beta = np.atleast_1d(np.asarray(wave_direction, dtype=float))
    key = cache_key(meshes, lids=lids, omega=omega, wave_direction=beta, water_depth=water_depth, rho=rho, g=g,
                    rotation_centers=rc, names=names)
    cdir = Path(cache_dir) if cache_dir is not None else default_cache_dir()
    cfile = cdir / f"{key}.nc"
    if use_cache and cfile.is_file():
        t0 = time.perf_counter()
        ds = read_capytaine(cfile)
        ds.attrs["cache_key"] = key
        log.info("compute_coefficients: cache hit %s (%.3f s)", cfile, time.perf_counter() - t0)
        return ds
    log.info("compute_coefficients: cache miss %s: running Capytaine %s", key[:12], cpt.__version__)
    t0 = time.perf_counter()
    bodies = []
    for mesh, name, c, lid_b in zip(meshes, names, rc, lids, strict=True):
        hull = mesh.immersed_part(water_depth=None if np.isinf(water_depth) else water_depth)
        lid_mesh = None
        if lid_b is not False and lid_b is not None:
            z = 0.0 if lid_b is True else float(lid_b)
            if isinstance(hull, cpt.RotationSymmetricMesh):
                # Capytaine 3.0.0 silently ignores a lid on a rotation-symmetric hull (same result as without)
                log.info("compute_coefficients: lid requested: rotation symmetry of %s dropped", name)
                hull = hull.merged()
            lid_mesh = hull.generate_lid(z=z)
        bodies.append(cpt.FloatingBody(mesh=hull, lid_mesh=lid_mesh, dofs=cpt.rigid_body_dofs(rotation_center=c),
                                       center_of_mass=c, name=name))
    body = bodies[0] if n_body == 1 else cpt.Multibody(bodies)
    w_all = np.concatenate([omega, [np.inf]]) if infinite_frequency else omega
    test = xr.Dataset(coords={"omega": w_all, "wave_direction": beta, "radiating_dof": list(body.dofs),
                              "water_depth": [water_depth], "rho": [rho], "g": [g]})
    solver = cpt.BEMSolver()
    res = solver.fill_dataset(test, body, n_jobs=n_jobs, hydrostatics=False)
    if infinite_frequency and not np.isfinite(res["added_mass"].sel(omega=np.inf).values).all():
        log.warning("compute_coefficients: the omega = inf solve failed (finite depth?): estimating A_inf")
        res = res.sel(omega=omega)
    # hydrostatics, buoyancy part: centre of mass at the rotation centre zeroes Capytaine's weight terms
    n = 6 * n_body
    C = np.zeros((n, n))
    vol = np.zeros(n_body)
    cob = np.zeros((n_body, 3))
    for b, fb in enumerate(bodies):
        C[6 * b:6 * b + 6, 6 * b:6 * b + 6] = fb.compute_hydrostatic_stiffness(rho=rho, g=g).values
        vol[b] = fb.disp_volume
        cob[b] = fb.center_of_buoyancy
    labels = dof_labels(names)
    res = res.assign_coords(influenced_dof=[str(x) for x in res["influenced_dof"].values],
                            radiating_dof=[str(x) for x in res["radiating_dof"].values])
    if n_body == 1:
        res = res.assign_coords(influenced_dof=labels, radiating_dof=labels)
    res = res.drop_vars([c for c in ("body", "rotation_center", "center_of_mass") if c in res.coords])
    res["hydrostatic_stiffness"] = (("influenced_dof", "radiating_dof"), C)
    res["disp_mass"] = (("body",), rho * vol)
    res["center_of_buoyancy"] = (("body", "space_coordinate"), cob)
    res = res.assign_coords(body=names, space_coordinate=["x", "y", "z"],
                            rotation_center=(("body", "space_coordinate"), rc))
    ds = from_capytaine(res)
    elapsed = time.perf_counter() - t0
    ds.attrs.update({"source": "Capytaine (computed by moorline)", "capytaine_version": cpt.__version__,
                     "cache_key": key, "compute_seconds": elapsed,
                     "mesh_faces": str([int(m.nb_faces) for m in meshes]), "lid": str(lids)})
    log.info("compute_coefficients: Capytaine took %.2f s", elapsed)
    if use_cache:
        cdir.mkdir(parents=True, exist_ok=True)
        write_netcdf(ds, cfile)
    return ds
