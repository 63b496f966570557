"""From a model's floating-body descriptions to the arrays of the compiled loop
(:class:`~moorline.core.layout.FloatArrays`, :class:`~moorline.core.layout.ExcitationArrays`).

Everything expensive is done here once: coefficient files read (or computed) and moved to each
body's reference point, the radiation impulse response and its state-space fit, and the wave
excitation of the model's sea, from the same components (amplitudes, phases, headings) that drive
the lines, so that body and lines see one sea.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from ..core.layout import (
    EXC_OFF,
    EXC_SUM,
    EXC_TABLE,
    RAD_CONVOLUTION,
    RAD_STATE_SPACE,
    ExcitationArrays,
    FloatArrays,
)
from ..core.waterkin import wave_numbers
from ..model import BemRun, Model, ModelError, rotation_xyz
from ..model.water import Waves

log = logging.getLogger("moorline")

#: sum the excitation of at most this many wave components at every evaluation; more are tabulated
#: over the sea's repeat period (when it has one) and interpolated
EXC_SUM_MAX = 16
#: table interval: this many samples per period of the highest component (cubic Hermite
#: interpolation with exact derivatives: relative error below (2 pi / 40)^4 / 384 = 1.6e-6)
EXC_SAMPLES_PER_PERIOD = 40
DOF_NAMES = ("Surge", "Sway", "Heave", "Roll", "Pitch", "Yaw")
#: rate of the pull that keeps a joint's child on its joint between projections, times dtM [-]:
#: the critically damped pull has a real eigenvalue -JOINT_PULL / dtM, inside every explicit
#: scheme's stability region, and gives Newton statics the stiffness across the joint it needs
JOINT_PULL = 0.3


def _hydro():
    from .. import hydro

    return hydro


def _quat(R: np.ndarray) -> np.ndarray:
    from ..core.layout import quat_from_matrix

    return quat_from_matrix(R)


def _quat_conj_mul(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a^-1 (x) b for unit quaternions (w, x, y, z)."""
    from ..core.layout import quat_product

    return quat_product((a[0], -a[1], -a[2], -a[3]), b)


def load_coefficients(h, env, model=None):
    """The coefficient Dataset of a body set (read from a WAMIT stem or a Capytaine NetCDF file
    when a path is given), checked against the environment's water density and gravity."""
    hy = _hydro()
    src = h.coefficients
    if isinstance(src, BemRun):
        return _compute(hy, src, h, env, model)
    if isinstance(src, (str, Path)):
        p = Path(src)
        if p.suffix.lower() in (".nc", ".nc4", ".netcdf"):
            ds = hy.read_capytaine(p)
        else:
            opts = dict(rho=env.rho, g=env.g)
            opts.update(h.wamit_options)
            ds = hy.read_wamit(p, **opts)
    else:
        ds = hy.from_capytaine(src)
    rho = float(ds.attrs.get("rho", ds["rho"].values if "rho" in ds else env.rho))
    g = float(ds.attrs.get("g", ds["g"].values if "g" in ds else env.g))
    if abs(rho - env.rho) > 1e-6 * env.rho or abs(g - env.g) > 1e-6 * env.g:
        raise ModelError(f"hydrodynamic coefficients for bodies {[b + 1 for b in h.bodies]} were computed with "
                         f"rho = {rho:g} kg/m^3, g = {g:g} m/s^2, but the environment has rho = {env.rho:g}, "
                         f"g = {env.g:g}: recompute them, or read the WAMIT files with the environment's values")
    return ds


def _hull_mesh(hy, hull):
    if hull.file is not None:
        mesh = hy.load_mesh(hull.file)
    else:
        p = hull.params
        if hull.shape == "cylinder":
            mesh = hy.mesh_cylinder(float(p["radius"]), float(p["draft"]), n_theta=hull.n_theta)
        elif hull.shape == "hemisphere":
            mesh = hy.mesh_hemisphere(float(p["radius"]), n_theta=hull.n_theta)
        else:
            mesh = hy.mesh_axisymmetric(np.asarray(p["profile"], dtype=float), n_theta=hull.n_theta)
    if np.any(hull.offset != 0.0):
        mesh = mesh.translated(hull.offset)
    return mesh


