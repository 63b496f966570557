"""Compile only the code a system needs: its :class:`Features`, carried in the type of ``Work``.

numba compiles a kernel together with every function it may call, whether a given system reaches
those calls or not: a chain catenary paid for the compilation of the rod, body and wave kernels
(about two thirds of its first-run compile time). Here the features of a system (rods or bodies,
water kinematics, bending stiffness, MoorDyn's fixed-point implicit schemes, stick-slip friction,
floating bodies, line states, MoorDyn's other time schemes) are a small Python
object stored in ``Work.features`` whose numba type names them, so ``Work`` has a different type
for each combination of features, and

    when(W, RIGID, rod_loads, (R, E, B, W, cd_scale))

calls ``rod_loads(R, E, B, W, cd_scale)`` in a kernel compiled for a system with rods or bodies,
and is no code at all (``rod_loads`` is not even compiled) in one compiled for a system without.
The decision is taken while numba types the kernel, so each combination of features met is
compiled once per machine and cached like any other specialisation.

A feature that is off must be unreachable: :func:`features_of` sets it whenever the arrays of the
layout could reach the code it guards (for instance RIGID whenever there is a rod or a body).
"""

from __future__ import annotations

import os
from typing import NamedTuple

import numpy as np
from numba import types
from numba.core import cgutils
from numba.extending import intrinsic

from .seabed import FRIC_STICKSLIP

#: rods or bodies (their kinematics, loads and rigid-body dynamics)
RIGID = "rigid"
#: water kinematics: waves, currents or externally set kinematics
WATER = "water"
#: lines with bending stiffness (curvature, bending forces, clamped ends)
BENDING = "bending"
#: MoorDyn's fixed-point implicit schemes BEuler<M> and Midpoint<M>
FIXED_POINT = "fixed_point"
#: moorline's stick-slip seabed friction
STICKSLIP = "stickslip"
#: floating bodies (potential-flow loads, radiation memory, joints and PTOs)
FLOATING = "floating"
#: lines with states of their own (viscoelastic and Syrope ropes, VIV phases)
LINE_STATES = "line_states"
#: MoorDyn's other explicit and fixed-point schemes: Heun, Adams-Bashforth, local Euler, ACA, Wilson
MOORDYN_SCHEMES = "moordyn_schemes"
#: every feature, in the order they are named
ALL_FEATURES = (RIGID, WATER, BENDING, FIXED_POINT, STICKSLIP, FLOATING, LINE_STATES, MOORDYN_SCHEMES)


class Features(NamedTuple):
    """What a system has: each field True (it has the feature) or None (it has not). numba types
    True as ``boolean`` and None as ``none``, so the type of a Features value (and of the Work
    that carries it) names the features, and numba's fast dispatch recognises it (a class of our
    own would be typed by a Python fallback at every call: 50 us per call measured).

    Build with :meth:`of`: ``Features.of(RIGID, WATER)``.
    """

    rigid: bool | None = None
    water: bool | None = None
    bending: bool | None = None
    fixed_point: bool | None = None
    stickslip: bool | None = None
    floating: bool | None = None
    line_states: bool | None = None
    moordyn_schemes: bool | None = None

    @classmethod
    def of(cls, *names: str) -> Features:
        """The Features with exactly ``names`` (some of :data:`ALL_FEATURES`)."""
        unknown = set(names) - set(ALL_FEATURES)
        if unknown:
            raise ValueError(f"unknown features {sorted(unknown)}; expected some of {ALL_FEATURES}")
        return cls(**dict.fromkeys(names, True))

    @property
    def names(self) -> frozenset:
        """The features the system has."""
        return frozenset(n for n in ALL_FEATURES if getattr(self, n))

    def __repr__(self) -> str:
        return f"Features.of({', '.join(repr(n) for n in ALL_FEATURES if getattr(self, n))})"


#: environment variable: set to 1, every system has every feature, so one compiled specialisation
#: serves all decks (compiled once, about a minute on 2 cores, instead of 10-30 s for each new
#: kind of deck); the test suite sets it (tests/conftest.py). Results are identical either way.
ALL_FEATURES_ENV = "MOORLINE_ALL_FEATURES"


