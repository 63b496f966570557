"""Imposed motions of the coupled degrees of freedom.

A :class:`Trajectory` is X(t) for every coupled DOF, stored as piecewise cubic polynomials that
the compiled time loop evaluates at every stage. Two interpolations:

- ``linear``: the piecewise-linear interpolant of the samples, with velocity constant within each
  interval. This is exactly what a MoorDyn driver imposes when it calls ``Step(x_k, v_k)`` with
  ``v_k = (X_{k+1} - X_k)/dt`` at the sample times.
- ``cubic``: a C2 cubic spline through the samples; velocities and accelerations are its
  derivatives (the smooth choice for motion records).

Before the first sample and after the last one the motion holds still.
"""

from __future__ import annotations

import csv
import logging
import math
from pathlib import Path

import numpy as np

from .core.layout import Motion
from .errors import DeckError

log = logging.getLogger("moorline")

_HOLD = 1.0e9  # length [s] of the hold pieces added before and after the samples


class Trajectory:
    """X(t) for the coupled DOFs.

    Parameters
    ----------
    t : ndarray (n,)
        Knot times [s], strictly increasing.
    c : ndarray (n-1, n_dof, 4)
        Polynomial coefficients of each piece in powers of (tau - t[k]).
    """

    def __init__(self, t: np.ndarray, c: np.ndarray):
        self.t = np.asarray(t, dtype=float)
        self.c = np.asarray(c, dtype=float)
        if self.c.ndim != 3 or self.c.shape[0] != self.t.size - 1 or self.c.shape[2] != 4:
            raise ValueError("coefficients must have shape (n_knots - 1, n_dof, 4)")
        self._motion = Motion(self.t, self.c)

    @property
    def n_dof(self) -> int:
        return self.c.shape[1]

    @property
    def t_start(self) -> float:
        return float(self.t[1]) if self.t.size > 2 else float(self.t[0])

    @property
    def t_end(self) -> float:
        return float(self.t[-2]) if self.t.size > 2 else float(self.t[-1])

    # ------------------------------------------------------------------ constructors
    @classmethod
    def hold(cls, x) -> Trajectory:
        """Hold the DOFs at ``x``."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        c = np.zeros((1, x.size, 4))
        c[0, :, 0] = x
        return cls(np.array([-_HOLD, _HOLD]), c)

    @classmethod
    def from_samples(cls, t, X, interpolation: str = "cubic") -> Trajectory:
        """Motion through samples ``X[k]`` at times ``t[k]``.

        Parameters
        ----------
        t : array_like (n,)
            Sample times [s], strictly increasing.
        X : array_like (n, n_dof)
            Samples [m] (or [rad] for angles).
        interpolation : {'cubic', 'linear'}
        """
        t = np.asarray(t, dtype=float).ravel()
        X = np.asarray(X, dtype=float)
        if X.ndim == 1:
            X = X[:, None]
        if X.shape[0] != t.size:
            raise ValueError(f"{t.size} times but {X.shape[0]} samples")
        if t.size < 2:
            return cls.hold(X[0])
        if np.any(np.diff(t) <= 0):
            raise ValueError("motion times must be strictly increasing")
        h = np.diff(t)
        n, nd = X.shape
        c = np.zeros((n - 1, nd, 4))
        if interpolation == "linear" or n < 3:
            c[:, :, 0] = X[:-1]
            c[:, :, 1] = np.diff(X, axis=0) / h[:, None]
        elif interpolation == "cubic":
            from scipy.interpolate import CubicSpline

            cs = CubicSpline(t, X, axis=0)
            # scipy stores the highest power first: cs.c[m, k, j] multiplies s**(3 - m)
            c[:, :, 3] = cs.c[0]
            c[:, :, 2] = cs.c[1]
            c[:, :, 1] = cs.c[2]
            c[:, :, 0] = cs.c[3]
        else:
            raise ValueError(f"interpolation must be 'cubic' or 'linear', got {interpolation!r}")
        # hold still before the first and after the last sample
        first = np.zeros((1, nd, 4))
        first[0, :, 0] = X[0]
        last = np.zeros((1, nd, 4))
        last[0, :, 0] = X[-1]
        tt = np.concatenate([[t[0] - _HOLD], t, [t[-1] + _HOLD]])
        return cls(tt, np.concatenate([first, c, last]))

    @classmethod
    def from_function(cls, f, t_end: float, dt: float, interpolation: str = "linear") -> Trajectory:
        """Sample ``f(t) -> X`` every ``dt`` from 0 to ``t_end`` (a MoorDyn driver with outer step dt)."""
        n = int(round(t_end / dt))
        t = np.arange(n + 1) * dt
        return cls.from_samples(t, np.array([np.atleast_1d(f(tk)) for tk in t]), interpolation)

    @classmethod
    def from_csv(cls, path, n_dof: int | None = None, interpolation: str = "cubic") -> Trajectory:
        """Read a motion CSV: a header row, time ``t`` [s] first, then one column per coupled DOF
        in MoorDyn's coupled-DOF order.

        Raises
        ------
        DeckError
            Naming the file, line and column of what is wrong.
        """
        path = Path(path)
        try:
            text = path.read_text()
        except OSError as e:
            raise DeckError(f"cannot read motion file: {e.strerror}", file=path) from None
        rows = list(csv.reader(text.splitlines()))
        if not rows:
            raise DeckError("motion file is empty; expected a header row and data rows", file=path)
        header = [h.strip() for h in rows[0]]
        if header[0].lower() not in ("t", "time"):
            raise DeckError(f"first column must be the time 't', got header {header[0]!r}", file=path, line=1,
                            row=text.splitlines()[0], field="t")
        ncol = len(header)
        if n_dof is not None and ncol - 1 != n_dof:
            raise DeckError(f"expected {n_dof} DOF columns after 't' (the system's coupled DOFs), "
                            f"found {ncol - 1}", file=path, line=1, row=text.splitlines()[0])
        data = []
        for k, row in enumerate(rows[1:], start=2):
            if not row or all(not c.strip() for c in row):
                continue
            if len(row) != ncol:
                raise DeckError(f"expected {ncol} comma-separated values, found {len(row)}", file=path, line=k,
                                row=",".join(row))
            vals = []
            for j, tok in enumerate(row):
                try:
                    v = float(tok)
                except ValueError:
                    raise DeckError(f"column {header[j]!r}: expected a number, got {tok.strip()!r}", file=path,
                                    line=k, row=",".join(row), field=header[j]) from None
                if not math.isfinite(v):
                    raise DeckError(f"column {header[j]!r}: value is not finite", file=path, line=k,
                                    row=",".join(row), field=header[j])
                vals.append(v)
            if data and vals[0] <= data[-1][0]:
                raise DeckError(f"times must increase; {vals[0]} follows {data[-1][0]}", file=path, line=k,
                                row=",".join(row), field="t")
            data.append(vals)
        if not data:
            raise DeckError("motion file has no data rows", file=path)
        arr = np.array(data)
        return cls.from_samples(arr[:, 0], arr[:, 1:], interpolation)

    # ------------------------------------------------------------------ evaluation
    def _piece(self, t: float) -> tuple[int, float]:
        k = int(np.clip(np.searchsorted(self.t, t, side="right") - 1, 0, self.t.size - 2))
        return k, t - self.t[k]

    def position(self, t: float) -> np.ndarray:
        k, s = self._piece(t)
        c = self.c[k]
        return c[:, 0] + s * (c[:, 1] + s * (c[:, 2] + s * c[:, 3]))

    def velocity(self, t: float) -> np.ndarray:
        k, s = self._piece(t)
        c = self.c[k]
        return c[:, 1] + s * (2.0 * c[:, 2] + 3.0 * s * c[:, 3])

    def as_motion(self) -> Motion:
        """The compiled-kernel form."""
        return self._motion
