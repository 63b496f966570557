"""Line states besides node positions and velocities: the stretch of the static branch of
viscoelastic and Syrope rope segments, and the lift phase of MoorDyn's VIV model (spec 3.4, 3.11).

They are first-order states in one block at the end of the state vector, after the radiation
states of floating bodies: ``y = [Q | U | Z | X]``, ``X`` at ``xs_offset(R) = 6 n3 + 13 n6 + nz``
(``R.dims[3]`` of them). ``LineArrays.seg_xs`` gives the index in ``X`` of each segment's stretch
(-1 for elastic lines), ``LineArrays.node_xs`` that of each internal node's VIV phase.

How a stretch state is used depends on ``LineArrays.xs_ctl[XC_MODE]``:

- ``MODE_RATE`` (explicit schemes, dynamic relaxation): the state from ``y`` sets the tension and
  the kernels return its rate, which the scheme integrates like any other state;
- ``MODE_TRAPEZOID`` (the implicit scheme's step map): the state at the end of a step of length
  ``h = xs_ctl[XC_H]`` is condensed by the trapezoidal rule, s1 = s0 + h/2 (f(s0) + f(s1)), from
  ``xs_s0``/``xs_f0`` (state and rate at the start of the step) and the segment's stretch and
  stretch rate at the iterate, so the Newton iterations (and their finite-difference Jacobian)
  see the rope's tension as a function of the node positions alone. Like the radiation states
  (:func:`moorline.core.floating.radiation_trapezoid`) it is second order and A-stable, matching
  the generalized-alpha scheme; unlike them it is nonlinear (models 3 and 4), so it is a scalar
  Newton solve per segment;
- ``MODE_STATIC`` (static solves): the state at rest, ds/dt = 0 with no stretch rate, and no
  damping force (a Syrope segment keeps its state: its slow strain is history, given by Tmean0).

Syrope segments also carry a history (``sy_T``: the largest mean tension seen, Tmax, and the mean
tension, Tmean; ``sy_wc``: the working curve of that Tmax), updated at every evaluation when
``xs_ctl[XC_HIST]`` is 1 (as MoorDyn does, stages included) and only once per accepted step by the
implicit scheme (:func:`commit_states`).
"""

from __future__ import annotations

import math

from .jit import derivative_kernel, kernel

# LineArrays.vis: axial model of each line (mirrors moorline.model ELASTIC ... SYROPE)
VIS_ELASTIC = 1
VIS_CONSTANT = 2
VIS_MEAN = 3
VIS_SYROPE = 4

# LineArrays.xs_ctl
XC_MODE = 0  # MODE_*
XC_H = 1  # step of the trapezoidal condensation [s]
XC_HIST = 2  # 1: update the Syrope history at every evaluation
XC_TOLD = 3  # VIV: time of the last update of the RMS histories [s]
XC_DTM = 4  # VIV: the time step those updates are spaced by [s]
XC_VIV = 5  # 1: VIV lift on (off while the initial conditions are found, as in MoorDyn)
XC_TIME = 6  # time of the current evaluation [s] (set by rhs)
XC_WCLINE = 7  # 1: one Syrope working curve per line, rebuilt by any of its segments (MoorDyn-C)
N_XC = 8

MODE_RATE = 0
MODE_TRAPEZOID = 1
MODE_STATIC = 2

# LineArrays.sy_par[:, 0]: working-curve shapes
WC_LINEAR = 0
WC_QUADRATIC = 1
WC_EXP = 2
#: points of a Syrope working curve (MoorDyn's nEApointsWC)
NWC = 30
#: VIV running-RMS window (MoorDyn's n_m)
VIV_NM = 500.0


@kernel(inline="always")
def xs_offset(R):
    """Index in the state where the line states start (after the radiation states)."""
    return xs_start(R.dims)


@derivative_kernel
def xs_start(dims):
    """:func:`xs_offset` from ``RigidArrays.dims`` alone (for kernels that take arrays)."""
    return 6 * dims[0] + 13 * dims[1] + dims[2]


