"""Quasi-static studies as :class:`xarray.Dataset`: one equilibrium (:func:`solution_dataset`),
offset curves (:func:`offset_curve`) and watch circles (:func:`watch_circle`).

The *target* of a study is what moves: a coupled body (its 6 DOFs, about its reference point), or,
for decks whose fairleads are coupled points (MoorDyn's usual "vessel" points), all coupled points
moved together as one rigid floater about a centre (default the origin). Loads on the target are the
mooring loads on it [N, N m], global axes, about its reference point (the centre for points).
"""

from __future__ import annotations

import math

import numpy as np
import xarray as xr

from ..model import rotation_xyz
from .solver import QuasiStaticError, QuasiStaticModel, QuasiStaticSolution

__all__ = ["Target", "displace_coupled", "offset_curve", "solution_dataset", "watch_circle"]

_SIX = ["x", "y", "z", "roll", "pitch", "yaw"]
_UNITS6 = "N (x, y, z), N m (roll, pitch, yaw)"


class Target:
    """What an offset study moves: one coupled body, or all coupled points as one rigid floater.

    Parameters
    ----------
    qs : QuasiStaticModel
    body : int, optional
        1-based number of a coupled body (6 coupled DOFs). Default: the first coupled body, else the
        coupled points.
    center : array_like, shape (3,), optional
        Centre of the rigid motion of coupled points [m] (default the origin).
    points : bool
        Move the coupled points even when the system has coupled bodies.
    """

    def __init__(self, qs: QuasiStaticModel, body: int | None = None, center=(0.0, 0.0, 0.0), *,
                 points: bool = False):
        self.qs = qs
        labels = qs.coupled_dof_labels
        nc = qs.n_coupled_dof
        if body is None and not points:
            six = [lab[:-4] for lab in labels if lab.startswith("B") and lab.endswith("_yaw")]
            body = int(six[0][1:]) if six else None
        self.center = np.asarray(center, dtype=float).reshape(3)
        if body is not None:
            name = f"B{int(body)}_"
            idx = [i for i, lab in enumerate(labels) if lab.startswith(name)]
            if len(idx) != 6:
                raise QuasiStaticError(f"body {body} is not a coupled body with 6 DOFs (coupled DOFs: "
                                       f"{', '.join(labels) or 'none'})")
            self.body = int(body)
            self.idx = np.array(idx)
            self.points = []
            self.label = f"body {body}"
        else:
            pts = sorted({int(lab[1:lab.index("_")]) for lab in labels if lab.startswith("P")})
            if not pts:
                raise QuasiStaticError("the system has no coupled body or coupled point to move")
            self.body = None
            self.points = pts
            self.idx = None
            self.label = "coupled points " + ", ".join(str(p) for p in pts)
        self.nc = nc

    def place(self, x0: np.ndarray, dq) -> np.ndarray:
        """The coupled DOF vector with the target displaced by ``dq`` = (dx, dy, dz [m], droll, dpitch,
        dyaw [rad]) from ``x0`` (for a body the angles are added to its Euler angles; coupled points
        turn about the centre by ``R(dq) (r - c)``)."""
        x = np.array(x0, dtype=float)
        dq = np.asarray(dq, dtype=float)
        if self.body is not None:
            x[self.idx] += dq
            return x
        R = rotation_xyz(dq[3:])
        for p in self.points:
            k = self.qs.coupled_dof_labels.index(f"P{p}_x")
            x[k:k + 3] = self.center + dq[:3] + R @ (x0[k:k + 3] - self.center)
        return x

    def map(self, x: np.ndarray) -> np.ndarray:
        """``B`` (nc, 6): coupled DOF increments of a small rigid motion of the target (small rotations)."""
        B = np.zeros((self.nc, 6))
        if self.body is not None:
            B[self.idx, np.arange(6)] = 1.0
            return B
        for p in self.points:
            k = self.qs.coupled_dof_labels.index(f"P{p}_x")
            a = x[k:k + 3] - self.center
            B[k:k + 3, :3] = np.eye(3)
            B[k:k + 3, 3:] = -np.array([[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]])
        return B

    def loads(self, sol: QuasiStaticSolution) -> np.ndarray:
        """Mooring loads on the target (6,) [N, N m] (about the centre for coupled points)."""
        return self.map(sol.x).T @ sol.loads

    def stiffness(self, sol: QuasiStaticSolution) -> np.ndarray:
        """Stiffness of the target (6, 6) (``B^T K B``)."""
        B = self.map(sol.x)
        return B.T @ sol.stiffness @ B


