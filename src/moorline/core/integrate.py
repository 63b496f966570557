"""Explicit time schemes and the compiled time loop.

The schemes only do algebra on state vectors; all physics is in :func:`moorline.core.rhs.rhs`.
``advance`` runs many internal steps of at most ``dtM`` in compiled code, never stepping across a
knot of the coupled trajectory (so a MoorDyn coupling step of length dt is covered by
floor(dt/dtM) full steps and one shorter remainder, exactly as MoorDyn does).
"""

from __future__ import annotations

import logging
import math
from enum import IntEnum

import numpy as np

from .features import FIXED_POINT, FLOATING, MOORDYN_SCHEMES, when
from .floating import floating_after_step
from .jit import kernel
from .linestates import XC_HIST
from .rhs import _any_viv, motion_piece, rhs, rhs_call
from .schemes import (
    SP_BETA,
    SP_GAMMA,
    SP_LINES,
    SP_ORDER,
    ab_step,
    heun_step,
    leuler_begin,
    leuler_end,
    newmark_step,
    wilson_step,
)

log = logging.getLogger("moorline.core")


class Scheme(IntEnum):
    EULER = 0
    RK2 = 1
    RK4 = 2
    IMPLICIT = 3  # MoorDyn's BEuler<M> / Midpoint<M>: M relaxed fixed-point iterations
    GENALPHA = 4  # generalized-alpha with Newton iterations (core.implicit): no stability limit
    HEUN = 5  # MoorDyn's Heun (core.schemes)
    AB = 6  # Adams-Bashforth 2-4 (and MoorDyn's LAB2-4, the same in MoorDyn-C)
    LEULER = 7  # MoorDyn's local-time-step Euler
    NEWMARK = 8  # MoorDyn's ACA<M>: Newmark average acceleration, M fixed-point iterations
    WILSON = 9  # MoorDyn's Wilson<M>: Wilson-theta, M fixed-point iterations


#: largest stable omega*dt of the highest axial segment mode for damping ratio ~0.5-1
#: (spec 5.4, linear analysis of a taut chain); used by the time-step report. The relaxed
#: fixed-point iterations of the "implicit" schemes are explicit in effect: RK2's value is used.
#: Heun and Adams-Bashforth are taken as RK2 (second order, one evaluation of the same kind of
#: extrapolation), local Euler as Euler.
STABLE_OMEGA_DT = {Scheme.EULER: 1.0, Scheme.RK2: 2.0, Scheme.RK4: 2.6, Scheme.IMPLICIT: 2.0,
                   Scheme.GENALPHA: math.inf, Scheme.HEUN: 2.0, Scheme.AB: 1.0, Scheme.LEULER: 1.0,
                   Scheme.NEWMARK: 2.0, Scheme.WILSON: 2.0}


#: default spectral radius at infinite frequency: 0 (asymptotic annihilation) damps the
#: lumped-mass model's axial and seabed-contact modes, which a large step cannot resolve, within a
#: step; on the OC3 chain catenary in surge (15 segments, 100 s) it is also the most accurate:
#: fairlead tension RMS error against RK4 0.62 % at dt 0.1 s and 0.65 % at 0.25 s, against 0.80 %
#: and 1.7 % with rho_inf 0.7 (the lumped-mass mesh error alone is 0.62 %)
RHO_INF = 0.0


def parse_rho(text: str) -> float:
    """Spectral radius from the tScheme suffix of ``GenAlpha[rho]`` (empty: the default)."""
    if not text:
        return RHO_INF
    try:
        rho = float(text)
    except ValueError:
        rho = -1.0
    if not 0.0 <= rho <= 1.0:
        raise ValueError(f"time scheme GenAlpha{text}: expected GenAlpha<rho_inf> with 0 <= rho_inf <= 1, "
                         f"e.g. GenAlpha0.7")
    return rho