@derivative_kernel
def _col_interp(A, r0, n, cx, cy, v):
    """Linear interpolation of column ``cy`` against column ``cx`` (increasing) of rows
    ``r0:r0+n`` of the table ``A``, clamped at both ends (MoorDyn's ``interp``)."""
    if v <= A[r0, cx]:
        return A[r0, cy]
    last = r0 + n - 1
    if v >= A[last, cx]:
        return A[last, cy]
    lo = r0
    hi = last
    while hi - lo > 1:
        mid = (lo + hi) // 2
        if A[mid, cx] <= v:
            lo = mid
        else:
            hi = mid
    f = (v - A[lo, cx]) / (A[lo + 1, cx] - A[lo, cx])
    return A[lo, cy] + f * (A[lo + 1, cy] - A[lo, cy])


@derivative_kernel
def _equal(a, b):
    """MoorDyn's EqualRealNos: equal within 50 machine epsilons of max(|a + b|, 1)."""
    return abs(a - b) <= max(abs(a + b), 1.0) * 50.0 * 2.220446049250313e-16


@derivative_kernel
def build_working_curve(L, li, w, tmax):
    """Working curve of line ``li`` for the largest mean tension ``tmax`` into ``L.sy_wc[w]``
    (columns: total strain, tension, slow strain; spec 3.4.3)."""
    r0 = L.sy_tab[li, 0]
    n = L.sy_tab[li, 1]
    owc = L.sy_owc
    alpha = L.vis_par[li, 0]
    beta = L.vis_par[li, 1]
    kind = int(L.sy_par[li, 0])
    k1 = L.sy_par[li, 1]
    k2 = L.sy_par[li, 2]
    eps_max = _col_interp(owc, r0, n, 1, 0, tmax)
    eps_min = owc[r0, 0] + k1 * (eps_max - owc[r0, 0])
    if kind == WC_LINEAR and k1 >= 1.0:
        eps_min = eps_max - tmax / k1
    wc = L.sy_wc[w]
    for i in range(NWC):
        x = eps_min + (eps_max - eps_min) * i / (NWC - 1)
        xi = (x - eps_min) / (eps_max - eps_min) if eps_max != eps_min else 0.0
        if kind == WC_LINEAR:
            t = tmax * xi
        elif kind == WC_QUADRATIC:
            t = tmax * xi * (k2 * xi + 1.0 - k2)
        else:
            t = tmax * (1.0 - math.exp(k2 * xi)) / (1.0 - math.exp(k2))
        wc[i, 0] = x
        wc[i, 1] = t
        wc[i, 2] = x - math.log(1.0 + beta / alpha * t) / beta


@derivative_kernel
def _wc_index(L, li, s):
    """Row of ``sy_wc`` that segment ``s`` of line ``li`` uses: its own, or its line's first
    segment's when one working curve is shared per line (MoorDyn-C)."""
    if L.xs_ctl[XC_WCLINE] != 0.0:
        return L.seg_ptr[li]
    return s


@derivative_kernel
def _rate(L, li, s, st, dl, ldot, l0, EA):
    """(tension magnitude, ds/dt, Tmean) of the static branch of segment ``s`` with stretch state
    ``st`` [m], total stretch ``dl`` [m] and stretch rate ``ldot`` [m/s] (spec 3.4)."""
    model = L.vis[li]
    BA = L.seg_BA[s]
    BAd = L.vis_par[li, 2]
    if model == VIS_SYROPE:
        alpha = L.vis_par[li, 0]
        beta = L.vis_par[li, 1]
        if _equal(L.sy_T[s, 1], L.sy_T[s, 0]):
            # still on the original working curve
            A = L.sy_owc
            r0 = L.sy_tab[li, 0]
            n = L.sy_tab[li, 1]
        else:
            A = L.sy_wc[_wc_index(L, li, s)]
            r0 = 0
            n = NWC
        tmean = _col_interp(A, r0, n, 2, 1, st / l0)
        eps_t = _col_interp(A, r0, n, 1, 0, tmean)
        sdot = ((dl - eps_t * l0) * (alpha + beta * tmean) + BAd * ldot) / (BA + BAd)
        return tmean, sdot, tmean
    if model == VIS_CONSTANT:
        ea2 = L.vis_par[li, 0]
        ea1 = ea2 * EA / (ea2 - EA)
    else:
        ea2, ea1 = _mean_stiffness(L, li, st, l0, EA)
    sdot = (ea2 * dl - (ea2 + ea1) * st + BAd * ldot) / (BAd + BA)
    return ea1 * st / l0, sdot, 0.0