def solution_dataset(qs: QuasiStaticModel, sol: QuasiStaticSolution | None = None) -> xr.Dataset:
    """One quasi-static solution as a Dataset (dims ``line``, ``end``, ``point``, ``body``, ``dof``,
    ``coupled_dof``).

    Variables: ``tension`` (line, end) [N]; ``grounded_length`` (line) [m]; ``point_position`` (point,
    xyz) [m]; ``body_pose`` (body, dof) [m, rad]; ``mooring_load`` (coupled_dof) [N, N m]; ``stiffness``
    (coupled_dof, coupled_dof_j) [N/m, N/rad, N m/m, N m/rad]; ``tension_gradient`` (line, end,
    coupled_dof) when the solution has it.
    """
    if sol is None:
        sol = qs.solve(gradients=True)
    m = qs.model
    lines = np.arange(1, len(m.lines) + 1)
    state = qs.line_state()
    labels = list(qs.coupled_dof_labels)
    data = {
        "tension": (("line", "end"), sol.tensions, {"units": "N", "long_name": "line tension at end A (anchor) "
                                                    "and end B (fairlead)"}),
        "grounded_length": ("line", state["grounded_length"], {"units": "m", "long_name": "unstretched length "
                                                               "lying on the seabed"}),
        "point_position": (("point", "xyz"), sol.points, {"units": "m"}),
        "body_pose": (("body", "dof"), sol.bodies, {"units": "m (x, y, z), rad (roll, pitch, yaw)"}),
        "mooring_load": ("coupled_dof", sol.loads, {"units": "N, N m",
                                                    "long_name": "mooring loads on the coupled DOFs"}),
    }
    if sol.stiffness is not None:
        data["stiffness"] = (("coupled_dof", "coupled_dof_j"), sol.stiffness,
                             {"units": "N/m, N/rad, N m/m, N m/rad", "long_name": "-d load / d x (small rotations "
                              "about the global axes)"})
    if sol.tension_gradient is not None:
        data["tension_gradient"] = (("line", "end", "coupled_dof"), sol.tension_gradient, {"units": "N/m, N/rad"})
    coords = {"line": lines, "end": ["A", "B"], "point": np.arange(1, len(m.points) + 1), "xyz": list("xyz"),
              "body": np.arange(1, len(m.bodies) + 1), "dof": _SIX, "coupled_dof": labels, "coupled_dof_j": labels}
    return xr.Dataset(data, coords=coords, attrs={"model": "quasi-static (elastic catenary lines)",
                                                  "source": str(m.source or ""), "iterations": sol.iterations})


def _direction(dof: str, heading: float) -> np.ndarray:
    """Unit rigid motion (6,) of an offset study: surge/sway along ``heading`` [deg], or one DOF."""
    h = math.radians(heading)
    d = np.zeros(6)
    if dof == "surge":
        d[:2] = (math.cos(h), math.sin(h))
    elif dof == "sway":
        d[:2] = (-math.sin(h), math.cos(h))
    elif dof in _SIX:
        d[_SIX.index(dof)] = 1.0
    elif dof == "heave":
        d[2] = 1.0
    else:
        raise QuasiStaticError(f"offset dof must be surge, sway, heave or one of {_SIX}, got {dof!r}")
    return d


def offset_curve(qs: QuasiStaticModel, offsets, *, heading: float = 0.0, dof: str = "surge", x0=None,
                 body: int | None = None, center=(0.0, 0.0, 0.0)) -> xr.Dataset:
    """Restoring load and line tensions against an offset of the floater.

    Parameters
    ----------
    qs : QuasiStaticModel
    offsets : array_like, shape (n,)
        Offsets [m] (surge, sway, heave, x, y, z) or [rad] (roll, pitch, yaw), solved in this order
        (each warm-started from the previous one).
    heading : float
        Direction of a surge offset [deg] from the x axis, counter-clockwise seen from above (sway is
        90 deg further).
    dof : str
        ``surge``, ``sway``, ``heave`` or one of x, y, z, roll, pitch, yaw.
    x0 : array_like, optional
        Coupled DOFs at zero offset (default: the deck positions).
    body, center
        The target (see :class:`Target`).

    Returns
    -------
    xarray.Dataset
        Dims ``offset``, ``line``, ``end``, ``dof``: ``mooring_load`` (offset, dof) loads on the target;
        ``restoring`` (offset) = minus the load along the offset direction [N or N m]; ``stiffness``
        (offset) along it (the analytic ``d^T K d``); ``tension`` (offset, line, end) [N];
        ``max_tension`` (offset) [N].
    """
    target = Target(qs, body, center)
    x0 = qs.deck_coupled_positions() if x0 is None else np.asarray(x0, dtype=float)
    d = _direction(dof, heading)
    offsets = np.asarray(offsets, dtype=float).ravel()
    n = offsets.size
    nL = len(qs.model.lines)
    load = np.zeros((n, 6))
    ten = np.zeros((n, nL, 2))
    kdir = np.zeros(n)
    for i, a in enumerate(offsets):
        sol = qs.solve(target.place(x0, a * d))
        load[i] = target.loads(sol)
        kdir[i] = d @ target.stiffness(sol) @ d
        ten[i] = sol.tensions
    rot = dof in ("roll", "pitch", "yaw")
    units = "rad" if rot else "m"
    return xr.Dataset(
        {"mooring_load": (("offset", "dof"), load, {"units": _UNITS6, "long_name": f"mooring loads on {target.label}"}),
         "restoring": ("offset", -(load @ d), {"units": "N m" if rot else "N",
                                               "long_name": f"restoring {'moment' if rot else 'force'} along the "
                                               "offset"}),
         "stiffness": ("offset", kdir, {"units": "N m/rad" if rot else "N/m", "long_name": "analytic stiffness "
                                        "along the offset"}),
         "tension": (("offset", "line", "end"), ten, {"units": "N"}),
         "max_tension": ("offset", ten.max(axis=(1, 2)), {"units": "N"})},
        coords={"offset": ("offset", offsets, {"units": units}), "line": np.arange(1, nL + 1), "end": ["A", "B"],
                "dof": _SIX},
        attrs={"dof": dof, "heading_deg": float(heading), "target": target.label, "source": str(qs.model.source or "")})


