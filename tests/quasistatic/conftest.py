"""Shared decks and helpers of the quasi-static tests."""

from __future__ import annotations

import copy
import math
from pathlib import Path

import numpy as np
import pytest

from moorline.io import read_deck
from moorline.model import BodyKind, PointKind, angles_xyz, rotation_xyz

DATA = Path(__file__).parent / "data"
SHARED = Path(__file__).resolve().parents[3] / "shared"
CONFORMANCE = SHARED / "conformance" / "inputs"

#: the four systems of issue 15 (deck, water depth [m])
SYSTEMS = {
    "oc3_spar": (DATA / "oc3_spar.dat", 320.0),
    "oc3_bridle": (DATA / "oc3_bridle.dat", 320.0),
    "clump_line": (DATA / "clump_line.dat", 200.0),
    "buoyed_line": (DATA / "buoyed_line.dat", 200.0),
}

#: OC3-Hywind hydrostatics (Jonkman 2010, "Definition of the floating system for phase IV of OC3"):
#: displaced volume [m^3], centre of buoyancy depth [m], waterplane diameter [m]
OC3_VOLUME = 8029.21
OC3_ZB = -62.06
OC3_D_WP = 6.5


def oc3_hydrostatics():
    from moorline.quasistatic import BodyHydrostatics

    r = OC3_D_WP / 2
    return BodyHydrostatics(OC3_VOLUME, (0.0, 0.0, OC3_ZB), waterplane_area=math.pi * r ** 2,
                            waterplane_inertia=(math.pi * r ** 4 / 4, math.pi * r ** 4 / 4))


def deck(name):
    if name in SYSTEMS:
        return read_deck(SYSTEMS[name][0])
    path = CONFORMANCE / name
    if not path.exists():
        pytest.skip(f"{path} is not available (../shared)")
    return read_deck(path)


def rotate_model(model, phi):
    """The whole system turned by ``phi`` [rad] about the vertical axis through the origin."""
    m = copy.deepcopy(model)
    Rz = rotation_xyz((0.0, 0.0, phi))
    for pt in m.points:
        if pt.kind != PointKind.BODY:
            pt.r = Rz @ pt.r
    for b in m.bodies:
        b.r = Rz @ b.r
        b.angles = np.degrees(angles_xyz(Rz @ b.rotation))
    return m


def reverse_lines(model):
    """Every line defined from its other end."""
    m = copy.deepcopy(model)
    for ln in m.lines:
        ln.end_a, ln.end_b = ln.end_b, ln.end_a
    return m


def small_rotation_pose(x, k, w):
    """Pose vector x (6,) turned by a small rotation w [rad] about global axis k (R <- exp(S(w e_k)) R)."""
    e = np.zeros(3)
    e[k] = w
    th = abs(w)
    K = np.array([[0.0, -e[2], e[1]], [e[2], 0.0, -e[0]], [-e[1], e[0], 0.0]]) / th
    E = np.eye(3) + math.sin(th) * K + (1 - math.cos(th)) * K @ K
    out = np.array(x, dtype=float)
    out[3:6] = angles_xyz(E @ rotation_xyz(x[3:6]))
    return out


def coupled_bodies(model):
    return [i for i, b in enumerate(model.bodies) if b.kind == BodyKind.COUPLED]
