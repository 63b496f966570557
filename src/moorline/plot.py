"""Matplotlib figures for cable design studies.

One run (:func:`moorline.simulate` results): :func:`curvature_envelope`. A sweep
(:func:`moorline.studies.run_sweep` dataset): :func:`envelopes_along_arc` (curvature, stress, ...
envelopes per case), :func:`damage_along_arc`, :func:`scatter_heatmap` (the fatigue Hs-Tz matrix)
and :func:`sensitivity` (how a result depends on each parameter). Quasi-static studies
(:mod:`moorline.quasistatic.studies` datasets): :func:`offset_curve` and :func:`watch_circle`. Floating
bodies: :func:`rao` (frequency-domain RAOs of :func:`moorline.hydro.rao`, with time-domain points) and
:func:`decay` (a free decay from a run's results). Every function draws into the axes it is given (or a
new figure) and returns the axes.
"""

from __future__ import annotations

import numpy as np
import xarray as xr

__all__ = ["cases", "curvature_envelope", "damage_along_arc", "decay", "envelopes_along_arc", "offset_curve", "rao",
           "scatter_heatmap", "sensitivity", "watch_circle"]


def _axes(ax, figsize=(7.0, 4.2)):
    if ax is not None:
        return ax
    import matplotlib.pyplot as plt

    return plt.subplots(figsize=figsize)[1]


def _parameters(ds: xr.Dataset) -> list[str]:
    """The sweep parameters: the dimensions that are not the result dimensions."""
    inner = {"sea_state", "node", "theta", "segment", "time", "xyz"}
    return [d for d in ds.dims if d not in inner]


def cases(ds: xr.Dataset):
    """Iterate (label, dict of parameter values, case Dataset) over the cases of a sweep dataset."""
    params = _parameters(ds)
    if not params:
        yield "", {}, ds
        return
    shape = [ds.sizes[p] for p in params]
    for idx in np.ndindex(*shape):
        sel = dict(zip(params, idx, strict=True))
        one = ds.isel(sel)
        values = {p: one[p].item() for p in params}
        yield ", ".join(f"{p}={v:g}" if isinstance(v, float) else f"{p}={v}" for p, v in values.items()), values, one


def curvature_envelope(ds: xr.Dataset, line: int | None = None, *, ax=None, allowable_bend_radius=None):
    """Curvature along the arc length of one run: min-max band, mean, and the largest value with
    its bend radius; an allowable bend radius as the curvature limit 1/R."""
    from .post import line_nodes

    _, sub = line_nodes(ds, line)
    ax = _axes(ax)
    s = sub.node_s.values
    k = sub.node_curvature.values
    kmax = k.max(axis=0)
    i = int(np.argmax(kmax))
    ax.fill_between(s, k.min(axis=0), kmax, color="tab:orange", alpha=0.35, label="min-max envelope")
    ax.plot(s, k.mean(axis=0), color="tab:orange", lw=1.5, label="mean")
    ax.plot(s[i], kmax[i], "kv", label=f"max {kmax[i]:.3g} 1/m (R = {1 / kmax[i]:.3g} m)" if kmax[i] > 0 else "max 0")
    if allowable_bend_radius:
        ax.axhline(1.0 / allowable_bend_radius, color="tab:red", ls="--", lw=1,
                   label=f"allowable bend radius {allowable_bend_radius:g} m")
    ax.set_xlabel("arc length from end A [m]")
    ax.set_ylabel("curvature [1/m]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def envelopes_along_arc(ds: xr.Dataset, var: str = "curvature_max", *, ax=None, reduce: str = "max", scale=1.0,
                        ylabel: str | None = None, highlight: dict | None = None, legend: bool = True):
    """One line per sweep case: ``var`` (with a node dimension, e.g. curvature_max, stress_max,
    tension_max) reduced over sea states (``reduce`` = 'max' or 'min') against arc length.

    Parameters
    ----------
    scale : float
        Multiply the values (e.g. 1e-6 for stress in MPa).
    highlight : dict, optional
        Parameter values of a case drawn thick and black (e.g. the baseline).
    """
    ax = _axes(ax)
    items = list(cases(ds))
    colors = _colors(len(items))
    for (label, values, one), c in zip(items, colors, strict=True):
        v = one[var]
        if "sea_state" in v.dims:
            v = getattr(v, reduce)("sea_state")
        for d in [d for d in v.dims if d != "node"]:
            v = getattr(v, reduce)(d)
        s = one.node_s.values
        hl = highlight is not None and all(values.get(k) == val for k, val in highlight.items())
        ax.plot(s, v.values * scale, color="k" if hl else c, lw=2.2 if hl else 1.0, label=label, zorder=3 if hl else 2)
    ax.set_xlabel("arc length from end A [m]")
    ax.set_ylabel(ylabel or var)
    ax.grid(alpha=0.3)
    if legend:
        ax.legend(fontsize=6, ncol=2)
    return ax