def _compute(hy, run: BemRun, h, env, model):
    """Capytaine coefficients of a BemRun (from the cache when they were computed before)."""
    if len(run.hulls) != len(h.bodies):
        raise ModelError(f"the Capytaine run of bodies {[b + 1 for b in h.bodies]} has {len(run.hulls)} hulls")
    centres = run.rotation_centers
    if centres is None:
        centres = np.array([model.bodies[b].r for b in h.bodies]) if model is not None else np.zeros((len(h.bodies), 3))
    depth = run.water_depth if run.water_depth is not None else env.depth
    meshes = [_hull_mesh(hy, hull) for hull in run.hulls]
    return hy.compute_coefficients(meshes, omega=run.omega, wave_direction=np.radians(run.wave_direction),
                                   water_depth=depth, rho=env.rho, g=env.g, rotation_center=centres,
                                   names=[f"body{b + 1}" for b in h.bodies] if len(h.bodies) > 1 else None,
                                   lid=run.lid, cache_dir=run.cache_dir)


def _body_dofs(ds, n_bodies: int, what: str) -> np.ndarray:
    """Indices of each body's six DOFs (surge ... yaw) in the Dataset's radiating_dof order,
    shape (n_bodies, 6)."""
    names = [str(v) for v in ds["radiating_dof"].values]
    if len(names) != 6 * n_bodies:
        raise ModelError(f"{what}: the coefficients have {len(names)} DOFs, expected 6 per body for "
                         f"{n_bodies} bodies")
    out = np.zeros((n_bodies, 6), dtype=np.int64)
    for b in range(n_bodies):
        for d, dn in enumerate(DOF_NAMES):
            k = 6 * b + d
            if not names[k].lower().endswith(dn.lower()):
                raise ModelError(f"{what}: DOF {k + 1} is {names[k]!r}, expected {dn} of body {b + 1} (six DOFs "
                                 "per body, surge to yaw, body after body)")
            out[b, d] = k
    return out


