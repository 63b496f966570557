"""WAMIT numeric output files (.1, .3, .hst, optional .3fk/.3sc and .out): reader and writer.

Conventions (WAMIT User Manual v7, ch. 3 "Definition of quantities", ch. 5 "Output files"; the exponents follow
from dimensional analysis and are the ones WAMIT states):

- ``.1``  rows ``PER I J Abar Bbar``; A = Abar rho L^k, B = Bbar rho omega L^k, k = 3 (both indices translations),
  4 (one translation, one rotation), 5 (both rotations). PER = -1 is the zero-frequency (infinite-period) limit
  and PER = 0 the infinite-frequency limit; those rows have no Bbar. A(I, J) is the force in mode I due to
  motion in mode J: I -> influenced_dof, J -> radiating_dof.
- ``.3``  rows ``PER BETA I |X| phase Re Im``; X = Xbar rho g L^m (per unit wave amplitude), m = 2 forces,
  3 moments; BETA [deg] is the direction the waves travel toward (same as Capytaine's wave_direction).
  WAMIT's complex amplitude means Re{X exp(+i omega t)}; the Dataset stores the conjugate (Capytaine).
- ``.hst`` rows ``I J Cbar``; C = Cbar rho g L^k, k = 2, 3, 4 for translation/translation, mixed, rotation/rotation.
  WAMIT's C includes the weight terms -m g z_g (C44, C55), +m g x_g (C46), +m g y_g (C56) for the centre of
  gravity it was given (VCG, body coordinates, mass rho V by default); they are removed here.
- Multi-body: DOF index I = 6 (b - 1) + dof; all coupling terms kept. Entries WAMIT left out below its print
  threshold are zero; a DOF that never appears is an error.
- Coefficients are about each body's origin XBODY (from the .out file), body axes parallel to global
  (PHIBODY = 0 is required).
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path

import numpy as np

from .dataset import RIGID_DOFS, HydroFileError, build_dataset, dof_labels, file_digest, matrix

log = logging.getLogger("moorline.hydro")

_FLOAT = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"


def _k_radiation(i: int, j: int) -> int:
    return 3 + ((i % 6) >= 3) + ((j % 6) >= 3)


def _k_stiffness(i: int, j: int) -> int:
    return 2 + ((i % 6) >= 3) + ((j % 6) >= 3)


def _m_excitation(i: int) -> int:
    return 2 + ((i % 6) >= 3)


def _dof_name(index0: int) -> str:
    return f"DOF {index0 + 1} (body {index0 // 6 + 1} {RIGID_DOFS[index0 % 6]})"


def _rows(path: Path, ncols: tuple[int, ...], what: str):
    """Yield (line number, floats, raw) for every data row; one text header line is allowed first."""
    with open(path, encoding="utf-8", errors="replace") as fh:
        seen_data = False
        for n, raw in enumerate(fh, start=1):
            toks = raw.split()
            if not toks:
                continue
            try:
                vals = [float(t.replace("D", "E").replace("d", "e")) for t in toks]
            except ValueError:
                if not seen_data and n == 1:
                    continue  # a text header line
                raise HydroFileError(f"malformed row: expected {what} ({' or '.join(map(str, ncols))} numbers)",
                                     file=path, line=n, row=raw) from None
            if len(vals) not in ncols:
                raise HydroFileError(f"malformed row: expected {what} ({' or '.join(map(str, ncols))} numbers), "
                                     f"got {len(vals)}", file=path, line=n, row=raw)
            if not all(math.isfinite(v) for v in vals):
                raise HydroFileError("non-finite value (NaN or Inf)", file=path, line=n, row=raw)
            seen_data = True
            yield n, vals, raw


def _index(v: float, path, n, raw, name="I") -> int:
    if v != int(v) or v < 1:
        raise HydroFileError(f"{name} must be a whole number >= 1, got {v}", file=path, line=n, row=raw)
    return int(v) - 1


def read_wamit_out(path) -> dict:
    """Parse the parts of a WAMIT ``.out`` report this reader uses.

    Returns
    -------
    dict
        ``g`` [m/s^2], ``length_scale`` [m], ``water_depth`` [m] (inf), ``periods`` [s] (list, in file order,
        finite ones only), ``headings`` [deg], and ``bodies``: a list of dicts with ``xbody`` (3,) [m] and
        ``phibody`` [deg], ``volume`` [m^3] (mean of VOLX, VOLY, VOLZ), ``cob`` and ``cog`` (3,) [m] in body
        coordinates. Missing items are absent from the dict.
    """
    path = Path(path)
    text = path.read_text(encoding="utf-8", errors="replace")
    out: dict = {"bodies": []}
    m = re.search(rf"Gravity:\s*({_FLOAT})", text)
    if m:
        out["g"] = float(m.group(1))
    m = re.search(rf"Length scale:\s*({_FLOAT})", text)
    if m:
        out["length_scale"] = float(m.group(1))
    m = re.search(rf"Water depth:\s*(infinite|{_FLOAT})", text)
    if m:
        out["water_depth"] = np.inf if m.group(1) == "infinite" else float(m.group(1))
    blocks = re.split(r"Body number:\s*N=\s*\d+", text)[1:]
    for blk in blocks:
        body: dict = {}
        m = re.search(rf"XBODY\s*=\s*({_FLOAT})\s*YBODY\s*=\s*({_FLOAT})\s*ZBODY\s*=\s*({_FLOAT})"
                      rf"\s*PHIBODY\s*=\s*({_FLOAT})", blk)
        if m:
            body["xbody"] = np.array([float(m.group(k)) for k in (1, 2, 3)])
            body["phibody"] = float(m.group(4))
        m = re.search(rf"Volumes \(VOLX,VOLY,VOLZ\):\s*({_FLOAT})\s+({_FLOAT})\s+({_FLOAT})", blk)
        if m:
            body["volume"] = float(np.mean([float(m.group(k)) for k in (1, 2, 3)]))
        m = re.search(rf"Center of Buoyancy \(Xb,Yb,Zb\):\s*({_FLOAT})\s+({_FLOAT})\s+({_FLOAT})", blk)
        if m:
            body["cob"] = np.array([float(m.group(k)) for k in (1, 2, 3)])
        m = re.search(rf"Center of Gravity\s*\(Xg,Yg,Zg\):\s*({_FLOAT})\s+({_FLOAT})\s+({_FLOAT})", blk)
        if m:
            body["cog"] = np.array([float(m.group(k)) for k in (1, 2, 3)])
        out["bodies"].append(body)
        if "Output from" in blk:
            break  # the per-body header blocks end where the results start
    out["periods"] = [float(v) for v in re.findall(rf"Wave period \(sec\)\s*=\s*({_FLOAT})", text)]
    out["headings"] = sorted({float(v) for v in re.findall(rf"Wave Heading \(deg\)\s*:\s*({_FLOAT})", text)})
    return out


def _omega_of(values, mode):
    v = np.asarray(values, dtype=float)
    return 2.0 * np.pi / v if mode == "period" else v


def _detect_period_column(first_col, limits, out_info, path):
    """Decide whether the first column holds periods [s] or frequencies [rad/s]."""
    finite = np.array(sorted(set(first_col)))
    if out_info and out_info.get("periods"):
        per = np.array(sorted(set(out_info["periods"])))
        if per.size == finite.size and np.allclose(per, finite, rtol=1e-5):
            return "period", "the .out file lists the same values as wave periods"
        if per.size == finite.size and np.allclose(np.sort(2 * np.pi / per), finite, rtol=1e-5):
            return "frequency", "the .out file lists wave periods 2 pi / (first column)"
    if "zero" in limits and "inf" in limits:
        a_lo = limits["_A"][finite[0]]
        a_hi = limits["_A"][finite[-1]]
        d = np.abs(np.diagonal(limits["inf"])) + np.abs(np.diagonal(limits["zero"])) + 1e-300
        # under the 'period' reading the smallest value is the highest frequency: it must sit near A_inf
        per_score = np.sum(np.abs(np.diagonal(a_lo) - np.diagonal(limits["inf"])) / d) + \
            np.sum(np.abs(np.diagonal(a_hi) - np.diagonal(limits["zero"])) / d)
        frq_score = np.sum(np.abs(np.diagonal(a_hi) - np.diagonal(limits["inf"])) / d) + \
            np.sum(np.abs(np.diagonal(a_lo) - np.diagonal(limits["zero"])) / d)
        mode = "period" if per_score <= frq_score else "frequency"
        return mode, (f"A(first column) approaches A_inf and A_0 at the matching ends "
                      f"({per_score:.3g} vs {frq_score:.3g})")
    return "period", "no .out file and no zero/infinite limits to judge by: WAMIT's default (period)"


def read_wamit(stem, rho: float = 1025.0, g: float | None = None, *, length_scale: float = 1.0,
               period_column: str = "auto", cog=None, mass=None, reference_point=None, body_names=None,
               displaced_volume=None, center_of_buoyancy=None):
    """Read a WAMIT first-order set (.1, .3, .hst; .3fk, .3sc and .out where present) into a coefficient Dataset.

    Parameters
    ----------
    stem : str or Path
        Path without the suffix (``.../rm3`` for rm3.1, rm3.3, rm3.hst).
    rho : float
        Water density [kg/m^3] to redimensionalise with (WAMIT files do not record it).
    g : float, optional
        Gravity [m/s^2]; default: the .out file's, else 9.81.
    length_scale : float
        WAMIT's ULEN [m] the files were made non-dimensional with.
    period_column : {"auto", "period", "frequency"}
        What the first column holds (WAMIT's IPEROUT is not recorded in the files). "auto" uses the .out file,
        else the zero/infinite-frequency limits, else assumes periods; an explicit choice is checked against
        the same evidence and a disagreement is logged as a warning.
    cog : array, shape (3,) or (n_body, 3), optional
        Centre of gravity WAMIT used, global frame [m]. Default: the .out file's (body coordinates + XBODY).
        Its weight terms are removed from the .hst stiffness.
    mass : float or array (n_body,), optional
        Body mass WAMIT used in its weight terms [kg]; default rho * displaced volume (WAMIT's default).
    reference_point : array (3,) or (n_body, 3), optional
        Body reference points [m] when there is no .out file (default origin, with a warning).
    body_names : list of str, optional
        Default ``body1``, ``body2``, ...
    displaced_volume : float or array (n_body,), optional
        [m^3], overriding or supplying what a .out file gives (e.g. HydroDyn's PtfmVol0 when there is no .out).
    center_of_buoyancy : array (3,) or (n_body, 3), optional
        [m], global frame, likewise.

    Returns
    -------
    xarray.Dataset
        See :mod:`moorline.hydro.dataset`.

    Raises
    ------
    HydroFileError
        Malformed rows, NaN, non-monotonic periods, a DOF absent from a file, inconsistent frequency sets.
    """
    stem = Path(stem)
    p1, p3, phst, pout = (stem.with_name(stem.name + s) for s in (".1", ".3", ".hst", ".out"))
    for p in (p1, p3, phst):
        if not p.is_file():
            raise FileNotFoundError(f"WAMIT file {p} not found")
    if period_column not in ("auto", "period", "frequency"):
        raise ValueError(f"period_column must be 'auto', 'period' or 'frequency', got {period_column!r}")
    out_info = read_wamit_out(pout) if pout.is_file() else None
    if g is None:
        g = out_info.get("g", 9.81) if out_info else 9.81
    L = float(length_scale)
    if out_info and "length_scale" in out_info and not np.isclose(out_info["length_scale"], L):
        log.warning("read_wamit: %s gives length scale %g but length_scale=%g was passed; using %g",
                    pout, out_info["length_scale"], L, L)

    # ---- .1: radiation ----------------------------------------------------------------------------------
    rad_rows = []
    order: list[float] = []
    last_block = None
    max_index = 0
    for n, vals, raw in _rows(p1, (4, 5), "PER I J Abar [Bbar]"):
        per = vals[0]
        i, j = _index(vals[1], p1, n, raw, "I"), _index(vals[2], p1, n, raw, "J")
        max_index = max(max_index, i + 1, j + 1)
        is_limit = per in (-1.0, 0.0) if period_column != "frequency" else len(vals) == 4
        if not is_limit and len(vals) != 5:
            raise HydroFileError("malformed row: a finite period needs PER I J Abar Bbar (5 numbers)",
                                 file=p1, line=n, row=raw)
        if not is_limit:
            if per <= 0:
                raise HydroFileError(f"period/frequency must be > 0 (or a -1/0 limit marker), got {per}",
                                     file=p1, line=n, row=raw)
            if per != last_block:
                if per in order:
                    raise HydroFileError(f"period {per} appears in two separate blocks", file=p1, line=n, row=raw)
                if len(order) >= 2 and np.sign(per - order[-1]) != np.sign(order[-1] - order[-2]):
                    raise HydroFileError(f"periods not monotonic: {order[-2]}, {order[-1]}, then {per}",
                                         file=p1, line=n, row=raw)
                order.append(per)
            last_block = per
        rad_rows.append((n, per, is_limit, i, j, vals[3], vals[4] if len(vals) == 5 else np.nan))
    if not rad_rows:
        raise HydroFileError("no data rows", file=p1)
    n_body = len(out_info["bodies"]) if out_info and out_info["bodies"] else -(-max_index // 6)
    ndof = 6 * n_body
    if max_index > ndof:
        raise HydroFileError(f"DOF index {max_index} exceeds 6 x {n_body} bodies", file=p1)
    present = np.zeros(ndof, dtype=bool)
    per_index = {p: k for k, p in enumerate(order)}
    abar = np.zeros((len(order), ndof, ndof))
    bbar = np.zeros((len(order), ndof, ndof))
    lim_raw: dict = {}
    for _n, per, is_limit, i, j, a, b in rad_rows:
        present[i] = present[j] = True
        if is_limit:
            key = _limit_key(per, period_column)
            lim_raw.setdefault(key, np.zeros((ndof, ndof)))[i, j] = a
        else:
            k = per_index[per]
            abar[k, i, j] = a
            bbar[k, i, j] = b
    if not present.all():
        missing = [_dof_name(k) for k in np.flatnonzero(~present)]
        raise HydroFileError(f"{', '.join(missing)} absent from the file: expected entries for every DOF of "
                             f"{n_body} bod{'y' if n_body == 1 else 'ies'}", file=p1)
    mode = period_column
    lim_for_detect = dict(lim_raw)
    lim_for_detect["_A"] = {p: abar[per_index[p]] for p in order}
    detected, why = _detect_period_column(order, lim_for_detect, out_info, p1)
    if mode == "auto":
        mode = detected
        log.info("read_wamit: first column of %s read as %s (%s)", p1, mode, why)
    elif mode != detected and ("zero" in lim_raw or out_info):
        log.warning("read_wamit: period_column=%r but the evidence points to %r (%s)", mode, detected, why)
    omega_file = _omega_of(order, mode)
    srt = np.argsort(omega_file)
    omega = omega_file[srt]
    if np.any(np.diff(omega) <= 0):
        raise HydroFileError("duplicate frequencies", file=p1)

    k_rad = np.array([[_k_radiation(i, j) for j in range(ndof)] for i in range(ndof)])
    scale_a = rho * L ** k_rad
    A = abar[srt] * scale_a
    B = bbar[srt] * scale_a * omega[:, None, None]
    A_inf = lim_raw["inf"] * scale_a if "inf" in lim_raw else None
    A_zero = lim_raw["zero"] * scale_a if "zero" in lim_raw else None
    if A_inf is None:
        log.warning("read_wamit: %s has no infinite-frequency (PER = 0) rows: added_mass_inf estimated from the "
                    "radiation damping by Ogilvie's relation", p1)

    # ---- .3: excitation ---------------------------------------------------------------------------------
    def read_exc(path):
        rows = list(_rows(path, (7,), "PER BETA I |X| phase Re Im"))
        if not rows:
            raise HydroFileError("no data rows", file=path)
        pers = sorted({r[1][0] for r in rows})
        betas = sorted({r[1][1] for r in rows})
        if not np.allclose(np.sort(_omega_of(pers, mode)), omega, rtol=1e-6):
            raise HydroFileError(f"frequencies differ from those of {p1.name} ({len(pers)} against {len(omega)})",
                                 file=path)
        wmap = {p: int(np.argmin(np.abs(omega - _omega_of([p], mode)[0]))) for p in pers}
        bmap = {b: k for k, b in enumerate(betas)}
        x = np.zeros((len(omega), len(betas), ndof), dtype=complex)
        seen = np.zeros(ndof, dtype=bool)
        for n, vals, raw in rows:
            i = _index(vals[2], path, n, raw, "I")
            if i >= ndof:
                raise HydroFileError(f"DOF index {i + 1} exceeds 6 x {n_body} bodies", file=path, line=n, row=raw)
            seen[i] = True
            x[wmap[vals[0]], bmap[vals[1]], i] = complex(vals[5], vals[6])
        if not seen.all():
            raise HydroFileError(f"{', '.join(_dof_name(k) for k in np.flatnonzero(~seen))} absent from the file",
                                 file=path)
        m_exc = np.array([_m_excitation(i) for i in range(ndof)])
        return np.conj(x) * (rho * g * L ** m_exc), np.radians(betas)

    X, beta = read_exc(p3)
    extra = {}
    for suffix, name in ((".3fk", "froude_krylov_force"), (".3sc", "diffraction_force")):
        p = stem.with_name(stem.name + suffix)
        if p.is_file():
            extra[name] = read_exc(p)[0]
    # headings -180 and 180 (or 0 and 360) describe the same waves: keep one
    beta_wrapped = np.mod(beta + np.pi, 2 * np.pi) - np.pi
    _, keep = np.unique(np.round(beta_wrapped, 9), return_index=True)
    if keep.size < beta.size:
        beta = beta_wrapped[keep]
        X = X[:, keep]
        extra = {k: v[:, keep] for k, v in extra.items()}

    # ---- .hst: hydrostatics ----------------------------------------------------------------------------
    C = np.zeros((ndof, ndof))
    for n, vals, raw in _rows(phst, (3,), "I J Cbar"):
        i, j = _index(vals[0], phst, n, raw, "I"), _index(vals[1], phst, n, raw, "J")
        if max(i, j) >= ndof:
            raise HydroFileError(f"DOF index {max(i, j) + 1} exceeds 6 x {n_body} bodies", file=phst, line=n, row=raw)
        C[i, j] = vals[2] * rho * g * L ** _k_stiffness(i, j)

    # ---- bodies: reference points, volumes, centres -------------------------------------------------------
    names = list(body_names) if body_names is not None else [f"body{b + 1}" for b in range(n_body)]
    if len(names) != n_body:
        raise ValueError(f"body_names has {len(names)} names for {n_body} bodies")
    ref = np.zeros((n_body, 3))
    vol = np.full(n_body, np.nan)
    cob = np.full((n_body, 3), np.nan)
    cog_src = None
    if out_info and out_info["bodies"]:
        for b, info in enumerate(out_info["bodies"]):
            if abs(info.get("phibody", 0.0)) > 1e-9:
                raise HydroFileError(f"body {b + 1} has PHIBODY = {info['phibody']} deg: rotated body axes are not "
                                     "supported (coefficients must be along global axes)", file=pout)
            ref[b] = info.get("xbody", np.zeros(3))
            vol[b] = info.get("volume", np.nan)
            if "cob" in info:
                cob[b] = ref[b] + info["cob"]
        if all("cog" in info for info in out_info["bodies"]):
            cog_src = np.array([ref[b] + info["cog"] for b, info in enumerate(out_info["bodies"])])
        if out_info.get("water_depth") is not None:
            depth = out_info["water_depth"]
        else:
            depth = np.inf
    else:
        depth = np.inf
        if reference_point is None:
            log.warning("read_wamit: no %s: reference points taken at the origin, volumes and centres of buoyancy "
                        "unknown (NaN), water depth taken as infinite", pout)
    if reference_point is not None:
        ref = np.broadcast_to(np.asarray(reference_point, dtype=float).reshape(-1, 3), (n_body, 3)).copy()

    if displaced_volume is not None:
        vol = np.broadcast_to(np.asarray(displaced_volume, dtype=float).reshape(-1), (n_body,)).copy()
    if center_of_buoyancy is not None:
        cob = np.broadcast_to(np.asarray(center_of_buoyancy, dtype=float).reshape(-1, 3), (n_body, 3)).copy()

    # ---- weight terms out of the stiffness ----------------------------------------------------------------
    if cog is not None:
        cog_used = np.broadcast_to(np.asarray(cog, dtype=float).reshape(-1, 3), (n_body, 3)).copy()
        cog_from = "given"
    elif cog_src is not None:
        cog_used, cog_from = cog_src, f"{pout.name} (VCG, body coordinates)"
    else:
        cog_used, cog_from = None, None
        log.warning("read_wamit: no centre of gravity given nor in a .out file: %s is taken as buoyancy-only", phst)
    removed = np.zeros((n_body, 4))
    if cog_used is not None:
        m_used = (rho * vol if mass is None else
                  np.broadcast_to(np.asarray(mass, dtype=float).reshape(-1), (n_body,)).copy())
        for b in range(n_body):
            rel = cog_used[b] - ref[b]
            if np.allclose(rel, 0.0):
                continue
            if not np.isfinite(m_used[b]):
                raise ValueError(f"body {b + 1}: centre of gravity {cog_used[b]} differs from the reference point but "
                                 "the mass is unknown (no .out volume): pass mass=")
            mg = m_used[b] * g
            o = 6 * b
            # WAMIT: C44, C55 += -m g zg; C46 += m g xg; C56 += m g yg (body coordinates) -> undo
            C[o + 3, o + 3] += mg * rel[2]
            C[o + 4, o + 4] += mg * rel[2]
            C[o + 3, o + 5] -= mg * rel[0]
            C[o + 4, o + 5] -= mg * rel[1]
            removed[b] = (mg * rel[2], mg * rel[2], -mg * rel[0], -mg * rel[1])
        log.info("read_wamit: weight terms removed from %s with the centre of gravity from %s: %s", phst, cog_from,
                 removed.tolist())

    if A_inf is None:
        from .irf import estimate_added_mass_inf
        A_inf = estimate_added_mass_inf(omega, A, B)
    files = [p for p in (p1, p3, phst, pout, stem.with_name(stem.name + ".3fk"), stem.with_name(stem.name + ".3sc"))
             if p.is_file()]
    ds = build_dataset(
        omega=omega, wave_direction=beta, body_names=names, added_mass=A, radiation_damping=B, added_mass_inf=A_inf,
        excitation_force=X, hydrostatic_stiffness=C, displaced_volume=vol, center_of_buoyancy=cob,
        rotation_center=ref, rho=rho, g=g, water_depth=depth, added_mass_zero=A_zero,
        froude_krylov_force=extra.get("froude_krylov_force"), diffraction_force=extra.get("diffraction_force"),
        attrs={"source": "WAMIT", "source_files": ", ".join(str(p) for p in files),
               "source_sha256": file_digest(files), "wamit_length_scale": L, "wamit_period_column": mode,
               "weight_terms_removed": ("C44, C55, C46, C56 per body [N m/rad]: " + str(removed.tolist())
                                        if cog_used is not None else "none (no centre of gravity known)"),
               "added_mass_inf_source": "file (PER = 0)" if "inf" in lim_raw else "Ogilvie estimate"})
    return ds


def _limit_key(per: float, mode: str) -> str:
    if mode == "frequency":
        return "zero" if per == 0.0 else "inf"
    return "zero" if per == -1.0 else "inf"


def write_wamit(ds, stem, *, length_scale: float = 1.0, write_out: bool = True) -> list[Path]:
    """Write a coefficient Dataset as WAMIT numeric files (.1, .3, .hst, and a minimal .out).

    The inverse of :func:`read_wamit` (periods in the first column, excitation conjugated to WAMIT's
    exp(+i omega t), stiffness written as it is, i.e. buoyancy only with the centre of gravity reported at
    each reference point so that no weight terms are implied). The .out file holds only what
    :func:`read_wamit` reads (gravity, length scale, depth, XBODY, volume, centres).

    Parameters
    ----------
    ds : xarray.Dataset
    stem : str or Path
    length_scale : float
        ULEN [m] to make the values non-dimensional with.
    write_out : bool
        Also write ``stem.out``.

    Returns
    -------
    list of Path
        The files written.
    """
    stem = Path(stem)
    stem.parent.mkdir(parents=True, exist_ok=True)
    rho, g, L = float(ds["rho"]), float(ds["g"]), float(length_scale)
    omega = ds["omega"].values
    A = matrix(ds["added_mass"])
    B = matrix(ds["radiation_damping"])
    ndof = A.shape[-1]
    k_rad = np.array([[_k_radiation(i, j) for j in range(ndof)] for i in range(ndof)])
    scale_a = rho * L ** k_rad
    files = []
    p1 = stem.with_name(stem.name + ".1")
    with open(p1, "w") as fh:
        fh.write(f" WAMIT-format numeric output written by moorline -- Filename {p1.name}\n")
        for key, per in (("added_mass_zero", -1.0), ("added_mass_inf", 0.0)):
            if key in ds:
                a = matrix(ds[key]) / scale_a
                for i in range(ndof):
                    for j in range(ndof):
                        fh.write(f" {per:14.6E} {i + 1:5d} {j + 1:5d} {a[i, j]:14.6E}\n")
        for k in np.argsort(omega):
            per = 2 * np.pi / omega[k]
            a = A[k] / scale_a
            b = B[k] / (scale_a * omega[k])
            for i in range(ndof):
                for j in range(ndof):
                    fh.write(f" {per:14.6E} {i + 1:5d} {j + 1:5d} {a[i, j]:14.6E} {b[i, j]:14.6E}\n")
    files.append(p1)
    m_exc = np.array([_m_excitation(i) for i in range(ndof)])
    for var, suffix in (("excitation_force", ".3"), ("Froude_Krylov_force", ".3fk"), ("diffraction_force", ".3sc")):
        if var not in ds:
            continue
        x = np.conj(ds[var].transpose("omega", "wave_direction", "influenced_dof").values) / (rho * g * L ** m_exc)
        p = stem.with_name(stem.name + suffix)
        with open(p, "w") as fh:
            fh.write(f" WAMIT-format numeric output written by moorline -- Filename {p.name}\n")
            for k in np.argsort(omega):
                per = 2 * np.pi / omega[k]
                for ib, beta in enumerate(np.degrees(ds["wave_direction"].values)):
                    for i in range(ndof):
                        z = x[k, ib, i]
                        fh.write(f" {per:14.6E} {beta:14.6E} {i + 1:5d} {abs(z):14.6E} {np.degrees(np.angle(z)):14.6E}"
                                 f" {z.real:14.6E} {z.imag:14.6E}\n")
        files.append(p)
    C = ds["hydrostatic_stiffness"].transpose("influenced_dof", "radiating_dof").values
    phst = stem.with_name(stem.name + ".hst")
    with open(phst, "w") as fh:
        fh.write(f" WAMIT-format hydrostatics written by moorline -- {phst.name}\n")
        for i in range(ndof):
            for j in range(ndof):
                fh.write(f" {i + 1:5d} {j + 1:5d} {C[i, j] / (rho * g * L ** _k_stiffness(i, j)):14.6E}\n")
    files.append(phst)
    if write_out:
        pout = stem.with_name(stem.name + ".out")
        depth = float(ds["water_depth"])
        ref = ds["rotation_center"].values.reshape(-1, 3)
        with open(pout, "w") as fh:
            fh.write(" Report subset written by moorline (read_wamit reads these lines)\n\n")
            fh.write(f" Gravity:     {g:.6f}                Length scale:     {L:.6f}\n")
            fh.write(f" Water depth:        {'infinite' if np.isinf(depth) else f'{depth:.6f}'}\n\n")
            for b in range(ref.shape[0]):
                vol = float(ds["displaced_volume"].values[b])
                cob = ds["center_of_buoyancy"].values[b] - ref[b]
                fh.write(f" Body number: N= {b + 1}\n")
                fh.write(f" XBODY = {ref[b, 0]:.6f} YBODY = {ref[b, 1]:.6f} ZBODY = {ref[b, 2]:.6f} PHIBODY = 0.0\n")
                fh.write(f" Volumes (VOLX,VOLY,VOLZ):  {vol:.9E} {vol:.9E} {vol:.9E}\n")
                fh.write(f" Center of Buoyancy (Xb,Yb,Zb):  {cob[0]:.9E} {cob[1]:.9E} {cob[2]:.9E}\n")
                fh.write(" Center of Gravity  (Xg,Yg,Zg):  0.0 0.0 0.0\n\n")
            fh.write(" Output from moorline\n")
            for w in np.sort(omega):
                fh.write(f" Wave period (sec) = {2 * np.pi / w:14.6E}\n")
        files.append(pout)
    return files


__all__ = ["read_wamit", "read_wamit_out", "write_wamit", "dof_labels"]
