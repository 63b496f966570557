"""Section loads along a line from a simulation: effective tension, curvature vector and bending
moments about two axes normal to the cable, per node and output time.

The curvature is recomputed from the recorded node positions with the kernel's definition
(spec 3.10, :func:`moorline.core.lines.line_bending`), so its magnitude equals the recorded
``node_curvature``; what the positions add is its direction. At an internal node i between the
unit segment vectors a = e_{i-1} and b = e_i (lengths l_{i-1}, l_i)::

    kappa_i = (4 / (l_{i-1} + l_i)) sin(theta/2) = (4 / (l_{i-1} + l_i)) sqrt((1 - a.b) / 2)
    p_i     = unit(a x b)                        (bending axis; zero when a, b are parallel)
    kappa_vec_i = kappa_i p_i,   M_vec_i = EI kappa_i p_i   (or M(kappa_i) p_i for an EI table)

At an end clamped to a rod the rod axis q plays the role of the missing segment and only the end
segment's length is used (kappa_0 = kappa(l_0, q_0, e_0)); pinned ends have no curvature. Where
the rod axis is not known (a zero-length rod takes its axis from its cables at run time), the
recorded curvature magnitude is kept with the bending axis of the neighbouring node.

Local frame (documented convention, see ``docs/fatigue.md``): at each node the tangent t is the
bisector of the adjacent segment directions (unit(a + b); the end segment at a pinned end,
unit(q + e) at a clamped end), pointing from end A to end B. With ``frame='reference'`` (default)
the first axis normal to the cable, y, is the horizontal normal unit(e_z x t_ref) of the node's
tangent at the first output time (normally the static equilibrium), carried along with the tangent
by projection, y = unit(y_ref - (y_ref . t) t); z = t x y completes the right-handed frame
(t, y, z). For a cable hanging in a vertical plane y is the horizontal normal to that plane at all
times and z is the in-plane normal pointing upward, so My is the in-plane and Mz the
out-of-plane bending moment. The frame does not flip when the tangent passes through the
vertical (a flip would create false stress cycles at a fixed point of the cross-section), which
is why it is attached to the reference tangent rather than to the instantaneous one
(``frame='horizontal'``, y = unit(e_z x t) at every time). Where the reference tangent is
vertical, y_ref = unit(e_y - (e_y . t_ref) t_ref).

With this frame the bending strain at the point r = (d/2)(cos(theta) y + sin(theta) z) of the
section is ((kappa_vec x r) . t), so the stress of :func:`moorline.post.stress.cross_section_stress`
is sigma = N/A + (My (d/2) sin(theta) - Mz (d/2) cos(theta)) / I, tensile positive.
"""

from __future__ import annotations

import logging

import numpy as np
import xarray as xr

log = logging.getLogger("moorline")

#: |e_z x t| below which a tangent counts as vertical when the horizontal normal is formed
VERTICAL_TOL = 1e-6

__all__ = ["clamp_tangents", "line_nodes", "section_loads"]


def line_nodes(ds: xr.Dataset, line: int | None = None) -> tuple[int, xr.Dataset]:
    """The nodes of one line of a results Dataset.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`moorline.simulate`.
    line : int, optional
        1-based line number; default the only line (an error when there are several).

    Returns
    -------
    (int, xarray.Dataset)
        The line number and ``ds`` restricted to that line's nodes (node 0 = end A).
    """
    lines = np.unique(ds.node_line.values)
    if line is None:
        if lines.size != 1:
            raise ValueError(f"the results hold lines {lines.tolist()}; say which one with line=")
        line = int(lines[0])
    if line not in lines:
        raise ValueError(f"no line {line} in the results (lines {lines.tolist()})")
    return int(line), ds.isel(node=np.flatnonzero(ds.node_line.values == line))


def clamp_tangents(model, line: int, ds: xr.Dataset | None = None) -> tuple:
    """Directions q_0 and q_N that the clamps of a line impose (None at an end that is not clamped,
    or whose rod direction is not known here).

    A line end attached to a rod end is clamped when the line has bending stiffness. The cable
    leaves the rod straight: with q_r the rod axis (unit vector from rod end A to rod end B), line
    end A on rod end B gives q_0 = +q_r, on rod end A q_0 = -q_r; line end B on rod end A gives
    q_N = +q_r, on rod end B q_N = -q_r (spec 3.10). The rod axis comes from the results when they
    hold it (a ``rod_axis`` variable, or the ``rod_end_position`` of a rod of non-zero length, at
    every output time), else from the model for a fixed rod of non-zero length (constant).

    Parameters
    ----------
    model : moorline.Model
    line : int
        1-based line number.
    ds : xarray.Dataset, optional
        The results, for rods that move.

    Returns
    -------
    (q_0, q_N)
        Each None, an array (3,) or an array (time, 3).
    """
    ln = model.lines[line - 1]
    lt = model.line_types[ln.line_type]
    out: list = []
    for j, att in enumerate((ln.end_a, ln.end_b)):
        if att.kind != "rod" or not lt.has_bending:
            out.append(None)
            continue
        q = _rod_axis(model, att.index, ds)
        if q is None:
            out.append(None)
            continue
        follows = (j == 0 and att.end == "B") or (j == 1 and att.end == "A")
        out.append(q if follows else -q)
    return out[0], out[1]


