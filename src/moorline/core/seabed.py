"""Seabed kernels: height and normal of a flat or gridded seabed, contact and friction of a node.

Contact (spec 3.8): a node below the local seabed height z_b is pushed out with
``F = (pen kBot - v_n cBot) d lam`` per unit contact area d * lam, where ``pen = (z_b - z) n_z`` is
the penetration measured normal to the seabed and ``v_n = v . n``, along the local unit normal n
(MoorDyn-F; on a flat seabed identical to MoorDyn-C). The ``vertical`` mode applies MoorDyn-C's
vertical force ``((z_b - z) kBot - v_z cBot) d lam`` even on a slope.

Friction (spec 3.9), on the node velocity in the seabed plane, with normal force N:

- isotropic (MoorDyn-C): saturated damping of the whole sliding velocity, mu cv |v| up to
  mc mu N, then mu N;
- directional (MoorDyn-F): the same, separately for the axial part (along the line tangent
  projected on the seabed plane; MoorDyn-F uses the unprojected tangent, which puts part of the
  friction normal to a slope) and the transverse part, with mu_kA and mu_kT;
- stickslip (moorline): every node in contact holds its place with an elastic friction spring
  (stiffness kShear, damping cBot, per unit contact area) to an anchor point, separately in the
  axial and transverse directions. While the spring force stays below the static limit
  mc mu N the node sticks; beyond it the anchor is dragged along so that the spring force is the
  kinetic limit mu N (the node slides), until the spring force drops below the kinetic limit again
  (the node sticks). Anchors are part of the system state; they are updated ("committed") once
  per time step, at its first stage, and reset to the node when it leaves the seabed.
"""

from __future__ import annotations

import math

from .jit import derivative_kernel, kernel
from .numerics import bracket, unit3

# seabed contact modes and friction models (mirrors of model.CONTACT_MODES / FRICTION_MODELS)
CONTACT_NORMAL = 0
CONTACT_VERTICAL = 1
FRIC_ISOTROPIC = 0
FRIC_DIRECTIONAL = 1
FRIC_STICKSLIP = 2


@kernel
def _locate(g, v):
    """Cell index i with g[i] <= v < g[i+1] (clamped) and the fraction within it."""
    n = g.size
    if n == 1 or v <= g[0]:
        return 0, 0.0
    if v >= g[n - 1]:
        return n - 2, 1.0
    lo = bracket(g, 0, n - 1, v)
    return lo, (v - g[lo]) / (g[lo + 1] - g[lo])


@kernel
def seabed_at(gx, gy, gz, depth, x, y):
    """Seabed height and unit normal at (x, y) of the grid (gx, gy, gz) (flat at -depth when
    ``gx`` is empty).

    Returns
    -------
    zb, nx, ny, nz : float
        Height [m] and the unit normal pointing out of the seabed.
    outside : bool
        The point lies outside the grid (the nearest edge value was used).
    """
    if gx.size == 0:
        return -depth, 0.0, 0.0, 1.0, False
    outside = x < gx[0] or x > gx[gx.size - 1] or y < gy[0] or y > gy[gy.size - 1]
    i, tx = _locate(gx, x)
    j, ty = _locate(gy, y)
    i1 = i + 1 if gx.size > 1 else i
    j1 = j + 1 if gy.size > 1 else j
    z00 = gz[j, i]
    z10 = gz[j, i1]
    z01 = gz[j1, i]
    z11 = gz[j1, i1]
    zb = (1.0 - tx) * (1.0 - ty) * z00 + tx * (1.0 - ty) * z10 + (1.0 - tx) * ty * z01 + tx * ty * z11
    # slope of the bilinear surface in the cell (zero along a clamped direction)
    dzdx = 0.0
    dzdy = 0.0
    if gx.size > 1 and gx[0] <= x <= gx[gx.size - 1]:
        dzdx = ((1.0 - ty) * (z10 - z00) + ty * (z11 - z01)) / (gx[i1] - gx[i])
    if gy.size > 1 and gy[0] <= y <= gy[gy.size - 1]:
        dzdy = ((1.0 - tx) * (z01 - z00) + tx * (z11 - z10)) / (gy[j1] - gy[j])
    inv = 1.0 / math.sqrt(1.0 + dzdx * dzdx + dzdy * dzdy)
    return zb, -dzdx * inv, -dzdy * inv, inv, outside