def damage_along_arc(ds: xr.Dataset, *, ax=None, var: str = "damage_per_year", highlight: dict | None = None,
                     legend: bool = True):
    """Annual damage along the arc length (the largest over the section points) per case, log scale."""
    ax = _axes(ax)
    items = list(cases(ds))
    for (label, values, one), c in zip(items, _colors(len(items)), strict=True):
        d = one[var]
        if "theta" in d.dims:
            d = d.max("theta")
        hl = highlight is not None and all(values.get(k) == val for k, val in highlight.items())
        ax.semilogy(one.node_s.values, np.where(d.values > 0, d.values, np.nan), color="k" if hl else c,
                    lw=2.2 if hl else 1.0, label=label, zorder=3 if hl else 2)
    ax.set_xlabel("arc length from end A [m]")
    ax.set_ylabel("damage per year [1/year]")
    ax.grid(alpha=0.3, which="both")
    if legend:
        ax.legend(fontsize=6, ncol=2)
    return ax


def scatter_heatmap(values: xr.DataArray, *, ax=None, log: bool = True, cmap: str = "magma_r",
                    label: str = "damage per year", annotate: bool = True, grid: xr.DataArray | None = None):
    """A heat map over the scatter diagram (Hs rows, Tz columns): per-sea-state values with ``Hs``
    and ``Tz`` coordinates along ``sea_state`` (e.g. ``damage_per_year_by_sea_state`` of one case),
    or a DataArray already on the (Hs, Tz) grid. Empty cells are blank; cells holding at least 1 %
    of the total are labelled with their share.

    Parameters
    ----------
    grid : xarray.DataArray, optional
        Something on the full (Hs, Tz) grid (e.g. ``ScatterDiagram.to_dataarray()``) whose
        coordinates the map spans.
    """
    import matplotlib.colors as mcolors

    from .post import to_scatter_grid

    g = to_scatter_grid(values) if "sea_state" in values.dims else values
    if grid is not None:
        g = g.reindex(Hs=grid.Hs.values, Tz=grid.Tz.values).sortby(["Hs", "Tz"])
    ax = _axes(ax, figsize=(8.0, 5.5))
    v = g.values.astype(float)
    pos = v[np.isfinite(v) & (v > 0)]
    norm = mcolors.LogNorm(vmin=pos.min(), vmax=pos.max()) if log and pos.size else None
    Tz, Hs = g.Tz.values, g.Hs.values
    m = ax.pcolormesh(_edges(Tz), _edges(Hs), np.where(v > 0, v, np.nan) if log else v, cmap=cmap, norm=norm,
                      shading="flat")
    ax.figure.colorbar(m, ax=ax, label=label)
    if annotate and pos.size:
        total = np.nansum(v)
        for i, j in zip(*np.nonzero(np.isfinite(v) & (v > 0)), strict=True):
            share = v[i, j] / total
            if share >= 0.01:
                ax.text(Tz[j], Hs[i], f"{100 * share:.0f}%", ha="center", va="center", fontsize=6,
                        color="w" if norm is not None and norm(v[i, j]) > 0.6 else "k")
    ax.set_xlabel("zero-crossing period Tz [s]")
    ax.set_ylabel("significant wave height Hs [m]")
    return ax