@derivative_kernel
def _static_state(L, li, s, dl, l0, EA, guess):
    """Stretch state at rest (ds/dt = 0, no stretch rate) for a total stretch ``dl``. A Syrope
    segment keeps its state ``guess``: its slow strain is history (the mean tension Tmean0 the
    deck gives), which creeps towards the working curve over hours, not a static unknown."""
    if L.vis[li] == VIS_SYROPE:
        return guess
    if L.vis[li] == VIS_CONSTANT:
        return dl * (1.0 - EA / L.vis_par[li, 0])
    # mean-load dependent: s = dl (1 - EA_s / EA_d(s)), a fixed point (EA_d varies slowly with s)
    st = guess
    for _ in range(100):
        # ea2 dl - (ea2 + ea1) st = 0 for st, with ea2 and ea1 at the current st
        ea2, ea1 = _mean_stiffness(L, li, st, l0, EA)
        nxt = ea2 * dl / (ea2 + ea1)
        if abs(nxt - st) <= 1e-13 * (abs(nxt) + 1e-12 * l0) + 1e-300:
            return nxt
        st = nxt
    return st


@derivative_kernel
def _mean_stiffness(L, li, st, l0, EA):
    """(EA_d, EA_1) of the mean-load dependent model at stretch state ``st``."""
    alpha = L.vis_par[li, 0]
    if st >= 0.0:
        beta = L.vis_par[li, 1]
        k = EA / l0
        ea2 = 0.5 * (alpha + beta * st * k + EA + math.sqrt(alpha * alpha + 2.0 * alpha * k * (beta * st - l0)
                                                            + k * k * (beta * st + l0) * (beta * st + l0)))
    else:
        ea2 = alpha
    return ea2, ea2 * EA / (ea2 - EA)


@derivative_kernel
def _trapezoid_state(L, li, s, x, dl, ldot, l0, EA, h):
    """Stretch state at the end of an implicit step: s1 = s0 + h/2 (f0 + f(s1)), with s0, f0 the
    state and rate at the start (``xs_s0``, ``xs_f0``). Linear in s1 for the constant model, a
    scalar Newton solve (secant derivative) otherwise."""
    s0 = L.xs_s0[x]
    f0 = L.xs_f0[x]
    c = 0.5 * h
    if L.vis[li] == VIS_CONSTANT:
        ea2 = L.vis_par[li, 0]
        ea1 = ea2 * EA / (ea2 - EA)
        den = L.vis_par[li, 2] + L.seg_BA[s]
        a = (ea2 * dl + L.vis_par[li, 2] * ldot) / den
        k = (ea2 + ea1) / den
        return (s0 + c * (f0 + a)) / (1.0 + c * k)
    st = s0 + h * f0
    scale = abs(s0) + abs(dl) + 1e-9 * l0
    for _ in range(50):
        T, f, _t = _rate(L, li, s, st, dl, ldot, l0, EA)
        g = st - s0 - c * (f0 + f)
        ds = 1e-7 * scale
        T2, f2, _t2 = _rate(L, li, s, st + ds, dl, ldot, l0, EA)
        dg = 1.0 - c * (f2 - f) / ds
        if dg == 0.0 or not math.isfinite(dg):
            dg = 1.0
        step = g / dg
        st -= step
        if abs(step) <= 1e-13 * scale:
            break
    return st


