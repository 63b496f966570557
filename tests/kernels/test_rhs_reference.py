"""The compiled state derivative (``moorline.core.rhs.rhs``) against a slow reference.

The reference below is written plainly from the spec (shared/spec, sections 3.1-3.9, 3.12, 3.13):
one line, one segment, one node at a time, with numpy 3-vectors, ``np.interp`` for the (clamped)
curves and ``np.linalg.solve`` for every mass matrix. It shares no code with the package: it does
not read the kernel's Work arrays as inputs (only the water kinematics the caller supplies), it
builds the state-row order itself from the brief (internal nodes of each line in line order, then
free points) and it converts ``-zeta`` to BA itself.

The system (3 lines, 4 points) is built so that every branch of the physics is exercised, and the
test asserts that each branch was actually hit:

* line 1, chain (constant EA and BA): anchor on the seabed -> free clump weight; nodes near the
  anchor lie on the seabed, some just below it (contact), some just above; their horizontal
  speeds are chosen so that both friction branches (linear creep and saturated kinetic) occur;
* line 2, polyester (tabulated EA, BA = -zeta): clump -> coupled fairlead above the water, so one
  segment pierces the free surface (partial-submergence fraction); one segment is stretched
  beyond the last table point (clamped tension);
* line 3, wire (constant EA, tabulated BA, mirrored or covering compression): second anchor ->
  clump;
* the free clump point has mass, volume, CdA, Ca and a constant external force and joins all
  three lines; the coupled fairlead moves with a velocity (and an acceleration);
* segments are randomly slack (no tension, damping only) or taut; water velocity, acceleration,
  surface elevation and drag scaling vary between cases.

Every case runs twice: with the layout's own choice (these lines are short, so the line kernel's
one scalar pass), and with every line that can take them (the chain: constant EA and BA) on the
kernel's vectorised loops for long lines (``core.layout.VECTOR_MIN_NODES`` lowered to 2).
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from moorline.core import layout as core_layout
from moorline.core.features import BENDING
from moorline.core.layout import Motion, build_layout
from moorline.core.lines import segment_wet_fraction
from moorline.core.rhs import rhs
from moorline.model import Curve, Environment, Model

#: agreement demanded of the kernel (brief): relative to the magnitude of the terms summed, so
#: that a component that is small because large terms cancel is judged on the terms' scale
RTOL = 1e-10

DEPTH = 50.0
ENV = dict(g=9.80665, rho=1025.0, depth=DEPTH, kBot=3.0e6, cBot=3.0e5, mu=0.6, fric_damp=200.0, stat_dyn=1.4)

# polyester working curve (strain -> tension [N]), starting at (0, 0)
EA_CURVE = Curve([0.0, 0.005, 0.01, 0.02, 0.04], [0.0, 2.0e5, 6.0e5, 1.6e6, 4.0e6])
# damping curves (strain rate [1/s] -> force [N]): mirrored (x >= 0) or covering compression (x < 0)
BA_MIRRORED = Curve([0.0, 0.01, 0.05, 0.2], [0.0, 3.0e3, 1.0e4, 2.5e4])
BA_SIGNED = Curve([-0.2, -0.01, 0.0, 0.03, 0.2], [-4.0e4, -2.0e3, 0.0, 8.0e3, 3.0e4])

ANCHOR1 = np.array([-80.0, 0.0, -DEPTH])
ANCHOR2 = np.array([10.0, -70.0, -DEPTH])
CLUMP0 = np.array([0.0, 0.0, -25.0])
FAIRLEAD0 = np.array([35.0, 5.0, 1.5])
N_SEGS = (8, 6, 5)


# ---------------------------------------------------------------------------------- the system
def make_model(ba_curve: Curve, lengths) -> Model:
    m = Model(env=Environment(**ENV))
    m.add_line_type("chain", d=0.12, w=120.0, EA=6.0e8, BA=2.0e7, Cd=2.4, Ca=1.0, CdAx=0.4, CaAx=0.5)
    m.add_line_type("poly", d=0.16, w=25.0, EA=EA_CURVE, BA=-0.7, Cd=1.2, Ca=0.9, CdAx=0.008, CaAx=0.1)
    m.add_line_type("wire", d=0.09, w=40.0, EA=7.0e8, BA=ba_curve, Cd=1.1, Ca=1.0, CdAx=0.05, CaAx=0.2)
    a1 = m.add_point("fixed", ANCHOR1)
    clump = m.add_point("free", CLUMP0, m=800.0, V=0.3, CdA=0.6, Ca=0.8, F_ext=(50.0, -20.0, 10.0))
    fl = m.add_point("coupled", FAIRLEAD0)
    a2 = m.add_point("fixed", ANCHOR2)
    m.add_line("chain", a1, clump, L=lengths[0], N=N_SEGS[0])
    m.add_line("poly", clump, fl, L=lengths[1], N=N_SEGS[1])
    m.add_line("wire", a2, clump, L=lengths[2], N=N_SEGS[2])
    return m


def path_nodes(ra, rb, N, sag, rng, noise):
    """N+1 nodes from ra to rb on a sagging path (internal nodes perturbed by ``noise`` [m])."""
    s = np.linspace(0.0, 1.0, N + 1)
    r = ra[None, :] + s[:, None] * (rb - ra)[None, :]
    r[:, 2] -= sag * 4.0 * s * (1.0 - s)
    r[1:-1] += rng.normal(scale=noise, size=(N - 1, 3))
    return r


def make_case(seed: int, *, ba_curve: Curve, cd_scale: float, waves: bool):
    """A random-but-physical state. Returns (model, y, t, motion, water kinematics, cd_scale)."""
    rng = np.random.default_rng(seed)
    t = 3.0 + rng.uniform(0.0, 1.0)
    # coupled fairlead: x(t) = c0 + c1 s + c2 s^2 on [2, 6]
    t0 = 2.0
    c1 = np.array([0.8, -0.3, 0.2]) + rng.normal(scale=0.1, size=3)
    c2 = rng.normal(scale=0.05, size=3)
    s = t - t0
    c0 = FAIRLEAD0 - c1 * s - c2 * s * s  # so that the fairlead is at FAIRLEAD0 at time t
    coef = np.zeros((1, 3, 4))
    coef[0, :, 0] = c0
    coef[0, :, 1] = c1
    coef[0, :, 2] = c2
    motion = Motion(np.array([t0, 6.0]), coef)
    fair_v = c1 + 2.0 * c2 * s

    clump = CLUMP0 + rng.normal(scale=0.3, size=3)
    clump_v = rng.normal(scale=0.2, size=3)

    # line 1: chain lying on the seabed near the anchor, then rising to the clump
    N1 = N_SEGS[0]
    r1 = np.zeros((N1 + 1, 3))
    xs = np.linspace(0.0, 1.0, N1 + 1)
    r1[:, 0] = ANCHOR1[0] + xs * (clump[0] - ANCHOR1[0])
    r1[:, 1] = ANCHOR1[1] + xs * (clump[1] - ANCHOR1[1])
    rise = np.clip((xs - 0.45) / 0.55, 0.0, None) ** 2
    r1[:, 2] = -DEPTH + rise * (clump[2] + DEPTH)
    r1[-1] = clump
    r1[1:-1, :2] += rng.normal(scale=0.03, size=(N1 - 1, 2))
    v1 = rng.normal(scale=0.3, size=(N1 + 1, 3))
    v1[0] = 0.0
    v1[-1] = clump_v
    # nodes 1-3 sit on the bed: tiny penetration (positive = below the bed) and tiny vertical speed
    # so that the normal force is small and both friction branches occur
    pen = np.array([1e-5, -5e-5, 2e-5]) + rng.uniform(0.0, 5e-6, size=3)
    for j, i in enumerate((1, 2, 3)):
        r1[i, 2] = -DEPTH - pen[j]
        v1[i, 2] = rng.normal(scale=1e-5)
    v1[1, :2] = [0.4, -0.3]  # fast: saturated (kinetic) friction
    v1[3, :2] = [2e-3, 1e-3]  # slow: linear creep branch
    # line 2: clump -> fairlead above the surface
    r2 = path_nodes(clump, FAIRLEAD0, N_SEGS[1], sag=2.0, rng=rng, noise=0.04)
    v2 = rng.normal(scale=0.3, size=r2.shape)
    v2[0] = clump_v
    v2[-1] = fair_v
    # line 3: anchor 2 -> clump
    r3 = path_nodes(ANCHOR2, clump, N_SEGS[2], sag=4.0, rng=rng, noise=0.04)
    v3 = rng.normal(scale=0.3, size=r3.shape)
    v3[0] = 0.0
    v3[-1] = clump_v

    # unstretched lengths: the median segment length, so some segments are slack and some taut;
    # the polyester line is set up with a few per cent of strain, and one segment beyond the table
    lengths = []
    for r, f in ((r1, 1.0 - 3e-4), (r2, 1.0 / 1.012), (r3, 1.0 - 2e-4)):
        ls = np.linalg.norm(np.diff(r, axis=0), axis=1)
        lengths.append(float(np.median(ls) * f * len(ls)))
    l0_poly = lengths[1] / N_SEGS[1]
    # stretch segment 2 of line 2 to ~5 % (beyond the last table strain 4 %)
    d = r2[3] - r2[2]
    shift = d / np.linalg.norm(d) * (1.05 * l0_poly - np.linalg.norm(d))
    r2[3:-1] += shift
    model = make_model(ba_curve, lengths)

    # state vector in the brief's order
    rows_r = [*r1[1:-1], *r2[1:-1], *r3[1:-1], clump]
    rows_v = [*v1[1:-1], *v2[1:-1], *v3[1:-1], clump_v]
    y = np.concatenate([np.ravel(rows_r), np.ravel(rows_v)])

    n_nodes = sum(n + 1 for n in N_SEGS)
    kin = {"U": np.zeros((n_nodes, 3)), "Ud": np.zeros((n_nodes, 3)), "zeta": np.zeros(n_nodes),
           "pU": np.zeros((4, 3))}
    if waves:
        kin["U"] = rng.normal(scale=0.5, size=(n_nodes, 3))
        kin["Ud"] = rng.normal(scale=0.4, size=(n_nodes, 3))
        kin["zeta"] = rng.uniform(-0.6, 0.6, size=n_nodes)
        kin["pU"] = rng.normal(scale=0.5, size=(4, 3))
    return model, y, t, motion, kin, cd_scale


CASES = {
    "still-water": dict(seed=1, ba_curve=BA_MIRRORED, cd_scale=1.0, waves=False),
    "waves-current": dict(seed=2, ba_curve=BA_MIRRORED, cd_scale=1.0, waves=True),
    "signed-BA-table": dict(seed=3, ba_curve=BA_SIGNED, cd_scale=1.0, waves=True),
    "drag-scaled": dict(seed=4, ba_curve=BA_SIGNED, cd_scale=4.0, waves=False),
}


# ---------------------------------------------------------------------------------- the reference
def unit(a):
    n = np.linalg.norm(a)
    return a / n if n > 0 else np.zeros(3)


def wet_fraction(ra, rb, zeta_a, zeta_b, d):
    """Spec 3.6, as written."""
    zs = 0.5 * (zeta_a + zeta_b)
    za, zb = ra[2] - zs, rb[2] - zs
    if za <= 0 and zb < 0:
        return 1.0
    if za > 0 and zb > 0:
        return 0.0
    if za == -zb:
        return 0.5
    s = rb - ra
    n = unit(np.cross(s, np.cross([0.0, 0.0, 1.0], s)))
    low, up = (za, zb) if za < zb else (zb, za)
    z_low = low - 0.5 * d * n[2]
    z_up = up + 0.5 * d * n[2]
    return abs(z_low) / (abs(z_low) + z_up)


def reference(model: Model, y, t, motion: Motion, kin, cd_scale):
    """Plain evaluation of spec 3.1-3.9, 3.12, 3.13. Returns a dict of results and their scales."""
    env = model.env
    g, rho, zbed = env.g, env.rho, -env.depth
    I3 = np.eye(3)

    # state rows: internal nodes of each line in line order, then free points in point order
    nrow = sum(ln.N - 1 for ln in model.lines) + sum(p.kind.name == "FREE" for p in model.points)
    q_state = y[:3 * nrow].reshape(nrow, 3)
    u_state = y[3 * nrow:].reshape(nrow, 3)
    row = 0
    line_rows = []
    for ln in model.lines:
        line_rows.append(list(range(row, row + ln.N - 1)))
        row += ln.N - 1
    point_row = {}
    for i, p in enumerate(model.points):
        if p.kind.name == "FREE":
            point_row[i] = row
            row += 1

    # point kinematics
    k = 0  # motion piece (the only one)
    sm = t - motion.t[k]
    pr, pv = [], []
    ci = 0
    for i, p in enumerate(model.points):
        if p.kind.name == "FIXED":
            pr.append(p.r.copy())
            pv.append(np.zeros(3))
        elif p.kind.name == "COUPLED":
            c = motion.c[k, 3 * ci:3 * ci + 3]
            pr.append(c[:, 0] + c[:, 1] * sm + c[:, 2] * sm**2 + c[:, 3] * sm**3)
            pv.append(c[:, 1] + 2 * c[:, 2] * sm + 3 * c[:, 3] * sm**2)
            ci += 1
        else:
            pr.append(q_state[point_row[i]].copy())
            pv.append(u_state[point_row[i]].copy())

    out = {"T": [], "Td": [], "F": [], "F_scale": [], "acc": {}, "acc_scale": {}, "seg_F": [],
           "branches": set(), "strain": []}
    end_load = []  # (point, F_end, M_end, scale)
    node = 0
    for li, ln in enumerate(model.lines):
        lt = model.line_types[ln.line_type]
        N = ln.N
        l0 = ln.L / N
        d, w = lt.d, lt.w
        A = math.pi * d * d / 4
        Cd, CdAx = lt.Cd * cd_scale, lt.CdAx * cd_scale
        EA_ref = lt.EA.y[-1] / lt.EA.x[-1] if isinstance(lt.EA, Curve) else lt.EA
        r = np.zeros((N + 1, 3))
        v = np.zeros((N + 1, 3))
        r[0], v[0] = pr[ln.end_a.index], pv[ln.end_a.index]
        r[N], v[N] = pr[ln.end_b.index], pv[ln.end_b.index]
        for j, rr in enumerate(line_rows[li], 1):
            r[j], v[j] = q_state[rr], u_state[rr]
        U = kin["U"][node:node + N + 1]
        Ud = kin["Ud"][node:node + N + 1]
        zeta = kin["zeta"][node:node + N + 1]

        # segments (3.1-3.3, 3.6)
        T = np.zeros((N, 3))
        Td = np.zeros((N, 3))
        Fw = np.zeros(N)
        for s in range(N):
            dr = r[s + 1] - r[s]
            ls = np.linalg.norm(dr)
            e = dr / ls
            ldot = e @ (v[s + 1] - v[s])
            eps = ls / l0 - 1
            out["strain"].append((lt.name, eps))
            if eps > 0:
                if isinstance(lt.EA, Curve):
                    Tm = np.interp(eps, lt.EA.x, lt.EA.y)  # clamped at both ends
                    out["branches"].add("EA table beyond last point" if eps > lt.EA.x[-1] else "EA table")
                else:
                    Tm = lt.EA * eps
                out["branches"].add("taut")
            else:
                Tm = 0.0
                out["branches"].add("slack")
            rate = ldot / l0
            if isinstance(lt.BA, Curve):
                if lt.BA.x[0] < 0:
                    Dm = np.interp(rate, lt.BA.x, lt.BA.y)
                    out["branches"].add("BA table signed")
                else:
                    Dm = math.copysign(np.interp(abs(rate), lt.BA.x, lt.BA.y), rate)
                    out["branches"].add("BA table mirrored")
            elif lt.BA < 0:
                Dm = -lt.BA * l0 * math.sqrt(EA_ref * w) * rate
                out["branches"].add("BA ratio")
            else:
                Dm = lt.BA * rate
            T[s] = Tm * e
            Td[s] = Dm * e
            Fw[s] = wet_fraction(r[s], r[s + 1], zeta[s], zeta[s + 1], d)
            if 0 < Fw[s] < 1:
                out["branches"].add("surface piercing")
        out["T"].append(T)
        out["Td"].append(Td)
        out["seg_F"].append(Fw)

        # nodes (3.5-3.9, 3.12)
        for i in range(N + 1):
            if i == 0:
                q = unit(r[1] - r[0])
            elif i == N:
                q = unit(r[N] - r[N - 1])
            else:
                q = unit(r[i + 1] - r[i - 1])
            lL = l0 if i > 0 else 0.0
            lR = l0 if i < N else 0.0
            lam = 0.5 * (lL + lR)
            lamw = 0.5 * (lL * (Fw[i - 1] if i > 0 else 0) + lR * (Fw[i] if i < N else 0))
            m = w * lam
            vol = A * lamw
            qq = np.outer(q, q)
            M = m * I3 + rho * vol * (lt.Ca * (I3 - qq) + lt.CaAx * qq)

            Wt = np.array([0.0, 0.0, -g * (m - rho * vol)])
            u = U[i] - v[i]
            u_q = (u @ q) * q
            u_p = u - u_q
            Dp = 0.5 * rho * Cd * d * lamw * np.linalg.norm(u_p) * u_p
            Dq = 0.5 * rho * CdAx * math.pi * d * lamw * np.linalg.norm(u_q) * u_q
            a_q = (Ud[i] @ q) * q
            a_p = Ud[i] - a_q
            Ap = rho * (1 + lt.Ca) * vol * a_p
            Aq = rho * (1 + lt.CaAx) * vol * a_q
            B = np.zeros(3)
            if r[i, 2] < zbed:
                B[2] = ((zbed - r[i, 2]) * env.kBot - v[i, 2] * env.cBot) * d * lam
                out["branches"].add("seabed contact")
                vh = np.array([v[i, 0], v[i, 1], 0.0])
                vhm = np.linalg.norm(vh)
                if env.mu > 0 and vhm > 0:
                    Nf = abs(B[2])
                    F_lin = env.mu * env.fric_damp * vhm
                    if F_lin <= env.stat_dyn * env.mu * Nf:
                        F_f = F_lin
                        out["branches"].add("friction creep")
                    else:
                        F_f = env.mu * Nf
                        out["branches"].add("friction kinetic")
                    B -= F_f * vh / vhm
            internal = np.zeros(3)
            iscale = 0.0
            if i < N:
                internal += T[i] + Td[i]
                iscale += np.linalg.norm(T[i]) + np.linalg.norm(Td[i])
            if i > 0:
                internal -= T[i - 1] + Td[i - 1]
                iscale += np.linalg.norm(T[i - 1]) + np.linalg.norm(Td[i - 1])
            terms = (Wt, Dp, Dq, Ap, Aq, B)
            F = internal + sum(terms)
            scale = iscale + sum(np.linalg.norm(x) for x in terms)
            out["F"].append(F)
            out["F_scale"].append(scale)
            if 0 < i < N:
                out["acc"][line_rows[li][i - 1]] = np.linalg.solve(M, F)
                out["acc_scale"][line_rows[li][i - 1]] = scale / m
            else:
                end_load.append(((ln.end_a if i == 0 else ln.end_b).index, F, M, scale))
        node += N + 1

    # points (3.13)
    pF, pM, pscale = [], [], []
    for i, p in enumerate(model.points):
        u = kin["pU"][i] - pv[i]
        own = p.F_ext + np.array([0.0, 0.0, g * (rho * p.V - p.m)]) \
            + 0.5 * rho * p.CdA * cd_scale * np.linalg.norm(u) * u
        F = own.copy()
        M = (p.m + rho * p.Ca * p.V) * I3
        scale = np.linalg.norm(own)
        for pi, Fe, Me, sc in end_load:
            if pi == i:
                F += Fe
                M += Me
                scale += sc
        pF.append(F)
        pM.append(M)
        pscale.append(scale)
        if p.kind.name == "FREE":
            out["acc"][point_row[i]] = np.linalg.solve(M, F)
            out["acc_scale"][point_row[i]] = scale / M[0, 0]

    out["T"] = np.vstack(out["T"])
    out["Td"] = np.vstack(out["Td"])
    out["seg_F"] = np.concatenate(out["seg_F"])
    out["F"] = np.array(out["F"])
    out["F_scale"] = np.array(out["F_scale"])
    out["pF"] = np.array(pF)
    out["pM"] = np.array(pM)
    out["pF_scale"] = np.array(pscale)
    dy = np.zeros_like(y)
    dy[:3 * nrow] = y[3 * nrow:]
    acc_scale = np.zeros(3 * nrow)
    for rr in range(nrow):
        dy[3 * nrow + 3 * rr:3 * nrow + 3 * rr + 3] = out["acc"][rr]
        acc_scale[3 * rr:3 * rr + 3] = out["acc_scale"][rr]
    out["dy"] = dy
    out["dy_scale"] = np.concatenate([np.abs(y[3 * nrow:]), acc_scale])
    return out


# ---------------------------------------------------------------------------------- the kernel
def run_kernel(model, y, t, motion, kin, cd_scale, vector=False):
    keep_min = core_layout.VECTOR_MIN_NODES
    core_layout.VECTOR_MIN_NODES = 2 if vector else keep_min
    try:
        layout = build_layout(model)
    finally:
        core_layout.VECTOR_MIN_NODES = keep_min
    # the chain (line 1) is the one line with constant EA and BA
    assert list(layout.lines.vec) == ([1, 0, 0] if vector else [0, 0, 0])
    W = layout.new_work()
    # everything rhs must compute is poisoned first: a value it forgets to (re)set shows up as NaN
    # (bending forces and clamped-end moments are written only in a system with bending stiffness:
    # without, no kernel touches them and they keep the zeros of new_work, see core.features)
    keep = ("features", "U", "Ud", "zeta", "pU") + (() if BENDING in W.features.names else ("Fbend", "end_moment"))
    for name in W._fields:
        if name not in keep:
            getattr(W, name)[...] = np.nan
    W.U[...] = kin["U"]
    W.Ud[...] = kin["Ud"]
    W.zeta[...] = kin["zeta"]
    W.pU[...] = kin["pU"]
    dy = np.full_like(y, np.nan)
    rhs(t, y, dy, layout.lines, layout.rigid, layout.points, layout.env, layout.seabed, motion, W, layout.fl,
        layout.new_float_work(), cd_scale, -1)
    return layout, W, dy


def rel_err(got, want, scale):
    """max |got - want| / scale, row-wise scale (broadcast over the last axis)."""
    got, want, scale = np.asarray(got), np.asarray(want), np.asarray(scale)
    if got.ndim > scale.ndim:
        scale = scale.reshape(scale.shape + (1,) * (got.ndim - scale.ndim))
    return float(np.max(np.abs(got - want) / np.maximum(scale, 1e-300)))


@pytest.fixture(scope="module", params=[(c, v) for c in CASES for v in ("scalar", "vector")],
                ids=lambda p: f"{p[0]}-{p[1]}")
def case(request):
    name, path = request.param
    model, y, t, motion, kin, cd_scale = make_case(**CASES[name])
    ref = reference(model, y, t, motion, kin, cd_scale)
    layout, W, dy = run_kernel(model, y, t, motion, kin, cd_scale, vector=path == "vector")
    return f"{name} ({path})", model, ref, layout, W, dy


# ---------------------------------------------------------------------------------- tests
def test_case_exercises_every_branch():
    """Guard of the fixture: together the cases hit every branch of the reference physics."""
    seen = set()
    for spec in CASES.values():
        seen |= reference(*make_case(**spec))["branches"]
    want = {"taut", "slack", "EA table", "EA table beyond last point", "BA ratio", "BA table mirrored",
            "BA table signed", "surface piercing", "seabed contact", "friction creep", "friction kinetic"}
    assert want <= seen, f"branches never exercised: {sorted(want - seen)}"


def test_each_case_has_slack_taut_contact_and_piercing(case):
    name, _, ref, *_ = case
    for b in ("taut", "slack", "surface piercing", "seabed contact", "friction creep", "friction kinetic",
              "EA table", "BA ratio"):
        assert b in ref["branches"], f"{name}: branch {b!r} not exercised"


def test_segment_tension_and_damping(case):
    name, _, ref, layout, W, _ = case
    tscale = np.linalg.norm(ref["T"], axis=1) + np.linalg.norm(ref["Td"], axis=1) + 1e-9
    assert rel_err(W.T, ref["T"], tscale) <= RTOL, name
    assert rel_err(W.Td, ref["Td"], tscale) <= RTOL, name


def test_submerged_fraction(case):
    name, _, ref, layout, W, _ = case
    np.testing.assert_allclose(W.seg_F, ref["seg_F"], rtol=0, atol=RTOL, err_msg=name)


def test_node_net_forces(case):
    name, _, ref, layout, W, _ = case
    err = rel_err(W.F, ref["F"], ref["F_scale"])
    assert err <= RTOL, f"{name}: node forces differ by {err:.3g} relative"


def test_point_forces_and_mass(case):
    name, _, ref, layout, W, _ = case
    err = rel_err(W.pF, ref["pF"], ref["pF_scale"])
    assert err <= RTOL, f"{name}: point forces differ by {err:.3g} relative"
    mscale = np.abs(ref["pM"]).max(axis=(1, 2))
    err = rel_err(W.pM, ref["pM"], mscale)
    assert err <= RTOL, f"{name}: point mass matrices differ by {err:.3g} relative"


def test_state_derivative(case):
    name, _, ref, layout, W, dy = case
    assert np.all(np.isfinite(dy)), name
    nrow = dy.size // 6
    np.testing.assert_array_equal(dy[:3 * nrow], ref["dy"][:3 * nrow], err_msg=f"{name}: dq/dt must be u")
    err = rel_err(dy[3 * nrow:], ref["dy"][3 * nrow:], ref["dy_scale"][3 * nrow:])
    assert err <= RTOL, f"{name}: accelerations differ by {err:.3g} relative"


def test_rhs_is_repeatable_and_pure(case):
    """A second call on the same inputs gives bit-identical results (no accumulation across calls)."""
    name, _, _, layout, W, dy = case
    _, y, t, motion, _, cd_scale = make_case(**CASES[name.split(" (")[0]])
    dy2 = np.zeros_like(dy)
    rhs(t, y, dy2, layout.lines, layout.rigid, layout.points, layout.env, layout.seabed, motion, W, layout.fl,
        layout.new_float_work(), cd_scale, -1)
    np.testing.assert_array_equal(dy2, dy)


# ---------------------------------------------------------------------------------- submergence
def test_wet_fraction_random_segments():
    """The kernel's submerged fraction against the reference for random segments near the surface
    (both orders of the nodes, random surface elevations)."""
    rng = np.random.default_rng(7)
    for _ in range(2000):
        ra = rng.uniform(-3.0, 3.0, size=3)
        rb = ra + rng.normal(scale=2.0, size=3)
        za, zb = rng.uniform(-0.5, 0.5, size=2)
        d = rng.uniform(0.05, 0.5)
        want = wet_fraction(ra, rb, za, zb, d)
        r = np.array([ra, rb])
        assert segment_wet_fraction(r, 0, 1, za, zb, d) == pytest.approx(want, abs=1e-12)
        assert segment_wet_fraction(r, 1, 0, zb, za, d) == pytest.approx(wet_fraction(rb, ra, zb, za, d), abs=1e-12)


@pytest.mark.parametrize("za, zb", [(-6.0, 0.0), (6.0, 0.0), (0.0, 6.0), (0.0, -6.0)],
                         ids=["below-to-surface", "above-to-surface", "surface-to-above", "surface-to-below"])
def test_wet_fraction_node_on_still_water_level(za, zb):
    """A node exactly at z = 0 (e.g. a fairlead or buoy point at the still-water level in a deck).

    Spec 3.6 (C): F = 1 only if z_a <= 0 and z_b < 0, F = 0 only if both are > 0; every other
    segment goes through the widened-ends formula. So a segment rising from below to a node at
    z = 0 is not fully wet (MoorDyn 2.7.2 gives F = 0.96875 for the first geometry, d = 0.5 m,
    10 m segment at 3:4 slope; see the oracle test of the same case), and one falling from above
    to z = 0 is not fully dry (MoorDyn: 0.03125). For the third geometry (z_a = 0 rising into the
    air) the spec's "lower and upper ends" give 0.03125 too; MoorDyn 2.7.2 itself returns 0.967
    there (it takes the upper node as the lower end), so the oracle test does not use that one."""
    ra = np.array([0.0, 0.0, za])
    rb = np.array([8.0, 0.0, zb])
    d = 0.5
    want = wet_fraction(ra, rb, 0.0, 0.0, d)
    got = segment_wet_fraction(np.array([ra, rb]), 0, 1, 0.0, 0.0, d)
    assert got == pytest.approx(want, abs=1e-12), \
        f"segment z_a = {za:g}, z_b = {zb:g}: submerged fraction {got:.6g}, spec 3.6 gives {want:.6g}"