def parse_scheme(name: str) -> tuple[Scheme, np.ndarray, str]:
    """Map a MoorDyn ``tScheme`` name to a :class:`Scheme`, its parameters and a label.

    Every MoorDyn-C v2.7 scheme is implemented: Euler, LEuler, Heun, RK2, RK4, AB2-AB4 (LAB2-LAB4
    are the same in MoorDyn-C), ``BEuler<M>`` and ``Midpoint<M>`` (M fixed-point iterations,
    evaluated at t + c dt with c = 1 or 1/2, relaxed as MoorDyn does), ``ACA<M>`` and
    ``Wilson<M>`` (:mod:`moorline.core.schemes`), and moorline's truly implicit
    ``GenAlpha[rho_inf]`` (generalized-alpha with Newton iterations, :mod:`moorline.core.implicit`;
    ``params[0]`` = rho_inf, default 0; ``GenAlpha1`` is the implicit trapezoidal rule, i.e. the
    ACA rule solved to convergence). Unknown names fall back to RK2 as MoorDyn does, with a warning.

    Returns
    -------
    scheme : Scheme
    params : ndarray (8,)
        [c, M, c0, c1, AB order, steps taken, gamma (theta), beta] (see :mod:`.schemes`); LEuler
        needs two more entries per line, which :class:`moorline.System` appends.
    label : str
    """
    key = str(name).strip().upper()
    params = np.zeros(SP_LINES)
    params[:4] = (1.0, 1.0, 0.9, 0.0)
    if key in ("EULER", "RK1"):
        return Scheme.EULER, params, "Euler"
    if key == "HEUN":
        return Scheme.HEUN, params, "Heun"
    if key == "LEULER":
        return Scheme.LEULER, params, "LEuler"
    if key in ("AB2", "AB3", "AB4", "LAB2", "LAB3", "LAB4"):
        # MoorDyn-C builds the same (non-local) Adams-Bashforth scheme for LAB<n> as for AB<n>
        params[SP_ORDER] = int(key[-1])
        return Scheme.AB, params, key
    for prefix, scheme, label, c0, c1 in (("ACA", Scheme.NEWMARK, "ACA", 0.9, 0.15),
                                          ("WILSON", Scheme.WILSON, "Wilson", 0.015, 0.0)):
        if key.startswith(prefix):
            rest = key[len(prefix):]
            if not rest.isdigit() or int(rest) < 1:
                raise ValueError(f"time scheme {name!r}: expected {label}<M> with M >= 1 iterations, e.g. {label}5")
            params[1] = int(rest)
            params[2] = c0
            params[3] = c1
            if scheme == Scheme.NEWMARK:
                params[SP_GAMMA] = 0.5
                params[SP_BETA] = 0.25
            else:
                params[SP_GAMMA] = 1.37
            return scheme, params, f"{label}{int(rest)}"
    if key == "RK2":
        return Scheme.RK2, params, "RK2"
    if key == "RK4":
        return Scheme.RK4, params, "RK4"
    if key.startswith("GENALPHA"):
        rho = parse_rho(key[len("GENALPHA"):])
        params[0] = rho
        return Scheme.GENALPHA, params, f"GenAlpha{rho:g}"
    for prefix, c, label in (("BEULER", 1.0, "BEuler"), ("MIDPOINT", 0.5, "Midpoint")):
        if key.startswith(prefix):
            rest = key[len(prefix):]
            if not rest.isdigit() or int(rest) < 1:
                raise ValueError(f"time scheme {name!r}: expected {label}<M> with M >= 1 iterations, e.g. "
                                 f"{label}5")
            params[0] = c
            params[1] = int(rest)
            return Scheme.IMPLICIT, params, f"{label}{int(rest)}"
    log.warning("unknown time scheme %r (expected Euler, LEuler, Heun, RK2, RK4, AB2-AB4, LAB2-LAB4, BEuler<M>, "
                "Midpoint<M>, ACA<M>, Wilson<M> or GenAlpha); using RK2 as MoorDyn does", name)
    return Scheme.RK2, params, "RK2"


