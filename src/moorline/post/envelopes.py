"""Envelopes along a line: curvature and bend radius against an allowable bend radius, tension
extremes, stress extremes and compression warnings.

The lumped-mass segments carry no compression: a segment shorter than its unstretched length
(strain < 0) has zero tension. Such segments are where the real cable would be in axial
compression (risk of buckling or kinking), so they are reported as compression warnings.
"""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

from .sections import line_nodes

log = logging.getLogger("moorline")

__all__ = ["envelopes"]


def envelopes(ds: xr.Dataset, line: int | None = None, *, sections: xr.Dataset | None = None,
              stress: xr.DataArray | None = None, allowable_bend_radius: float | None = None,
              compression_strain: float = 0.0, warn: bool = True) -> xr.Dataset:
    """Extremes over time along one line.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`moorline.simulate` (node data needed).
    line : int, optional
        1-based line number (default: the only line).
    sections : xarray.Dataset, optional
        From :func:`moorline.post.section_loads`: adds the bending-moment envelope.
    stress : xarray.DataArray, optional
        From :func:`moorline.post.cross_section_stress`: adds the stress envelope (extremes over
        time and theta).
    allowable_bend_radius : float, optional
        Minimum allowable bend radius [m]; nodes whose bend radius falls below it are flagged
        and logged as a warning.
    compression_strain : float
        Segments with strain below this (default 0) count as compressed.
    warn : bool
        Log a warning for bend radii below the allowable and for compressed segments.

    Returns
    -------
    xarray.Dataset
        Per node: ``curvature_max`` [1/m], ``bend_radius_min`` [m], ``tension_max``,
        ``tension_min`` [N] (and ``moment_max`` [N m], ``stress_max``, ``stress_min`` [Pa],
        ``bend_radius_ok`` when asked); per segment of the line: ``segment_tension_max``,
        ``segment_tension_min`` [N], ``strain_min`` [-], ``compressed_fraction`` [-] (share of the
        output times with strain below ``compression_strain``). Attributes summarise the extremes.
    """
    line, sub = line_nodes(ds, line)
    kap = sub.node_curvature
    kmax = kap.max("time")
    with np.errstate(divide="ignore"):
        rmin = xr.where(kmax > 0, 1.0 / kmax.where(kmax > 0, 1.0), np.inf)
    out = xr.Dataset(coords={c: sub.coords[c] for c in ("node_s", "node_index") if c in sub.coords})
    out["curvature_max"] = kmax.assign_attrs(units="1/m", long_name="largest curvature")
    out["bend_radius_min"] = rmin.assign_attrs(units="m", long_name="smallest bend radius")
    out["tension_max"] = sub.node_tension.max("time").assign_attrs(units="N")
    out["tension_min"] = sub.node_tension.min("time").assign_attrs(units="N")
    if sections is not None:
        out["moment_max"] = sections.bending_moment.max("time").assign_attrs(units="N m")
    if stress is not None:
        out["stress_max"] = stress.max(("time", "theta")).assign_attrs(units="Pa")
        out["stress_min"] = stress.min(("time", "theta")).assign_attrs(units="Pa")
    i = int(np.argmax(kmax.values))
    s = sub.node_s.values
    out.attrs.update(line=line, curvature_max=float(kmax.values[i]), curvature_max_s=float(s[i]),
                     bend_radius_min=float(rmin.values[i]), tension_max=float(out.tension_max.max()),
                     tension_min=float(out.tension_min.min()))
    if allowable_bend_radius is not None:
        ok = rmin >= allowable_bend_radius
        out["bend_radius_ok"] = ok.assign_attrs(long_name=f"bend radius >= {allowable_bend_radius} m")
        out.attrs["allowable_bend_radius"] = float(allowable_bend_radius)
        out.attrs["bend_radius_utilisation"] = float(allowable_bend_radius * kmax.values[i])
        if warn and not bool(ok.all()):
            bad = s[~ok.values]
            log.warning("line %d: bend radius below the allowable %.4g m between s = %.4g and %.4g m "
                        "(smallest %.4g m at s = %.4g m)", line, allowable_bend_radius, bad.min(), bad.max(),
                        rmin.values[i], s[i])
    if "segment_tension" in ds:
        seg = np.flatnonzero(ds.segment_line.values == line)
        st = ds.segment_tension.isel(segment=seg)
        strain = ds.segment_strain.isel(segment=seg)
        comp = strain < compression_strain
        frac = comp.mean("time")
        for name, v, attrs in (("segment_tension_max", st.max("time"), {"units": "N"}),
                               ("segment_tension_min", st.min("time"), {"units": "N"}),
                               ("strain_min", strain.min("time"), {"units": "1"}),
                               ("compressed_fraction", frac, {"units": "1", "long_name": "share of output times "
                                                               f"with strain < {compression_strain:g}"})):
            out[name] = v.assign_attrs(attrs)
        n_comp = int((frac > 0).sum())
        out.attrs["compressed_segments"] = n_comp
        if warn and n_comp:
            ss = st.segment_s.values[frac.values > 0]
            t_first = float(ds.time.values[int(np.argmax(comp.any("segment").values))])
            log.warning("line %d: %d segments in compression (strain < %g) between s = %.4g and %.4g m, first at "
                        "t = %.4g s; the model carries no compression there", line, n_comp, compression_strain,
                        ss.min(), ss.max(), t_first)
    return out
