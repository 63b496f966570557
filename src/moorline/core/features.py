"""Compile only the code a system needs: its :class:`Features`, carried in the type of ``Work``.

numba compiles a kernel together with every function it may call, whether a given system reaches
those calls or not: a chain catenary paid for the compilation of the rod, body and wave kernels
(about two thirds of its first-run compile time). Here the features of a system (rods or bodies,
water kinematics, bending stiffness, MoorDyn's fixed-point implicit schemes) are a small Python
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

from numba import types
from numba.core import cgutils
from numba.extending import NativeValue, intrinsic, models, register_model, typeof_impl, unbox

#: rods or bodies (their kinematics, loads and rigid-body dynamics)
RIGID = "rigid"
#: water kinematics: waves, currents or externally set kinematics
WATER = "water"
#: lines with bending stiffness (curvature, bending forces, clamped ends)
BENDING = "bending"
#: MoorDyn's fixed-point implicit schemes BEuler<M> and Midpoint<M>
FIXED_POINT = "fixed_point"
#: every feature, in the order they are named
ALL_FEATURES = (RIGID, WATER, BENDING, FIXED_POINT)


class Features:
    """An immutable set of feature names (``RIGID``, ``WATER``, ``BENDING``, ``FIXED_POINT``).

    Parameters
    ----------
    names : str
        The features the system has.
    """

    __slots__ = ("names",)

    def __init__(self, *names: str):
        unknown = set(names) - set(ALL_FEATURES)
        if unknown:
            raise ValueError(f"unknown features {sorted(unknown)}; expected some of {ALL_FEATURES}")
        self.names = frozenset(names)

    def __contains__(self, name: str) -> bool:
        return name in self.names

    def __eq__(self, other) -> bool:
        return isinstance(other, Features) and other.names == self.names

    def __hash__(self) -> int:
        return hash(self.names)

    def __reduce__(self):
        return Features, tuple(sorted(self.names))

    def __repr__(self) -> str:
        return f"Features({', '.join(repr(n) for n in ALL_FEATURES if n in self.names)})"


#: environment variable: set to 1, every system has every feature, so one compiled specialisation
#: serves all decks (compiled once, about a minute on 2 cores, instead of 10-30 s for each new
#: kind of deck); the test suite sets it (tests/conftest.py). Results are identical either way.
ALL_FEATURES_ENV = "MOORLINE_ALL_FEATURES"


def features_of(layout, scheme: int | None = None) -> Features:
    """The features of a :class:`~moorline.core.layout.Layout` (and of the time scheme, an
    ``integrate.Scheme`` value, when given); all of them when ``MOORLINE_ALL_FEATURES=1``."""
    if os.environ.get(ALL_FEATURES_ENV) == "1":
        return Features(*ALL_FEATURES)
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
    return Features(*names)


# ---------------------------------------------------------------------------------------- numba side
class FeaturesType(types.Type):
    """numba type of a :class:`Features` value: the names are part of the type."""

    def __init__(self, names):
        self.names = frozenset(names)
        super().__init__(name=f"Features({','.join(n for n in ALL_FEATURES if n in self.names)})")


@typeof_impl.register(Features)
def _typeof_features(val, c):
    return FeaturesType(val.names)


@register_model(FeaturesType)
class _FeaturesModel(models.OpaqueModel):
    """No data at run time: everything a kernel needs is in the type."""


@unbox(FeaturesType)
def _unbox_features(typ, obj, c):
    return NativeValue(c.context.get_constant_null(typ))


def _features_in(W) -> frozenset:
    if isinstance(W, types.BaseNamedTuple) and "features" in W.fields:
        ft = W.types[W.fields.index("features")]
        if isinstance(ft, FeaturesType):
            return ft.names
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