class _Builder:
    """Collects the per-body and per-pair arrays of all coefficient sets."""

    def __init__(self, model: Model):
        self.model = model
        self.env = model.env
        # floating bodies in coefficient-set order
        self.order = [b for h in model.hydro for b in h.bodies]
        self.index = {b: f for f, b in enumerate(self.order)}
        nf = len(self.order)
        self.nf = nf
        self.C = np.zeros((nf, 6, 6))
        self.F0 = np.zeros((nf, 6))
        self.pose0 = np.zeros((nf, 3))
        self.R0 = np.zeros((nf, 3, 3))
        self.Ainf = np.zeros((6 * nf, 6 * nf))
        self.pairs: list[tuple[int, int, np.ndarray, np.ndarray, np.ndarray]] = []
        self.irf = None
        self.exc = np.zeros((0, 6 * nf), dtype=complex)  # (n_components, 6 nf) WAMIT-convention complex forces
        self.irf_dt = 1.0
        methods = {h.radiation for h in model.hydro}
        if len(methods) > 1:
            raise ModelError("all coefficient sets of a model must use the same radiation method, got "
                             f"{sorted(methods)}")
        self.method = methods.pop() if methods else "state_space"

    # ------------------------------------------------------------------ one coefficient set
    def add_set(self, h, waves: Waves | None) -> None:
        hy = _hydro()
        m = self.model
        nb = len(h.bodies)
        what = f"coefficients of bodies {[b + 1 for b in h.bodies]}"
        ds = load_coefficients(h, self.env, m)
        dofs = _body_dofs(ds, nb, what)
        # mean poses (deck pose by default) and where the BEM coordinates sit in the system
        poses = np.array(h.mean_poses, dtype=float) if h.mean_poses is not None else \
            np.array([np.concatenate([m.bodies[b].r, np.radians(m.bodies[b].angles)]) for b in h.bodies])
        centres = np.asarray(ds["rotation_center"].values, dtype=float).reshape(nb, 3)
        shift = np.zeros(3) if h.reference_points is None else h.reference_points[0] - centres[0]
        if h.reference_points is not None and not np.allclose(h.reference_points - centres, shift, atol=1e-9):
            raise ModelError(f"{what}: reference_points must move all bodies of a set by the same offset (the BEM "
                             "run's relative positions are fixed)")
        # coefficients about each body's reference point, in the BEM run's coordinates
        ds = hy.transform_reference(ds, poses[:, :3] - shift)
        rho, g = self.env.rho, self.env.g
        ainf = np.asarray(hy.matrix(ds["added_mass_inf"]), dtype=float)  # [influenced, radiating]
        C = np.asarray(hy.matrix(ds["hydrostatic_stiffness"]), dtype=float)
        vol = np.asarray(ds["displaced_volume"].values, dtype=float).reshape(nb)
        cob = np.asarray(ds["center_of_buoyancy"].values, dtype=float).reshape(nb, 3)
        for bi, b in enumerate(h.bodies):
            if m.floating_body(b).displaced_mass:
                m.bodies[b].m = rho * float(vol[bi])
                log.info("body %d: mass set to the displaced mass rho V = %.6g kg", b + 1, m.bodies[b].m)
            if m.bodies[b].m <= 0.0:
                raise ModelError(f"body {b + 1} floats but has no mass: give its mass (or 'displaced')")
        fidx = np.array([self.index[b] for b in h.bodies])
        gdof = (6 * fidx[:, None] + np.arange(6)[None, :])  # global floating DOF of each body DOF
        for bi, b in enumerate(h.bodies):
            f = self.index[b]
            self.pose0[f] = poses[bi, :3]
            self.R0[f] = rotation_xyz(poses[bi, 3:])
            self.C[f] = C[np.ix_(dofs[bi], dofs[bi])]
            fb = rho * g * vol[bi]
            arm = cob[bi] - (poses[bi, :3] - shift)
            self.F0[f] = [0.0, 0.0, fb, arm[1] * fb, -arm[0] * fb, 0.0]
            for bj in range(nb):
                self.Ainf[np.ix_(gdof[bi], gdof[bj])] = ainf[np.ix_(dofs[bi], dofs[bj])]
        flat = dofs.ravel()
        gflat = gdof.ravel()
        self.irf_dt = h.irf_dt
        t = np.arange(0.0, h.irf_duration + 0.5 * h.irf_dt, h.irf_dt)
        if self.method == "convolution":
            K = np.asarray(hy.impulse_response(ds, t).transpose("time", "radiating_dof", "influenced_dof").values)
            if self.irf is None:
                self.irf = np.zeros((t.size, 6 * self.nf, 6 * self.nf))
            if self.irf.shape[0] != t.size:
                raise ModelError("all coefficient sets of a model must use the same impulse-response length and "
                                 "sampling with radiation='convolution'")
            self.irf[np.ix_(np.arange(t.size), gflat, gflat)] = K[np.ix_(np.arange(t.size), flat, flat)]
        else:
            fit = hy.fit_state_space(ds, t=t, rtol=h.ss_rtol, max_order=h.ss_max_order)
            pk = fit.pack()
            local = {int(k): int(gflat[np.where(flat == k)[0][0]]) for k in flat}
            for p in range(pk.pair_i.size):
                s0, s1 = int(pk.state_ptr[p]), int(pk.state_ptr[p + 1])
                n = s1 - s0
                self.pairs.append((local[int(pk.pair_i[p])], local[int(pk.pair_j[p])], pk.A[s0:s1, :n].copy(),
                                   pk.B[s0:s1].copy(), pk.C[s0:s1].copy()))
        if h.excitation and waves is not None:
            self._add_excitation(hy, ds, waves, shift, flat, gflat, what)

    def _add_excitation(self, hy, ds, waves: Waves, shift, flat, gflat, what) -> None:
        w = np.asarray(waves.omega, dtype=float)
        if self.exc.shape[0] == 0:
            self.exc = np.zeros((w.size, 6 * self.nf), dtype=complex)
        keep = w > 0.0
        if not np.any(keep):
            return
        k = wave_numbers(w, self.env.g, self.env.depth)
        beta = np.radians(np.asarray(waves.heading, dtype=float))
        for b in np.unique(beta[keep]):
            sel = keep & (beta == b)
            X = np.asarray(hy.excitation_transfer(ds, w[sel], float(b), outside="zero"), dtype=complex)
            phase = np.exp(-1j * k[sel] * (shift[0] * math.cos(b) + shift[1] * math.sin(b)))
            coef = np.conj(X[:, flat]) * (waves.amplitude[sel] * phase)[:, None]
            self.exc[np.ix_(np.where(sel)[0], gflat)] = coef

    # ------------------------------------------------------------------ the arrays
    def float_arrays(self) -> FloatArrays:
        m = self.model
        nf = self.nf
        nb = len(m.bodies)
        of_body = -np.ones(nb, dtype=np.int64)
        for f, b in enumerate(self.order):
            of_body[b] = f
        settings = [m.floating_body(b) for b in self.order]
        Blin = np.array([s.linear_damping for s in settings]).reshape(nf, 6, 6)
        Bquad = np.array([s.quadratic_damping for s in settings]).reshape(nf, 6, 6)
        Kext = np.array([s.stiffness for s in settings]).reshape(nf, 6, 6)
        Fc = np.array([s.force for s in settings]).reshape(nf, 6)
        # groups: bodies of one coefficient set, merged by joints (union-find)
        parent = list(range(nf))

        def root(a):
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        def union(a, b):
            parent[root(a)] = root(b)

        for h in m.hydro:
            fs = [self.index[b] for b in h.bodies]
            for a in fs[1:]:
                union(a, fs[0])
        for j in m.joints:
            if j.parent is not None:
                union(self.index[j.child], self.index[j.parent])
        roots = sorted({root(f) for f in range(nf)})
        members = [[f for f in range(nf) if root(f) == r] for r in roots]
        grp_ptr = np.zeros(len(members) + 1, dtype=np.int64)
        grp_ptr[1:] = np.cumsum([len(g) for g in members])
        grp_members = np.array([f for g in members for f in g], dtype=np.int64)
        child_joint = -np.ones(nf, dtype=np.int64)
        for jn, j in enumerate(m.joints):
            child_joint[self.index[j.child]] = jn
        grouped = np.zeros(nf, dtype=np.int64)
        for g in members:
            if len(g) > 1 or any(child_joint[f] >= 0 for f in g):
                grouped[g] = 1
        # joints
        nj = len(m.joints)
        jt = {k: np.zeros((nj, 3)) for k in ("axis", "d0")}
        jq = np.zeros((nj, 4))
        for jn, j in enumerate(m.joints):
            c = m.bodies[j.child]
            Rc = c.rotation
            if j.parent is None:
                jt["d0"][jn] = c.r
                jq[jn] = _quat(Rc)
            else:
                p = m.bodies[j.parent]
                Rp = p.rotation
                jt["d0"][jn] = Rp.T @ (c.r - p.r)
                jq[jn] = _quat_conj_mul(_quat(Rp), _quat(Rc))
            jt["axis"][jn] = j.axis
        # state-space pairs, flat
        orders = [a.shape[0] for _, _, a, _, _ in self.pairs]
        mo = max(orders, default=1)
        ss_ptr = np.zeros(len(self.pairs) + 1, dtype=np.int64)
        ss_ptr[1:] = np.cumsum(orders)
        nz = int(ss_ptr[-1])
        ss_A = np.zeros((nz, mo))
        ss_B = np.zeros(nz)
        ss_C = np.zeros(nz)
        for p, (_, _, A, B, C) in enumerate(self.pairs):
            n = A.shape[0]
            ss_A[ss_ptr[p]:ss_ptr[p] + n, :n] = A
            ss_B[ss_ptr[p]:ss_ptr[p] + n] = B
            ss_C[ss_ptr[p]:ss_ptr[p] + n] = C
        strips = [(self.index[s_b], st) for s_b in self.order for st in m.floating_body(s_b).morison]
        ns = len(strips)
        irf = self.irf if self.irf is not None else np.zeros((0, 6 * nf, 6 * nf))
        return FloatArrays(
            body=np.array(self.order, dtype=np.int64), of_body=of_body, grouped=grouped, grp_ptr=grp_ptr,
            grp_members=grp_members, dof_y=np.zeros(6 * nf, dtype=np.int64), C=self.C, F0=self.F0,
            pose0=self.pose0, R0=self.R0, Blin=Blin, Bquad=Bquad, Kext=Kext, Fc=Fc, Ainf=self.Ainf,
            ss_i=np.array([p[0] for p in self.pairs], dtype=np.int64),
            ss_j=np.array([p[1] for p in self.pairs], dtype=np.int64), ss_ptr=ss_ptr, ss_A=ss_A, ss_B=ss_B,
            ss_C=ss_C, irf=irf, child_joint=child_joint,
            jt_child=np.array([self.index[j.child] for j in m.joints], dtype=np.int64),
            jt_parent=np.array([-1 if j.parent is None else self.index[j.parent] for j in m.joints], dtype=np.int64),
            jt_axis=jt["axis"], jt_d0=jt["d0"], jt_q=jq,
            jt_k=np.array([j.pto_stiffness for j in m.joints], dtype=float),
            jt_c=np.array([j.pto_damping for j in m.joints], dtype=float),
            jt_s0=np.array([j.pto_rest for j in m.joints], dtype=float),
            ms_fb=np.array([f for f, _ in strips], dtype=np.int64),
            ms_rA=np.array([s.rA for _, s in strips], dtype=float).reshape(ns, 3),
            ms_rB=np.array([s.rB for _, s in strips], dtype=float).reshape(ns, 3),
            ms_d=np.array([s.d for _, s in strips], dtype=float),
            ms_Cd=np.array([s.Cd for _, s in strips], dtype=float),
            ms_n=np.array([s.n for _, s in strips], dtype=np.int64), ql_F=np.zeros(6 * nf),
            ql_K=np.zeros((6 * nf, 6 * nf)), ql_x0=np.zeros(6 * nf), par=np.array([self.irf_dt, 0.0]),
            ctl=np.array([RAD_CONVOLUTION if self.method == "convolution" else RAD_STATE_SPACE, 0], dtype=np.int64))

    def excitation_arrays(self, waves: Waves | None) -> ExcitationArrays:
        nd = 6 * self.nf
        if waves is None or self.exc.shape[0] == 0 or not np.any(self.exc):
            from ..core.layout import no_excitation

            return no_excitation(nd)
        w = np.asarray(waves.omega, dtype=float)
        keep = np.any(self.exc != 0.0, axis=1)
        w, c = w[keep], self.exc[keep]
        par = np.array([float(waves.ramp_time), 1.0, 1.0])
        if w.size <= EXC_SUM_MAX or waves.base_omega is None:
            return ExcitationArrays(np.array([EXC_SUM], dtype=np.int64), par, w, c.real.copy(), c.imag.copy(),
                                    np.zeros((1, nd)), np.zeros((1, nd)))
        period = 2.0 * math.pi / float(waves.base_omega)
        n = int(math.ceil(period * float(w.max()) / (2.0 * math.pi) * EXC_SAMPLES_PER_PERIOD))
        dt = period / n
        t = np.arange(n + 1) * dt
        ph = np.exp(1j * np.outer(t, w))  # (n+1, nc)
        G = (ph @ c).real
        dG = ((ph * (1j * w)[None, :]) @ c).real
        par[1] = dt
        par[2] = period
        log.info("wave excitation of %d components tabulated over its repeat period %.6g s (%d samples)", w.size,
                 period, n)
        return ExcitationArrays(np.array([EXC_TABLE], dtype=np.int64), par, np.zeros(0), np.zeros((0, nd)),
                                np.zeros((0, nd)), G, dG)


def floating_arrays(model: Model) -> tuple[FloatArrays, ExcitationArrays] | None:
    """The arrays of the model's floating bodies for :func:`moorline.core.layout.build_layout`,
    or None when nothing floats."""
    if not model.floating:
        return None
    model._check_floating()
    waves = model.env.waves
    if waves is not None and waves.evaluation == "external":
        log.warning("external wave kinematics (set per node by the coupling program) carry no wave components: the "
                    "floating bodies get no wave excitation")
        waves = None
    b = _Builder(model)
    for h in model.hydro:
        b.add_set(h, waves)
    fl = b.float_arrays()
    exc = b.excitation_arrays(waves)
    log.info("floating bodies: %d (%d radiation states, %s radiation), excitation %s", b.nf, fl.ss_B.size,
             b.method, {EXC_OFF: "off", EXC_SUM: "summed", EXC_TABLE: "tabulated"}[int(exc.ctl[0])])
    return fl, exc
