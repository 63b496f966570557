"""Hydrostatics of a floating body for the quasi-static equilibrium: :class:`BodyHydrostatics`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

__all__ = ["BodyHydrostatics"]


@dataclass
class BodyHydrostatics:
    """Buoyancy of one body about its reference point, at a reference pose.

    The quasi-static model applies to the body (all loads about its reference point, global axes):

    * the buoyancy ``rho g displaced_volume`` upwards at the centre of buoyancy, which rotates with
      the body (so the ``rho g V z_B`` part of the roll and pitch stiffness and the moments of an
      off-axis centre of buoyancy are exact for large rotations);
    * a linear waterplane restoring ``-C_wp (q - reference_pose)``, ``q = (x, y, z, roll, pitch, yaw)``
      (Euler angles, ``R = Rx Ry Rz``), with ``C_wp`` chosen so that at the reference pose the total
      buoyancy stiffness equals ``hydrostatic_stiffness``: ``C_wp = hydrostatic_stiffness - K_B``,
      ``K_B`` the stiffness of the rotating buoyancy force alone. Without ``hydrostatic_stiffness``,
      ``C_wp`` is built from the waterplane: ``C33 = rho g A_wp``, ``C44 = rho g I_xx``,
      ``C55 = rho g I_yy``.

    The body's weight (deck mass ``m`` at its centre of gravity, BODIES row) is applied separately and
    rotates with the body, so ``hydrostatic_stiffness`` must be **buoyancy only**: without the
    ``-m g z_G`` terms of the weight.

    Parameters
    ----------
    displaced_volume : float
        Displaced volume at the reference pose [m^3].
    center_of_buoyancy : array_like, shape (3,)
        Centre of buoyancy relative to the reference point, body axes [m].
    hydrostatic_stiffness : array_like, shape (6, 6), optional
        Buoyancy-only hydrostatic stiffness about the reference point at the reference pose [N/m,
        N/rad, N m/m, N m/rad], DOF order surge, sway, heave, roll, pitch, yaw (WAMIT/Capytaine order).
    waterplane_area : float, optional
        Waterplane area ``A_wp`` [m^2] (used when ``hydrostatic_stiffness`` is not given).
    waterplane_inertia : array_like, shape (2,), optional
        Second moments of the waterplane area ``(I_xx, I_yy)`` = (integral of y^2, of x^2) about the
        body's x and y axes through the reference point [m^4].
    reference_pose : array_like, shape (6,), optional
        Pose ``(x, y, z, roll, pitch, yaw)`` [m, rad] at which the volume, centre of buoyancy and
        stiffness hold; default: the body's deck pose.
    """

    displaced_volume: float
    center_of_buoyancy: np.ndarray = field(default_factory=lambda: np.zeros(3))
    hydrostatic_stiffness: np.ndarray | None = None
    waterplane_area: float = 0.0
    waterplane_inertia: np.ndarray = field(default_factory=lambda: np.zeros(2))
    reference_pose: np.ndarray | None = None

    def __post_init__(self):
        self.displaced_volume = float(self.displaced_volume)
        if not self.displaced_volume >= 0.0:
            raise ValueError(f"displaced_volume must be >= 0, got {self.displaced_volume}")
        self.center_of_buoyancy = _array(self.center_of_buoyancy, (3,), "center_of_buoyancy")
        if self.hydrostatic_stiffness is not None:
            self.hydrostatic_stiffness = _array(self.hydrostatic_stiffness, (6, 6), "hydrostatic_stiffness")
        self.waterplane_area = float(self.waterplane_area)
        self.waterplane_inertia = _array(self.waterplane_inertia, (2,), "waterplane_inertia")
        if self.reference_pose is not None:
            self.reference_pose = _array(self.reference_pose, (6,), "reference_pose")

    def buoyancy_stiffness(self, rho: float, g: float, R=None) -> np.ndarray:
        """Stiffness ``-dF/dq`` of the rotating buoyancy force alone at rotation ``R`` (default
        identity), shape (6, 6); nonzero only in the rotation block: ``(f.rho) I - rho f^T``."""
        R = np.eye(3) if R is None else np.asarray(R, dtype=float)
        arm = R @ self.center_of_buoyancy
        f = np.array([0.0, 0.0, rho * g * self.displaced_volume])
        K = np.zeros((6, 6))
        K[3:, 3:] = float(f @ arm) * np.eye(3) - np.outer(arm, f)
        return K

    def waterplane_stiffness(self, rho: float, g: float, R=None) -> np.ndarray:
        """The linear part ``C_wp`` (6, 6) [N/m, N/rad, N m/m, N m/rad] (see the class docstring)."""
        if self.hydrostatic_stiffness is not None:
            return self.hydrostatic_stiffness - self.buoyancy_stiffness(rho, g, R)
        C = np.zeros((6, 6))
        C[2, 2] = rho * g * self.waterplane_area
        C[3, 3] = rho * g * self.waterplane_inertia[0]
        C[4, 4] = rho * g * self.waterplane_inertia[1]
        return C

    def total_stiffness(self, rho: float, g: float) -> np.ndarray:
        """Buoyancy-only hydrostatic stiffness at the reference pose, shape (6, 6) (equal to
        ``hydrostatic_stiffness`` when it was given)."""
        if self.hydrostatic_stiffness is not None:
            return self.hydrostatic_stiffness.copy()
        return self.waterplane_stiffness(rho, g) + self.buoyancy_stiffness(rho, g)


def _array(v, shape, name) -> np.ndarray:
    a = np.asarray(v, dtype=float)
    if a.shape != shape:
        raise ValueError(f"{name}: expected shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: values must be finite")
    return a.copy()
