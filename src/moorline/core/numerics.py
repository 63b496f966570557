"""Small numerical building blocks shared by the kernels: bisection, 3-vectors, quaternions and
rotation matrices, small dense solves, rigid offsets of 6x6 mass matrices.

(compiled inline where small; how every kernel is compiled, and why without numba's reference
counting, is in :mod:`moorline.core.jit`).
"""

from __future__ import annotations

import math

import numpy as np

from .jit import derivative_kernel, kernel


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


@derivative_kernel
def quat_to_R(y, o, Rm):
    """Rotation matrix of the quaternion ``y[o:o+4]`` (normalised here) into ``Rm`` (3, 3)."""
    w = y[o]
    x = y[o + 1]
    yy = y[o + 2]
    z = y[o + 3]
    n = math.sqrt(w * w + x * x + yy * yy + z * z)
    if n > 0.0:
        w /= n
        x /= n
        yy /= n
        z /= n
    else:
        w = 1.0
    Rm[0, 0] = 1.0 - 2.0 * (yy * yy + z * z)
    Rm[0, 1] = 2.0 * (x * yy - w * z)
    Rm[0, 2] = 2.0 * (x * z + w * yy)
    Rm[1, 0] = 2.0 * (x * yy + w * z)
    Rm[1, 1] = 1.0 - 2.0 * (x * x + z * z)
    Rm[1, 2] = 2.0 * (yy * z - w * x)
    Rm[2, 0] = 2.0 * (x * z - w * yy)
    Rm[2, 1] = 2.0 * (yy * z + w * x)
    Rm[2, 2] = 1.0 - 2.0 * (x * x + yy * yy)


@derivative_kernel
def quat_rate(y, o, wx, wy, wz, dy, od):
    """dQ/dt = 0.5 (0, omega) (x) Q for the quaternion ``y[o:o+4]``, omega in global axes."""
    w = y[o]
    x = y[o + 1]
    yy = y[o + 2]
    z = y[o + 3]
    dy[od] = -0.5 * (wx * x + wy * yy + wz * z)
    dy[od + 1] = 0.5 * (wx * w + wy * z - wz * yy)
    dy[od + 2] = 0.5 * (wy * w + wz * x - wx * z)
    dy[od + 3] = 0.5 * (wz * w + wx * yy - wy * x)


@derivative_kernel
def euler_R(roll, pitch, yaw, Rm):
    """Rm = Rx(roll) Ry(pitch) Rz(yaw) (MoorDyn's coupling and deck convention)."""
    cr = math.cos(roll)
    sr = math.sin(roll)
    cp = math.cos(pitch)
    sp = math.sin(pitch)
    cy = math.cos(yaw)
    sy = math.sin(yaw)
    Rm[0, 0] = cp * cy
    Rm[0, 1] = -cp * sy
    Rm[0, 2] = sp
    Rm[1, 0] = cr * sy + sr * sp * cy
    Rm[1, 1] = cr * cy - sr * sp * sy
    Rm[1, 2] = -sr * cp
    Rm[2, 0] = sr * sy - cr * sp * cy
    Rm[2, 1] = sr * cy + cr * sp * sy
    Rm[2, 2] = cr * cp


@derivative_kernel
def solve_dense(A, b, x, n, a):
    """Solve the n x n system A x = b (Gaussian elimination with partial pivoting) without
    changing A or b, in the scratch ``a`` (at least n x (n + 1)). Returns False (x = NaN) if A is
    singular."""
    for i in range(n):
        for j in range(n):
            a[i, j] = A[i, j]
        a[i, n] = b[i]
    for c in range(n):
        p = c
        big = abs(a[c, c])
        for i in range(c + 1, n):
            if abs(a[i, c]) > big:
                big = abs(a[i, c])
                p = i
        if not big > 0.0:
            for i in range(n):
                x[i] = np.nan
            return False
        if p != c:
            for j in range(c, n + 1):
                tmp = a[c, j]
                a[c, j] = a[p, j]
                a[p, j] = tmp
        for i in range(c + 1, n):
            f = a[i, c] / a[c, c]
            if f != 0.0:
                for j in range(c, n + 1):
                    a[i, j] -= f * a[c, j]
    for i in range(n - 1, -1, -1):
        s = a[i, n]
        for j in range(i + 1, n):
            s -= a[i, j] * x[j]
        x[i] = s / a[i, i]
    return True


@derivative_kernel
def skew3(S, rx, ry, rz):
    """S a = r x a."""
    S[0, 0] = 0.0
    S[0, 1] = -rz
    S[0, 2] = ry
    S[1, 0] = rz
    S[1, 1] = 0.0
    S[1, 2] = -rx
    S[2, 0] = -ry
    S[2, 1] = rx
    S[2, 2] = 0.0