@derivative_kernel
def _saturate(mu, cv, mc, N, vx, vy, vz):
    """MoorDyn's saturated-damping friction on a sliding velocity: mu cv |v| while that is below
    mc mu N, else mu N; opposite to v."""
    vm = math.sqrt(vx * vx + vy * vy + vz * vz)
    if vm == 0.0 or mu == 0.0:
        return 0.0, 0.0, 0.0
    flin = mu * cv * vm
    ff = flin if flin <= mc * mu * N else mu * N
    return -ff * vx / vm, -ff * vy / vm, -ff * vz / vm


@derivative_kernel
def _stick(k, c, mu, mc, N, dd, vv, slipping, commit):
    """One direction of the stick-slip friction: spring extension ``dd`` [m] and velocity ``vv``
    [m/s] along it. Returns (force, new extension, new slip flag)."""
    lim = mu * N if slipping else mc * mu * N
    f = -k * dd - c * vv
    if f > lim:
        f = lim
    elif f < -lim:
        f = -lim
    flag = 1.0 if slipping else 0.0
    if commit:
        fe = k * abs(dd)
        if fe > lim:
            # slide: the anchor is dragged so that the spring carries the kinetic limit
            dd = dd * (mu * N / fe)
            flag = 1.0
        else:
            flag = 0.0
    return f, dd, flag


@kernel(inline="always")
def _ramp(pen, ramp):
    """Factor on the contact damping: 1 (MoorDyn), or the smoothstep u^2 (3 - 2 u), u = pen / ramp,
    while the penetration is below ``ramp`` [m], so the contact force starts from zero with a zero
    slope (continuous and continuously differentiable, as Newton's method needs)."""
    if ramp > 0.0 and pen < ramp:
        u = max(pen, 0.0) / ramp
        return u * u * (3.0 - 2.0 * u)
    return 1.0


@kernel(inline="always")
def _ramp_slope(pen, ramp):
    """d(_ramp)/d(pen) [1/m]."""
    if ramp > 0.0 and 0.0 < pen < ramp:
        u = pen / ramp
        return 6.0 * u * (1.0 - u) / ramp
    return 0.0


@kernel(inline="always")
def _spring(pen, blend):
    """Penetration the contact spring acts on: ``pen`` (MoorDyn), or with a blend width
    ``blend`` [m] > 0 the C1 curve pen^2 / (2 blend) up to ``blend`` and pen - blend / 2 beyond,
    so the spring stiffness grows linearly from zero instead of jumping to kBot at first contact."""
    if blend > 0.0:
        if pen < blend:
            p = max(pen, 0.0)
            return 0.5 * p * p / blend
        return pen - 0.5 * blend
    return pen


@kernel(inline="always")
def _spring_slope(pen, blend):
    """d(_spring)/d(pen) [-]."""
    if blend > 0.0 and pen < blend:
        return max(pen, 0.0) / blend
    return 1.0


def resting_penetration(pen_static: float, blend: float) -> float:
    """Penetration [m] at which the contact spring (with blend width ``blend``, see
    :func:`_spring`) carries what a linear spring carries at ``pen_static``."""
    if blend <= 0.0 or pen_static >= 0.5 * blend:
        return pen_static + 0.5 * max(blend, 0.0)
    return math.sqrt(2.0 * blend * pen_static)


@kernel(inline="always")
def _contact_frame(E, zb, nx, ny, nz, rz, vx, vy, vz):
    """Direction the contact force acts along (the seabed normal n, or z in MoorDyn-C's vertical
    mode), the penetration along it and the velocity along it."""
    if E.contact != CONTACT_NORMAL:
        # MoorDyn-C: vertical contact, friction on the horizontal velocity
        nx = 0.0
        ny = 0.0
        nz = 1.0
    return nx, ny, nz, (zb - rz) * nz, vx * nx + vy * ny + vz * nz


