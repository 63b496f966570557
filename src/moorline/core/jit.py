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

from numba import njit, typeof

#: options of every kernel (see the module docstring)
KERNEL_OPTIONS = {"cache": True, "error_model": "numpy", "_nrt": False}


def kernel(fn=None, *, inline: str = "never"):
    """Compile ``fn`` as a moorline kernel (``@kernel`` or ``@kernel(inline="always")``).

    Parameters
    ----------
    fn : function, optional
        The Python function (when used as ``@kernel`` without arguments).
    inline : {'never', 'always'}
        numba's IR-level inlining: ``'always'`` copies the function into each caller (no call,
        no dispatcher of its own; use it for small functions only: numba's inliner copies the
        callee's IR once per call site, at a cost that grows with its size).

    Returns
    -------
    numba dispatcher, or a decorator when ``fn`` is None.
    """
    opts = dict(KERNEL_OPTIONS)
    if inline != "never":
        opts["inline"] = inline
    if fn is None:
        return njit(**opts)
    return njit(**opts)(fn)


def compile_for(dispatcher, args) -> None:
    """Compile ``dispatcher`` (or load it from numba's cache) for the types of ``args``, without
    running it: the specialisation a later ``dispatcher(*args)`` call uses."""
    dispatcher.compile(tuple(typeof(a) for a in args))
