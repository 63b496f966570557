"""Seabed bathymetry grid files (spec sections 1.11.2 and 3.8).

Two layouts are read, both into a :class:`moorline.model.types.Bathymetry` whose ``z[j, i]`` is
the seabed *height* at ``(x[i], y[j])`` (negative below the still-water level):

* :func:`read_seafloor_grid` -- the MoorDyn-C ``SeafloorFile`` layout::

      nx ny
      x_1 ... x_nx            (ascending)
      y_1 ... y_ny            (ascending)
      x y z                   (nx*ny rows, any order; z is the seabed height, e.g. -40.0)

* :func:`read_depth_grid` -- the MoorDyn-F layout, named by a non-numeric ``WtrDpth``::

      any title line
      nGridX <nx>
      nGridY <ny>
              x_1  ...  x_nx
      y_1     D_11 ...  D_1nx    (positive depths: the seabed is at z = -D)
      ...

:func:`find_seafloor_file` resolves the name given to ``SeafloorFile``.

Deliberate differences from MoorDyn-C, all of which turn a silent surprise into a located
:class:`~moorline.errors.DeckError`:

* a node row whose x or y is not one of the grid ticks is an error (MoorDyn places it by an
  insertion search into a neighbouring cell);
* a grid node listed twice is an error (MoorDyn keeps the last row);
* a grid node never listed is an error (MoorDyn leaves it at z = 0, i.e. puts the seabed at the
  still-water surface there).

Tokens are separated by whitespace (spaces or tabs); blank lines and everything after a ``#`` are
ignored (in the F layout the title line is taken verbatim).
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from ..errors import DeckError
from ..model.types import Bathymetry

log = logging.getLogger("moorline.io")

__all__ = ["find_seafloor_file", "read_depth_grid", "read_seafloor_grid"]

#: relative tolerance (times the grid extent) within which a node row's x, y must equal a tick
TICK_RTOL = 1e-9

_Row = tuple[int, str, list[str]]  # (1-based line number, raw text, tokens)


# ------------------------------------------------------------------------------------ helpers
def _read_lines(path: Path, what: str) -> list[str]:
    """The file's lines (any line-break convention), or a DeckError if it cannot be read."""
    try:
        text = path.read_text(encoding="utf-8", errors="replace")
    except OSError as e:
        raise DeckError(f"cannot read {what}: {e.strerror or e}", file=path) from None
    return text.splitlines()


def _data_rows(lines: list[str], start: int = 0) -> list[_Row]:
    """Non-blank rows from ``lines[start:]`` with ``#`` comments removed."""
    rows = []
    for k in range(start, len(lines)):
        raw = lines[k]
        tokens = raw.split("#", 1)[0].split()
        if tokens:
            rows.append((k + 1, raw, tokens))
    return rows


def _float_or_nan(tok: str) -> float:
    try:
        return float(tok)
    except ValueError:
        return math.nan


def _number(tok: str, row: _Row, path: Path, what: str) -> float:
    """A finite float from a token, or a located DeckError naming what was expected."""
    v = _float_or_nan(tok)
    if not math.isfinite(v):
        raise DeckError(f"{what}: expected a finite number, got {tok!r}", file=path, line=row[0], row=row[1],
                        field=what)
    return v


def _whole(tok: str, row: _Row, path: Path, what: str) -> int:
    """A whole number >= 1 from a token (``5`` or ``5.0``), or a located DeckError."""
    v = _float_or_nan(tok)
    if not (math.isfinite(v) and v.is_integer() and v >= 1):
        raise DeckError(f"{what}: expected a whole number >= 1, got {tok!r}", file=path, line=row[0], row=row[1],
                        field=what)
    return int(v)


def _ticks(row: _Row, tokens: list[str], n: int, path: Path, axis: str, declared: str) -> np.ndarray:
    """Exactly ``n`` strictly ascending grid coordinates from ``tokens``."""
    if len(tokens) != n:
        raise DeckError(f"expected exactly {n} {axis} values ({declared}), got {len(tokens)}", file=path,
                        line=row[0], row=row[1], field=axis)
    v = np.array([_number(t, row, path, f"{axis} value") for t in tokens])
    bad = np.nonzero(np.diff(v) <= 0)[0]
    if bad.size:
        k = int(bad[0])
        raise DeckError(f"{axis} values must be strictly ascending: value {k + 2} ({tokens[k + 1]}) does not "
                        f"exceed value {k + 1} ({tokens[k]})", file=path, line=row[0], row=row[1], field=axis)
    return v


