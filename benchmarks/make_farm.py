"""Write a farm-like MoorDyn v2 deck for the speed benchmark: many copies of a three-line chain
catenary, one per floating turbine, on a rectangular grid.

    python benchmarks/make_farm.py out/farm.dat [--turbines 20] [--segments 50] [--spacing 1500]

Every turbine has the OC3-Hywind mooring (the properties of
``examples/catenary_3line/catenary_3line.dat``'s source, ``conformance/inputs/catenary_3line``):
three 902.2 m studless chains of 0.09 m (77.7066 kg/m, EA 384.243 MN) in 320 m of water, anchors on
an 853.87 m radius, fairleads on a 5.2 m radius 70 m below the surface, legs at 0, 120 and 240
degrees. Anchors are Fixed points, fairleads Coupled points. The turbines sit on a grid of
``spacing`` metres, as close to square as the count allows (20 turbines: 5 x 4). With the defaults
(20 turbines, 50 segments per line) the deck has 60 lines and 3060 line nodes.

Point numbering: turbine k (0-based) owns points 6k+1..6k+3 (its anchors) and 6k+4..6k+6 (its
fairleads), and lines 3k+1..3k+3 (anchor 6k+i to fairlead 6k+3+i). The coupled DOFs are therefore
the fairleads turbine by turbine, legs in order.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

#: OC3-Hywind mooring (Jonkman 2010), as in conformance/inputs/catenary_3line/lines.txt
DEPTH = 320.0
ANCHOR_RADIUS = 853.87
FAIRLEAD_RADIUS = 5.2
FAIRLEAD_Z = -70.0
LENGTH = 902.2
LEG_ANGLES = (0.0, 120.0, 240.0)

_HEADER = """\
moorline benchmark deck (written by benchmarks/make_farm.py): {n} floating turbines on a {cols} x {rows}
grid, {spacing:g} m apart, each moored by the OC3-Hywind three-line chain catenary (0.09 m chain, 902.2 m
per line, {segs} segments per line) in 320 m of water. {n_lines} lines, {nodes} line nodes. Anchors are
Fixed points, fairleads Coupled points (turbine k: points 6k+1..6k+3 anchors, 6k+4..6k+6 fairleads).
---------------------- LINE TYPES ------------------------------------------------------------------
TypeName   Diam    Mass/m     EA         BA/-zeta   EI    Cd     Ca     CdAx   CaAx
(-)        (m)     (kg/m)     (N)        (N-s/-)    (N-m^2) (-)  (-)    (-)    (-)
chain      0.09    77.7066    384.243e6  -0.8       0     1.6    1.0    0.1    0.0
---------------------- POINTS ----------------------------------------------------------------------
ID    Attachment  X           Y           Z          Mass   Volume   CdA    Ca
(-)   (-)         (m)         (m)         (m)        (kg)   (m^3)    (m^2)  (-)
"""

_LINES_HEADER = """\
---------------------- LINES -----------------------------------------------------------------------
ID    LineType  AttachA  AttachB  UnstrLen  NumSegs  Outputs
(-)   (-)       (-)      (-)      (m)       (-)      (-)
"""

_OPTIONS = """\
---------------------- OPTIONS ---------------------------------------------------------------------
0          writeLog   no log file
RK2        tScheme    time integration scheme
0.002      dtM        internal time step (s)
320.0      WtrDpth    water depth (m)
1025.0     rho        water density (kg/m^3)
3.0e6      kBot       seabed contact stiffness (Pa/m)
3.0e5      cBot       seabed contact damping (Pa-s/m)
1.0        dtIC       IC convergence check interval (s)
100.0      TmaxIC     IC pseudo-time limit (s)
4.0        CdScaleIC  drag scaling for the dynamic-relaxation IC (-)
0.001      threshIC   IC convergence threshold (-)
---------------------- OUTPUTS ---------------------------------------------------------------------
FairTen1 FairTen2 FairTen3
---------------------------------------------------------------------------------------------------
"""


def grid_shape(n_turbines: int) -> tuple[int, int]:
    """Columns and rows of the most nearly square grid holding ``n_turbines``."""
    cols = math.ceil(math.sqrt(n_turbines))
    rows = math.ceil(n_turbines / cols)
    return cols, rows


def farm_text(n_turbines: int = 20, n_segs: int = 50, spacing: float = 1500.0) -> str:
    """The deck text of a farm of ``n_turbines`` three-line catenary moorings.

    Parameters
    ----------
    n_turbines : int
        Number of turbines (at least 1).
    n_segs : int
        Segments per line (at least 1).
    spacing : float
        Distance between neighbouring turbines [m].

    Returns
    -------
    str
    """
    if n_turbines < 1 or n_segs < 1:
        raise ValueError("n_turbines and n_segs must be at least 1")
    cols, rows = grid_shape(n_turbines)
    points, lines = [], []
    for k in range(n_turbines):
        cx, cy = (k % cols) * spacing, (k // cols) * spacing
        for kind, radius, z in (("Fixed", ANCHOR_RADIUS, -DEPTH), ("Coupled", FAIRLEAD_RADIUS, FAIRLEAD_Z)):
            for a in LEG_ANGLES:
                c, s = math.cos(math.radians(a)), math.sin(math.radians(a))
                points.append(f"{len(points) + 1:<5d} {kind:<10s}  {cx + radius * c:<10.3f}  {cy + radius * s:<10.3f}  "
                              f"{z:<9.1f}  0      0        0      0")
        for i in range(3):
            lines.append(f"{len(lines) + 1:<5d} chain     {6 * k + 1 + i:<8d} {6 * k + 4 + i:<8d} {LENGTH:<9.1f} "
                         f"{n_segs:<8d} -")
    head = _HEADER.format(n=n_turbines, cols=cols, rows=rows, spacing=spacing, segs=n_segs, n_lines=3 * n_turbines,
                          nodes=3 * n_turbines * (n_segs + 1))
    return head + "\n".join(points) + "\n" + _LINES_HEADER + "\n".join(lines) + "\n" + _OPTIONS


def write_farm(path, n_turbines: int = 20, n_segs: int = 50, spacing: float = 1500.0) -> Path:
    """Write the farm deck of :func:`farm_text` to ``path`` (overwritten) and return the path."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(farm_text(n_turbines, n_segs, spacing))
    return path


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("path", help="deck file to write")
    ap.add_argument("--turbines", type=int, default=20)
    ap.add_argument("--segments", type=int, default=50, help="segments per line")
    ap.add_argument("--spacing", type=float, default=1500.0, help="turbine spacing [m]")
    a = ap.parse_args(argv)
    p = write_farm(a.path, a.turbines, a.segments, a.spacing)
    print(f"wrote {p}: {a.turbines} turbines, {3 * a.turbines} lines, {3 * a.turbines * (a.segments + 1)} line nodes")
    return 0


if __name__ == "__main__":
    sys.exit(main())