def features_of(layout, scheme: int | None = None) -> Features:
    """The features of a :class:`~moorline.core.layout.Layout` (and of the time scheme, an
    ``integrate.Scheme`` value, when given); all of them when ``MOORLINE_ALL_FEATURES=1``."""
    if os.environ.get(ALL_FEATURES_ENV) == "1":
        return Features.of(*ALL_FEATURES)
    names = []
    R = layout.rigid
    if R.rod_kind.size or R.body_kind.size:
        names.append(RIGID)
    for E in (layout.env, layout.env_ic):
        K = E.water
        if K.wave_mode != 0 or K.current_mode != 0 or K.U_ext.shape[0] > 0:
            names.append(WATER)
            break
    L = layout.lines
    if (L.EI > 0.0).any() or (L.ei_tab[:, 1] > 0).any():
        names.append(BENDING)
    if scheme is not None and int(scheme) == 3:  # integrate.Scheme.IMPLICIT (not imported: integrate imports us)
        names.append(FIXED_POINT)
    if scheme is not None and int(scheme) >= 5:  # integrate.Scheme.HEUN and after (core.schemes)
        names.append(MOORDYN_SCHEMES)
    if layout.env.fric == FRIC_STICKSLIP or layout.env_ic.fric == FRIC_STICKSLIP:
        names.append(STICKSLIP)
    if L.xs_s0.size:
        names.append(LINE_STATES)
    fl = getattr(layout, "fl", None)
    if fl is not None and fl.body.size:
        names.append(FLOATING)
    return Features.of(*names)


# ----------------------------------------------------------------------- what the kernels are passed
class NoRigid(NamedTuple):
    """The :class:`~moorline.core.layout.RigidArrays` of a system without rods or bodies, as its
    kernels take them: the fields read by code outside the RIGID feature, whose code is not
    compiled for such a system. numba unboxes every array of every argument of a call from
    Python, some 30-40 ns each on the reference machine, whether empty or not: this leaves out
    26 empty ones (benchmarks/RESULTS.md section 6, session 9).

    Every ``No*`` tuple ends with ``absent`` (True), a field of another type than the others: a
    NamedTuple whose fields all have one type is numba's homogeneous ``NamedUniTuple``, an LLVM
    array, and a derivative taking five of them cost 7.2 us per call from compiled code against
    2.2-2.7 us for the full arrays (WD0050_Chain; 3.3 us with ``absent``)."""

    dims: np.ndarray
    body_kind: np.ndarray
    rod_kind: np.ndarray
    absent: bool = True


class NoFloating(NamedTuple):
    """The :class:`~moorline.core.layout.FloatArrays` of a system without floating bodies, as its
    kernels take them (see :class:`NoRigid`): what the rigid-body code outside the FLOATING
    feature reads."""

    body: np.ndarray
    of_body: np.ndarray
    grouped: np.ndarray
    absent: bool = True


class NoFloatWork(NamedTuple):
    """The :class:`~moorline.core.layout.FloatWork` of a system without floating bodies, as its
    kernels take them (see :class:`NoRigid`; with :class:`NoFloating`, 68 arrays fewer)."""

    F: np.ndarray
    absent: bool = True


class NoWater(NamedTuple):
    """The water kinematics (``EnvArrays.water``) of a system without waves, currents or external
    kinematics, as its kernels take them (see :class:`NoRigid`): the two modes the derivative and
    the floating bodies' viscous loads test (both 0) and none of the 30 empty arrays."""

    wave_mode: int
    current_mode: int
    absent: bool = True


class NoExcitation(NamedTuple):
    """The wave excitation (``EnvArrays.exc``) of a system without floating bodies, as its kernels
    take them (see :class:`NoRigid`)."""

    ctl: np.ndarray
    absent: bool = True


def kernel_env(features: Features, E):
    """The environment ``E`` as the kernels of a system with ``features`` take it: without the
    arrays of the water kinematics when it has no WATER, and without those of the wave excitation
    when it has no FLOATING (:class:`NoWater`, :class:`NoExcitation`). Every kernel that reads
    the kinematics does so under ``when(W, WATER, ...)`` (a floating body's viscous loads in
    ``floating.floating_loads`` too, behind their run-time test of still water)."""
    if not features.water:
        E = E._replace(water=NoWater(E.water.wave_mode, E.water.current_mode))
    if not features.floating:
        E = E._replace(exc=NoExcitation(E.exc.ctl))
    return E