@kernel
def _axpy(out, y, h, k):
    for i in range(y.size):
        out[i] = y[i] + h * k[i]


@kernel
def _moordyn_step(y, t, h, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    """One step of MoorDyn's other schemes (core.schemes), compiled only for decks that use them."""
    if scheme == 5:
        heun_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece)
    elif scheme == 6:
        ab_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece)
    elif scheme == 8:
        newmark_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece)
    else:
        wilson_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece)


@kernel(inline="always")
def step(y, t, h, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    """One step of length ``h`` in place, on trajectory piece ``piece``. ``S``: (5, n) scratch;
    for the implicit schemes ``S[3]`` keeps the derivative of the previous step (zero at the
    start), for local Euler ``S[0]``; ``S[4]`` is scratch (the stages' input state, and the time
    loop's final evaluation); ``sp`` = [c, M, c0, c1] (spec 5.2).

    The stages of Euler, RK2 and RK4 share one call of ``rhs`` (stage s evaluates the derivative
    into ``S[s]``): each call site of ``rhs`` passes some 1,500 machine words of arrays, and
    compiling one instead of four roughly halves the compile time of the time loop.

    MoorDyn's local Euler (scheme 7) is Euler with the lines' bookkeeping before and after its one
    evaluation (:func:`.schemes.leuler_begin`, :func:`.schemes.leuler_end`); it writes into
    ``S[0]`` as Euler does, and there a line not evaluated keeps its rows of its last update, so
    nothing else writes ``S[0]`` between steps. It shares that call too: through a scheme
    function of its own every step passed all the arrays twice more (some 2,000 machine words per
    call), a third of the step of a small system."""
    if scheme == 3:
        when(W, FIXED_POINT, _implicit_step, (y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece))
        return
    if scheme >= 5 and scheme != 7:
        when(W, MOORDYN_SCHEMES, _moordyn_step, (y, t, h, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece))
        return
    if scheme == 7:
        when(W, MOORDYN_SCHEMES, leuler_begin, (h, sp, L.node_ptr, L.calc))
    yt = S[4]
    n_stages = 1 if (scheme == 0 or scheme == 7) else (2 if scheme == 1 else 4)
    for s in range(n_stages):
        # stage inputs: y at t; then y + h/2 k1, y + h/2 k2 at t + h/2; y + h k3 at t + h
        if s == 0:
            ys = y
            ts = t
        else:
            a = h if s == 3 else 0.5 * h
            _axpy(yt, y, a, S[s - 1])
            ys = yt
            ts = t + a
        # the stick-slip friction anchors are committed at the first stage of every step
        B.ctl[1] = 1 if s == 0 else 0
        rhs(ts, ys, S[s], L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
    B.ctl[1] = 0
    if scheme == 7:
        when(W, MOORDYN_SCHEMES, leuler_end, (sp, L.calc))
    if scheme == 0 or scheme == 7:
        k1 = S[0]
        for i in range(y.size):
            y[i] += h * k1[i]
    elif scheme == 1:
        k2 = S[1]
        for i in range(y.size):
            y[i] += h * k2[i]
    else:
        k1 = S[0]
        k2 = S[1]
        k3 = S[2]
        k4 = S[3]
        c = h / 6.0
        for i in range(y.size):
            y[i] += c * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i])


