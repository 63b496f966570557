"""Simulation results as a labelled :class:`xarray.Dataset`, its NetCDF writer, and
:class:`NetCDFStream`, which writes them as a run goes (attribute ``complete`` 0 until it ends).

Dimensions: ``time``, ``node`` (all nodes of all lines), ``segment`` (all segments), ``line``,
``point``, ``xyz`` and ``dof`` (coupled DOFs). Node and segment coordinates say which line they
belong to, their index within it and their unstretched arc length from end A, so lines of
different lengths share one Dataset: ``ds.node_position.where(ds.node_line == 2, drop=True)``.
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict
from pathlib import Path

import h5netcdf
import numpy as np
import xarray as xr

from . import __version__
from .core.layout import FC_NAMES
from .errors import CheckpointError
from .io.atomic import atomic_path


def model_hash(model) -> str:
    """SHA-256 of the deck text (or of the model description when built in Python)."""
    h = hashlib.sha256()
    if model.source is not None and Path(model.source).exists():
        h.update(Path(model.source).read_bytes())
    else:
        h.update(repr((model.line_types, model.points, model.lines, model.env, model.options)).encode())
    return h.hexdigest()


def _environment_summary(env) -> dict:
    """The environment as JSON-ready values; a bathymetry grid is named by its source and size."""
    out = asdict(env)
    for key in ("waves", "current"):
        w = getattr(env, key)
        out[key] = getattr(w, "source", "") or (type(w).__name__ if w is not None else None)
    b = env.bathymetry
    if b is not None:
        out["bathymetry"] = {"source": b.source, "nx": int(b.x.size), "ny": int(b.y.size),
                             "x_range": [float(b.x[0]), float(b.x[-1])], "y_range": [float(b.y[0]), float(b.y[-1])],
                             "z_range": [float(b.z.min()), float(b.z.max())]}
    return out


def _cat(arrays) -> np.ndarray:
    return np.concatenate(arrays) if len(arrays) else np.zeros(0)


class Recorder:
    """Collects the state of a :class:`~moorline.system.System` at output times.

    Parameters
    ----------
    system : System
    nodes : bool
        Record node positions, velocities, tensions and curvatures (the bulk of the data).
    """

    def __init__(self, system, *, nodes: bool = True, probes=None):
        self.system = system
        self.nodes = nodes
        self.probes = None if probes is None else np.asarray(probes, dtype=float).reshape(-1, 3)
        self.t: list[float] = []
        #: the points recorded: those of the model at the start (a line failure adds free points to
        #: the running system; their motion is that of the released line ends' nodes)
        self.n_points = len(system.points)
        self.data: dict[str, list] = {k: [] for k in (
            "node_position", "node_velocity", "node_tension", "node_curvature", "node_bending_moment",
            "segment_tension",
            "segment_strain", "line_tension_a", "line_tension_b", "point_position", "point_velocity",
            "point_force", "coupled_position", "coupled_force", "rod_end_position", "rod_force", "body_pose",
            "body_velocity", "body_force", "probe_kinematics", "float_force", "float_displacement", "joint_slide",
            "joint_slide_rate", "pto_power")}

    def record(self) -> None:
        s = self.system
        w = s.work
        self.t.append(s.t)
        d = self.data
        if self.nodes:
            d["node_position"].append(w.r.copy())
            d["node_velocity"].append(w.v.copy())
            d["node_tension"].append(_cat([ln.node_tensions() for ln in s.lines]))
            d["node_curvature"].append(_cat([ln.node_curvatures() for ln in s.lines]))
            d["node_bending_moment"].append(_cat([ln.node_bending_moments() for ln in s.lines]))
        d["segment_tension"].append(np.linalg.norm(w.T + w.Td, axis=1))
        d["segment_strain"].append(w.seg_len / s.layout.lines.seg_l0 - 1.0)
        T = s.line_end_tensions()  # the quasi-static lines' in the quasi-static mode
        d["line_tension_a"].append(T[:, 0])
        d["line_tension_b"].append(T[:, 1])
        n = self.n_points
        d["point_position"].append(w.pr[:n].copy())
        d["point_velocity"].append(w.pv[:n].copy())
        d["point_force"].append(w.pF[:n].copy())
        d["coupled_position"].append(w.xc.copy())
        d["coupled_force"].append(s.coupled_forces())
        if s.rods:
            d["rod_end_position"].append(w.rodr.copy())
            d["rod_force"].append(w.rod6F.copy())
        if self.probes is not None:
            d["probe_kinematics"].append(s.water_at(self.probes))
        if s.bodies:
            d["body_pose"].append(np.array([b.pose() for b in s.bodies]))
            d["body_velocity"].append(np.concatenate([w.bv, w.bw], axis=1))
            d["body_force"].append(w.b6F.copy())
        fl = s.layout.fl
        if fl.body.size:
            d["float_force"].append(s.fwork.F.copy())
            d["float_displacement"].append(s.fwork.xi.copy())
            if fl.jt_child.size:
                d["joint_slide"].append(s.fwork.jt[:, 0].copy())
                d["joint_slide_rate"].append(s.fwork.jt[:, 1].copy())
                d["pto_power"].append(s.fwork.jt[:, 2].copy())

    def to_dataset(self, start: int = 0, stop: int | None = None) -> xr.Dataset:
        """The samples ``start:stop`` (default all) as a Dataset."""
        s = self.system
        lay = s.layout
        nl = len(s.lines)
        node_line = np.repeat(np.arange(1, nl + 1), lay.line_N + 1)
        node_index = _cat([np.arange(n + 1) for n in lay.line_N]).astype(int)
        node_s = _cat([np.linspace(0.0, lay.line_L[i], lay.line_N[i] + 1) for i in range(nl)])
        seg_line = np.repeat(np.arange(1, nl + 1), lay.line_N)
        seg_index = _cat([np.arange(1, n + 1) for n in lay.line_N]).astype(int)
        seg_s = _cat([(np.arange(lay.line_N[i]) + 0.5) * lay.line_L[i] / lay.line_N[i] for i in range(nl)])
        d = {k: np.asarray(v[start:stop]) for k, v in self.data.items() if len(v)}
        T = ("time",)
        dv = {}

        def add(name, dims, attrs):
            if name in d:
                dv[name] = (T + dims, d[name], attrs)

        add("node_position", ("node", "xyz"), {"units": "m", "long_name": "node position"})
        add("node_velocity", ("node", "xyz"), {"units": "m/s", "long_name": "node velocity"})
        add("node_tension", ("node",), {"units": "N", "long_name": "node tension (mean of adjacent segments)"})
        add("node_curvature", ("node",), {"units": "1/m", "long_name": "curvature"})
        add("node_bending_moment", ("node",), {"units": "N m", "long_name": "bending moment (0 without EI)"})
        add("segment_tension", ("segment",), {"units": "N", "long_name": "segment tension incl. damping |T+Td|"})
        add("segment_strain", ("segment",), {"units": "1", "long_name": "segment strain"})
        add("line_tension_a", ("line",), {"units": "N", "long_name": "end-A segment tension |T+Td|"})
        add("line_tension_b", ("line",), {"units": "N", "long_name": "end-B (fairlead) segment tension |T+Td|"})
        add("point_position", ("point", "xyz"), {"units": "m"})
        add("point_velocity", ("point", "xyz"), {"units": "m/s"})
        add("point_force", ("point", "xyz"), {"units": "N", "long_name": "net force on the point"})
        add("rod_end_position", ("rod", "rod_end", "xyz"), {"units": "m", "long_name": "rod end positions"})
        add("rod_force", ("rod", "dof6"), {"units": "N, N m", "long_name": "net force and moment about end A"})
        add("body_pose", ("body", "pose"), {"units": "m, rad", "long_name": "reference point and roll, pitch, yaw "
                                            "(R = Rx Ry Rz)"})
        add("body_velocity", ("body", "dof6"), {"units": "m/s, rad/s", "long_name": "velocity and angular velocity"})
        add("body_force", ("body", "dof6"), {"units": "N, N m", "long_name": "net force and moment about the "
                                             "reference point"})
        add("float_force", ("floating_body", "force_component", "dof6"),
            {"units": "N, N m", "long_name": "potential-flow and extra loads on each floating body about its "
                                             "reference point (radiation: memory part; A_inf acts through the mass)"})
        add("float_displacement", ("floating_body", "dof6"),
            {"units": "m, rad", "long_name": "displacement from the mean pose (hydrostatics are linear in it)"})
        add("joint_slide", ("joint",), {"units": "m", "long_name": "slide of the joint's child along its axis"})
        add("joint_slide_rate", ("joint",), {"units": "m/s"})
        add("pto_power", ("joint",), {"units": "W", "long_name": "power absorbed by the PTO damper c s'^2"})
        if "probe_kinematics" in d:
            pk = d.pop("probe_kinematics")
            d["probe_velocity"], d["probe_acceleration"] = pk[:, :, 0:3], pk[:, :, 3:6]
            d["probe_elevation"], d["probe_pressure"] = pk[:, :, 6], pk[:, :, 7]
            add("probe_elevation", ("probe",), {"units": "m", "long_name": "wave surface elevation"})
            add("probe_velocity", ("probe", "xyz"), {"units": "m/s", "long_name": "water velocity (waves + current)"})
            add("probe_acceleration", ("probe", "xyz"), {"units": "m/s^2", "long_name": "water acceleration"})
            add("probe_pressure", ("probe",), {"units": "Pa", "long_name": "wave dynamic pressure"})
        if s.n_coupled_dof:
            add("coupled_position", ("dof",), {"units": "m"})
            add("coupled_force", ("dof",), {"units": "N", "long_name": "load of the mooring on the coupled DOF"})
        coords = {
            "time": ("time", np.asarray(self.t[start:stop], dtype=float), {"units": "s"}),
            "xyz": ("xyz", ["x", "y", "z"]),
            "line": ("line", np.arange(1, (d["line_tension_b"].shape[1] if "line_tension_b" in d else nl) + 1)),
            "point": ("point", np.arange(1, self.n_points + 1)),
            "node_line": ("node", node_line),
            "node_index": ("node", node_index),
            "node_s": ("node", node_s, {"units": "m", "long_name": "unstretched arc length from end A"}),
            "segment_line": ("segment", seg_line),
            "segment_index": ("segment", seg_index),
            "segment_s": ("segment", seg_s, {"units": "m"}),
            "line_type": ("line", np.array([ln.line_type for ln in s.full_model.lines], dtype=str)),
            "point_kind": ("point", np.array([p.kind.name.lower() for p in s.model.points[:self.n_points]],
                                          dtype=str)),
        }
        if s.n_coupled_dof:
            coords["dof"] = ("dof", s.coupled_dof_labels)
        if s.rods:
            coords["rod"] = ("rod", np.arange(1, len(s.rods) + 1))
            coords["rod_end"] = ("rod_end", ["A", "B"])
        if s.rods or s.bodies:
            coords["dof6"] = ("dof6", ["x", "y", "z", "rx", "ry", "rz"])
        if self.probes is not None:
            coords["probe_position"] = (("probe", "xyz"), self.probes, {"units": "m"})
        if s.bodies:
            coords["body"] = ("body", np.arange(1, len(s.bodies) + 1))
            coords["pose"] = ("pose", ["x", "y", "z", "roll", "pitch", "yaw"])
        fl = lay.fl
        if fl.body.size:
            coords["floating_body"] = ("floating_body", fl.body + 1, {"long_name": "deck body number"})
            coords["force_component"] = ("force_component", list(FC_NAMES))
            if fl.jt_child.size:
                coords["joint"] = ("joint", np.arange(1, fl.jt_child.size + 1))
        opts = asdict(s.model.options)
        attrs = {
            "title": f"moorline simulation of {s.model.source.name if s.model.source else 'a Python-built model'}",
            "moorline_version": __version__,
            "input_sha256": model_hash(s.model),
            "source": str(s.model.source) if s.model.source else "",
            "time_scheme": s.scheme_label,
            "dtM": s.dtM,
            "options": json.dumps(opts, default=str),
            "environment": json.dumps(_environment_summary(s.model.env)),
            "ic": json.dumps(s.ic_report, default=str),
            # the initial state: how it was found, whether it is at rest, and its largest residual
            # acceleration of a free DOF at zero velocity [m/s^2] (-1: not measured, no IC solve)
            "ic_method": str(s.ic_report.get("method", "catenary start")),
            "ic_converged": int(bool(s.ic_report.get("converged", True))),
            "ic_residual": float(s.ic_report.get("residual", -1.0)),
        }
        return xr.Dataset(dv, coords=coords, attrs=attrs)


def write_netcdf(ds: xr.Dataset, path, *, unlimited_dims=None) -> Path:
    """Write ``ds`` to ``path`` atomically (a temporary file renamed into place); ``unlimited_dims``
    as xarray's (dimensions a later append may extend)."""
    path = Path(path)
    with atomic_path(path) as tmp:
        ds.to_netcdf(tmp, engine="h5netcdf", unlimited_dims=unlimited_dims)
    return path


