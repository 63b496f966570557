"""The outer-program interface: :class:`System` with ``init(x, xd)`` and ``step(x, xd, t, dt)``.

It mirrors MoorDyn's coupling API so that coupling scripts port by renaming::

    sys = moorline.System.from_file("mooring.dat")      # MoorDyn_Create
    f = sys.init(x, xd)                                  # MoorDyn_Init
    f = sys.step(x, xd, t, dt)                           # MoorDyn_Step
    sys.lines[0].fairlead_tension()                      # MoorDyn_GetLineFairTen

``x`` and ``xd`` are the coupled degrees of freedom in MoorDyn's order: coupled bodies and rods
(6 each, x y z roll pitch yaw; 3 when pinned), then coupled points (3 each). Forces returned are the
loads the mooring system exerts on the coupled objects [N, N m].
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from ..core.features import features_of, kernel_env, kernel_parts
from ..core.floating import floating_restart
from ..core.implicit import advance_implicit, build_implicit, new_implicit_work
from ..core.integrate import FINAL_END, FINAL_LAST_STAGE, RHO_INF, Scheme, advance, parse_scheme
from ..core.jacobian import (
    S_AVALID,
    S_H,
    S_HJ,
    S_NBACK,
    S_NFAC,
    S_NIT,
    S_NJAC,
    S_NREJ,
    S_NRHS,
    S_NSLOW,
    S_NSTEP,
)
from ..core.jit import FastCall, compile_for
from ..core.layout import P_FREE, Motion, build_layout, quat_between, quat_from_matrix, static_motion, step_motion
from ..core.linestates import XC_DTM, XC_HIST
from ..core.rhs import rhs
from ..core.schemes import SP_STEPS
from ..core.seabed import bed_damping_ramp, bed_spring_blend
from ..core.stability import choose_dtM, segment_period, stability_report
from ..core.waterkin import fluid_kinematics
from ..errors import SimulationError
from ..model import BodyKind, Model, RodKind, rotation_xyz
from ..quasistatic.catenary import CatenaryStatus
from . import checkpoint
from .failures import FailureEvent, connection_load, fire, new_event
from .floating import JOINT_PULL, floating_arrays
from .initial import (
    MAX_NODE_SPEED,
    catenary_start,
    quasistatic_equilibrium,
    report_residual,
    solve_initial_conditions,
)
from .limits import check_model
from .moordyn_start import start_from_moordyn_state
from .qsmooring import QuasiStaticMooring
from .stepplan import F8, FORCE_FIELD, make_plan
from .views import BodyView, LineView, PointView, RodView

log = logging.getLogger("moorline")


class System:
    """A mooring system ready to integrate.

    Parameters
    ----------
    model : Model
        The description (from :func:`moorline.io.read_deck` or built in Python).
    dtM : float, optional
        Internal time step [s]; default from the model options (``dtM`` or ``CFL``).
    scheme : str, optional
        Time scheme name (Euler, RK2, RK4, BEuler<M>, Midpoint<M>, or moorline's implicit
        ``GenAlpha[rho_inf]``); default the model's ``tScheme``. With GenAlpha, ``dtM`` is the
        largest step (there is no stability limit; the step is halved where Newton struggles).
    loads_at : {'end', 'last_stage'}
        What loads (tensions, forces, curvatures) the views report after a step. ``'end'``
        (default): evaluated at the state and time at the end of the step, consistent with the
        reported positions. ``'last_stage'``: MoorDyn's convention, the loads of the last
        derivative evaluation inside the step (for RK2 the midpoint stage, half a dtM earlier),
        with positions and velocities from the end of the step. The two differ only in the
        fastest (axial segment) modes; use ``'last_stage'`` to compare with MoorDyn sample by sample.
    """

    def __init__(self, model: Model, *, dtM: float | None = None, scheme: str | None = None,
                 loads_at: str = "end", mooring: str = "dynamic", qs_interval: float | None = None,
                 qs_friction=0.0, _floating=None):
        if loads_at not in ("end", "last_stage"):
            raise ValueError(f"loads_at must be 'end' or 'last_stage', got {loads_at!r}")
        if mooring not in ("dynamic", "quasistatic"):
            raise ValueError(f"mooring must be 'dynamic' or 'quasistatic', got {mooring!r}")
        self.loads_at = loads_at
        self.mooring = mooring
        self.full_model = model
        self._qsm = None
        if mooring == "quasistatic":
            self._qsm = QuasiStaticMooring(model, seabed_friction=qs_friction)
            model = self._qsm.dynamic_model(model)
        self.model = model
        check_model(model)
        #: the floating bodies' arrays (kept: a line failure rebuilds the layout with them)
        self._floating = floating_arrays(model) if _floating is None else _floating
        self.layout = build_layout(model, floating=self._floating)
        if self._qsm is not None:
            self.layout.fl.ctl[1] = 1
        self._scheme_name = scheme if scheme is not None else model.options.tScheme
        self.scheme, self.scheme_params, self.scheme_label = parse_scheme(self._scheme_name)
        self.dtM = float(dtM) if dtM is not None else choose_dtM(model, self.layout)
        if not self.dtM > 0:
            raise ValueError(f"dtM must be > 0, got {self.dtM}")
        if self.scheme == Scheme.LEULER:
            # each line's update interval: 0.999 CFL times its segment period (MoorDyn's LEuler)
            cfl = float(model.options.CFL)
            T = np.array([segment_period(model, self.layout, li) for li in range(len(model.lines))])
            self.scheme_params = np.concatenate([self.scheme_params, 0.999 * cfl * T, cfl * T])
        if self.scheme == Scheme.GENALPHA:
            ramp = bed_damping_ramp(self.layout)
            blend = bed_spring_blend(self.layout)
            self.layout.env = self.layout.env._replace(bed_ramp=ramp, bed_blend=blend)
            self.layout.env_ic = self.layout.env_ic._replace(bed_ramp=ramp, bed_blend=blend)
        # a joint's child is pulled back onto its joint at 0.3 / dtM (see core.floating.floating_motion)
        self.layout.fl.par[1] = JOINT_PULL / self.dtM
        # VIV refreshes its running RMS values once per time step (core.linestates)
        self.layout.lines.xs_ctl[XC_DTM] = self.dtM
        self.work = self.layout.new_work()
        self.fwork = self.layout.new_float_work()
        self._features_key = None
        self._kernel_arrays()  # the scheme's features join the layout's (see core.features)
        n = self.layout.n_state
        self.y = np.zeros(n)
        self._S = np.zeros((5, n))
        self._dy_eval = np.zeros(n)
        self._imp = None  # structure and work of the implicit solves, built on first use
        self.t = 0.0
        self._motion = static_motion(self.deck_coupled_positions())
        # the coupling step's trajectory, filled in place by step() (no allocation per call)
        nc = self.layout.n_coupled_dof
        self._step_motion = Motion(np.zeros(2), np.zeros((1, nc, 4)))
        self._deck_x = self.deck_coupled_positions()
        self._gather = self._coupled_gather()
        self._call_advance = FastCall()
        self._call_rhs = FastCall()
        self._plan = None  # the coupling step's fast path (system.stepplan), made by the first step()
        self.lines = [LineView(self, i) for i in range(len(model.lines))]
        self.points = [PointView(self, i) for i in range(len(model.points))]
        self.rods = [RodView(self, i) for i in range(len(model.rods))]
        self.bodies = [BodyView(self, i) for i in range(len(model.bodies))]
        self.initialized = False
        self._grid_warned = False
        self.ic_report: dict = {}
        #: quasi-static mode: the lines are re-solved and re-linearised every qs_interval [s]
        self.qs_interval = float(qs_interval) if qs_interval is not None else max(self.dtM, 0.02)
        if model.failures and mooring == "quasistatic":
            raise ValueError("line failures (a FAILURE section) need the dynamic mooring; the quasi-static mode "
                             "(mooring='quasistatic') does not support them")
        #: line failures (the model's, and those added by :meth:`add_failure` and :meth:`break_line`),
        #: pending or happened (:class:`moorline.system.failures.FailureEvent`)
        self.failures = [FailureEvent(f) for f in model.failures]
        #: what the free point of a failure is: "massless" (MoorDyn's documented failure) or "copy"
        #: (MoorDyn-C 2.7's BreakLine: a copy of the old point's mass, volume, CdA and Ca)
        self.failure_new_point = "massless"
        #: longest simulated time [s] between two checks of the tension-triggered failures inside
        #: one ``advance_to`` (each ``step`` call is checked at its end, as MoorDyn checks after every
        #: coupling step); time-triggered failures happen at their time exactly
        self.failure_check_interval = math.inf

    @classmethod
    def from_file(cls, path, **kwargs) -> System:
        """Read a MoorDyn v2 deck (see :func:`moorline.io.read_deck`)."""
        from ..io import read_deck

        return cls(read_deck(Path(path)), **kwargs)

    # ------------------------------------------------------------------ coupled DOFs
    @property
    def n_coupled_dof(self) -> int:
        """Number of coupled degrees of freedom: 6 per coupled body or rod (x, y, z, roll, pitch,
        yaw), 3 per coupled-pinned body or rod and per coupled point."""
        return self.layout.n_coupled_dof

    @property
    def coupled_dof_labels(self) -> list[str]:
        """Labels of the coupled DOFs in order (bodies, rods, points), e.g. ``['B1_x', ..., 'B1_yaw',
        'P4_x', ...]``."""
        labels = []
        six = ("x", "y", "z", "roll", "pitch", "yaw")
        for i in self.layout.coupled_bodies:
            n = 6 if self.layout.rigid.body_kind[i] == int(BodyKind.COUPLED) else 3
            labels += [f"B{i + 1}_{c}" for c in six[:n]]
        for k in self.layout.coupled_rods:
            n = 6 if self.layout.rigid.rod_kind[k] == int(RodKind.COUPLED) else 3
            labels += [f"R{k + 1}_{c}" for c in six[:n]]
        labels += [f"P{p + 1}_{c}" for p in self.layout.coupled_points for c in "xyz"]
        return labels

    def deck_coupled_positions(self) -> np.ndarray:
        """Coupled DOF vector with every coupled object where the deck puts it (angles [rad])."""
        out = []
        m = self.model
        for i in self.layout.coupled_bodies:
            b = m.bodies[i]
            out.append(np.concatenate([b.r, np.radians(b.angles)]) if b.kind == BodyKind.COUPLED else b.r)
        for k in self.layout.coupled_rods:
            rod = m.rods[k]
            out.append(np.concatenate([rod.rA, np.zeros(3)]) if rod.kind == RodKind.COUPLED else rod.rA)
        P = self.layout.points
        out += [P.r0[p] for p in self.layout.coupled_points]
        return np.concatenate(out) if out else np.zeros(0)

    def _check_dof(self, x, name):
        if x is None:
            return None
        x = np.asarray(x, dtype=float).ravel()
        if x.size != self.n_coupled_dof:
            raise ValueError(f"{name} has {x.size} values; the system has {self.n_coupled_dof} coupled DOF "
                             f"({', '.join(self.coupled_dof_labels) or 'none'})")
        return x

    # ------------------------------------------------------------------ evaluation
    def _kernel_arrays(self):
        """(lines, rods, points, env, seabed, work, floating, floating work): what every kernel call
        takes. ``work.features`` is brought up to date first when the layout or the scheme were
        replaced since (the kernels are compiled without the code of the features they lack, see
        :mod:`moorline.core.features`), and the rods, floating bodies, water kinematics and wave
        excitation of a system without them are passed without their (empty) arrays
        (:func:`moorline.core.features.kernel_parts`, :func:`~moorline.core.features.kernel_env`)."""
        lay = self.layout
        key = (id(lay.lines), id(lay.rigid), id(lay.env), id(lay.env_ic), id(lay.fl), id(self.fwork),
               int(self.scheme))
        if key != self._features_key:
            f = features_of(lay, self.scheme)
            if f != self.work.features:
                self.work = self.work._replace(features=f)
                self._drop_step_plan()
            self._features_key = key
            # (held, so that no id of the key can be taken by another object while it is the key)
            self._features_refs = (lay.lines, lay.rigid, lay.env, lay.env_ic, lay.fl, self.fwork)
            # the rods' and floating bodies' arrays are left out for a system without them (numba
            # unboxes every array of every call, empty or not: core.features.NoRigid)
            self._kernel_rff = kernel_parts(f, lay.rigid, lay.fl, self.fwork)
            self._kernel_envs = (kernel_env(f, lay.env), kernel_env(f, lay.env_ic))
        R, F, FW = self._kernel_rff
        return lay.lines, R, lay.points, self._kernel_envs[0], lay.seabed, self.work, F, FW

    def _kernel_env_ic(self):
        """The environment of the initial conditions (waves off) as the kernels take it (see
        :meth:`_kernel_arrays`)."""
        self._kernel_arrays()
        return self._kernel_envs[1]

    def _evaluate(self, piece: int = -1) -> None:
        """Evaluate every load at the current state and time (refreshes what the views report).
        ``piece``: the coupled-trajectory piece (that of the step just taken, so the coupled
        velocity at the end of a step is the one imposed during it)."""
        L, R, P, E, B, W, F, FW = self._kernel_arrays()
        # an evaluation for the views is not a step: the line-state histories (Syrope, VIV) and the
        # accelerations VIV remembers are left as the last step left them
        hist = L.xs_ctl[XC_HIST]
        L.xs_ctl[XC_HIST] = 0.0
        viv = bool(np.any(L.viv[:, 0] > 0))
        acc = W.acc.copy() if viv else None
        self._call_rhs(rhs, (self.t, self.y, self._dy_eval, L, R, P, E, B, self._motion, W, F, FW, 1.0, int(piece)))
        L.xs_ctl[XC_HIST] = hist
        if viv:
            W.acc[...] = acc  # VIV's "previous evaluation" stays the last one of the step

    def _drop_step_plan(self) -> None:
        """Forget the coupling step's fast path (:mod:`moorline.system.stepplan`): called by every
        path that replaces an object it holds; the next ``step`` makes it again."""
        self._plan = None

    _FORCE_FIELD = FORCE_FIELD  # Work arrays of the coupled loads (one table with the fast path's gather)

    def _coupled_gather(self) -> list[tuple[str, int, int, int]]:
        lay = self.layout
        out = []
        o = 0
        for i in lay.coupled_bodies:
            k = 6 if lay.rigid.body_kind[i] == int(BodyKind.COUPLED) else 3
            out.append(("body", int(i), k, o))
            o += k
        for r in lay.coupled_rods:
            k = 6 if lay.rigid.rod_kind[r] == int(RodKind.COUPLED) else 3
            out.append(("rod", int(r), k, o))
            o += k
        for p in lay.coupled_points:
            out.append(("point", int(p), 3, o))
            o += 3
        return out

    @property
    def coupled_slots(self) -> list[tuple[str, int, int, int]]:
        """Where each coupled object sits in the coupled-DOF vector, in order: (``'body'``,
        ``'rod'`` or ``'point'``, its 0-based index, its number of DOF (6, or 3 when pinned or a
        point), its offset)."""
        return self._gather

    def coupled_forces(self, out: np.ndarray | None = None) -> np.ndarray:
        """Loads of the mooring system on the coupled DOFs [N, N m], in coupled-DOF order: F6 - M a_in
        of coupled bodies and rods (3 forces when pinned), the net force of coupled points.
        ``out``: a float array of n_coupled_dof values to write them into (returned)."""
        if out is None:
            out = np.empty(self.layout.n_coupled_dof)
        W = self.work
        for kind, i, k, o in self._gather:
            out[o:o + k] = getattr(W, self._FORCE_FIELD[kind])[i, :k]
        return out

    # ------------------------------------------------------------------ init
    def init(self, x=None, xd=None, *, solve_ic: bool = True) -> np.ndarray:
        """Place coupled objects at ``x``, start every line on its catenary and (with
        ``solve_ic``) find the initial equilibrium with the deck's IC settings; time is reset to 0.

        Parameters
        ----------
        x, xd : array_like (n_coupled_dof,), optional
            Coupled positions [m] and velocities [m/s]; default: the deck positions, at rest.
        solve_ic : bool
            False starts from the catenary profile as MoorDyn's Init_NoIC does.

        Returns
        -------
        ndarray (n_coupled_dof,)
            Forces on the coupled DOFs [N].
        """
        x = self._check_dof(x, "x")
        if x is None:
            x = self.deck_coupled_positions()
        xd = self._check_dof(xd, "xd")
        self._drop_step_plan()
        self.t = 0.0
        self._motion = static_motion(x)
        B = self.layout.seabed
        B.ctl[:] = 0  # stick-slip friction is off while the initial conditions are found
        failed = catenary_start(self.layout, x, self.y, self.work)
        for li, status in failed:
            log.warning("line %d: catenary solve unsuccessful (%s); starting from the straight chord%s", li + 1,
                        CatenaryStatus(status).name.lower(),
                        " (Newton statics: folded on the seabed)" if status == CatenaryStatus.TOO_LONG else "")
        self.ic_report = {"catenary_failed": [li + 1 for li, _ in failed],
                          "catenary_too_long": [li + 1 for li, st in failed if st == CatenaryStatus.TOO_LONG]}
        opts = self.model.options
        if opts.fileIC and self._qsm is None:
            start_from_moordyn_state(self, opts.fileIC)  # after the catenary start, before the IC solve (spec 6.1)
        if self._qsm is not None:
            self._evaluate()
            self._qsm.update(self)
            if solve_ic:
                quasistatic_equilibrium(self)
        elif solve_ic and opts.TmaxIC > 0 and self.layout.n_rows + self.layout.n_blocks + self.layout.n_line_states > 0:
            solve_initial_conditions(self)
            report_residual(self)
        if xd is not None:
            self._motion = step_motion(x, xd, 0.0, 1.0)
        self.t = 0.0
        if self.layout.fl.body.size:  # (not compiled for systems without floating bodies)
            floating_restart(0.0, self.y, self.layout.rigid, self.work, self.layout.fl, self.fwork)
        self._reset_scheme()
        self._evaluate()
        # friction springs start relaxed at the initial position of every node
        B.anchor[...] = self.work.r
        B.slip[...] = 0.0
        B.ctl[0] = 1
        self._report_stability()
        self._check_grid()
        self.initialized = True
        return self.coupled_forces()

    def _check_grid(self) -> None:
        B = self.layout.seabed
        if B.ctl[2] > 0 and not self._grid_warned:
            self._grid_warned = True
            log.warning("line nodes reached beyond the bathymetry grid (x %.6g..%.6g, y %.6g..%.6g m) by t = %.6g s; "
                        "the seabed height of the nearest grid edge is used there", B.gx[0], B.gx[-1], B.gy[0],
                        B.gy[-1], self.t)

    def _lines_on_seabed(self) -> np.ndarray:
        """Lines with a node in seabed contact at the last evaluation (for the seabed modes)."""
        L = self.layout.lines
        fbed = np.any(self.work.Fbed != 0.0, axis=1)
        return np.array([np.any(fbed[L.node_ptr[i]:L.node_ptr[i + 1]]) for i in range(len(self.lines))])

    def _report_stability(self) -> None:
        gov, limit, text = stability_report(self.model, self.layout, self.dtM, self.scheme, self._lines_on_seabed(),
                                            self.scheme_label)
        self.stability = {"governing": gov.where, "mode": gov.kind, "rate": gov.rate,
                          "dtM_limit": limit, "text": text}
        if self.dtM > limit:
            log.warning("%s: dtM is likely unstable", text)
        else:
            log.info(text)

    # ------------------------------------------------------------------ stepping
    def step(self, x, xd, t: float, dt: float, *, out: np.ndarray | None = None) -> np.ndarray:
        """Advance from ``t`` to ``t + dt`` with the coupled DOFs at ``x + xd (tau - t)``.

        Returns the forces on the coupled DOFs at the end of the step [N]. With ``dt <= 0``
        nothing is integrated and the current forces are returned. ``out``: a float array of
        n_coupled_dof values the forces are written into (and returned), for hosts that call
        this thousands of times: the call then allocates nothing.

        The compiled call, its arguments and the force gather are kept between calls and made
        again only when something they hold is replaced (:mod:`moorline.system.stepplan`). While
        a failure triggered by a load is pending, in the call a failure happens in, with
        quasi-static lines, ``dt <= 0`` or an ``out`` of another shape or type, the call takes the
        general path. The results are the same bit for bit.
        """
        if not self.initialized:
            raise RuntimeError("call init() before step()")
        p = self._plan
        if p is None or not p.current(self):
            p = self._plan = make_plan(self)
        if p.fn is not None:
            t = float(t)
            dt = float(dt)
            if dt >= 1e-300 and (out is None or (type(out) is np.ndarray and out.shape == p.shape
                                                 and out.dtype is F8)) and (not p.pending or self._none_due(p, t, dt)):
                # the fast path (system.stepplan): the general path's arithmetic with the kept call
                if x is None:
                    p.cx[...] = p.deck_x
                elif type(x) is np.ndarray and x.shape == p.shape and x.dtype is F8:
                    p.cx[...] = x
                else:
                    p.cx[...] = self._check_dof(x, "x")
                if xd is None:
                    p.cxd[...] = 0.0
                elif type(xd) is np.ndarray and xd.shape == p.shape and xd.dtype is F8:
                    p.cxd[...] = xd
                else:
                    p.cxd[...] = self._check_dof(xd, "xd")
                tk = p.tk
                tk[0] = t
                tk[1] = t_end = t + dt
                self._motion = p.motion
                self.t, bad, row, piece = p.fn(*p.head, t, t_end, *p.tail)
                if p.implicit:  # (status, row): 1 unstable, 2 Newton failed, as in _advance_interval
                    if bad == 1:
                        raise self._instability(self.t, int(row), "")
                    if bad == 2:
                        raise self._newton_failure(self.t, int(row))
                elif bad >= 0:
                    raise self._instability(self.t, int(bad), "")
                if not self._grid_warned and p.bed_ctl[2] > 0:
                    self._check_grid()
                if out is None:
                    out = np.empty(p.shape)
                if p.take is None:
                    return p.gather(out)
                p.take(p.idx, out=out, mode="clip")  # (one kind of coupled object: one take)
                return out
        return self._step_general(x, xd, t, dt, out)

    def _none_due(self, p, t: float, dt: float) -> bool:
        """No pending failure (of the plan's, all on a time alone) is due in the step from ``t`` to
        ``t + dt`` by _advance's test, and that step takes one: _advance then does what the
        plain time loop does."""
        t_end = t + dt
        tol = 1e-9 * self.dtM
        if not t_end - t > tol:
            return False
        return all(ev.pending and ev.failure.time > t_end + tol for ev in p.pending)

    def _step_general(self, x, xd, t, dt, out) -> np.ndarray:
        """:meth:`step` where its fast path does not apply (every case; see :mod:`.stepplan`)."""
        mo = self._step_motion
        c = mo.c
        c[0, :, 0] = self._deck_x if x is None else self._check_dof(x, "x")
        if xd is None:
            c[0, :, 1] = 0.0
        else:
            c[0, :, 1] = self._check_dof(xd, "xd")
        self.t = t = float(t)
        dt = float(dt)
        mo.t[0] = t
        mo.t[1] = t + max(dt, 1e-300)
        if dt <= 0:
            self._motion = mo
            self._evaluate()
            return self.coupled_forces(out)
        self._advance(mo, t + dt)
        return self.coupled_forces(out)

    def advance_to(self, t_end: float, motion: Motion) -> None:
        """Integrate to ``t_end`` [s] following the coupled trajectory ``motion`` (compiled loop)."""
        if not self.initialized:
            raise RuntimeError("call init() before advancing")
        self._advance(motion, float(t_end))

    # ------------------------------------------------------------------ implicit solves
    def _implicit(self):
        """(structure, work) of the Newton solves (generalized-alpha steps and statics)."""
        if self._imp is None:
            rho = float(self.scheme_params[0]) if self.scheme == Scheme.GENALPHA else RHO_INF
            A = build_implicit(self.layout, rho)
            self._imp = (A, new_implicit_work(self.layout, A, self.dtM))
        return self._imp

    def _reset_scheme(self) -> None:
        """Forget what the time scheme carries between steps (after the state was set from outside)."""
        self._S[...] = 0.0  # the fixed-point schemes start without a previous derivative
        self.scheme_params[SP_STEPS] = 0.0  # Adams-Bashforth start-up, local Euler's first step
        if self._imp is not None:
            st = self._imp[1].stat
            st[S_AVALID] = 0.0
            st[S_HJ] = 0.0
            st[S_H] = self.dtM

    @property
    def solver_stats(self) -> dict:
        """Counters of the implicit solver: steps, rejected steps, Newton iterations, Jacobians,
        derivative evaluations, and the current step [s] (empty for the explicit schemes)."""
        if self._imp is None:
            return {}
        st = self._imp[1].stat
        A = self._imp[0]
        return {"steps": int(st[S_NSTEP]), "rejected": int(st[S_NREJ]), "iterations": int(st[S_NIT]),
                "jacobians": int(st[S_NJAC]), "refactors": int(st[S_NFAC]), "evaluations": int(st[S_NRHS]),
                "backtracks": int(st[S_NBACK]), "slow_rebuilds": int(st[S_NSLOW]), "step": float(st[S_H]),
                "colours": int(A.col_ptr.size - 1), "bandwidth": (int(A.band[0]), int(A.band[1]))}

    def _advance_call(self, motion: Motion, t_end: float):
        """(kernel, arguments) of the compiled time loop from now to ``t_end``."""
        L, R, P, E, B, W, F, FW = self._kernel_arrays()
        if self.scheme == Scheme.GENALPHA:
            A, IW = self._implicit()
            return advance_implicit, (self.y, self.t, t_end, self.dtM, A, IW, L, R, P, E, B, motion, W, F, FW,
                                      MAX_NODE_SPEED, True)
        final = FINAL_LAST_STAGE if self.loads_at == "last_stage" else FINAL_END
        return advance, (self.y, self.t, t_end, self.dtM, int(self.scheme), self.scheme_params, L, R, P, E, B,
                         motion, W, F, FW, 1.0, self._S, MAX_NODE_SPEED, final)

    def warm_up(self, motion: Motion | None = None) -> None:
        """Compile the time loop of this system now (or load it from numba's cache), without
        integrating: the first ``step`` or ``advance_to`` then starts at full speed. ``init`` does
        the same for the kernels of the initial conditions (by running them)."""
        kernel, args = self._advance_call(self._motion if motion is None else motion, self.t)
        compile_for(kernel, args)

    def _advance(self, motion: Motion, t_end: float) -> None:
        """Integrate to ``t_end``, stopping at failure times and checking failure loads between
        compiled intervals (see :mod:`moorline.system.failures`)."""
        pending = [ev for ev in self.failures if ev.pending]
        if not pending:
            self._advance_plain(motion, t_end)
            return
        tol = 1e-9 * self.dtM
        while True:
            self._fire_due(tol)
            pending = [ev for ev in self.failures if ev.pending]
            t_next = min([t_end] + [ev.failure.time for ev in pending])
            if any(math.isfinite(ev.failure.tension) for ev in pending):
                t_next = min(t_next, self.t + self.failure_check_interval)
            if t_next - self.t > tol:
                self._advance_plain(motion, t_next)
            if t_end - self.t <= tol:
                self._fire_due(tol)
                return

    def _fire_due(self, tol: float) -> None:
        """Let every pending failure whose time has come or whose load is reached happen now."""
        for ev in self.failures:
            if not ev.pending:
                continue
            f = ev.failure
            if f.time <= self.t + tol:
                fire(self, ev, "time", new_point=self.failure_new_point)
            elif math.isfinite(f.tension) and connection_load(self, f.attachment, f.lines) >= f.tension:
                fire(self, ev, "tension", new_point=self.failure_new_point)

    # ------------------------------------------------------------------ line failures
    def add_failure(self, attachment, lines, *, time: float = math.inf, tension: float = math.inf):
        """Let ``lines`` (0-based indices) go of ``attachment`` at ``time`` [s] or once the load they
        carry there (the magnitude of the vector sum of their end tensions) reaches ``tension`` [N].

        ``attachment``: a point number (1-based, as in the deck), a deck word (``'P3'``, ``'R1A'``) or
        an :class:`~moorline.model.Attachment`. The released ends are joined to one new free point
        (see :mod:`moorline.system.failures`). Returns the pending
        :class:`~moorline.system.failures.FailureEvent`."""
        ev = new_event(self, attachment, lines, time, tension)
        self.failures.append(ev)
        self._drop_step_plan()  # (a pending failure: step() takes the general path, which checks it)
        return ev

    def break_line(self, line, end: str, *, new_point: str | None = None) -> int:
        """Detach end ``end`` ('A' or 'B') of line ``line`` (0-based index or a LineView) from what it
        is attached to, now (MoorDyn's BreakLine). The end becomes a new free point, starting where
        the attachment was with its velocity; returns its 0-based index. ``new_point``: "massless"
        (default :attr:`failure_new_point`) or "copy" (see :mod:`moorline.system.failures`)."""
        if not self.initialized:
            raise RuntimeError("call init() before break_line()")
        li = line.index if isinstance(line, LineView) else int(line)
        if not 0 <= li < len(self.model.lines):
            raise ValueError(f"line {li}: there are {len(self.model.lines)} lines (0-based indices)")
        e = str(end).upper()
        if e not in ("A", "B"):
            raise ValueError(f"end must be 'A' or 'B', got {end!r}")
        ln = self.model.lines[li]
        att = ln.end_a if e == "A" else ln.end_b
        ev = new_event(self, att, [li], math.inf, math.inf)
        self.failures.append(ev)
        fire(self, ev, "call", new_point=new_point or self.failure_new_point)
        return ev.point

    def _advance_plain(self, motion: Motion, t_end: float) -> None:
        if self._qsm is None:
            self._advance_interval(motion, t_end)
            return
        # quasi-static lines: re-solved at the start of every interval, linearised over it
        while t_end - self.t > 1e-9 * self.dtM:
            self._qsm.update(self)
            self._advance_interval(motion, min(t_end, self.t + self.qs_interval))

    def line_end_tensions(self) -> np.ndarray:
        """Tension at end A (anchor) and end B (fairlead) of every line [N], shape (n_lines, 2):
        of the dynamic lines, or of the quasi-static ones at their last solve."""
        if self._qsm is not None:
            return self._qsm.tensions()
        return np.array([[ln.anchor_tension(), ln.fairlead_tension()] for ln in self.lines]).reshape(-1, 2)

    def _advance_interval(self, motion: Motion, t_end: float) -> None:
        self._motion = motion
        kernel, args = self._advance_call(motion, t_end)
        if self.scheme == Scheme.GENALPHA:
            t, status, row, piece = self._call_advance(kernel, args)
            self.t = t
            if status == 1:
                raise self._instability(t, int(row), "")
            if status == 2:
                raise self._newton_failure(t, int(row))
            self._check_grid()
            return
        # (with loads_at='last_stage' the time loop ends with core.integrate.last_stage_keep)
        t, bad, _, piece = self._call_advance(kernel, args)
        self.t = t
        if bad >= 0:
            raise self._instability(t, int(bad), "")
        self._check_grid()

    # ------------------------------------------------------------------ save and restart
    def save(self, path, *, meta: dict | None = None) -> Path:
        """Write a checkpoint (MoorDyn's Save): everything a restart needs to continue bitwise
        identically, see :mod:`moorline.system.checkpoint`. ``meta``: JSON-ready values kept with
        it (returned by :meth:`load`)."""
        return checkpoint.save(self, path, meta=meta)

    def load(self, path) -> dict:
        """Restore a checkpoint written by :meth:`save` (MoorDyn's Load) into this system, built
        from the same model with the same scheme and time step; returns its ``meta``. Raises
        :class:`moorline.errors.CheckpointError` for a checkpoint of another model."""
        return checkpoint.load(self, path)

    # ------------------------------------------------------------------ state access
    def state_rows(self) -> list[tuple[str, int, int]]:
        """What each state row is: ``('line', line number, node)``, ``('point', number, 0)``,
        ``('rod', number, 0)`` for the 3-DOF rows, then ``('rod', number, 0)`` or
        ``('body', number, 0)`` for each 6-DOF block (numbered after the rows)."""
        lay = self.layout
        rows: list[tuple[str, int, int]] = [("", 0, 0)] * (lay.n_rows + lay.n_blocks)
        L = lay.lines
        for li in range(len(self.lines)):
            for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
                rows[int(L.node_row[n])] = ("line", li + 1, n - int(L.node_ptr[li]))
        P = lay.points
        for p in range(len(P.kind)):
            if P.kind[p] == P_FREE:
                rows[int(P.row[p])] = ("point", p + 1, 0)
        R = lay.rigid
        for k in range(len(R.rod_kind)):
            if R.rod_row[k] >= 0:
                rows[int(R.rod_row[k])] = ("rod", k + 1, 0)
            if R.rod_blk[k] >= 0:
                rows[lay.n_rows + int(R.rod_blk[k])] = ("rod", k + 1, 0)
        for i in range(len(R.body_kind)):
            if R.body_blk[i] >= 0:
                rows[lay.n_rows + int(R.body_blk[i])] = ("body", i + 1, 0)
        return rows

    def _put_state(self, line_positions=None, line_velocities=None, point_positions=None,
                   point_velocities=None) -> None:
        """Write the state rows of :meth:`set_state` (same arguments), nothing else."""
        L = self.layout.lines
        uoff = self.layout.u_offset
        for arrs, off in ((line_positions, 0), (line_velocities, uoff)):
            if arrs is None:
                continue
            for li, a in enumerate(arrs):
                a = np.asarray(a, dtype=float)
                for n in range(int(L.node_ptr[li]) + 1, int(L.node_ptr[li + 1]) - 1):
                    row = int(L.node_row[n])
                    self.y[off + 3 * row: off + 3 * row + 3] = a[n - int(L.node_ptr[li])]
        P = self.layout.points
        for arr, off in ((point_positions, 0), (point_velocities, uoff)):
            if arr is None:
                continue
            arr = np.asarray(arr, dtype=float)
            for p in range(len(P.kind)):
                if P.kind[p] == P_FREE:
                    row = int(P.row[p])
                    self.y[off + 3 * row: off + 3 * row + 3] = arr[p]

    def set_state(self, line_positions=None, line_velocities=None, point_positions=None,
                  point_velocities=None) -> None:
        """Overwrite the state: internal node positions/velocities of lines (lists of (N+1, 3) arrays,
        ends ignored) and free point positions/velocities ((n_points, 3), non-free rows ignored).
        Used to start from another program's initial state."""
        self._put_state(line_positions, line_velocities, point_positions, point_velocities)
        self._reset_scheme()
        if self.initialized:
            self._evaluate()
            # stick-slip friction springs restart relaxed at the new node positions
            B = self.layout.seabed
            B.anchor[...] = self.work.r
            B.slip[...] = 0.0
            self._evaluate()

    # ------------------------------------------------------------------ external water kinematics
    @property
    def n_water_nodes(self) -> int:
        """Number of points whose water kinematics an outer program sets (MoorDyn's
        ``ExternalWaveKinInit``): every line node, every rod node, every point, the ground body and
        every body."""
        return int(self.layout.env.water.U_ext.shape[0]) or (
            self.work.r.shape[0] + self.work.rn_r.shape[0] + len(self.points) + 1 + len(self.bodies))

    def water_at(self, points, t: float | None = None) -> np.ndarray:
        """Water kinematics of the model's sea at ``points`` (array_like (n, 3) [m]) at time ``t``
        [s] (default: now), shape (n, 8): velocity (3) [m/s], acceleration (3) [m/s^2], surface
        elevation [m], dynamic pressure [Pa]. External kinematics (WaveKin 1) are per node and give
        only the current here."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        return fluid_kinematics(self.layout.env.water, self.t if t is None else float(t), p)

    def water_node_positions(self) -> np.ndarray:
        """Current positions of the water-kinematics points [m], shape (n_water_nodes, 3), in
        MoorDyn's order (``ExternalWaveKinGetCoordinates``): line nodes (line by line, node 0 to N),
        rod nodes, points, the ground body (origin), bodies."""
        w = self.work
        return np.vstack([w.r, w.rn_r, w.pr, np.zeros((1, 3)), w.br])

    def set_water_kinematics(self, U, Ud) -> None:
        """Set the water velocity [m/s] and acceleration [m/s^2] at every water-kinematics point
        (shape (n_water_nodes, 3), order of :meth:`water_node_positions`); they hold until the next
        call (MoorDyn's ``ExternalWaveKinSet``). Needs ``WaveKin 1`` (external waves) in the model."""
        K = self.layout.env.water
        if K.U_ext.shape[0] == 0:
            raise RuntimeError("the model has no external water kinematics: set WaveKin 1 in the deck or "
                               "env.waves = Waves.external()")
        U = np.asarray(U, dtype=float)
        Ud = np.asarray(Ud, dtype=float)
        if U.shape != K.U_ext.shape or Ud.shape != K.Ud_ext.shape:
            raise ValueError(f"U and Ud must have shape {K.U_ext.shape}, got {U.shape} and {Ud.shape}")
        K.U_ext[...] = U
        K.Ud_ext[...] = Ud

    def set_rod_state(self, k: int, *, end_a=None, axis=None, velocity=None, angular_velocity=None) -> None:
        """Overwrite the state of rod ``k`` (0-based): end-A position [m] and velocity [m/s] of a
        free rod, axis (unit vector A to B; the quaternion becomes the smallest rotation from the
        deck axis) and angular velocity [rad/s] of a free or pinned rod. Values a rod's kind does
        not hold in its state are ignored."""
        lay = self.layout
        R = lay.rigid
        j = int(R.rod_blk[k])
        if j >= 0:
            q, u = lay.block_slices(j)
            free = R.rod_kind[k] == int(RodKind.FREE)
            if end_a is not None and free:
                self.y[q.start:q.start + 3] = end_a
            if axis is not None:
                self.y[q.start + 3:q.stop] = quat_between(R.rod_qref[k], np.asarray(axis, dtype=float))
            if velocity is not None and free:
                self.y[u.start:u.start + 3] = velocity
            if angular_velocity is not None:
                self.y[u.start + 3:u.stop] = angular_velocity
        elif R.rod_row[k] >= 0:
            o = 3 * int(R.rod_row[k])
            if end_a is not None:
                self.y[o:o + 3] = end_a
            if velocity is not None:
                self.y[lay.u_offset + o:lay.u_offset + o + 3] = velocity
        self._restart()

    def set_body_state(self, i: int, *, position=None, angles=None, velocity=None, angular_velocity=None) -> None:
        """Overwrite the state of body ``i`` (0-based; free or coupled-pinned): reference-point
        position [m] and velocity [m/s] (free bodies), roll, pitch, yaw [rad] (Rx Ry Rz) and angular
        velocity [rad/s]."""
        lay = self.layout
        j = int(lay.rigid.body_blk[i])
        if j < 0:
            return
        q, u = lay.block_slices(j)
        free = lay.rigid.body_kind[i] == int(BodyKind.FREE)
        if position is not None and free:
            self.y[q.start:q.start + 3] = position
        if angles is not None:
            self.y[q.start + 3:q.stop] = quat_from_matrix(rotation_xyz(angles))
        if velocity is not None and free:
            self.y[u.start:u.start + 3] = velocity
        if angular_velocity is not None:
            self.y[u.start + 3:u.stop] = angular_velocity
        self._restart()

    def _restart(self) -> None:
        if self.layout.fl.body.size:  # (not compiled for systems without floating bodies)
            floating_restart(self.t, self.y, self.layout.rigid, self.work, self.layout.fl, self.fwork)
        self._reset_scheme()
        if self.initialized:
            self._evaluate()

    def _where_dof(self, dof: int) -> tuple[str, int, int]:
        """(kind, number, node) of the state row holding velocity-space DOF ``dof``."""
        lay = self.layout
        row = dof // 3 if dof < 3 * lay.n_rows else lay.n_rows + (dof - 3 * lay.n_rows) // 6
        return self.state_rows()[row]

    def _newton_failure(self, t: float, dof: int) -> SimulationError:
        what, num, node = self._where_dof(dof)
        where = f"line {num} node {node}" if what == "line" else f"{what} {num}"
        h = float(self._imp[1].stat[S_H])
        msg = (f"implicit solver ({self.scheme_label}) failed at t = {t:.6g} s: Newton iterations did not converge "
               f"even with the step cut to {h:.3g} s (dtM = {self.dtM:.4g} s); largest residual at {where}. "
               f"Check the model there (a line pulled beyond its breaking stretch, a node far below the seabed, "
               f"a zero mass), or run an explicit scheme to see the motion")
        return SimulationError(msg, time=t, line=num if what == "line" else None,
                               node=node if what == "line" else None, point=num if what == "point" else None,
                               suggested_dtM=h)

    def _instability(self, t: float, row: int, context: str) -> SimulationError:
        what, num, node = self.state_rows()[row]
        lay = self.layout
        if row < lay.n_rows:
            v = self.y[lay.u_offset + 3 * row: lay.u_offset + 3 * row + 3]
        else:
            v = self.y[lay.block_slices(row - lay.n_rows)[1]][:3]
        speed = float(np.linalg.norm(v)) if np.all(np.isfinite(v)) else math.nan
        _, limit, _ = stability_report(self.model, self.layout, self.dtM, self.scheme, self._lines_on_seabed(),
                                       self.scheme_label)
        suggest = min(0.5 * self.dtM, 0.8 * limit)
        where = f"line {num} node {node}" if what == "line" else f"{what} {num}"
        reason = "non-finite state" if not math.isfinite(speed) else f"speed {speed:.3g} m/s > {MAX_NODE_SPEED} m/s"
        msg = (f"simulation unstable at t = {t:.6g} s {context}: {where}: {reason}. "
               f"dtM = {self.dtM:.4g} s with {self.scheme_label}; try dtM <= {suggest:.3g} s")
        return SimulationError(msg, time=t, line=num if what == "line" else None,
                               node=node if what == "line" else None, point=num if what == "point" else None,
                               suggested_dtM=suggest)
