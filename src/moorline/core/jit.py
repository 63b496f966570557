"""The one decorator of every compiled kernel: :func:`kernel`.

All kernels are compiled the same way: ``cache=True`` (compiled once per machine, then loaded
from numba's on-disk cache), ``error_model="numpy"`` (a division by zero gives inf or nan, as in
numpy, instead of raising) and without numba's runtime for reference-counted memory
(``_nrt=False``).

Why ``_nrt=False``: with the runtime, every NamedTuple of arrays (``Work`` has 60) that reaches a
function which calls another non-inlined function is reference counted array by array, two atomic
updates per array and per call. Measured on the OC3 chain (63 nodes) this was 10 us of a 13 us
derivative evaluation; without it the evaluation takes 2.9 us. The price: the kernels allocate
nothing (scratch arrays live in ``Work`` and ``WaterKin``), and a kernel compiled without the
runtime cannot call one that allocates.

``_nrt`` is a private numba option (a leading underscore: numba may change or drop it without
notice). It is used here and nowhere else, and ``tests/kernels/test_jit.py`` fails loudly when
numba stops accepting it or when it stops removing the reference counting.
"""

from __future__ import annotations

import contextlib
import operator

import llvmlite.binding as llvm_binding
import numpy as np
from numba import njit, typeof

#: options of every kernel (see the module docstring)
KERNEL_OPTIONS = {"cache": True, "error_model": "numpy", "_nrt": False}

#: LLVM fast-math flags of the kernels that evaluate the derivative (``kernel(fastmath=True)``):
#: reassociation, contraction into fused multiply-adds, reciprocals for divisions, no signed
#: zeros. Each changes results by round-off only. ``nnan`` and ``ninf`` are left out on purpose:
#: an unstable run is caught by its non-finite state, so the code must keep treating inf and nan
#: as values; ``afn`` (approximate square roots and other functions) is left out too.
SAFE_FASTMATH = frozenset({"reassoc", "contract", "arcp", "nsz"})


#: run-time overlap checks LLVM's loop vectoriser may insert in a :func:`vector_kernel` before it
#: gives up on a loop (LLVM's limit is 8 otherwise). numba cannot tell LLVM that two arrays are
#: distinct, so a loop that reads and writes a dozen arrays needs a check per pair of them.
VECTORIZER_CHECKS = 1024
#: the LLVM options that limit those checks, and LLVM's defaults, restored after each vector
#: kernel is compiled
_CHECK_OPTIONS = (("-runtime-memory-check-threshold", 8), ("-vectorize-memory-check-threshold", 128),
                  ("-vectorize-scev-check-threshold", 16))
# (the third limits the checks that index arithmetic does not wrap, which the node and segment
# indices of one loop, offset from each other, need)

#: doubles per vector in a :func:`vector_kernel`'s loops, and no interleaving of vector iterations.
#: The lines these loops serve have 16 to a few hundred nodes, most under 60: left to itself, LLVM
#: vectorises 8 doubles at a time where the processor has 512-bit registers (AMD Zen 4), and a
#: 20-node line then runs two vector iterations and a scalar remainder of up to 7 nodes; on a Zen 4
#: the line force kernel of MoorDyn's 3 x 21-node `lines` deck took 2.2 us per evaluation with 8, as
#: long as its scalar pass, and 1.8-1.9 with 4 (benchmarks/RESULTS.md, section 6, session 15). Four
#: is what LLVM chooses by itself for 256-bit registers (AVX2, and Intel's AVX-512 processors, which
#: it tunes to prefer 256-bit vectors), so the width no longer depends on the processor's family.
VECTOR_WIDTH = 4
#: (LLVM's option, its value within :func:`overlap_checks`, its default: 0 lets LLVM choose)
_WIDTH_OPTIONS = (("-force-vector-width", VECTOR_WIDTH, 0), ("-force-vector-interleave", 1, 0))


def _set_check_limit(limit: int | None) -> None:
    for name, default in _CHECK_OPTIONS:
        llvm_binding.set_option("moorline", f"{name}={default if limit is None else limit}")
    for name, value, default in _WIDTH_OPTIONS:
        llvm_binding.set_option("moorline", f"{name}={default if limit is None else value}")


