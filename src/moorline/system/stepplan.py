"""The coupling step's fast path: what :meth:`System.step` keeps ready between calls.

A host calls ``step(x, xd, t, dt)`` thousands of times per simulated minute with the same system,
so everything one call needs apart from ``x``, ``xd``, ``t`` and ``dt`` is found once and kept in a
:class:`StepPlan`: the compiled entry point of the time loop (``core.integrate.advance``) and its
argument tuple, views of the coupling trajectory's coefficients that ``x`` and ``xd`` are copied
into, and flat indices that gather the coupled loads from the Work arrays (one ``take`` per kind of
coupled object instead of a Python loop over the objects). A call then costs one identity check
per kept dependency, two small copies, the compiled call and the gather; the arithmetic is the
general path's, argument for argument, so the results are bitwise the same.

When the plan is built, and what it depends on
----------------------------------------------
It is built on the first ``step`` after :meth:`System.init` and whenever a guarded dependency was
replaced. It holds (and :meth:`StepPlan.current` checks by identity on every call) the system's
``layout`` and each of its kernel arrays (lines, rigid, points, env, seabed, fl), ``work`` (a new
feature set replaces it, see :mod:`moorline.core.features`), ``fwork``, the state ``y``, the scheme's
carried derivatives ``_S`` and parameters ``scheme_params``, ``dtM``, ``scheme``, ``loads_at``, the
implicit solver's ``_imp`` and the ``failures`` list with its length. The paths inside moorline that
replace any of these also drop the plan explicitly (:meth:`System._drop_step_plan`): a line failure
(``failures.fire``, which rebuilds the layout, state and Work arrays), ``add_failure``, a checkpoint
load (which replays failures and replaces the failure list), ``init``, and ``_kernel_arrays`` when it
gives ``work`` new features.
State written in place (``set_state``, ``set_rod_state``, a checkpoint's arrays, ``advance_to`` on
another trajectory) leaves the plan valid: the arrays it holds are the ones written.

With ``loads_at='last_stage'`` (MoorDyn's convention, and that of :mod:`moorline.moordyn`) the
kept call ends, as the general path's does, with the evaluation at the state reached that keeps
the last stage's loads (``core.integrate.last_stage_keep``, inside the compiled call).

With the implicit GenAlpha scheme the kept call is that of ``core.implicit.advance_implicit``,
and the plan also holds (and checks) the implicit solver's structure and work, ``_imp``.

The plan does not apply, and ``step`` takes the general path, while a failure triggered by a
load is pending (loads are checked between compiled intervals), with quasi-static lines, for
``dt`` below 1e-300 s (``dt <= 0`` only evaluates the loads), and for an ``out`` that is not a
float64 array of n_coupled_dof values. Failures pending on a time alone leave the fast path to
the calls that end more than the general path's tolerance (1e-9 dtM) before the earliest of
them and take a step; the call in which one happens is the general path's, which stops there.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

from ..core.implicit import advance_implicit
from ..core.integrate import FINAL_END, FINAL_LAST_STAGE, Scheme, advance
from ..core.jit import compile_for

if TYPE_CHECKING:
    from .runtime import System

F8 = np.dtype(np.float64)

#: the Work array holding each kind of coupled object's loads
FORCE_FIELD = {"body": "b6F", "rod": "rod6F", "point": "pF"}


class ForceGather:
    """The coupled loads of ``work`` in coupled-DOF order, by one ``take`` per kind of object.

    ``segments``: (flat view of a Work array, flat indices, first, last coupled DOF) for each kind
    present (bodies, rods, points occupy consecutive DOF, see ``System.coupled_slots``).
    """

    __slots__ = ("segments", "whole", "n")

    def __init__(self, slots, work, n: int):
        by_kind: dict[str, list] = {}
        for kind, i, k, o in slots:
            by_kind.setdefault(kind, []).append((i, k, o))
        segments = []
        for kind, objs in by_kind.items():
            a = getattr(work, FORCE_FIELD[kind])
            flat = a.reshape(-1)
            if not np.shares_memory(flat, a):  # (Work arrays are C-contiguous: reshape gives a view)
                raise ValueError(f"Work.{FORCE_FIELD[kind]} is not contiguous")
            idx = np.concatenate([i * a.shape[1] + np.arange(k) for i, k, _ in objs]).astype(np.intp)
            o0 = objs[0][2]
            o1 = objs[-1][2] + objs[-1][1]
            if o1 - o0 != idx.size:
                raise ValueError(f"coupled {kind}s do not occupy consecutive DOF")
            segments.append((flat, idx, o0, o1))
        self.segments = tuple(segments)
        self.whole = len(segments) == 1 and segments[0][2] == 0 and segments[0][3] == n
        self.n = n

    def __call__(self, out: np.ndarray) -> np.ndarray:
        """Write the loads into ``out`` (float64, shape (n,)) and return it."""
        if self.whole:
            flat, idx, _, _ = self.segments[0]
            flat.take(idx, out=out, mode="clip")  # ('clip': no buffered copy; the indices are in range)
            return out
        for flat, idx, o0, o1 in self.segments:
            flat.take(idx, out=out[o0:o1], mode="clip")
        return out


class StepPlan:
    """See the module docstring. ``fn`` is None when the fast path does not apply to the system as
    it was when the plan was made (the plan still records what it was made for, so that it is made
    again only when that changes)."""

    __slots__ = ("fn", "head", "tail", "cx", "cxd", "tk", "shape", "deck_x", "gather", "take", "idx",
                 "bed_ctl", "motion", "implicit", "imp", "pending",
                 "layout", "L", "R", "P", "E", "B", "F", "work", "fwork", "y", "S", "sp", "dtM", "scheme",
                 "loads_at", "failures", "n_failures")

    def current(self, s: System) -> bool:
        """True while every dependency is the object the plan was made with."""
        lay = s.layout
        return (lay is self.layout and s.work is self.work and s.y is self.y and s._S is self.S
                and s.fwork is self.fwork and s.scheme_params is self.sp and s.dtM is self.dtM
                and s.scheme is self.scheme and s.loads_at is self.loads_at and s._imp is self.imp
                and s.failures is self.failures
                and len(s.failures) == self.n_failures and lay.lines is self.L and lay.rigid is self.R
                and lay.points is self.P and lay.env is self.E and lay.seabed is self.B and lay.fl is self.F)


def make_plan(s: System) -> StepPlan:
    """A :class:`StepPlan` for ``s`` as it is now (``fn`` None where the fast path does not apply)."""
    p = StepPlan()
    p.fn = None
    mo = s._step_motion
    # failures pending on a time only: the fast path serves the calls that end before it (checked per call)
    p.pending = tuple(ev for ev in s.failures if ev.pending)
    applies = (s._qsm is None and s.loads_at in ("end", "last_stage")
               and not any(math.isfinite(ev.failure.tension) for ev in p.pending))
    p.implicit = s.scheme == Scheme.GENALPHA
    # (the implicit steps report the loads at the state reached whatever loads_at says)
    final = True if p.implicit else FINAL_LAST_STAGE if s.loads_at == "last_stage" else FINAL_END
    if applies:
        kernel, args = s._advance_call(mo, s.t)  # (first: it may give ``work`` new features)
        if (kernel is (advance_implicit if p.implicit else advance) and args[11] is mo
                and args[-1] == final):
            fn = compile_for(kernel, args)
            if callable(fn):
                p.fn = fn
                p.head = (args[0],)  # y
                p.tail = args[3:]  # dtM, scheme, scheme parameters, kernel arrays, motion, ..., final evaluation
    lay = s.layout
    p.layout, p.L, p.R, p.P, p.E, p.B, p.F = lay, lay.lines, lay.rigid, lay.points, lay.env, lay.seabed, lay.fl
    p.work, p.fwork, p.y, p.S, p.sp = s.work, s.fwork, s.y, s._S, s.scheme_params
    p.dtM, p.scheme, p.loads_at, p.imp = s.dtM, s.scheme, s.loads_at, s._imp
    p.failures, p.n_failures = s.failures, len(s.failures)
    p.motion = mo
    p.cx = mo.c[0, :, 0]
    p.cxd = mo.c[0, :, 1]
    p.tk = mo.t
    n = lay.n_coupled_dof
    p.shape = (n,)
    p.deck_x = s._deck_x
    p.gather = g = ForceGather(s.coupled_slots, s.work, n)
    # one kind of coupled object (the usual case): step() calls its take itself
    p.take, p.idx = (g.segments[0][0].take, g.segments[0][1]) if g.whole else (None, None)
    p.bed_ctl = lay.seabed.ctl
    return p
