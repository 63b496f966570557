"""Stress at points around a thick-walled tubular cross-section.

For a tube of outer diameter do and inner diameter di::

    A = pi/4 (do^2 - di^2),   I = pi/64 (do^4 - di^4)
    sigma(theta) = N/A + (My (do/2) sin(theta) - Mz (do/2) cos(theta)) / I

at the point of the outer surface at angle theta from the section axis y toward z (see
:mod:`moorline.post.sections` for the frame), tensile positive. N is the effective tension.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import xarray as xr

__all__ = ["TubeSection", "cross_section_stress", "theta_points"]


@dataclass(frozen=True)
class TubeSection:
    """A thick-walled tube (a solid bar when ``di = 0``).

    Parameters
    ----------
    do : float
        Outer diameter [m].
    di : float
        Inner diameter [m], 0 <= di < do.
    """

    do: float
    di: float = 0.0

    def __post_init__(self):
        if not self.do > 0 or not 0 <= self.di < self.do:
            raise ValueError(f"need do > 0 and 0 <= di < do, got do = {self.do}, di = {self.di}")

    @property
    def A(self) -> float:
        """Area pi/4 (do^2 - di^2) [m^2]."""
        return math.pi / 4.0 * (self.do**2 - self.di**2)

    @property
    def I(self) -> float:  # noqa: E743  (the field's symbol)
        """Second moment of area about a diameter, pi/64 (do^4 - di^4) [m^4]."""
        return math.pi / 64.0 * (self.do**4 - self.di**4)

    @property
    def c(self) -> float:
        """Distance of the outer fibre from the centre, do/2 [m]."""
        return 0.5 * self.do

    def stress(self, N, My, Mz, theta):
        """sigma = N/A + (My c sin(theta) - Mz c cos(theta)) / I [Pa].

        Parameters
        ----------
        N : array_like
            Effective tension [N].
        My, Mz : array_like
            Bending moments about the section axes y and z [N m].
        theta : array_like
            Angle of the point from y toward z [rad]; broadcast against N, My, Mz.
        """
        N, My, Mz, theta = (v if isinstance(v, xr.DataArray) else np.asarray(v, dtype=float)
                            for v in (N, My, Mz, theta))
        return N / self.A + (My * self.c * np.sin(theta) - Mz * self.c * np.cos(theta)) / self.I


def theta_points(n_theta: int = 12) -> np.ndarray:
    """``n_theta`` angles equally spaced around the section, starting at 0 [deg]."""
    if n_theta < 1:
        raise ValueError(f"n_theta must be >= 1, got {n_theta}")
    return np.arange(n_theta) * 360.0 / n_theta


def cross_section_stress(sections: xr.Dataset, section: TubeSection, *, n_theta: int = 12, theta=None,
                         tensile_only: bool = False) -> xr.DataArray:
    """Axial stress at points around the outer surface, per time and node.

    Parameters
    ----------
    sections : xarray.Dataset
        From :func:`moorline.post.section_loads` (``tension``, ``My``, ``Mz``).
    section : TubeSection
    n_theta : int
        Number of points, 360/n_theta degrees apart starting at theta = 0 (default 12: 30 deg).
    theta : array_like, optional
        The angles [deg] instead.
    tensile_only : bool
        Set compressive stresses to zero (before cycle counting: only the tensile part of the
        history then counts, as in the study of copper conductors).

    Returns
    -------
    xarray.DataArray
        ``stress`` [Pa], dimensions (time, node, theta); the coordinate ``theta`` is in degrees.
    """
    th = theta_points(n_theta) if theta is None else np.atleast_1d(np.asarray(theta, dtype=float))
    rad = xr.DataArray(np.deg2rad(th), dims="theta", coords={"theta": th})
    s = section.stress(sections.tension, sections.My, sections.Mz, rad)
    if tensile_only:
        s = s.clip(min=0.0)
    s = s.transpose("time", "node", "theta")
    s.name = "stress"
    s.coords["theta"].attrs.update(units="deg", long_name="angle from section axis y toward z")
    s.attrs.update(units="Pa", long_name="axial stress" + (" (compression set to zero)" if tensile_only else ""),
                   do=section.do, di=section.di, tensile_only=int(tensile_only))
    return s