@contextlib.contextmanager
def overlap_checks(limit: int = VECTORIZER_CHECKS):
    """Within the block, LLVM's loop vectoriser may insert up to ``limit`` run-time overlap checks
    per loop (and as many run-time checks of its index arithmetic), and vectorises
    :data:`VECTOR_WIDTH` doubles at a time without interleaving; LLVM's defaults after it."""
    _set_check_limit(limit)
    try:
        yield
    finally:
        _set_check_limit(None)


def vector_kernel(signature: str):
    """Compile a loop kernel now, for ``signature``, with :data:`SAFE_FASTMATH` and LLVM allowed
    :data:`VECTORIZER_CHECKS` run-time overlap checks per loop, so that LLVM vectorises its loop
    (:data:`VECTOR_WIDTH` doubles at a time).

    The limit is an LLVM command-line option (llvmlite's public ``set_option``), global to the
    process: it is raised for this one compilation and set back to LLVM's default right after,
    so no other numba code, moorline's or the user's, is compiled under it. Hence the eager
    compilation: the kernel must not be compiled later, lazily, by whatever calls it first. From
    numba's cache it is loaded as compiled; a caller compiled afterwards links the vectorised code
    (tests/kernels/test_jit.py checks both).
    """
    def deco(fn):
        with overlap_checks():
            return njit(signature, **KERNEL_OPTIONS, fastmath=set(SAFE_FASTMATH))(fn)
    return deco


def kernel(fn=None, *, inline: str = "never", fastmath: bool = False, forceinline: bool = False):
    """Compile ``fn`` as a moorline kernel (``@kernel`` or ``@kernel(inline="always")``).

    Parameters
    ----------
    fn : function, optional
        The Python function (when used as ``@kernel`` without arguments).
    inline : {'never', 'always'}
        numba's IR-level inlining: ``'always'`` copies the function into each caller (no call,
        no dispatcher of its own; use it for small functions only: numba's inliner copies the
        callee's IR once per call site, at a cost that grows with its size).
    fastmath : bool
        Compile with :data:`SAFE_FASTMATH` (a function inlined with ``inline="always"`` takes
        its caller's flags).
    forceinline : bool
        LLVM-level inlining into every caller (numba's ``forceinline``), whatever LLVM's size
        heuristics say. For the derivative: a call that is not inlined passes its ~220 arrays one
        by one, about 0.65 us per evaluation, and LLVM's heuristic stops inlining it as soon as it
        grows a little (benchmarks/RESULTS.md section 6).

    Both flags are always passed to numba, False included. numba compiles a function that leaves
    one of them unset with the value of the function being compiled when it first meets it
    (``Flags.inherit_if_not_set``), and its cache keeps that compilation: a kernel's fast-math
    and inlining then depended on which caller compiled it first, in this process or in whichever
    process filled the cache (the floating bodies' kernels compiled from Python before the
    derivative did were compiled without them, and changed results in the last bit). See
    :func:`derivative_kernel`.

    Returns
    -------
    numba dispatcher, or a decorator when ``fn`` is None.
    """
    opts = dict(KERNEL_OPTIONS)
    if inline != "never":
        opts["inline"] = inline
    opts["fastmath"] = set(SAFE_FASTMATH) if fastmath else False
    opts["forceinline"] = bool(forceinline)
    if fn is None:
        return njit(**opts)
    return njit(**opts)(fn)


def derivative_kernel(fn):
    """A kernel of the derivative (``core.rhs.rhs`` and the kernels it calls, down to the water
    kinematics, rods, bodies, floating bodies and seabed forces): :data:`SAFE_FASTMATH` and
    ``forceinline``, so that the derivative is one function with no calls (each non-inlined call
    passes its tuples' arrays one by one). These are the flags numba gave them before they were
    set explicitly, when the derivative compiled them first, as it does in a run that starts with
    its initial conditions (:func:`kernel` on why they are explicit). A kernel the derivative
    calls that other code compiled first then (``seabed.seabed_at``, which the initial conditions
    call from Python) keeps plain :func:`kernel`, as it had."""
    return kernel(fn, fastmath=True, forceinline=True)


#: numba types of argument structures already met (:func:`_type_key` -> numba type)
_TYPES: dict = {}