@derivative_kernel
def segment_axial(L, W, li, s, ls, ldot, l0):
    """Tension and internal damping magnitudes [N] of segment ``s`` of a viscoelastic or Syrope
    line ``li`` with stretched length ``ls`` and stretch rate ``ldot``; the stretch state used (and
    its rate) go to ``W.seg_s`` / ``W.seg_sdot``."""
    x = L.seg_xs[s]
    EA = L.seg_EA[s]
    dl = ls - l0
    mode = L.xs_ctl[XC_MODE]
    if mode == MODE_TRAPEZOID:
        st = _trapezoid_state(L, li, s, x, dl, ldot, l0, EA, L.xs_ctl[XC_H])
    elif mode == MODE_STATIC:
        st = _static_state(L, li, s, dl, l0, EA, W.seg_s[s])
        ldot = 0.0
    else:
        st = W.seg_s[s]
    T, sdot, tmean = _rate(L, li, s, st, dl, ldot, l0, EA)
    W.seg_s[s] = st
    W.seg_sdot[s] = sdot
    if L.vis[li] == VIS_SYROPE and L.xs_ctl[XC_HIST] != 0.0:
        update_history(L, li, s, tmean)
    if dl < 0.0:
        T = 0.0
    elif mode == MODE_TRAPEZOID and T != 0.0:
        # The static branch can carry a tension while the whole segment goes slack (its stretch s
        # relaxes slowly), so MoorDyn's cut-off makes the tension jump to zero at dl = 0: a force
        # discontinuity at which Newton has no root (the node chatters there in explicit schemes).
        # The implicit scheme blends the cut-off in (C1) over the stretch the static stiffness
        # would need to carry that tension, delta = |T| l / EA_s, so the blended tension is no
        # stiffer than 1.5 EA_s / l; explicit schemes keep MoorDyn's switch.
        delta = abs(T) * l0 / EA
        if dl < delta:
            xi = dl / delta
            T *= xi * xi * (3.0 - 2.0 * xi)
    if mode == MODE_STATIC:
        return T, 0.0  # at rest: no damping (a Syrope segment's creep rate does not load it statically)
    return T, L.seg_BA[s] * sdot / l0


@derivative_kernel
def update_history(L, li, s, tmean):
    """Syrope history of segment ``s``: the mean tension, and the largest one with its working curve."""
    L.sy_T[s, 1] = tmean
    if tmean > L.sy_T[s, 0]:
        L.sy_T[s, 0] = tmean
        build_working_curve(L, li, _wc_index(L, li, s), tmean)


# ------------------------------------------------------------------------------------------ VIV
@derivative_kernel
def viv_before(L, W):
    """Keep the node accelerations of the previous evaluation (MoorDyn's rdd_old) for the VIV
    nodes, before the line kernels overwrite them."""
    if L.xs_ctl[XC_HIST] == 0.0:
        return  # an evaluation that is not a step's (views, Jacobian columns) keeps the history
    for n in range(L.node_xs.size):
        if L.node_xs[n] >= 0:
            for c in range(3):
                W.acc_old[n, c] = W.acc[n, c]