@derivative_kernel
def _contact(E, zb, nx, ny, nz, rz, vx, vy, vz, area):
    """Contact force of a node below the seabed and its normal force, normal and sliding velocity."""
    nx, ny, nz, pen, vn = _contact_frame(E, zb, nx, ny, nz, rz, vx, vy, vz)
    fn = (_spring(pen, E.bed_blend) * E.kBot - vn * E.cBot * _ramp(pen, E.bed_ramp)) * area
    return fn * nx, fn * ny, fn * nz, fn, nx, ny, nz, vx - vn * nx, vy - vn * ny, vz - vn * nz


@kernel
def contact_slope(E, zb, nx, ny, nz, rz, vx, vy, vz, area):
    """Derivatives of the normal contact force fn of :func:`_contact` (friction left out) of a node
    below the seabed: ``(k, c, nx, ny, nz)`` with dF/dr = -k n n^T [N/m] and dF/dv = -c n n^T
    [N s/m] (the seabed taken as locally plane; the ``vertical`` mode acts along z)."""
    nx, ny, nz, pen, vn = _contact_frame(E, zb, nx, ny, nz, rz, vx, vy, vz)
    k = (_spring_slope(pen, E.bed_blend) * E.kBot - vn * E.cBot * _ramp_slope(pen, E.bed_ramp)) * area
    c = E.cBot * _ramp(pen, E.bed_ramp) * area
    return k, c, nx, ny, nz


@derivative_kernel
def _plane_axis(qx, qy, qz, nx, ny, nz):
    """The line tangent projected on the seabed plane, normalised (MoorDyn-F splits along the
    unprojected tangent, which gives the friction a component normal to the seabed wherever the
    line is tilted against it: on a slope that pushes the node off the seabed)."""
    qn = qx * nx + qy * ny + qz * nz
    ux, uy, uz, _ = unit3(qx - qn * nx, qy - qn * ny, qz - qn * nz)
    return ux, uy, uz


@derivative_kernel
def seabed_force(E, zb, nx, ny, nz, rx, ry, rz, vx, vy, vz, qx, qy, qz, d, lam):
    """Contact and saturated-damping friction (isotropic or directional) on a line node at
    (rx, ry, rz), below the local seabed height ``zb`` with unit normal n, moving at (vx, vy, vz)
    with tangent q, diameter ``d`` and unstretched nodal length ``lam``. Scalars only, so that a
    node in contact costs no array reference counting. Returns (fx, fy, fz)."""
    bx, by, bz, fn, nx, ny, nz, sx, sy, sz = _contact(E, zb, nx, ny, nz, rz, vx, vy, vz, d * lam)
    N = abs(fn)
    if E.fric == FRIC_ISOTROPIC:
        fx, fy, fz = _saturate(E.muT, E.cv, E.mc, N, sx, sy, sz)
        return bx + fx, by + fy, bz + fz
    ux, uy, uz = _plane_axis(qx, qy, qz, nx, ny, nz)
    va = sx * ux + sy * uy + sz * uz
    ax, ay, az = _saturate(E.muA, E.cv, E.mc, N, va * ux, va * uy, va * uz)
    tx, ty, tz = _saturate(E.muT, E.cv, E.mc, N, sx - va * ux, sy - va * uy, sz - va * uz)
    return bx + ax + tx, by + ay + ty, bz + az + tz