def _type_key(a):
    """What numba's ``typeof`` of ``a`` depends on, as a hashable key, or None for a value this
    does not know (typed by ``typeof`` itself, every time). An array's type is its dtype, number
    of dimensions, layout (C, F or neither) and whether it is read-only
    (``numba.core.typing.typeof._typeof_ndarray``); a tuple's, its class and its items' types;
    a Python int's, whether it fits in 64 signed bits; other scalars', their class."""
    t = type(a)
    if t is np.ndarray:
        f = a.flags
        return (a.dtype, a.ndim, f.c_contiguous, f.f_contiguous, f.writeable)
    if t is float or t is bool or a is None or isinstance(a, np.number):
        return t
    if t is int:
        return t if a.bit_length() < 64 else None
    if isinstance(a, tuple):
        items = tuple(map(_type_key, a))
        return None if None in items else (t, items)
    return None


def fast_typeof(a):
    """numba's ``typeof(a)``, looked up by the structure of ``a`` once it has been met. numba types a
    tuple in Python, item by item (about 15 us per array): the eight NamedTuples of some 260
    arrays that every kernel entry point is looked up with cost 2-4 ms per lookup, and a start
    looks up a dozen (13 ms of the 36 ms start-up of section 2's lazy-wave cable); the key costs
    under 1 us per array."""
    k = _type_key(a)
    if k is None:
        return typeof(a)
    ty = _TYPES.get(k)
    if ty is None:
        ty = _TYPES[k] = typeof(a)
    return ty


def compile_for(dispatcher, args):
    """Compile ``dispatcher`` (or load it from numba's cache) for the types of ``args``, without
    running it: the specialisation a later ``dispatcher(*args)`` call uses. Returns its compiled
    entry point (what :meth:`numba.core.dispatcher.Dispatcher.compile` returns)."""
    return dispatcher.compile(tuple(map(fast_typeof, args)))


class FastCall:
    """Calls of one kernel with the same argument objects, step after step, without numba's
    per-call type dispatch.

    A dispatcher call types every argument before it runs (``numba.typeof``, in Python for
    tuples): for the time loop's eight NamedTuples of some 210 arrays that is about 30 us per call,
    three times the unboxing itself. A coupled host calls ``step`` thousands of times per simulated
    minute, so the entry point of the compiled specialisation is kept and called directly for as
    long as the arguments are the same objects (same arrays, same NamedTuples) and the scalars
    have the same Python types: then their numba types cannot have changed. Any other call types
    its arguments afresh. The kept arguments hold their objects alive, so an ``id`` cannot be
    reused by another object while it is a key.

    ``Dispatcher.compile(signature)`` is public; that it returns the entry point is checked by
    ``tests/kernels/test_jit.py``, which fails if a numba release changes it.
    """

    __slots__ = ("_dispatcher", "_fn", "_objs", "_types", "_get_objs", "_get_scalars", "_n")

    def __init__(self):
        self._dispatcher = None
        self._fn = None

    def _same(self, dispatcher, args) -> bool:
        if dispatcher is not self._dispatcher or len(args) != self._n:
            return False
        if not all(map(operator.is_, self._get_objs(args), self._objs)):
            return False
        return tuple(map(type, self._get_scalars(args))) == self._types

    def __call__(self, dispatcher, args):
        if self._fn is None or not self._same(dispatcher, args):
            fn = compile_for(dispatcher, args)
            if not callable(fn):  # (a numba that no longer returns the entry point: dispatch as usual)
                fn = dispatcher
            objs = [i for i, a in enumerate(args) if isinstance(a, (tuple, np.ndarray))]
            scalars = [i for i in range(len(args)) if i not in objs]
            # itemgetter of one index returns the item, not a 1-tuple: pad with a fixed index
            self._get_objs = operator.itemgetter(*objs, *objs[:1]) if objs else (lambda a: ())
            self._get_scalars = operator.itemgetter(*scalars, *scalars[:1]) if scalars else (lambda a: ())
            self._objs = self._get_objs(args)  # held: their ids cannot be reused while kept
            self._types = tuple(map(type, self._get_scalars(args)))
            self._n = len(args)
            self._dispatcher = dispatcher
            self._fn = fn
        return self._fn(*args)
