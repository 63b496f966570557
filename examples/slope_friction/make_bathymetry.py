"""Write slope_bathymetry.txt: the seabed of slope_chain.dat as a MoorDyn-C SeafloorFile grid.

A coastal slope: the seabed rises from about 62 m depth offshore (-x, the anchor side) to about
36 m inshore (+x, under the floater), steepest (about 4 degrees) around x = -150 m, with a uniform
cross-slope of 3 % rising toward +y, so the mooring leg (laid along the x axis) also lies across
the slope:

    z(x, y) = -48 + 14 tanh((x + 150) / 200) + 0.03 y        [m, negative below the surface]

The grid samples it every 25 m in x (-500 ... 100 m) and every 50 m in y (-150 ... 150 m);
moorline interpolates bilinearly between the nodes, which is exact in y (the surface is linear
there) and within 0.03 m of the formula in x. Heights are written with 3 decimals so that the
anchor's z in the deck (on the grid tick x = -400, y = 0) is exactly the grid value.

File layout (MoorDyn-C ``SeafloorFile``): ``nx ny``, the x ticks, the y ticks, then one
``x y z`` row per grid node with z the seabed *height*.
"""

from pathlib import Path

import numpy as np

X = np.arange(-500.0, 100.0 + 1.0, 25.0)
Y = np.arange(-150.0, 150.0 + 1.0, 50.0)


OUT = Path(__file__).with_name("slope_bathymetry.txt")


def seabed_height(x, y):
    """The seabed height [m] of the formula above (not rounded)."""
    return -48.0 + 14.0 * np.tanh((np.asarray(x) + 150.0) / 200.0) + 0.03 * np.asarray(y)


def main(path=OUT):
    rows = [f"{X.size} {Y.size}",
            " ".join(f"{v:g}" for v in X),
            " ".join(f"{v:g}" for v in Y)]
    for y in Y:
        for x in X:
            rows.append(f"{x:g} {y:g} {seabed_height(x, y):.3f}")
    Path(path).write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path


if __name__ == "__main__":
    p = main()
    print(p)
    print(f"anchor (x = -400, y = 0): z = {seabed_height(-400.0, 0.0):.3f} m; "
          f"under the fairlead (x = 0, y = 0): z = {seabed_height(0.0, 0.0):.3f} m")