def sensitivity(ds: xr.Dataset, metric: str = "life_years", *, axes=None, log: bool = True, label: str | None = None):
    """How ``metric`` (a per-case result, e.g. life_years) depends on each parameter: one panel per
    parameter, a thin line through the cases that differ only in that parameter, and the
    geometric (log) or arithmetic mean over the other parameters, thick."""
    import matplotlib.pyplot as plt

    params = _parameters(ds)
    if axes is None:
        _, axes = plt.subplots(1, len(params), figsize=(3.6 * len(params), 3.6), sharey=True, squeeze=False)
        axes = axes[0]
    da = ds[metric]
    for ax, p in zip(axes, params, strict=True):
        x = ds[p].values
        others = [q for q in params if q != p]
        lines = da.transpose(p, *others).values.reshape(len(x), -1)
        for j in range(lines.shape[1]):
            ax.plot(x, lines[:, j], color="0.6", lw=0.8, marker=".", ms=4)
        with np.errstate(divide="ignore"):
            mean = np.exp(np.nanmean(np.log(lines), axis=1)) if log else np.nanmean(lines, axis=1)
        ax.plot(x, mean, color="tab:blue", lw=2.2, marker="o", label="mean over the others")
        if log:
            ax.set_yscale("log")
        ax.set_xlabel(f"{p}" + (f" [{ds[p].attrs['units']}]" if "units" in ds[p].attrs else ""))
        ax.grid(alpha=0.3, which="both")
    axes[0].set_ylabel(label or metric)
    axes[0].legend(fontsize=8)
    return axes


def offset_curve(ds: xr.Dataset, *, axes=None, end: str = "B", lines=None):
    """Restoring force (top) and line tensions (bottom) against the offset of a quasi-static offset
    curve (:func:`moorline.quasistatic.studies.offset_curve`).

    Parameters
    ----------
    ds : xarray.Dataset
        The offset curve.
    axes : sequence of two Axes, optional
        Where to draw (default: a new figure with two stacked axes).
    end : {"A", "B"}
        Which end's tension to draw (B: fairlead, A: anchor).
    lines : iterable of int, optional
        Line numbers to draw (default all).
    """
    if axes is None:
        import matplotlib.pyplot as plt

        axes = plt.subplots(2, 1, figsize=(7.0, 6.0), sharex=True)[1]
    rot = ds.offset.attrs.get("units") == "rad"
    x = np.degrees(ds.offset.values) if rot else ds.offset.values
    scale = 1e-6 if rot else 1e-3
    axes[0].plot(x, ds.restoring.values * scale, color="k", lw=1.8)
    axes[0].set_ylabel("restoring moment [MN m]" if rot else "restoring force [kN]")
    head = f" at {ds.attrs['heading_deg']:g} deg" if ds.attrs.get("dof") in ("surge", "sway") else ""
    axes[0].set_title(f"{ds.attrs.get('dof', 'offset')} offset{head}: {ds.attrs.get('target', '')}", fontsize=10)
    sel = ds.line.values if lines is None else list(lines)
    colors = _colors(len(sel))
    for c, ln in zip(colors, sel, strict=True):
        axes[1].plot(x, ds.tension.sel(line=ln, end=end).values * 1e-3, color=c, lw=1.3, label=f"line {ln}")
    axes[1].set_ylabel(f"{'fairlead' if end == 'B' else 'anchor'} tension [kN]")
    axes[1].set_xlabel(f"{ds.attrs.get('dof', 'offset')} offset [{'deg' if rot else 'm'}]")
    if len(sel) <= 12:
        axes[1].legend(fontsize=8, ncol=2 if len(sel) > 4 else 1)
    for ax in axes:
        ax.grid(alpha=0.3)
    return axes


