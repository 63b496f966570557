"""Small numerical building blocks shared by the kernels (compiled inline).

Reference counting: the kernels of the time loop (``rhs`` and everything it calls, the explicit
schemes and their loop) are compiled with ``_nrt=False``, i.e. without numba's runtime for
reference-counted memory. With it, every NamedTuple of arrays (``Work`` has 60) that reaches a
function which calls another non-inlined function is reference counted array by array, two
atomic updates per array and per call: measured on the OC3 chain (63 nodes), 10 us of a 13 us
derivative evaluation. Without it the evaluation takes 2.9 us. The price: those kernels
allocate nothing (scratch arrays live in ``Work`` and ``WaterKin``), and a kernel compiled
without the runtime cannot call one that allocates.
"""

from __future__ import annotations

import math

from numba import njit


@njit(cache=True, error_model="numpy", inline="always", _nrt=False)
def bracket(a, lo, hi, v):
    """Index i in [lo, hi) with a[i] <= v < a[i+1], by bisection; ``a[lo] <= v < a[hi]`` is assumed
    (callers clamp first)."""
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if a[mid] <= v:
            lo = mid
        else:
            hi = mid
    return lo


@njit(cache=True, error_model="numpy", inline="always", _nrt=False)
def unit3(x, y, z):
    """(x, y, z) / |(x, y, z)| and the norm; the zero vector stays zero."""
    n = math.sqrt(x * x + y * y + z * z)
    if n > 0.0:
        return x / n, y / n, z / n, n
    return 0.0, 0.0, 0.0, 0.0