def kernel_parts(features: Features, R, F, FW):
    """(R, F, FW) as the kernels of a system with ``features`` (a ``Features``) take them: the
    arrays of a feature the system lacks are left out (:class:`NoRigid`, :class:`NoFloating`,
    :class:`NoFloatWork`), the same objects otherwise. Python code keeps using the full ones."""
    if not features.rigid:
        R = NoRigid(R.dims, R.body_kind, R.rod_kind)
    if not features.floating:
        F = NoFloating(F.body, F.of_body, F.grouped)
        FW = NoFloatWork(FW.F)
    return R, F, FW


# ---------------------------------------------------------------------------------------- numba side
def _features_in(W) -> frozenset:
    """The features named by the numba type of a Work (a field typed boolean is present)."""
    if isinstance(W, types.BaseNamedTuple) and "features" in W.fields:
        ft = W.types[W.fields.index("features")]
        if isinstance(ft, types.BaseNamedTuple) and tuple(ft.fields) == ALL_FEATURES:
            return frozenset(n for n, t in zip(ft.fields, ft.types, strict=True) if t == types.boolean)
    raise TypeError(f"when(): the first argument must be a Work with a 'features' field, got {W}")


@intrinsic(prefer_literal=True)
def when(typingctx, W, feature, fn, args):
    """In a kernel, ``when(W, FEATURE, fn, (a, b, ...))``: ``fn(a, b, ...)`` if the system of ``W``
    (a ``Work``) has ``FEATURE``, else nothing, and then ``fn`` is not compiled at all.

    An intrinsic rather than an overload: numba compiles the implementation of an overload as a
    function of its own (with a Python wrapper that unboxes every array of ``W``, about a second
    of compile time per call site); an intrinsic only emits the call."""
    if not isinstance(feature, types.StringLiteral):
        raise TypeError("when(): the feature must be a compile-time constant: import RIGID, WATER, ... by name "
                        "(an attribute lookup such as features.RIGID is not one)")
    if feature.literal_value not in ALL_FEATURES:
        raise TypeError(f"when(): unknown feature {feature.literal_value!r}; expected one of {ALL_FEATURES}")
    sig = types.none(W, feature, fn, args)
    if feature.literal_value not in _features_in(W):
        def skip(context, builder, signature, llargs):
            return context.get_dummy_value()

        return sig, skip
    arg_types = tuple(args.types)
    fn_sig = fn.get_call_type(typingctx, tuple(types.unliteral(a) for a in arg_types), {})

    def call(context, builder, signature, llargs):
        values = cgutils.unpack_tuple(builder, llargs[3], len(arg_types))
        values = [context.cast(builder, v, a, b) for v, a, b in zip(values, arg_types, fn_sig.args, strict=True)]
        context.get_function(fn, fn_sig)(builder, values)
        return context.get_dummy_value()

    return sig, call


@intrinsic(prefer_literal=True)
def either(typingctx, W, feature, fn, args, other, other_args):
    """In a kernel, ``either(W, FEATURE, fn, (a, ...), other, (b, ...))``: ``fn(a, ...)`` if the
    system of ``W`` has ``FEATURE``, else ``other(b, ...)``; only the one called is compiled (for a
    call with a result, where :func:`when` has none)."""
    if not isinstance(feature, types.StringLiteral):
        raise TypeError("either(): the feature must be a compile-time constant: import RIGID, WATER, ... by name")
    if feature.literal_value not in ALL_FEATURES:
        raise TypeError(f"either(): unknown feature {feature.literal_value!r}; expected one of {ALL_FEATURES}")
    on = feature.literal_value in _features_in(W)
    callee, arg_types, k = (fn, tuple(args.types), 3) if on else (other, tuple(other_args.types), 5)
    callee_sig = callee.get_call_type(typingctx, tuple(types.unliteral(a) for a in arg_types), {})

    def call(context, builder, signature, llargs):
        values = cgutils.unpack_tuple(builder, llargs[k], len(arg_types))
        values = [context.cast(builder, v, a, b) for v, a, b in zip(values, arg_types, callee_sig.args, strict=True)]
        return context.get_function(callee, callee_sig)(builder, values)

    return callee_sig.return_type(W, feature, fn, args, other, other_args), call