def watch_circle(qs: QuasiStaticModel, force: float, headings=None, *, x0=None, body: int | None = None,
                 center=(0.0, 0.0, 0.0), tol: float = 1e-6, max_iter: int = 50) -> xr.Dataset:
    """Mean horizontal offsets of the floater under a steady horizontal force from every heading.

    The target moves in surge and sway only (heave and rotations stay at ``x0``) until the mooring's
    horizontal load balances ``force`` acting towards each heading (Newton with the analytic
    stiffness). Offsets are measured from ``x0``; with ``force = 0`` the result is the neutral position
    where the horizontal mooring load vanishes (``x0`` itself for a symmetric pattern).

    Parameters
    ----------
    qs : QuasiStaticModel
    force : float
        Magnitude of the horizontal environmental force [N].
    headings : array_like, optional
        Directions the force acts towards [deg] (default every 10 deg).
    x0, body, center
        As in :func:`offset_curve`.
    tol : float
        Convergence tolerance on the force balance, relative to ``force`` [-].
    max_iter : int
        Newton iterations per heading.

    Returns
    -------
    xarray.Dataset
        Dims ``heading``, ``line``, ``end``: ``offset_x``, ``offset_y``, ``offset`` [m]; ``tension``
        (heading, line, end) [N]; ``max_tension`` (heading) [N].
    """
    target = Target(qs, body, center)
    x0 = qs.deck_coupled_positions() if x0 is None else np.asarray(x0, dtype=float)
    headings = np.arange(0.0, 360.0, 10.0) if headings is None else np.asarray(headings, dtype=float).ravel()
    nL = len(qs.model.lines)
    ox = np.zeros(headings.size)
    oy = np.zeros(headings.size)
    ten = np.zeros((headings.size, nL, 2))
    xy = np.zeros(2)
    for i, h in enumerate(headings):
        F = force * np.array([math.cos(math.radians(h)), math.sin(math.radians(h))])
        for _ in range(max_iter):
            sol = qs.solve(target.place(x0, np.r_[xy, 0.0, 0.0, 0.0, 0.0]))
            r = target.loads(sol)[:2] + F
            if np.max(np.abs(r)) <= tol * max(force, 1.0):
                break
            K = target.stiffness(sol)[:2, :2]
            step = np.linalg.solve(K, r)
            lim = 0.1 * float(np.min(qs.lf[:, 0]))
            if np.max(np.abs(step)) > lim:
                step *= lim / np.max(np.abs(step))
            xy = xy + step
        else:
            raise QuasiStaticError(f"watch circle: no balance of {force:.6g} N towards {h:g} deg after {max_iter} "
                                   "iterations")
        ox[i], oy[i] = xy
        ten[i] = sol.tensions
    return xr.Dataset(
        {"offset_x": ("heading", ox, {"units": "m"}), "offset_y": ("heading", oy, {"units": "m"}),
         "offset": ("heading", np.hypot(ox, oy), {"units": "m"}),
         "tension": (("heading", "line", "end"), ten, {"units": "N"}),
         "max_tension": ("heading", ten.max(axis=(1, 2)), {"units": "N"})},
        coords={"heading": ("heading", headings, {"units": "deg", "long_name": "direction the force acts towards"}),
                "line": np.arange(1, nL + 1), "end": ["A", "B"]},
        attrs={"force_N": float(force), "target": target.label, "source": str(qs.model.source or "")})


def displace_coupled(qs: QuasiStaticModel, dq, x0=None) -> np.ndarray:
    """The coupled DOF vector with every coupled object displaced by the rigid motion ``dq`` = (dx,
    dy, dz [m], droll, dpitch, dyaw [rad]) from ``x0`` (default the deck): coupled bodies add it to
    their pose, coupled points move as one rigid floater about the origin."""
    x = qs.deck_coupled_positions() if x0 is None else np.asarray(x0, dtype=float).copy()
    dq = np.asarray(dq, dtype=float).reshape(6)
    labels = qs.coupled_dof_labels
    if not labels:
        raise QuasiStaticError("the system has no coupled body or coupled point to displace")
    bodies = sorted({int(lab[1:lab.index("_")]) for lab in labels if lab.startswith("B")})
    for b in bodies:
        idx = [i for i, lab in enumerate(labels) if lab.startswith(f"B{b}_")]
        x[idx] += dq[:len(idx)]
    if any(lab.startswith("P") for lab in labels):
        x = Target(qs, points=True).place(x, dq)
    return x

