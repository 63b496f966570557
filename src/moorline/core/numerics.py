"""Small numerical building blocks shared by the kernels (compiled inline; how every kernel is
compiled, and why without numba's reference counting, is in :mod:`moorline.core.jit`)."""

from __future__ import annotations

import math

from .jit import kernel


@kernel(inline="always")
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


@kernel(inline="always")
def unit3(x, y, z):
    """(x, y, z) / |(x, y, z)| and the norm; the zero vector stays zero."""
    n = math.sqrt(x * x + y * y + z * z)
    if n > 0.0:
        return x / n, y / n, z / n, n
    return 0.0, 0.0, 0.0, 0.0