@derivative_kernel
def viv_after(L, E, W):
    """Cross-flow lift of the synchronisation model at every internal node of the VIV lines (spec
    3.11), added to the node forces and accelerations; the phase rates go to ``W.dphi``. The
    running RMS values of the cross-flow velocity and acceleration are refreshed once per time step
    ``xs_ctl[XC_DTM]``, as in MoorDyn."""
    t = L.xs_ctl[XC_TIME]
    on = L.xs_ctl[XC_VIV] != 0.0
    refresh = (t >= L.xs_ctl[XC_TOLD] + L.xs_ctl[XC_DTM] or t == 0.0) and L.xs_ctl[XC_HIST] != 0.0
    node_ptr = L.node_ptr
    seg_ptr = L.seg_ptr
    for li in range(node_ptr.size - 1):
        Cl = L.viv[li, 0]
        if Cl <= 0.0 or L.calc[li] == 0:
            continue
        dF = L.viv[li, 1]
        cF = L.viv[li, 2]
        d = L.d[li]
        n0 = node_ptr[li]
        N = node_ptr[li + 1] - n0 - 1
        s0 = seg_ptr[li]
        for i in range(1, N):
            n = n0 + i
            W.Flift[n, 0] = 0.0
            W.Flift[n, 1] = 0.0
            W.Flift[n, 2] = 0.0
            W.dphi[n] = 0.0
            if not on:
                continue
            qx = W.q[n, 0]
            qy = W.q[n, 1]
            qz = W.q[n, 2]
            ux = W.U[n, 0] - W.v[n, 0]
            uy = W.U[n, 1] - W.v[n, 1]
            uz = W.U[n, 2] - W.v[n, 2]
            uq = ux * qx + uy * qy + uz * qz
            px = ux - uq * qx
            py = uy - uq * qy
            pz = uz - uq * qz
            pm = math.sqrt(px * px + py * py + pz * pz)
            # cross-flow direction q x unit(vp)
            if pm > 0.0:
                cx = (qy * pz - qz * py) / pm
                cy = (qz * px - qx * pz) / pm
                cz = (qx * py - qy * px) / pm
            else:
                cx = 0.0
                cy = 0.0
                cz = 0.0
            yd = W.v[n, 0] * cx + W.v[n, 1] * cy + W.v[n, 2] * cz
            ydd = W.acc_old[n, 0] * cx + W.acc_old[n, 1] * cy + W.acc_old[n, 2] * cz
            yd_rms = math.sqrt(((VIV_NM - 1.0) * L.viv_h[n, 0] ** 2 + yd * yd) / VIV_NM)
            ydd_rms = math.sqrt(((VIV_NM - 1.0) * L.viv_h[n, 1] ** 2 + ydd * ydd) / VIV_NM)
            if refresh:
                L.viv_h[n, 0] = yd_rms
                L.viv_h[n, 1] = ydd_rms
            if yd_rms == 0.0 or ydd_rms == 0.0:
                phi_y = math.atan2(-ydd, yd)
            else:
                phi_y = math.atan2(-ydd / ydd_rms, yd / yd_rms)
            if phi_y < 0.0:
                phi_y += 2.0 * math.pi
            phi = W.phi[n] - 2.0 * math.pi * math.floor(W.phi[n] / (2.0 * math.pi))
            fhat = cF + dF * math.sin(phi_y - phi)
            W.dphi[n] = 2.0 * math.pi * fhat * pm / d
            lamw = 0.5 * (L.seg_l0[s0 + i - 1] * W.seg_F[s0 + i - 1] + L.seg_l0[s0 + i] * W.seg_F[s0 + i])
            f = 0.5 * E.rho * d * pm * Cl * math.cos(phi) * lamw
            lx = f * (qy * pz - qz * py)
            ly = f * (qz * px - qx * pz)
            lz = f * (qx * py - qy * px)
            W.Flift[n, 0] = lx
            W.Flift[n, 1] = ly
            W.Flift[n, 2] = lz
            W.F[n, 0] += lx
            W.F[n, 1] += ly
            W.F[n, 2] += lz
            # the node's acceleration with the lift: closed-form inverse of its mass matrix
            fq = lx * qx + ly * qy + lz * qz
            ip = 1.0 / (W.mass[n, 0] + W.mass[n, 1])
            iq = 1.0 / (W.mass[n, 0] + W.mass[n, 2])
            W.acc[n, 0] += (lx - fq * qx) * ip + fq * qx * iq
            W.acc[n, 1] += (ly - fq * qy) * ip + fq * qy * iq
            W.acc[n, 2] += (lz - fq * qz) * ip + fq * qz * iq
    if refresh:
        L.xs_ctl[XC_TOLD] = t


@derivative_kernel
def line_state_rates(L, R, W, dy):
    """Write the rates of the line states (stretch of viscoelastic segments, VIV phases) into the
    derivative ``dy``. In the implicit scheme's trapezoidal mode and in static solves the states
    are condensed, so their rate in ``dy`` is the one at the condensed value (unused there)."""
    xo = xs_offset(R)
    calc = L.calc
    for li in range(calc.size):
        if calc[li] == 0:
            continue  # local Euler: a line not evaluated now keeps its rows of dy
        for s in range(L.seg_ptr[li], L.seg_ptr[li + 1]):
            x = L.seg_xs[s]
            if x >= 0:
                dy[xo + x] = W.seg_sdot[s]
        for n in range(L.node_ptr[li], L.node_ptr[li + 1]):
            x = L.node_xs[n]
            if x >= 0:
                dy[xo + x] = W.dphi[n]


