"""Frequency-domain response (RAO) of one or several rigid bodies, with an optional constrained two-body PTO.

Equation of motion for x(t) = Re{X exp(-i w t)} (Capytaine's convention, as the excitation in the Dataset):

    [ -w^2 (M + A(w)) - i w (B(w) + B_extra) + C + K_extra ] X = F_exc(w, beta)

(with WAMIT's exp(+i w t) the damping term is +i w B; the two forms give conjugate X for conjugate F.)

Two bodies joined so that only their relative translation along an axis n is free (a float sliding on a spar),
with a linear PTO force F = -k_pto dz - c_pto dz' on body a and the opposite on body b (dz = n . (u_a - u_b)):
reduced coordinates q = (six DOFs of body b about its reference point, dz), x = T q with

    body b:  x_b = q_b
    body a:  u_a = u_b + theta_b x (r_a - r_b) + n dz,   theta_a = theta_b

(r_a, r_b the reference points), and T^H Z T q = T^H F with Z the 12 x 12 impedance including the PTO terms
(k_pto - i w c_pto) P, P = p p^T, p = (n, 0, -n, 0). The PTO does no work on the constrained motion, so adding it to
Z before the projection or as a term on dz afterwards is the same.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import xarray as xr

from .dataset import matrix, skew
from .excitation import excitation_transfer


def mass_matrix(m, cog, inertia, ref_point) -> np.ndarray:
    """Rigid-body mass matrix about a reference point (block diagonal for several bodies).

    Parameters
    ----------
    m : float or array (n_body,)
        Masses [kg].
    cog : array (3,) or (n_body, 3)
        Centres of gravity [m], global frame.
    inertia : array (3, 3) or (n_body, 3, 3)
        Inertia tensors about the centre of gravity [kg m^2]; (3,) for one body or (n_body, 3) for several give
        the diagonals.
    ref_point : array (3,) or (n_body, 3)
        Reference points the DOFs are about [m].

    Returns
    -------
    array (6 n_body, 6 n_body)
        M with generalised forces f = M a for accelerations a = (u'', theta'') at the reference point:
        [[m I, -m [r]x], [m [r]x, I_G - m [r]x [r]x]] with r = cog - ref_point.
    """
    m = np.atleast_1d(np.asarray(m, dtype=float))
    n = m.size
    cog = np.asarray(cog, dtype=float).reshape(n, 3)
    ref = np.broadcast_to(np.asarray(ref_point, dtype=float).reshape(-1, 3), (n, 3))
    inertia = np.asarray(inertia, dtype=float)
    if inertia.shape == (3,) and n == 1:
        inertia = np.diag(inertia)[None]
    elif inertia.shape == (n, 3) and n > 1:
        inertia = np.array([np.diag(v) for v in inertia])
    inertia = inertia.reshape(n, 3, 3)
    out = np.zeros((6 * n, 6 * n))
    for b in range(n):
        s = skew(cog[b] - ref[b])
        o = 6 * b
        out[o:o + 3, o:o + 3] = m[b] * np.eye(3)
        out[o:o + 3, o + 3:o + 6] = -m[b] * s
        out[o + 3:o + 6, o:o + 3] = m[b] * s
        out[o + 3:o + 6, o + 3:o + 6] = inertia[b] - m[b] * s @ s
    return out


@dataclass
class LinearPTO:
    """Linear PTO between two bodies along an axis, all other relative motions locked (prismatic joint).

    Attributes
    ----------
    body_a, body_b : int
        Body indices (body_a slides on body_b; the PTO force on a is -k dz - c dz').
    axis : array (3,)
        Joint axis (normalised internally).
    stiffness : float [N/m]
    damping : float [N s/m]
    """

    body_a: int = 0
    body_b: int = 1
    axis: tuple = (0.0, 0.0, 1.0)
    stiffness: float = 0.0
    damping: float = 0.0

    def vector(self, n_dof: int) -> np.ndarray:
        """p with dz = p . x, shape (n_dof,)."""
        nvec = np.asarray(self.axis, dtype=float)
        nvec = nvec / np.linalg.norm(nvec)
        p = np.zeros(n_dof)
        p[6 * self.body_a:6 * self.body_a + 3] = nvec
        p[6 * self.body_b:6 * self.body_b + 3] = -nvec
        return p

    def constraint_matrix(self, ref_points, n_dof: int) -> np.ndarray:
        """T (n_dof, 7) with x = T q, q = (body_b's six DOFs, dz) (module docstring)."""
        if n_dof != 12:
            raise ValueError("the constrained PTO solve handles two bodies (12 DOFs)")
        ref = np.asarray(ref_points, dtype=float).reshape(-1, 3)
        nvec = np.asarray(self.axis, dtype=float)
        nvec = nvec / np.linalg.norm(nvec)
        a, b = self.body_a, self.body_b
        T = np.zeros((n_dof, 7))
        T[6 * b:6 * b + 6, :6] = np.eye(6)
        # u_a = u_b + theta_b x (r_a - r_b) = u_b - (r_a - r_b) x theta_b
        T[6 * a:6 * a + 3, 0:3] = np.eye(3)
        T[6 * a:6 * a + 3, 3:6] = -skew(ref[a] - ref[b])
        T[6 * a + 3:6 * a + 6, 3:6] = np.eye(3)
        T[6 * a:6 * a + 3, 6] = nvec
        return T


def _interp_matrix(w, wd, M):
    flat = M.reshape(M.shape[0], -1)
    out = np.stack([np.interp(w, wd, flat[:, k]) for k in range(flat.shape[1])], axis=-1)
    return out.reshape((w.size,) + M.shape[1:])


def impedance(ds: xr.Dataset, mass, omega=None, *, damping=None, stiffness=None) -> tuple[np.ndarray, np.ndarray]:
    """Z(w) = -w^2 (M + A(w)) - i w (B(w) + B_extra) + C + K_extra, shape (n_w, n, n) [influenced, radiating].

    A and B are interpolated linearly in omega (inside the computed band only) when ``omega`` is given.
    Returns (omega, Z).
    """
    wd = ds["omega"].values
    A = matrix(ds["added_mass"])
    B = matrix(ds["radiation_damping"])
    if omega is None:
        w = wd
    else:
        w = np.atleast_1d(np.asarray(omega, dtype=float))
        if np.any(w < wd[0] * (1 - 1e-12)) or np.any(w > wd[-1] * (1 + 1e-12)):
            raise ValueError(f"omega outside the computed band [{wd[0]:.6g}, {wd[-1]:.6g}] rad/s: no extrapolation")
        A = _interp_matrix(w, wd, A)
        B = _interp_matrix(w, wd, B)
    n = A.shape[-1]
    C = ds["hydrostatic_stiffness"].transpose("influenced_dof", "radiating_dof").values
    Bx = np.zeros((n, n)) if damping is None else np.asarray(damping, dtype=float)
    Kx = np.zeros((n, n)) if stiffness is None else np.asarray(stiffness, dtype=float)
    M = np.asarray(mass, dtype=float)
    Z = (-w[:, None, None] ** 2 * (M[None] + A) - 1j * w[:, None, None] * (B + Bx[None]) + (C + Kx)[None])
    return w, Z


def rao(ds: xr.Dataset, mass_matrix, *, wave_direction: float, omega=None, damping=None, stiffness=None,
        pto: LinearPTO | None = None, constrained: bool = True) -> xr.Dataset:
    """Response amplitude operators in Capytaine's convention.

    Parameters
    ----------
    ds : xarray.Dataset
        Coefficient Dataset.
    mass_matrix : array (n_dof, n_dof)
        Rigid-body mass matrix about the Dataset's reference points (see :func:`mass_matrix`) [kg, kg m, kg m^2].
    wave_direction : float
        [rad].
    omega : array, optional
        Frequencies [rad/s] inside the band; default the Dataset's.
    damping, stiffness : arrays (n_dof, n_dof), optional
        Extra linear damping [N s/m ...] and stiffness (e.g. linearised mooring) [N/m ...], [influenced, radiating].
    pto : LinearPTO, optional
        Spring-damper between two bodies along an axis.
    constrained : bool
        With a PTO: lock every other relative DOF by reduced coordinates (module docstring); False adds only the
        spring-damper between the otherwise free bodies.

    Returns
    -------
    xarray.Dataset
        ``rao`` (omega, influenced_dof) complex [m/m, rad/m]: x(t) = Re{RAO a exp(-i w t)} for a wave of amplitude a
        at the origin; with a PTO also ``pto_displacement`` (omega) [m/m] and ``pto_power`` (omega) [W/m^2], the
        mean absorbed power 0.5 c w^2 |dz|^2 per unit amplitude squared.
    """
    w, Z = impedance(ds, mass_matrix, omega, damping=damping, stiffness=stiffness)
    F = excitation_transfer(ds, w, wave_direction)
    n = Z.shape[-1]
    X = np.zeros((w.size, n), dtype=complex)
    dz = None
    if pto is not None:
        p = pto.vector(n)
        Z = Z + (pto.stiffness - 1j * w[:, None, None] * pto.damping) * np.outer(p, p)[None]
    if pto is not None and constrained:
        T = pto.constraint_matrix(ds["rotation_center"].values, n)
        for k in range(w.size):
            q = np.linalg.solve(T.conj().T @ Z[k] @ T, T.conj().T @ F[k])
            X[k] = T @ q
    else:
        for k in range(w.size):
            X[k] = np.linalg.solve(Z[k], F[k])
    out = xr.Dataset({"rao": (("omega", "influenced_dof"), X)},
                     coords={"omega": w, "influenced_dof": ds["influenced_dof"].values,
                             "wave_direction": float(wave_direction)})
    out["rao"].attrs.update({"units": "m/m (translations), rad/m (rotations)", "convention": "Re{X exp(-i omega t)}"})
    if pto is not None:
        dz = X @ pto.vector(n)
        out["pto_displacement"] = ("omega", dz)
        out["pto_power"] = ("omega", 0.5 * pto.damping * w ** 2 * np.abs(dz) ** 2)
        out["pto_power"].attrs["units"] = "W per m^2 of wave amplitude"
    return out