@derivative_kernel
def add_translated3(M6, M3, rx, ry, rz, S):
    """M6 += T^T [[M3, 0], [0, 0]] T for a point mass matrix M3 at offset r: the blocks
    [[M3, -M3 S], [S M3, -S M3 S]], S = S(r). ``S`` is (3, 3) scratch."""
    add_translated6(M6, M3, M3, M3, M3, 1, rx, ry, rz, S)


@derivative_kernel
def add_translated6(Md, A, Bm, C, D, point_only, rx, ry, rz, S):
    """Md += T^T [[A, Bm], [C, D]] T, T = [[I, -S], [0, I]], S = S(r): a mass about a point offset
    by r moved to the parent's point. With ``point_only`` the blocks Bm, C, D are taken as zero
    (a point mass A). ``S`` is (3, 3) scratch."""
    skew3(S, rx, ry, rz)
    for i in range(3):
        for j in range(3):
            AS = 0.0
            SA = 0.0
            for k in range(3):
                AS += A[i, k] * S[k, j]
                SA += S[i, k] * A[k, j]
            Md[i, j] += A[i, j]
            Md[i, 3 + j] -= AS
            Md[3 + i, j] += SA
            if point_only == 0:
                Md[i, 3 + j] += Bm[i, j]
                Md[3 + i, j] += C[i, j]
                Md[3 + i, 3 + j] += D[i, j]
    # rotational block: - S A S (+ S Bm - C S)
    for i in range(3):
        for j in range(3):
            v = 0.0
            for k in range(3):
                ASkj = 0.0
                for m in range(3):
                    ASkj += A[k, m] * S[m, j]
                v -= S[i, k] * ASkj
                if point_only == 0:
                    v += S[i, k] * Bm[k, j] - C[i, k] * S[k, j]
            Md[3 + i, 3 + j] += v


@kernel(inline="always")
def cross3(ax, ay, az, bx, by, bz):
    return ay * bz - az * by, az * bx - ax * bz, ax * by - ay * bx


@kernel(inline="always")
def matvec3(Rm, x, y, z):
    """Rm (x, y, z) for a 3x3 matrix Rm."""
    return (Rm[0, 0] * x + Rm[0, 1] * y + Rm[0, 2] * z, Rm[1, 0] * x + Rm[1, 1] * y + Rm[1, 2] * z,
            Rm[2, 0] * x + Rm[2, 1] * y + Rm[2, 2] * z)


@kernel(inline="always")
def mattvec3(Rm, x, y, z):
    """Rm^T (x, y, z) for a 3x3 matrix Rm (a rotation's global -> body axes)."""
    return (Rm[0, 0] * x + Rm[1, 0] * y + Rm[2, 0] * z, Rm[0, 1] * x + Rm[1, 1] * y + Rm[2, 1] * z,
            Rm[0, 2] * x + Rm[1, 2] * y + Rm[2, 2] * z)


@kernel(inline="always")
def quat_mul(aw, ax, ay, az, b, ob, out, oo):
    """out[oo:oo+4] = (aw, ax, ay, az) (x) b[ob:ob+4], quaternions (w, x, y, z)."""
    bw = b[ob]
    bx = b[ob + 1]
    by = b[ob + 2]
    bz = b[ob + 3]
    out[oo] = aw * bw - ax * bx - ay * by - az * bz
    out[oo + 1] = aw * bx + ax * bw + ay * bz - az * by
    out[oo + 2] = aw * by - ax * bz + ay * bw + az * bx
    out[oo + 3] = aw * bz + ax * by - ay * bx + az * bw


@kernel
def lu_factor(M, o, n, piv):
    """In-place LU factors with partial pivoting of the n x n matrix in rows o..o+n-1, columns
    0..n-1 of M (the row swaps in piv[o:o+n]). Returns False if a pivot is zero."""
    for c in range(n):
        q = c
        big = abs(M[o + c, c])
        for r in range(c + 1, n):
            if abs(M[o + r, c]) > big:
                big = abs(M[o + r, c])
                q = r
        piv[o + c] = q
        if not big > 0.0:
            return False
        if q != c:
            for k in range(n):
                tmp = M[o + c, k]
                M[o + c, k] = M[o + q, k]
                M[o + q, k] = tmp
        for r in range(c + 1, n):
            M[o + r, c] /= M[o + c, c]
            for k in range(c + 1, n):
                M[o + r, k] -= M[o + r, c] * M[o + c, k]
    return True


@kernel
def lu_solve(M, o, n, piv, b):
    """Solve in place (b[0:n]) with the factors of :func:`lu_factor` in rows o..o+n-1 of M."""
    for c in range(n):
        q = piv[o + c]
        if q != c:
            tmp = b[c]
            b[c] = b[q]
            b[q] = tmp
        for r in range(c + 1, n):
            b[r] -= M[o + r, c] * b[c]
    for r in range(n - 1, -1, -1):
        s = b[r]
        for c in range(r + 1, n):
            s -= M[o + r, c] * b[c]
        b[r] = s / M[o + r, r]