def watch_circle(ds: xr.Dataset, *, ax=None, color_by_tension: bool = True):
    """Mean offsets of a quasi-static watch circle (:func:`moorline.quasistatic.studies.watch_circle`)
    in the horizontal plane, coloured by the largest line tension."""
    ax = _axes(ax, figsize=(5.6, 5.0))
    x = np.append(ds.offset_x.values, ds.offset_x.values[:1])
    y = np.append(ds.offset_y.values, ds.offset_y.values[:1])
    ax.plot(x, y, color="0.4", lw=1.0)
    if color_by_tension:
        sc = ax.scatter(ds.offset_x, ds.offset_y, c=ds.max_tension.values * 1e-3, cmap="viridis", zorder=3)
        ax.figure.colorbar(sc, ax=ax, label="largest line tension [kN]")
    ax.plot(0.0, 0.0, "k+", ms=10)
    ax.set_aspect("equal")
    ax.set_xlabel("offset x [m]")
    ax.set_ylabel("offset y [m]")
    ax.set_title(f"watch circle, {ds.attrs.get('force_N', 0.0) / 1e3:g} kN", fontsize=10)
    ax.grid(alpha=0.3)
    return ax


def _edges(c: np.ndarray) -> np.ndarray:
    """Cell edges around bin centres."""
    c = np.asarray(c, dtype=float)
    if c.size == 1:
        return np.array([c[0] - 0.5, c[0] + 0.5])
    mid = 0.5 * (c[1:] + c[:-1])
    return np.concatenate([[c[0] - (mid[0] - c[0])], mid, [c[-1] + (c[-1] - mid[-1])]])


def _colors(n: int):
    import matplotlib.pyplot as plt

    cmap = plt.get_cmap("viridis")
    return [cmap(i / max(n - 1, 1)) for i in range(n)]


def rao(ds: xr.Dataset, dofs, *, ax=None, period: bool = True, time_domain=None, labels=None):
    """Amplitudes of response amplitude operators against period (or frequency).

    Parameters
    ----------
    ds : xarray.Dataset
        From :func:`moorline.hydro.rao` (variable ``rao`` over omega and influenced_dof).
    dofs : list of str
        DOF labels to draw (e.g. ``["body1__Heave", "body2__Heave"]``).
    time_domain : dict, optional
        ``{dof: (omega array, amplitude array)}`` steady time-domain amplitudes per unit wave
        amplitude, drawn as markers on the same axes.
    """
    ax = _axes(ax)
    w = ds["omega"].values
    x = 2 * np.pi / w if period else w
    for k, dof in enumerate(dofs):
        label = labels[k] if labels else dof
        line, = ax.plot(x, np.abs(ds["rao"].sel(influenced_dof=dof).values), label=f"{label} (frequency domain)")
        if time_domain and dof in time_domain:
            wt, amp = time_domain[dof]
            xt = 2 * np.pi / np.asarray(wt) if period else np.asarray(wt)
            ax.plot(xt, amp, "o", color=line.get_color(), label=f"{label} (time domain)")
    ax.set_xlabel("wave period [s]" if period else "wave frequency [rad/s]")
    ax.set_ylabel("amplitude per unit wave amplitude [m/m, rad/m]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    return ax


def decay(ds: xr.Dataset, body: int, dof: str, *, ax=None, mean=None):
    """A free decay from a run's results: the body's pose component ``dof`` (x, y, z, roll, pitch,
    yaw) against time, with its peaks and the damped period from the zero crossings about ``mean``
    (default: the last sample)."""
    ax = _axes(ax)
    t = ds["time"].values
    x = ds["body_pose"].sel(body=body, pose=dof).values
    m = x[-1] if mean is None else mean
    ax.plot(t, x, lw=1.2)
    d = x - m
    i = np.where(np.sign(d[:-1]) != np.sign(d[1:]))[0]
    if i.size >= 3:
        zc = t[i] - d[i] * (t[i + 1] - t[i]) / (d[i + 1] - d[i])
        period = 2.0 * float(np.mean(np.diff(zc)))
        ax.set_title(f"body {body} {dof} decay: damped period {period:.3g} s", fontsize=10)
    unit = "m" if dof in ("x", "y", "z") else "rad"
    ax.set_xlabel("time [s]")
    ax.set_ylabel(f"{dof} [{unit}]")
    ax.grid(True, alpha=0.3)
    return ax