def _rod_axis(model, k: int, ds: xr.Dataset | None):
    """Axis of rod k (0-based) [-], (time, 3) from the results or (3,) from the model; None if unknown."""
    if ds is not None and "rod_axis" in ds:
        return np.asarray(ds.rod_axis.isel(rod=k).values, dtype=float)
    if ds is not None and "rod_end_position" in ds:
        ends = ds.rod_end_position.isel(rod=k).values  # (time, 2, 3)
        q, n = _unit(ends[:, 1] - ends[:, 0])
        if np.all(n > 0.0):
            return q
    rod = model.rods[k]
    d = np.asarray(rod.rB, dtype=float) - np.asarray(rod.rA, dtype=float)
    n = np.linalg.norm(d)
    if getattr(rod.kind, "name", "FIXED") == "FIXED" and rod.N > 0 and n > 0.0:  # a zero-length rod turns
        return d / n
    return None


def _unit(v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit vectors along the last axis and the norms; zero vectors stay zero."""
    n = np.linalg.norm(v, axis=-1)
    return v / np.where(n > 0.0, n, 1.0)[..., None], n


def curvature(lam: np.ndarray, a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The kernel's curvature (4/lam) sin(theta/2) = (2/lam) |a - b| between unit vectors ``a``
    and ``b`` (last axis) over the length ``lam``, and the unit bending axis a x b, vectorised
    (see ``moorline.core.lines._kappa``: the chord, not MoorDyn's sqrt((1 - a.b)/2), which
    cancels to round-off on a nearly straight line). Zero where a = b or lam <= 0."""
    kap = 2.0 / np.where(lam > 0.0, lam, 1.0) * np.linalg.norm(a - b, axis=-1)
    ok = (kap > 0.0) & (lam > 0.0)
    p, _ = _unit(np.cross(a, b))
    return np.where(ok, kap, 0.0), np.where(ok[..., None], p, 0.0)


def _horizontal_normal(t: np.ndarray) -> np.ndarray:
    """unit(e_z x t); for a vertical t, the projection of e_y normal to t."""
    y = np.stack([-t[..., 1], t[..., 0], np.zeros_like(t[..., 0])], axis=-1)  # e_z x t
    y, n = _unit(y)
    vert = n < VERTICAL_TOL
    if np.any(vert):
        ey = np.array([0.0, 1.0, 0.0])
        alt, _ = _unit(ey - np.einsum("...k,k->...", t, ey)[..., None] * t)
        y = np.where(vert[..., None], alt, y)
    return y


def _moment_function(EI):
    """M(kappa) [N m] from a constant EI [N m^2], a table with ``x`` (curvature) and ``y``
    (moment) arrays (moorline.model.Curve, clamped at both ends as the kernel does), or a callable."""
    if hasattr(EI, "x") and hasattr(EI, "y"):
        x = np.asarray(EI.x, dtype=float)
        y = np.asarray(EI.y, dtype=float)
        return lambda k: np.interp(k, x, y), "table"
    if callable(EI):
        return EI, "callable"
    EI = float(EI)
    return (lambda k: EI * k), EI


def section_loads(ds: xr.Dataset, line: int | None = None, *, model=None, EI=None, clamps=None,
                  frame: str = "reference") -> xr.Dataset:
    """Effective tension, curvature vector and bending moments of one line, per node and time.

    Parameters
    ----------
    ds : xarray.Dataset
        Results of :func:`moorline.simulate` with node data (``node_position``, ``node_tension``).
    line : int, optional
        1-based line number (default: the only line).
    model : moorline.Model, optional
        The simulated model: gives EI of the line type and the clamp directions of ends attached
        to rods (see :func:`clamp_tangents`).
    EI : float, moorline.model.Curve or callable, optional
        Bending stiffness [N m^2], or a moment-curvature table / function kappa [1/m] -> M [N m];
        overrides the model's.
    clamps : (array_like or None, array_like or None), optional
        Clamp directions (q_0, q_N), each (3,) or (time, 3) (unit vectors pointing along the cable,
        from end A to end B); overrides the model's.
    frame : {'reference', 'horizontal'}
        How the axis y normal to the cable is chosen (see the module docstring).

    Returns
    -------
    xarray.Dataset
        Dimensions (time, node) of the line, plus xyz for vectors:
        ``tension`` [N] (effective tension: MoorDyn's node tension, the mean of the adjacent segment
        forces), ``curvature`` [1/m], ``curvature_vector`` [1/m], ``tangent``, ``axis_y``,
        ``axis_z`` [-], ``kappa_y``, ``kappa_z`` [1/m], ``bending_moment``, ``My``, ``Mz`` [N m].
        The coordinates ``node_s`` (unstretched arc length from end A [m]) and ``node_index``
        come along.

    Raises
    ------
    ValueError
        When the line, EI or frame cannot be determined.
    """
    if frame not in ("reference", "horizontal"):
        raise ValueError(f"frame must be 'reference' or 'horizontal', got {frame!r}")
    line, sub = line_nodes(ds, line)
    if "node_position" not in sub:
        raise ValueError("the results hold no node data (simulate with record_nodes=True)")
    if EI is None:
        if model is None:
            raise ValueError("the bending stiffness is unknown: pass EI= or model=")
        EI = model.line_types[model.lines[line - 1].line_type].EI
    moment, ei_label = _moment_function(EI)
    if clamps is None:
        clamps = clamp_tangents(model, line, sub) if model is not None else (None, None)
    qA, qB = (None if q is None else _unit(np.asarray(q, dtype=float))[0] for q in clamps)

    r = sub.node_position.values  # (T, n, 3)
    if r.shape[1] < 2:
        raise ValueError(f"line {line} has fewer than two nodes")
    e, seg_l = _unit(np.diff(r, axis=1))  # (T, N, 3), (T, N)
    T, n = r.shape[0], r.shape[1]
    kap = np.zeros((T, n))
    p = np.zeros((T, n, 3))
    t = np.empty((T, n, 3))
    if n > 2:
        kap[:, 1:-1], p[:, 1:-1] = curvature(seg_l[:, :-1] + seg_l[:, 1:], e[:, :-1], e[:, 1:])
        bis, nb = _unit(e[:, :-1] + e[:, 1:])
        t[:, 1:-1] = np.where((nb > 0.0)[..., None], bis, e[:, :-1])  # a folded node keeps e_{i-1}
    t[:, 0] = e[:, 0]
    t[:, -1] = e[:, -1]
    for end, q in ((0, qA), (-1, qB)):
        if q is not None:
            qq = np.broadcast_to(q, e[:, end].shape)
            a, b = (qq, e[:, 0]) if end == 0 else (e[:, -1], qq)
            kap[:, end], p[:, end] = curvature(seg_l[:, end], a, b)
            bis, nb = _unit(a + b)
            t[:, end] = np.where((nb > 0.0)[..., None], bis, e[:, end])
        elif "node_curvature" in sub and np.any(sub.node_curvature.values[:, end] > 0.0):
            # clamped in the run, but the clamp direction is unknown here: keep the recorded
            # magnitude and borrow the bending axis of the neighbouring node
            nb_ = 1 if end == 0 else n - 2
            log.warning("line %d end %s has curvature but no clamp direction was given (pass model= or "
                        "clamps=); its bending axis is taken from the neighbouring node", line, "AB"[end])
            kap[:, end] = sub.node_curvature.values[:, end]
            p[:, end] = p[:, nb_]

    if frame == "reference":
        y_ref = _horizontal_normal(t[0])  # (n, 3)
        y, ny = _unit(y_ref - np.einsum("tnk,nk->tn", t, y_ref)[..., None] * t)
        bad = ny < VERTICAL_TOL
        if np.any(bad):  # the tangent turned onto y_ref: fall back to the instantaneous horizontal normal
            y = np.where(bad[..., None], _horizontal_normal(t), y)
    else:
        y = _horizontal_normal(t)
    z = np.cross(t, y)

    kvec = kap[..., None] * p
    ky = np.einsum("tnk,tnk->tn", kvec, y)
    kz = np.einsum("tnk,tnk->tn", kvec, z)
    M = np.asarray(moment(kap), dtype=float)
    My = M * np.einsum("tnk,tnk->tn", p, y)
    Mz = M * np.einsum("tnk,tnk->tn", p, z)

    TN = ("time", "node")
    TNX = ("time", "node", "xyz")
    coords = {c: sub.coords[c] for c in ("time", "node_s", "node_index", "node_line") if c in sub.coords}
    coords["xyz"] = ["x", "y", "z"]
    out = xr.Dataset(
        {
            "tension": (TN, sub.node_tension.values, {"units": "N", "long_name": "effective tension"}),
            "curvature": (TN, kap, {"units": "1/m", "long_name": "curvature (4/lam) sin(theta/2)"}),
            "curvature_vector": (TNX, kvec, {"units": "1/m", "long_name": "curvature times unit bending axis"}),
            "tangent": (TNX, t, {"units": "1", "long_name": "unit tangent (from end A to end B)"}),
            "axis_y": (TNX, y, {"units": "1", "long_name": "section axis y (horizontal normal of the "
                                "reference tangent)" if frame == "reference" else "section axis y"}),
            "axis_z": (TNX, z, {"units": "1", "long_name": "section axis z = t x y"}),
            "kappa_y": (TN, ky, {"units": "1/m", "long_name": "curvature about y"}),
            "kappa_z": (TN, kz, {"units": "1/m", "long_name": "curvature about z"}),
            "bending_moment": (TN, M, {"units": "N m", "long_name": "bending moment magnitude"}),
            "My": (TN, My, {"units": "N m", "long_name": "bending moment about y"}),
            "Mz": (TN, Mz, {"units": "N m", "long_name": "bending moment about z"}),
        },
        coords=coords,
        attrs={"line": line, "frame": frame, "EI": str(ei_label),
               "clamped_ends": "".join(k for k, q in (("A", qA), ("B", qB)) if q is not None)},
    )
    return out