@derivative_kernel
def load_line_states(y, L, R, W):
    """Copy the line states from the state ``y`` into ``W.seg_s`` and ``W.phi``."""
    xo = xs_offset(R)
    for s in range(L.seg_xs.size):
        x = L.seg_xs[s]
        if x >= 0:
            W.seg_s[s] = y[xo + x]
    for n in range(L.node_xs.size):
        x = L.node_xs[n]
        if x >= 0:
            W.phi[n] = y[xo + x]


@kernel
def store_line_states(y, L, R, W, h, history):
    """Write the stretch states of the last evaluation (``W.seg_s``: condensed in the trapezoidal
    or static modes) into the state ``y``, and their rates into ``xs_f0``. With ``h > 0`` (the end
    of an implicit step of length ``h``) the VIV phases advance by the trapezoidal rule on their
    rates at both ends of the step, phi1 = phi0 + h/2 (dphi0 + dphi1) (they are not Newton
    unknowns: the lift acts through the explicit phase, as a lagged load). With ``history``, update
    the Syrope history with that evaluation's mean tensions."""
    xo = xs_offset(R)
    for s in range(L.seg_xs.size):
        x = L.seg_xs[s]
        if x < 0:
            continue
        y[xo + x] = W.seg_s[s]
        L.xs_f0[x] = W.seg_sdot[s]
    if h > 0.0:
        for n in range(L.node_xs.size):
            x = L.node_xs[n]
            if x < 0:
                continue
            y[xo + x] = L.xs_s0[x] + 0.5 * h * (L.xs_f0[x] + W.dphi[n])
            L.xs_f0[x] = W.dphi[n]
    if history:
        for li in range(L.vis.size):
            if L.vis[li] != VIS_SYROPE:
                continue
            for s in range(L.seg_ptr[li], L.seg_ptr[li + 1]):
                st = W.seg_s[s]
                l0 = L.seg_l0[s]
                # the mean tension of the committed state (on the curve the history points to)
                if _equal(L.sy_T[s, 1], L.sy_T[s, 0]):
                    tmean = _col_interp(L.sy_owc, L.sy_tab[li, 0], L.sy_tab[li, 1], 2, 1, st / l0)
                else:
                    tmean = _col_interp(L.sy_wc[_wc_index(L, li, s)], 0, NWC, 2, 1, st / l0)
                update_history(L, li, s, tmean)


@kernel
def start_line_states(y, L, R, h):
    """Remember the line states at the start of an implicit step of length ``h`` (``xs_s0``) and
    switch the stretch states to the trapezoidal condensation."""
    xo = xs_offset(R)
    for x in range(L.xs_s0.size):
        L.xs_s0[x] = y[xo + x]
    L.xs_ctl[XC_MODE] = MODE_TRAPEZOID
    L.xs_ctl[XC_H] = h
    L.xs_ctl[XC_HIST] = 0.0


@kernel
def end_line_states(L):
    """Back to plain rate evaluations (after an implicit step or a static solve)."""
    L.xs_ctl[XC_MODE] = MODE_RATE
    L.xs_ctl[XC_HIST] = 1.0


@kernel
def keep_rates(dy, L, R):
    """Keep the line-state rates of the derivative ``dy`` (evaluated in the rate mode) in ``xs_f0``."""
    xo = xs_offset(R)
    for x in range(L.xs_f0.size):
        L.xs_f0[x] = dy[xo + x]

#: the arrays of the lines that are history, not model: line states at the step start, VIV
#: running means, Syrope peak/mean tensions and working curves, the local-Euler evaluation flags
LINE_HISTORY = ("viv_h", "xs_ctl", "xs_s0", "xs_f0", "sy_T", "sy_wc", "calc")