class NetCDFStream:
    """Writes the samples of a :class:`Recorder` to a NetCDF file as a run goes.

    The file is created at the first :meth:`flush` (with an unlimited ``time`` dimension) and the
    samples recorded since are appended at every later flush, the file being opened, extended
    and closed each time, so a run that is killed leaves a valid file up to its last flush. Its
    attribute ``complete`` is 0 until :meth:`finish` sets it to 1 (a run that stops on an error
    keeps 0 and says why in ``status``); ``simulated_until`` is the time of the last sample.

    Parameters
    ----------
    path : path-like
    resume : dict, optional
        A checkpoint's cursor (:meth:`cursor`): the file is cut back to the samples it had when the
        checkpoint was written, and appended to.
    """

    name = "netcdf"

    def __init__(self, path, *, resume: dict | None = None):
        self.path = Path(path)
        self._resume = resume
        self.recorder: Recorder | None = None
        self.rows = 0
        self._flushed = 0
        self._t_written = -np.inf

    @property
    def paths(self) -> list[Path]:
        """The file, once written."""
        return [self.path] if self.rows else []

    def start(self, system, recorder: Recorder) -> None:
        self.recorder = recorder
        if self._resume is None:
            return
        rows = int(self._resume["rows"])
        try:
            with h5netcdf.File(self.path, "a") as f:
                have = f.dimensions["time"].size
                if have < rows:
                    raise CheckpointError(f"{self.path} has {have} samples, fewer than the {rows} it had when the "
                                          "checkpoint was written")
                f.resize_dimension("time", rows)
                f.attrs["complete"] = 0
                self._t_written = float(f.variables["time"][rows - 1]) if rows else -np.inf
        except OSError as e:
            raise CheckpointError(f"cannot reopen the results of the interrupted run: {e}") from None
        self.rows = rows

    def record(self, system) -> None:
        """Nothing to do: the run's Recorder holds the samples."""

    def flush(self) -> None:
        """Append the samples recorded since the last flush."""
        rec = self.recorder
        n = len(rec.t)
        start = self._flushed
        while start < n and rec.t[start] <= self._t_written:
            start += 1
        self._flushed = n
        if start >= n:
            return
        ds = rec.to_dataset(start, n)
        if self.rows == 0:
            ds.attrs.update(complete=0, simulated_until=float(rec.t[n - 1]))
            write_netcdf(ds, self.path, unlimited_dims=["time"])
        else:
            with h5netcdf.File(self.path, "a") as f:
                n0 = f.dimensions["time"].size
                f.resize_dimension("time", n0 + n - start)
                for name, var in ds.variables.items():
                    if var.dims and var.dims[0] == "time":
                        f.variables[name][n0:] = var.values
                f.attrs["simulated_until"] = float(rec.t[n - 1])
        self.rows += n - start
        self._t_written = rec.t[n - 1]

    def finish(self, error: BaseException | None = None, attrs: dict | None = None) -> None:
        """Write what is left and mark the file complete (or, after ``error``, say why it stops)."""
        self.flush()
        if self.rows == 0:
            return
        with h5netcdf.File(self.path, "a") as f:
            for key, val in (attrs or {}).items():
                f.attrs[key] = val
            if error is None:
                f.attrs["complete"] = 1
            else:
                f.attrs["status"] = f"stopped at t = {self._t_written:.6g} s: {error}"

    def cursor(self) -> dict:
        """Samples in the file now (for a checkpoint)."""
        return {"rows": self.rows}