@derivative_kernel
def seabed_force_stickslip(E, zb, nx, ny, nz, anchor, slip, ctl, n, rx, ry, rz, vx, vy, vz, qx, qy, qz, d, lam):
    """Contact and stick-slip friction on line node ``n`` (arguments as :func:`seabed_force`, plus
    the stick-slip state (anchor, slip, ctl) of :class:`~moorline.core.layout.Seabed`). The
    friction springs act only while ``ctl[0]`` is set (not during the IC solve); the anchors are
    committed when ``ctl[1]`` is set. Returns (fx, fy, fz)."""
    area = d * lam
    bx, by, bz, fn, nx, ny, nz, sx, sy, sz = _contact(E, zb, nx, ny, nz, rz, vx, vy, vz, area)
    if ctl[0] == 0:
        return bx, by, bz
    commit = ctl[1] != 0
    ux, uy, uz = _plane_axis(qx, qy, qz, nx, ny, nz)
    N = max(fn, 0.0)
    dx = rx - anchor[n, 0]
    dy = ry - anchor[n, 1]
    dz = rz - anchor[n, 2]
    dn = dx * nx + dy * ny + dz * nz
    dx -= dn * nx
    dy -= dn * ny
    dz -= dn * nz
    k = E.kshear * area
    c = E.cshear * area
    da = dx * ux + dy * uy + dz * uz
    va = sx * ux + sy * uy + sz * uz
    fa, da2, sa = _stick(k, c, E.muA, E.mc, N, da, va, slip[n, 0] != 0.0, commit)
    # transverse: the in-plane remainder, as a vector along its own direction
    tx = dx - da * ux
    ty = dy - da * uy
    tz = dz - da * uz
    wx = sx - va * ux
    wy = sy - va * uy
    wz = sz - va * uz
    ex, ey, ez, tm = unit3(tx, ty, tz)
    if tm == 0.0:
        ex, ey, ez, _ = unit3(wx, wy, wz)
    vt = wx * ex + wy * ey + wz * ez
    ft, tm2, st = _stick(k, c, E.muT, E.mc, N, tm, vt, slip[n, 1] != 0.0, commit)
    if commit:
        # new anchor: the node minus the committed in-plane extensions (normal offset dropped)
        anchor[n, 0] = rx - da2 * ux - tm2 * ex
        anchor[n, 1] = ry - da2 * uy - tm2 * ey
        anchor[n, 2] = rz - da2 * uz - tm2 * ez
        slip[n, 0] = sa
        slip[n, 1] = st
    return bx + fa * ux + ft * ex, by + fa * uy + ft * ey, bz + fa * uz + ft * ez


# ------------------------------------------------------------------ contact law of the implicit scheme
#: the implicit scheme ramps the seabed damping in over this many static penetrations
BED_RAMP_FACTOR = 10.0


#: and the seabed spring stiffness over this many
BED_BLEND_FACTOR = 1.0


def static_penetration(layout) -> float:
    """Static seabed penetration [m] of the heaviest line under its own submerged weight,
    (w - rho A) g / (kBot d) (0 without seabed stiffness or sinking lines)."""
    L, E = layout.lines, layout.env
    if E.kBot <= 0.0:
        return 0.0
    pen = 0.0
    for li in range(len(layout.line_N)):
        wsub = L.w[li] - E.rho * L.A[li]
        if wsub > 0.0 and L.d[li] > 0.0:
            pen = max(pen, wsub * E.g / (E.kBot * L.d[li]))
    return float(pen)


def bed_damping_ramp(layout) -> float:
    """Penetration [m] over which the implicit scheme ramps the seabed contact damping in (a
    smoothstep): BED_RAMP_FACTOR times the static penetration, at least 1 mm. MoorDyn's contact
    force jumps by cBot v_n d l when a node lands: the residual then has no root for Newton's
    method (it cycles between contact and no contact). With the ramp the force is continuous."""
    if layout.env.kBot <= 0.0 or layout.env.cBot <= 0.0:
        return 0.0
    return float(max(BED_RAMP_FACTOR * static_penetration(layout), 1e-3))


def bed_spring_blend(layout) -> float:
    """Penetration [m] over which the implicit scheme blends the seabed spring in (stiffness
    growing linearly from zero to kBot, a C1 force): BED_BLEND_FACTOR times the static
    penetration. The line then rests deeper by about half of it (a few mm for chain)."""
    return float(BED_BLEND_FACTOR * static_penetration(layout))