def _end_of_file(path: Path, lines: list[str], expected: str) -> DeckError:
    """DeckError for a file that ends before ``expected``."""
    return DeckError(f"file ends before {expected}", file=path, line=len(lines),
                     row=lines[-1] if lines else None)


def _warn_above_surface(z: np.ndarray, path: Path, hint: str) -> None:
    n = int(np.count_nonzero(z >= 0.0))
    if n:
        log.warning("%s: %d of %d seabed grid heights are at or above the still-water level (z >= 0)%s",
                    path, n, z.size, hint)


# --------------------------------------------------------------------------- MoorDyn-C layout
def _match_tick(value: float, ticks: np.ndarray, tol: float) -> int | None:
    """Index of the tick within ``tol`` of ``value`` (the nearest one), or None."""
    k = int(np.searchsorted(ticks, value))
    best = None
    for c in (k - 1, k):
        if 0 <= c < ticks.size and abs(ticks[c] - value) <= tol and (
                best is None or abs(ticks[c] - value) < abs(ticks[best] - value)):
            best = c
    return best


def _tick_tolerance(x: np.ndarray, y: np.ndarray) -> float:
    """TICK_RTOL times the grid extent (times the coordinate scale, or 1 m, for a 1x1 grid)."""
    extent = max(x[-1] - x[0], y[-1] - y[0])
    if extent <= 0.0:
        extent = max(1.0, float(np.max(np.abs(x))), float(np.max(np.abs(y))))
    return TICK_RTOL * extent


