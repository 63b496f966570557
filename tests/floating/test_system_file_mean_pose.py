"""The system file's ``mean_poses``: a deck body placed off the pose its hydrostatics are linearised
about (WEC-Sim's "initial displacement": the RM3 MoorDyn deck puts the spar 0.21 m below its WAMIT
pose) keeps the hydrostatic restoring of that offset. Without the key the deck pose is the mean pose,
so the body starts in equilibrium where it was put, whatever its draft."""

from __future__ import annotations

import numpy as np
import pytest

import moorline
from moorline import hydro
from moorline.errors import DeckError
from moorline.io.system_file import read_system_file

from .conftest import C33, MASS, three_pole_dataset

DECK = """moorline test: one coupled body, no lines
---------------------- BODIES ---------------------------------------------------------------------
ID  Attachment  X0   Y0   Z0    r0   p0   y0   Mass  CG   I     Volume  CdA  Ca
(#) (-)         (m)  (m)  (m)   (deg)(deg)(deg)(kg)  (m)  (kg-m^2) (m^3) (m^2) (-)
1   Coupled     0    0    -0.5  0    0    0    0     0    0     0       0    0
---------------------- OPTIONS --------------------------------------------------------------------
RK4        tScheme
0.01       dtM
200.0      WtrDpth
1025.0     rho
9.80665    g
---------------------- OUTPUTS --------------------------------------------------------------------
---------------------------------------------------------------------------------------------------
"""


def _files(tmp_path, extra=""):
    (tmp_path / "deck.dat").write_text(DECK)
    hydro.write_netcdf(three_pole_dataset(), tmp_path / "coeffs.nc")
    (tmp_path / "system.yaml").write_text(
        "deck: deck.dat\n"
        f"bodies:\n  - {{body: 1, mass: {MASS}, inertia: [1.0e6, 1.0e6, 1.0e6]}}\n"
        "hydrodynamics:\n  - bodies: [1]\n    capytaine: coeffs.nc\n" + extra)
    return tmp_path / "system.yaml"


def test_mean_pose_is_read_in_metres_and_degrees(tmp_path):
    sf = read_system_file(_files(tmp_path, "    mean_poses: [[0, 0, 0, 0, 2.0, 0]]\n"))
    assert np.allclose(sf.model.hydro[0].mean_poses, [[0.0, 0.0, 0.0, 0.0, np.radians(2.0), 0.0]])


def test_a_body_off_its_mean_pose_returns_to_it(tmp_path):
    """The body is put 0.5 m below the pose its coefficients hold (buoyancy = weight there): with
    mean_poses it rises back to z = 0 under C33; without, the deck pose is the mean pose and it stays."""
    with_pose = read_system_file(_files(tmp_path, "    mean_poses: [[0, 0, 0, 0, 0, 0]]\n")).model
    s = moorline.System(with_pose)
    s.init()
    assert s.bodies[0].pose()[2] == pytest.approx(0.0, abs=1e-6)
    without = read_system_file(_files(tmp_path)).model
    s = moorline.System(without)
    s.init()
    assert s.bodies[0].pose()[2] == pytest.approx(-0.5, abs=1e-6)
    # the restoring force of the 0.5 m offset is what tells them apart
    assert C33 * 0.5 > 0.1 * MASS * 9.80665


def test_mean_poses_needs_one_pose_per_body(tmp_path):
    with pytest.raises(DeckError, match="mean_poses"):
        read_system_file(_files(tmp_path, "    mean_poses: [[0, 0, 0, 0, 0, 0], [0, 0, 0, 0, 0, 0]]\n"))