@kernel
def _implicit_step(y, t, h, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece):
    """MoorDyn's implicit Euler family: M fixed-point iterations of y* = y + c h f, f = f(t + c h, y*),
    relaxed between iterations with rho_m = c0 (1 - 1/M) + c1 (1 - (tanh(4 ((m+1)/M - 1/2)) + 1)/2),
    starting from the derivative of the previous step; then y += h f."""
    c = sp[0]
    M = int(sp[1])
    c0 = sp[2]
    c1 = sp[3]
    f = S[3]
    fold = S[2]
    ys = S[4]
    for i in range(y.size):
        fold[i] = f[i]
    for m in range(M):
        _axpy(ys, y, c * h, f)
        B.ctl[1] = 1 if m == 0 else 0
        rhs_call(t + c * h, ys, f, L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
        if m < M - 1:
            rel = c0 * (1.0 - 1.0 / M) + c1 * (1.0 - 0.5 * (math.tanh(4.0 * ((m + 1.0) / M - 0.5)) + 1.0))
            for i in range(y.size):
                f[i] = (1.0 - rel) * f[i] + rel * fold[i]
                fold[i] = f[i]
    B.ctl[1] = 0
    for i in range(y.size):
        y[i] += h * f[i]


@kernel
def check_state(y, vmax, n3, n6):
    """Index of the first state row (3-DOF rows, then 6-DOF blocks numbered n3 + j) with a
    non-finite value or a speed above ``vmax``, else -1."""
    uoff = 3 * n3 + 7 * n6
    v2 = vmax * vmax
    for r in range(n3):
        o = 3 * r
        s = y[uoff + o] ** 2 + y[uoff + o + 1] ** 2 + y[uoff + o + 2] ** 2
        if not (s < v2) or not np.isfinite(y[o] + y[o + 1] + y[o + 2]):
            return r
    for j in range(n6):
        oq = 3 * n3 + 7 * j
        ou = uoff + 3 * n3 + 6 * j
        s = y[ou] ** 2 + y[ou + 1] ** 2 + y[ou + 2] ** 2
        f = 0.0
        for i in range(7):
            f += y[oq + i]
        for i in range(6):
            f += y[ou + i]
        if not (s < v2) or not np.isfinite(f):
            return n3 + j
    return -1


@kernel
def knot_step(Mo, j, t, h, tol):
    """Shorten a step of length ``h`` from ``t`` so that it does not cross a knot of the coupled
    trajectory ``Mo``; ``j`` is the index of the first knot not yet passed (advanced here).
    Returns (h, j)."""
    nk = Mo.t.size
    while j < nk and Mo.t[j] <= t + tol:
        j += 1
    if j < nk and Mo.t[j] - t < h:
        h = Mo.t[j] - t
    return h, j


@kernel
def step_end(Mo, j, t, h, t_end, tol):
    """Time after a step of length ``h`` from ``t``: snapped to ``t_end`` or to the knot ``j``
    when it ends within ``tol`` of them (so round-off never leaves a sliver of a step)."""
    if t_end - (t + h) <= tol:
        return t_end
    if j < Mo.t.size and abs(Mo.t[j] - (t + h)) <= tol:
        return Mo.t[j]
    return t + h


#: ``final_eval`` of :func:`advance`: no evaluation after the last step, an evaluation at the
#: state reached (``loads_at='end'``), or MoorDyn's convention (``loads_at='last_stage'``)
FINAL_NONE = 0
FINAL_END = 1
FINAL_LAST_STAGE = 2


@kernel
def _keep(a, k, o, back):
    """Copy the C-contiguous array ``a`` into ``k[o:]`` (``back``: from ``k[o:]`` into ``a``);
    returns the offset after it."""
    f = a.reshape(a.size)
    if back:
        for i in range(f.size):
            f[i] = k[o + i]
    else:
        for i in range(f.size):
            k[o + i] = f[i]
    return o + f.size


@kernel
def last_stage_keep(back, kept, xs_ctl, piece, viv, T, Td, seg_len, seg_ldot, Fn, Fhyd, Fbed, Wt, kurv, pF, pa,
                    acc):
    """MoorDyn's convention for the loads after a step (``loads_at='last_stage'``): the time loop
    evaluates at the state reached, so that positions, velocities and everything else in Work
    describe it, but keeps the loads of the step's last stage over that evaluation: the line
    tensions and damping (``T``, ``Td``), segment lengths and rates, node forces (``Fn``,
    ``Fhyd``, ``Fbed``, weight ``Wt``), curvatures, point forces and accelerations. This puts them
    aside in ``kept`` (Work.kept) before the evaluation, and back after it (``back``).
    ``piece`` < 0 (no step taken): nothing is kept (a plain evaluation). The evaluation is not a
    step: the line-state histories (Syrope) are not updated over it (``xs_ctl``), and with
    ``viv`` the accelerations VIV remembers (``acc``) stay those of the last stage.

    The evaluation itself is the time loop's own call of ``rhs_call`` (one call site: a kernel of
    its own calling it would be compiled with the derivative's closure linked in and optimised
    once more for it, some 8 s of CPU in a first run). Arrays only and nothing inlined: a kernel
    taking Work (70 arrays) or inlining a dozen helpers takes seconds to compile, and this one is
    compiled for every system, whatever its ``loads_at``."""
    if piece >= 0:
        o = _keep(T, kept, 0, back)
        o = _keep(Td, kept, o, back)
        o = _keep(seg_len, kept, o, back)
        o = _keep(seg_ldot, kept, o, back)
        o = _keep(Fn, kept, o, back)
        o = _keep(Fhyd, kept, o, back)
        o = _keep(Fbed, kept, o, back)
        o = _keep(Wt, kept, o, back)
        o = _keep(kurv, kept, o, back)
        o = _keep(pF, kept, o, back)
        _keep(pa, kept, o, back)
    o = kept.size - acc.size
    if viv:
        _keep(acc, kept, o, back)
    if back:
        xs_ctl[XC_HIST] = kept[o - 1]
    else:
        kept[o - 1] = xs_ctl[XC_HIST]
        xs_ctl[XC_HIST] = 0.0


@kernel
def advance(y, t, t_end, dtM, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, vmax, final_eval):
    """Integrate ``y`` in place from ``t`` to ``t_end`` in steps of at most ``dtM``. ``final_eval``
    (:data:`FINAL_END`): evaluate all loads once more at the final state (on the last step's
    trajectory piece) so that the Work arrays describe the state at ``t_end``;
    :data:`FINAL_LAST_STAGE`: the same but with the last stage's loads kept
    (:func:`last_stage_keep`); :data:`FINAL_NONE`: no evaluation.

    Returns
    -------
    t : float
        Time reached (``t_end`` unless the state went bad).
    bad_row : int
        -1, or the state row that became non-finite or exceeded ``vmax`` [m/s].
    n_steps : int
    piece : int
        Trajectory piece of the last step (-1 if no step was taken).
    """
    tol = 1e-9 * dtM
    j = 0
    n_steps = 0
    piece = -1
    while t_end - t > tol:
        h, j = knot_step(Mo, j, t, min(dtM, t_end - t), tol)
        piece = motion_piece(Mo, t + 0.5 * h)
        step(y, t, h, scheme, sp, L, R, P, E, B, Mo, W, F, FW, cd_scale, S, piece)
        n_steps += 1
        t = step_end(Mo, j, t, h, t_end, tol)
        when(W, FLOATING, floating_after_step, (t, y, R, W, F, FW))
        bad = check_state(y, vmax, R.dims[0], R.dims[1])
        if bad >= 0:
            return t, bad, n_steps, piece
    if final_eval == FINAL_LAST_STAGE:
        viv = _any_viv(L)
        last_stage_keep(False, W.kept, L.xs_ctl, piece, viv, W.T, W.Td, W.seg_len, W.seg_ldot, W.F, W.Fhyd, W.Fbed,
                        W.W, W.kurv, W.pF, W.pa, W.acc)
    if final_eval != FINAL_NONE:
        # into S[4], the scratch row: local Euler carries S[0] from step to step
        rhs_call(t, y, S[4], L, R, P, E, B, Mo, W, F, FW, cd_scale, piece)
    if final_eval == FINAL_LAST_STAGE:
        last_stage_keep(True, W.kept, L.xs_ctl, piece, viv, W.T, W.Td, W.seg_len, W.seg_ldot, W.F, W.Fhyd, W.Fbed,
                        W.W, W.kurv, W.pF, W.pa, W.acc)
    return t, -1, n_steps, piece