def _ticks_text(ticks: np.ndarray, limit: int = 6) -> str:
    vals = [f"{v:g}" for v in ticks]
    if len(vals) > limit:
        vals = vals[: limit // 2] + ["..."] + vals[-(limit // 2):]
    return ", ".join(vals)


def read_seafloor_grid(path) -> Bathymetry:
    """Read a MoorDyn-C ``SeafloorFile`` bathymetry grid (spec 1.11.2).

    The first data line holds ``nx ny`` (whole numbers >= 1), the next exactly nx ascending x
    ticks, the next exactly ny ascending y ticks, then exactly nx*ny rows ``x y z`` in any order,
    where z is the seabed height (negative below the still-water level). Each row is placed at the
    grid node whose ticks equal its x and y within 1e-9 times the grid extent. Blank lines and
    ``#`` comments are ignored; tokens are separated by spaces or tabs.

    A single tick along a direction means the seabed is constant along it (1x1, 1xN and Nx1
    grids are allowed; a 1x1 grid is a flat seabed).

    Parameters
    ----------
    path : str or Path
        The grid file.

    Returns
    -------
    Bathymetry
        ``z`` of shape (ny, nx), ``source`` set to ``str(path)``.

    Raises
    ------
    DeckError
        Naming the file, the 1-based line, the row and what was expected, for: a bad header,
        a wrong number of ticks, ticks not strictly ascending, a node row without exactly three
        numbers, a bad number, a row whose x or y is not a grid tick, a node listed twice, or a
        node never listed (MoorDyn-C would leave it at z = 0, i.e. put the seabed at the surface;
        moorline refuses).
    """
    path = Path(path)
    lines = _read_lines(path, "seafloor grid file")
    rows = _data_rows(lines)
    if not rows:
        raise DeckError("empty seafloor grid file: expected a first line 'nx ny'", file=path, line=len(lines) or None)

    head = rows[0]
    if len(head[2]) != 2:
        raise DeckError(f"expected the grid size 'nx ny' (two whole numbers), got {len(head[2])} value(s)",
                        file=path, line=head[0], row=head[1], field="nx ny")
    nx = _whole(head[2][0], head, path, "nx")
    ny = _whole(head[2][1], head, path, "ny")

    if len(rows) < 2:
        raise _end_of_file(path, lines, f"the line of {nx} x values")
    x = _ticks(rows[1], rows[1][2], nx, path, "x", f"nx = {nx} on line {head[0]}")
    if len(rows) < 3:
        raise _end_of_file(path, lines, f"the line of {ny} y values")
    x_line = rows[1][0]
    y = _ticks(rows[2], rows[2][2], ny, path, "y", f"ny = {ny} on line {head[0]}")
    y_line = rows[2][0]
    tol = _tick_tolerance(x, y)

    z = np.zeros((ny, nx))
    where = np.zeros((ny, nx), dtype=int)  # line number that set each node, 0 = not yet
    for row in rows[3:]:
        lineno, raw, tokens = row
        if len(tokens) != 3:
            raise DeckError(f"expected a grid node row 'x y z' (3 numbers), got {len(tokens)} value(s)",
                            file=path, line=lineno, row=raw, field="x y z")
        xv = _number(tokens[0], row, path, "x")
        yv = _number(tokens[1], row, path, "y")
        zv = _number(tokens[2], row, path, "z")
        i = _match_tick(xv, x, tol)
        if i is None:
            raise DeckError(f"x = {tokens[0]} is not one of the {nx} x ticks of line {x_line} ({_ticks_text(x)}); "
                            "every node row must lie on a grid tick", file=path, line=lineno, row=raw, field="x")
        j = _match_tick(yv, y, tol)
        if j is None:
            raise DeckError(f"y = {tokens[1]} is not one of the {ny} y ticks of line {y_line} ({_ticks_text(y)}); "
                            "every node row must lie on a grid tick", file=path, line=lineno, row=raw, field="y")
        if where[j, i]:
            raise DeckError(f"grid node (x = {x[i]:g}, y = {y[j]:g}) is listed twice (first on line {where[j, i]}); "
                            "expected each of the nx*ny nodes exactly once", file=path, line=lineno, row=raw,
                            field="x y")
        where[j, i] = lineno
        z[j, i] = zv

    missing = np.argwhere(where == 0)
    if missing.size:
        found = nx * ny - len(missing)
        names = "; ".join(f"(x = {x[i]:g}, y = {y[j]:g})" for j, i in missing[:5])
        more = f" and {len(missing) - 5} more" if len(missing) > 5 else ""
        last = rows[-1]
        raise DeckError(f"expected nx*ny = {nx * ny} node rows (nx = {nx}, ny = {ny} on line {head[0]}), "
                        f"found {found}; "
                        f"grid node(s) never listed: {names}{more}. MoorDyn-C silently leaves unlisted nodes at "
                        "z = 0; moorline refuses because that would put the seabed at the still-water surface",
                        file=path, line=last[0], row=last[1], field="x y z")

    _warn_above_surface(z, path, "; the third column is the seabed z (negative below the surface), not a depth")
    log.debug("%s: seafloor grid %d x %d, z in [%g, %g]", path, nx, ny, z.min(), z.max())
    return Bathymetry(x=x, y=y, z=z, source=str(path))


# --------------------------------------------------------------------------- MoorDyn-F layout
def _grid_count(rows: list[_Row], k: int, key: str, path: Path, lines: list[str]) -> int:
    """The value of the ``key <n>`` line at ``rows[k]``."""
    if k >= len(rows):
        raise _end_of_file(path, lines, f"the '{key} <n>' line")
    row = rows[k]
    tokens = row[2]
    if tokens[0].lower() != key.lower():
        raise DeckError(f"expected '{key} <n>' (the number of grid {key[-1].lower()} values), got {tokens[0]!r}",
                        file=path, line=row[0], row=row[1], field=key)
    if len(tokens) < 2:
        raise DeckError(f"expected '{key} <n>': the value is missing", file=path, line=row[0], row=row[1],
                        field=key)
    return _whole(tokens[1], row, path, key)


def read_depth_grid(path) -> Bathymetry:
    """Read a MoorDyn-F bathymetry file (the value of ``WtrDpth`` when it is a file name).

    Layout: line 1 is a free title; then ``nGridX <nx>`` and ``nGridY <ny>`` (key words
    case-insensitive, value a whole number >= 1, anything after the value is ignored); then a row
    of nx strictly ascending x values; then exactly ny rows ``y D_1 ... D_nx`` with strictly
    ascending y and positive depths D (the seabed is at z = -D). Blank lines and ``#`` comments
    after the title are ignored.

    Parameters
    ----------
    path : str or Path
        The bathymetry file.

    Returns
    -------
    Bathymetry
        ``z = -D`` of shape (ny, nx), ``source`` set to ``str(path)``.

    Raises
    ------
    DeckError
        Naming the file, the 1-based line, the row and what was expected, for: a missing or
        misspelt ``nGridX``/``nGridY`` line, a bad count, a wrong number of x values, x or y not
        strictly ascending, a depth row without exactly nx + 1 numbers, a bad number, or a wrong
        number of depth rows.
    """
    path = Path(path)
    lines = _read_lines(path, "bathymetry file")
    if not lines:
        raise DeckError("empty bathymetry file: expected a title line, then 'nGridX <nx>'", file=path)
    rows = _data_rows(lines, start=1)  # line 1 is the title, taken verbatim
    nx = _grid_count(rows, 0, "nGridX", path, lines)
    ny = _grid_count(rows, 1, "nGridY", path, lines)
    nx_line, ny_line = rows[0][0], rows[1][0]

    if len(rows) < 3:
        raise _end_of_file(path, lines, f"the row of {nx} x values")
    x = _ticks(rows[2], rows[2][2], nx, path, "x", f"nGridX = {nx} on line {nx_line}")

    depth_rows = rows[3:]
    D = np.zeros((ny, nx))
    y = np.zeros(ny)
    for j, row in enumerate(depth_rows):
        lineno, raw, tokens = row
        if j >= ny:
            raise DeckError(f"expected exactly {ny} depth rows (nGridY = {ny} on line {ny_line}); this is row "
                            f"{j + 1}", file=path, line=lineno, row=raw, field="y D")
        if len(tokens) != nx + 1:
            raise DeckError(f"expected a depth row 'y D_1 ... D_{nx}' ({nx + 1} numbers: y then nGridX = {nx} "
                            f"depths), got {len(tokens)} value(s)", file=path, line=lineno, row=raw, field="y D")
        y[j] = _number(tokens[0], row, path, "y")
        D[j] = [_number(t, row, path, "depth") for t in tokens[1:]]
        if j > 0 and y[j] <= y[j - 1]:
            raise DeckError(f"y values must be strictly ascending: {tokens[0]} does not exceed {y[j - 1]:g} of "
                            f"line {depth_rows[j - 1][0]}", file=path, line=lineno, row=raw, field="y")
    if len(depth_rows) < ny:
        raise _end_of_file(path, lines, f"all {ny} depth rows (nGridY = {ny} on line {ny_line}; found "
                                        f"{len(depth_rows)})")

    z = -D
    _warn_above_surface(z, path, "; depths in this layout are positive below the surface")
    log.debug("%s: depth grid %d x %d, depth in [%g, %g]", path, nx, ny, D.min(), D.max())
    return Bathymetry(x=x, y=y, z=z, source=str(path))


# ----------------------------------------------------------------------------- file lookup
def find_seafloor_file(name, deck_dir=None) -> Path:
    """Resolve the file named by the ``SeafloorFile`` option.

    MoorDyn-C opens it relative to the process working directory, while every other auxiliary
    file is relative to the deck's folder. moorline tries the deck's folder first, then the working
    directory, and logs (INFO, logger ``moorline.io``) which one it used. An absolute name is used
    as it is.

    Parameters
    ----------
    name : str or Path
        The option value.
    deck_dir : str or Path or None
        Folder of the input deck; None to look in the working directory only.

    Returns
    -------
    Path
        The existing file.

    Raises
    ------
    DeckError
        When the file is in neither place; the message names every path tried.
    """
    name = Path(name)
    if name.is_absolute():
        candidates = [("as given", name)]
    else:
        candidates = []
        if deck_dir is not None:
            candidates.append(("the deck's folder", Path(deck_dir) / name))
        candidates.append(("the working directory", Path.cwd() / name))
    for where, p in candidates:
        if p.is_file():
            log.info("SeafloorFile %s: using %s (found in %s)", name, p, where)
            return p
    tried = " and ".join(f"{p} ({where})" for where, p in candidates)
    raise DeckError(f"SeafloorFile {str(name)!r} not found; tried {tried}", field="SeafloorFile")


def write_seafloor_grid(bathymetry: Bathymetry, path) -> Path:
    """Write ``bathymetry`` in the MoorDyn-C ``SeafloorFile`` layout (``repr`` floats, so it reads
    back exactly)."""
    path = Path(path)
    b = bathymetry
    rows = [f"{b.x.size} {b.y.size}", " ".join(repr(float(v)) for v in b.x), " ".join(repr(float(v)) for v in b.y)]
    rows += [f"{float(x)!r} {float(y)!r} {float(b.z[j, i])!r}" for j, y in enumerate(b.y) for i, x in enumerate(b.x)]
    path.write_text("\n".join(rows) + "\n", encoding="utf-8")
    return path
