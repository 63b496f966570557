"""The quasi-static time-domain mode: floating bodies on quasi-static lines.

The lines, points and their network are solved by :mod:`moorline.quasistatic` (elastic catenaries,
free junctions, clump weights and buoys in equilibrium) at the bodies' pose at the start of every
update interval, and act on the bodies over the interval as the load linearised there,
``F0 - K (pose - pose0)`` with ``K`` the analytic stiffness with respect to the pose (position and
roll, pitch, yaw, ``R = Rx Ry Rz``). The same system can then be run with dynamic and with
quasi-static lines and compared (lines without inertia, drag or seabed dynamics).
"""

from __future__ import annotations

import copy
import logging

import numpy as np

from ..model import BodyKind, Model, ModelError

log = logging.getLogger("moorline")


class QuasiStaticMooring:
    """The lines of ``model`` as a quasi-static mooring of its floating bodies.

    Parameters
    ----------
    model : Model
        The full model (lines, points, floating bodies).
    seabed_friction : float or "deck" or dict
        Seabed friction of the quasi-static lines (see :class:`moorline.quasistatic.QuasiStaticModel`).
    """

    def __init__(self, model: Model, *, seabed_friction=0.0):
        from ..quasistatic import QuasiStaticModel

        floating = {f.body for f in model.floating}
        for i, b in enumerate(model.bodies):
            if b.kind != BodyKind.FIXED and i not in floating:
                raise ModelError(f"quasi-static mooring: body {i + 1} is not fixed and does not float; only floating "
                                 "bodies can move on quasi-static lines")
        for k, rod in enumerate(model.rods, 1):
            if rod.body is None:
                raise ModelError(f"quasi-static mooring: rod {k} is not on a body; the quasi-static model has no rods")
        self.qs = QuasiStaticModel(model, bodies_free=False, seabed_friction=seabed_friction)
        self.bodies = self.qs.coupled_bodies
        self.solution = None
        self.n_lines = len(model.lines)

    def dynamic_model(self, model: Model) -> Model:
        """The model the time loop integrates: its bodies (with their rods), without lines and points."""
        m = copy.copy(model)
        m.lines = []
        m.points = []
        m.line_types = {}
        m.outputs = [o for o in model.outputs if o.strip().upper().startswith(("BODY", "B", "ROD", "R"))]
        m.floating = list(model.floating)
        m.hydro = list(model.hydro)
        m.joints = list(model.joints)
        return m

    def update(self, system) -> None:
        """Solve the quasi-static lines at the bodies' current poses and linearise their load there
        (into ``system.layout.fl``)."""
        x = np.concatenate([system.bodies[i].pose() for i in self.bodies])
        sol = self.qs.solve(x, stiffness=True)
        self.solution = sol
        F = system.layout.fl
        K = sol.stiffness_euler
        cols = np.concatenate([6 * int(F.of_body[i]) + np.arange(6) for i in self.bodies])
        F.ql_F[:] = 0.0
        F.ql_K[:] = 0.0
        F.ql_F[cols] = sol.loads
        F.ql_K[np.ix_(cols, cols)] = K
        F.ql_x0[cols] = x

    def tensions(self) -> np.ndarray:
        """Tensions at end A (anchor) and B (fairlead) of every line at the last update, (n_lines, 2) [N]."""
        if self.solution is None:
            return np.full((self.n_lines, 2), np.nan)
        return self.solution.tensions.copy()
