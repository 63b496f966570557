"""State-space approximation of the radiation memory (one SISO realisation per DOF pair).

For each retained pair (i influenced, j radiating) the kernel K_ij(t) is approximated by C_r exp(A_r t) B_r, so
that the memory force is

    F_i(t) = - sum_j C_ij z_ij(t),    dz_ij/dt = A_ij z_ij + B_ij v_j(t),    z_ij(0) = 0,

with v the body velocity [m/s, rad/s] and A_ij real with eigenvalues of negative real part.

Method: realisation from the sampled kernel by the singular value decomposition of its Hankel matrix (Kung's
algorithm / the eigensystem realisation algorithm; WEC-Sim's BEMIO does the same family of fit). Chosen because it
works on K directly (the quantity whose error we state), gives balanced, well-conditioned realisations, picks
the order from the Hankel singular values without an iterative nonlinear fit, and needs no initial guess.
The discrete realisation (A_d, B_d, C_d) at the fit step dt_f reproduces K(k dt_f) = C_d A_d^k B_d; the
continuous one is A = log(A_d) / dt_f, B = B_d, C = C_d (exact at the samples, no bilinear-transform warping).
Orders 1, 2, ... max_order are tried and the lowest whose relative L2 error on K over the fitted time window is
<= rtol, with every eigenvalue of A in the open left half plane, is kept; if none reaches rtol, the stable one
with the smallest error is kept and reported.

Pairs skipped as negligible: a DOF is inactive when max|K_ii| < skip_tol x the largest max|K_kk| over all DOFs,
both scaled to translation units with a length L_b = V_b^(1/3) per body (rotation DOFs divided by L_b^2), which
drops e.g. the yaw of an axisymmetric body whose coefficients are solver noise; an off-diagonal pair (i, j) is
skipped when max|K_ij| < skip_tol x sqrt(max|K_ii| max|K_jj|) or when i or j is inactive. Default skip_tol = 1e-3.

Passivity: the fitted damping B_ss(w) = Re{K_ss(i w)} (the whole n_dof x n_dof matrix, symmetrised) must be
positive semi-definite at every frequency. :meth:`StateSpaceFit.passivity` reports its smallest eigenvalue over a
dense frequency grid after scaling each DOF by its peak damping; :func:`fit_state_space` with
``enforce_passivity=True`` fixes a violation by adding first-order diagonal terms r/(s + a), whose damping is
positive at every frequency, at the worst frequency until the matrix is positive semi-definite
(``_enforce_passivity``); the kernel errors reported afterwards include those terms.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.linalg as sla
import xarray as xr

from .dataset import dof_body_index, is_rotation
from .irf import impulse_response

log = logging.getLogger("moorline.hydro")


@dataclass
class PairRealisation:
    """One SISO realisation: K_ij(t) ~ C exp(A t) B.

    Attributes
    ----------
    i, j : int
        Influenced and radiating DOF indices (0-based, body-major order).
    A : array (n, n), B : array (n,), C : array (n,)
    error : float
        Relative L2 error ||K - K_ss|| / ||K|| over the fitted time window [-].
    """

    i: int
    j: int
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray
    error: float
    error_fit: float = float("nan")  # error of the Hankel fit before any passivity correction

    @property
    def order(self) -> int:
        return self.A.shape[0]

    def kernel(self, t) -> np.ndarray:
        """K_ss(t), shape (n_t,)."""
        lam, V = np.linalg.eig(self.A)
        cb = (self.C @ V) * np.linalg.solve(V, self.B)
        return np.real(np.exp(np.outer(t, lam)) @ cb)

    def transfer(self, omega) -> np.ndarray:
        """K_ss(i w) = C (i w I - A)^-1 B, shape (n_w,) complex."""
        lam, V = np.linalg.eig(self.A)
        cb = (self.C @ V) * np.linalg.solve(V, self.B)
        return (cb[None, :] / (1j * np.asarray(omega)[:, None] - lam[None, :])).sum(axis=1)


class PackedStateSpace(NamedTuple):
    """Flat arrays of all pair realisations, for compiled time loops.

    Attributes
    ----------
    pair_i : int64 (n_pairs,)
        Influenced DOF of each pair (receives the force).
    pair_j : int64 (n_pairs,)
        Radiating DOF (its velocity drives the pair).
    state_ptr : int64 (n_pairs + 1,)
        Pair p owns states ``state_ptr[p]:state_ptr[p+1]`` of one state vector of length n_states.
    A : float64 (n_states, max_order)
        Row r of pair p's A_r is ``A[state_ptr[p] + r, :order_p]`` (order_p = state_ptr[p+1] - state_ptr[p]).
    B : float64 (n_states,)
    C : float64 (n_states,)

    For pair p with states z = x[s0:s1]: dz/dt = A[s0:s1, :s1-s0] @ z + B[s0:s1] * v[pair_j[p]], and the
    force on DOF pair_i[p] gets  -= C[s0:s1] @ z.
    """

    pair_i: np.ndarray
    pair_j: np.ndarray
    state_ptr: np.ndarray
    A: np.ndarray
    B: np.ndarray
    C: np.ndarray


@dataclass
class PassivityReport:
    """Smallest eigenvalue of the symmetrised fitted damping over frequency."""

    omega: np.ndarray
    min_eigenvalue: np.ndarray
    max_eigenvalue: float
    margin: float  # min over w of lambda_min / max over w of lambda_max (>= 0: passive)
    passive: bool
    corrections: int = 0  # first-order diagonal terms added per diagonal pair to enforce passivity


@dataclass
class StateSpaceFit:
    """All pair realisations of one coefficient set, with the data they were fitted to."""

    pairs: list[PairRealisation]
    dofs: list[str]
    added_mass_inf: np.ndarray  # (n_dof, n_dof), [influenced, radiating]
    t: np.ndarray
    dt_fit: float
    rtol: float
    skipped: list[tuple[int, int]] = field(default_factory=list)
    passivity_report: PassivityReport | None = None

    @property
    def n_dof(self) -> int:
        return len(self.dofs)

    def kernel(self, t=None) -> xr.DataArray:
        """K_ss(t) as a DataArray (radiating_dof, influenced_dof, time) like :func:`impulse_response`."""
        t = self.t if t is None else np.asarray(t, dtype=float)
        K = np.zeros((self.n_dof, self.n_dof, t.size))
        for p in self.pairs:
            K[p.j, p.i] = p.kernel(t)
        return xr.DataArray(K, dims=("radiating_dof", "influenced_dof", "time"),
                            coords={"radiating_dof": self.dofs, "influenced_dof": self.dofs, "time": t})

    def transfer(self, omega) -> np.ndarray:
        """K_ss(i w), shape (n_w, n_dof, n_dof) in [w, influenced, radiating] order."""
        omega = np.asarray(omega, dtype=float)
        H = np.zeros((omega.size, self.n_dof, self.n_dof), dtype=complex)
        for p in self.pairs:
            H[:, p.i, p.j] = p.transfer(omega)
        return H

    def frequency_response(self, omega):
        """Added mass and damping of the fitted model: A_ss = A_inf + Im K_ss(iw) / w, B_ss = Re K_ss(iw).

        Returns
        -------
        A, B : arrays (n_w, n_dof, n_dof) in [w, radiating, influenced] layout (as ``ds.added_mass``).
        """
        omega = np.asarray(omega, dtype=float)
        H = self.transfer(omega)
        A = self.added_mass_inf[None] + H.imag / omega[:, None, None]
        return np.swapaxes(A, 1, 2), np.swapaxes(H.real, 1, 2)

    def passivity(self, omega=None, *, tol: float = 1e-6) -> PassivityReport:
        """Check that the symmetrised Re K_ss(i w) is positive semi-definite on a frequency grid.

        The matrix is scaled to D^-1/2 B_ss D^-1/2 with D_i the peak of the fitted diagonal damping B_ss,ii over
        the grid (so the eigenvalues are dimensionless fractions of each DOF's peak damping and PSD-ness, which
        is unit-independent, is judged on one scale).

        Parameters
        ----------
        omega : array, optional
            Frequencies [rad/s]; default 2000 points log-spaced from 1e-3 to 4 x the Nyquist frequency of the fit.
        tol : float
            Passive when the smallest scaled eigenvalue is >= -tol.
        """
        if omega is None:
            omega = np.geomspace(1e-3, 4 * np.pi / self.dt_fit, 2000)
        H = self.transfer(omega).real
        d = np.sqrt(np.maximum(np.abs(np.einsum("wii->wi", H)).max(axis=0), 1e-300))
        Hs = H / np.outer(d, d)[None]
        ev = np.linalg.eigvalsh(0.5 * (Hs + np.swapaxes(Hs, 1, 2)))
        margin = float(ev[:, 0].min())
        return PassivityReport(np.asarray(omega), ev[:, 0], float(ev[:, -1].max()), margin, margin >= -tol)

    def pack(self) -> PackedStateSpace:
        """Flat arrays for the time loop (see :class:`PackedStateSpace`)."""
        orders = np.array([p.order for p in self.pairs], dtype=np.int64)
        ptr = np.zeros(len(self.pairs) + 1, dtype=np.int64)
        ptr[1:] = np.cumsum(orders)
        n_states = int(ptr[-1])
        max_order = int(orders.max()) if orders.size else 0
        A = np.zeros((n_states, max_order))
        B = np.zeros(n_states)
        C = np.zeros(n_states)
        for k, p in enumerate(self.pairs):
            s0, s1 = ptr[k], ptr[k + 1]
            A[s0:s1, :p.order] = p.A
            B[s0:s1] = p.B
            C[s0:s1] = p.C
        return PackedStateSpace(np.array([p.i for p in self.pairs], dtype=np.int64),
                                np.array([p.j for p in self.pairs], dtype=np.int64), ptr, A, B, C)

    def radiation_force(self, velocity, dt: float) -> np.ndarray:
        """Memory force of the fitted model for a sampled velocity (exact for velocity linear between samples).

        Parameters
        ----------
        velocity : array (n_t, n_dof) [m/s, rad/s], starting from rest (z = 0).
        dt : float [s]

        Returns
        -------
        array (n_t, n_dof): F_i = -sum_j C_ij z_ij [N, N m].
        """
        v = np.asarray(velocity, dtype=float)
        F = np.zeros_like(v)
        for p in self.pairs:
            n = p.order
            M = np.zeros((n + 2, n + 2))
            M[:n, :n] = p.A
            M[:n, n] = p.B
            M[n, n + 1] = 1.0
            E = sla.expm(M * dt)
            phi, g0, g1 = E[:n, :n], E[:n, n], E[:n, n + 1]
            vj = v[:, p.j]
            dv = np.diff(vj) / dt
            z = np.zeros(n)
            out = np.zeros(v.shape[0])
            for k in range(v.shape[0] - 1):
                z = phi @ z + g0 * vj[k] + g1 * dv[k]
                out[k + 1] = p.C @ z
            F[:, p.i] -= out
        return F

    def summary(self) -> str:
        """One line per pair: DOFs, order, relative error."""
        lines = [f"{'influenced':>16} {'radiating':>16} {'order':>5} {'rel. L2 error':>13}"]
        for p in self.pairs:
            lines.append(f"{self.dofs[p.i]:>16} {self.dofs[p.j]:>16} {p.order:5d} {p.error:13.3e}")
        return "\n".join(lines)


def _era(h, max_order):
    """Hankel-SVD realisations of orders 1..max_order from samples h_k = C A^k B, k = 0..N-1."""
    N = h.size
    r = (N - 1) // 2
    s = N - 1 - r
    H0 = sla.hankel(h[:r], h[r - 1:r - 1 + s])
    H1 = sla.hankel(h[1:r + 1], h[r:r + s])
    U, S, Vt = np.linalg.svd(H0, full_matrices=False)
    out = []
    for n in range(1, min(max_order, int(np.sum(S > S[0] * 1e-12))) + 1):
        sq = np.sqrt(S[:n])
        Ad = (U[:, :n].T @ H1 @ Vt[:n].T) / np.outer(sq, sq)
        Bd = sq * Vt[:n, 0]
        Cd = U[0, :n] * sq
        out.append((Ad, Bd, Cd))
    return out


def _continuous(Ad, Bd, Cd, dt):
    lam, V = np.linalg.eig(Ad)
    if np.any(np.abs(lam) >= 1.0) or np.any((np.abs(lam.imag) < 1e-12) & (lam.real <= 0)):
        return None
    Ac = V @ np.diag(np.log(lam)) @ np.linalg.inv(V) / dt
    if np.max(np.abs(Ac.imag)) > 1e-8 * max(np.max(np.abs(Ac.real)), 1e-300):
        return None
    Ac = Ac.real
    if np.any(np.linalg.eigvals(Ac).real >= 0):
        return None
    return Ac, Bd.astype(float), Cd.astype(float)


def _enforce_passivity(fit: StateSpaceFit, w_low: float, *, max_iter: int = 40) -> PassivityReport:
    """Raise the fitted damping matrix to positive semi-definite by first-order diagonal terms.

    While the smallest scaled eigenvalue lambda (see :meth:`StateSpaceFit.passivity`) is negative, at its
    frequency w* every fitted diagonal pair i taking part in its eigenvector (u_i^2 >= 0.01) gets a term
    r_i/(s + a) with a = max(w*, w_low) (w_low the lowest computed frequency of the data, so that a correction
    below the band does not leave a slowly decaying tail) and r_i chosen to add 1.05 |lambda| D_i of damping at
    w*. Such a term has positive damping r a/(a^2 + w^2) at every frequency, so it never makes another frequency
    worse; the kernel of pair i changes by r_i exp(-a t), which is included in the reported errors.
    """
    diag = {p.i: p for p in fit.pairs if p.i == p.j}
    rep = fit.passivity()
    omega = rep.omega
    H = fit.transfer(omega).real
    d = np.abs(np.einsum("wii->wi", H)).max(axis=0)
    n_added = 0
    for _ in range(max_iter):
        if rep.passive:
            break
        k = int(np.argmin(rep.min_eigenvalue))
        lam = -rep.min_eigenvalue[k]
        a = max(float(omega[k]), w_low)
        Hk = fit.transfer(omega[k:k + 1]).real[0]
        ds_ = np.sqrt(np.maximum(d, 1e-300))
        _, vec = np.linalg.eigh(0.5 * (Hk + Hk.T) / np.outer(ds_, ds_))
        u2 = vec[:, 0] ** 2
        log.debug("passivity correction at w = %.4g rad/s, scaled eigenvalue %.3g", omega[k], -lam)
        for i, p in diag.items():
            if u2[i] < 1e-2:
                continue
            r = 1.05 * lam * d[i] * (a * a + omega[k] ** 2) / a
            n = p.order
            A = np.zeros((n + 1, n + 1))
            A[:n, :n] = p.A
            A[n, n] = -a
            p.A, p.B, p.C = A, np.append(p.B, 1.0), np.append(p.C, r)
        n_added += 1
        rep = fit.passivity(omega)
    log.info("fit_state_space: %d passivity corrections, margin now %.3g", n_added, rep.margin)
    if not rep.passive:
        log.warning("fit_state_space: model still not passive after %d corrections (margin %.3g)", n_added, rep.margin)
    rep.corrections = n_added
    return rep


def fit_state_space(source, *, t=None, rtol: float = 0.002, max_order: int = 24, skip_tol: float = 1e-3,
                    dt_fit: float | None = None, taper: float = 0.5, passive_data: bool = True,
                    enforce_passivity: bool = True,
                    added_mass_inf=None) -> StateSpaceFit:
    """Fit a state-space realisation to every non-negligible radiation kernel pair.

    Parameters
    ----------
    source : xarray.Dataset or xarray.DataArray
        A coefficient Dataset (K is computed with :func:`impulse_response` on ``t``) or a kernel DataArray
        (radiating_dof, influenced_dof, time) from :func:`impulse_response`.
    t : array, optional
        Kernel time grid [s]; required with a Dataset unless the default ``0 .. 60 s`` suits. Its end is the
        fitted window (the truncation time).
    rtol : float
        Target relative L2 error on each K_ij over the window [-].
    max_order : int
        Largest order tried per pair.
    skip_tol : float
        Threshold for negligible pairs (module docstring).
    dt_fit : float, optional
        Sample step of the Hankel matrix [s]; default pi / (2 w_top) with w_top the top of the extended band
        (or, for a kernel input, the step giving at most 400 samples over the window).
    taper : float
        Band taper passed to :func:`impulse_response`.
    passive_data : bool
        Fit the kernel of the symmetric positive semi-definite projection of B (:func:`passive_damping`).
    enforce_passivity : bool
        Scale off-diagonal pairs if needed (module docstring).
    added_mass_inf : array (n_dof, n_dof), optional
        [influenced, radiating]; taken from the Dataset when one is given.

    Returns
    -------
    StateSpaceFit
    """
    if isinstance(source, xr.Dataset):
        ds = source
        if t is None:
            t = np.arange(0.0, 60.0, 0.01)
        K = impulse_response(ds, t, taper=taper, passive=passive_data)
        a_inf = ds["added_mass_inf"].transpose("influenced_dof", "radiating_dof").values
        w_top = float(ds["omega"].values[-1]) * (1 + taper)
        w_low = float(ds["omega"].values[0])
        if dt_fit is None:
            dt_fit = np.pi / (2 * w_top)
        bodies = dof_body_index(ds)
        vol = ds["displaced_volume"].values
        length = np.where(np.isfinite(vol) & (vol > 0), np.cbrt(np.where(np.isfinite(vol), vol, 1.0)), 1.0)[bodies]
    else:
        K = source
        t = K["time"].values
        a_inf = np.zeros((K.sizes["influenced_dof"],) * 2) if added_mass_inf is None else np.asarray(added_mass_inf)
        if dt_fit is None:
            dt_fit = max(t[-1] / 400, t[1] - t[0])
        length = np.ones(K.sizes["influenced_dof"])
        w_low = 1e-3
    t = np.asarray(t, dtype=float)
    Kv = K.transpose("radiating_dof", "influenced_dof", "time").values
    dofs = [str(d) for d in K["influenced_dof"].values]
    n = len(dofs)
    rot = is_rotation(dofs)
    peak = np.abs(Kv).max(axis=2)  # [j, i]
    diag = np.diagonal(peak).copy()
    scaled = diag / np.where(rot, length ** 2, 1.0)
    active = scaled >= skip_tol * scaled.max()
    step = max(1, int(round(dt_fit / (t[1] - t[0]))))
    dt_f = step * (t[1] - t[0])
    pairs, skipped = [], []
    for i in range(n):
        for j in range(n):
            if not (active[i] and active[j]) or peak[j, i] < skip_tol * np.sqrt(diag[i] * diag[j]):
                skipped.append((i, j))
                continue
            k_ij = Kv[j, i]
            h = k_ij[::step]
            norm = np.linalg.norm(k_ij)
            best = None
            t_h = t[::step]
            norm_h = np.linalg.norm(h)
            for Ad, Bd, Cd in _era(h, max_order):
                cont = _continuous(Ad, Bd, Cd, dt_f)
                if cont is None:
                    continue
                pr = PairRealisation(i, j, *cont, error=0.0)
                # order search on the fit samples; the reported error is on the full grid
                pr.error = float(np.linalg.norm(pr.kernel(t_h) - h) / norm_h)
                if best is None or pr.error < best.error:
                    best = pr
                if pr.error <= rtol:
                    best = pr
                    break
            if best is not None:
                best.error = best.error_fit = float(np.linalg.norm(best.kernel(t) - k_ij) / norm)
            if best is None:
                raise RuntimeError(f"no stable realisation found for pair ({dofs[i]}, {dofs[j]})")
            if best.error > rtol:
                log.debug("fit_state_space: pair (%s, %s) reached error %.3g > rtol %.3g at order %d",
                          dofs[i], dofs[j], best.error, rtol, best.order)
            pairs.append(best)
    missed = [p for p in pairs if p.error > rtol]
    if missed:
        worst = max(missed, key=lambda p: p.error)
        log.warning("fit_state_space: %d of %d pairs did not reach rtol %.3g by order %d (worst: (%s, %s), error "
                    "%.3g); the summary() of the fit lists them", len(missed), len(pairs), rtol, max_order,
                    dofs[worst.i], dofs[worst.j], worst.error)
    fit = StateSpaceFit(pairs, dofs, a_inf, t, dt_f, rtol, skipped)
    rep = fit.passivity()
    if not rep.passive and enforce_passivity:
        rep = _enforce_passivity(fit, w_low)
        for p in fit.pairs:
            p.error = float(np.linalg.norm(p.kernel(t) - Kv[p.j, p.i]) / np.linalg.norm(Kv[p.j, p.i]))
    fit.passivity_report = rep
    log.info("fit_state_space: %d pairs, %d states, max error %.3g, passivity margin %.3g",
             len(fit.pairs), sum(p.order for p in fit.pairs), max((p.error for p in fit.pairs), default=0.0),
             rep.margin)
    return fit
