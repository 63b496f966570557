"""MoorDyn-C water-kinematics files (spec sections 1.11.3 and 4) and the ``WaveKin`` / ``Currents``
options.

Files, all in the deck's folder under fixed names (:data:`FILES`):

* ``wave_frequencies.txt`` -- rows ``omega Re(a) Im(a) [beta]`` [rad/s, m, m, rad], no header
  (:func:`read_wave_frequencies`);
* ``wave_elevation.txt`` -- rows ``t zeta`` [s, m], no header (:func:`read_wave_elevation`);
* ``water_grid.txt`` -- three header lines, then for x, y and z a type line (0 single 0,
  1 list, 2 ``first last n``) and a values line (:func:`read_water_grid`);
* ``current_profile.txt`` -- three header lines, rows ``z ux [uy [uz]]`` (:func:`read_current_profile`);
* ``current_profile_dynamic.txt`` -- lines 1-4 free, line 5 the z levels, line 6 free, rows
  ``t ux(z_1..z_nz) [uy(...) [uz(...)]]`` (:func:`read_current_profile_dynamic`);
* ``current_profile_4d.txt`` -- line 1 ``nx ny nz nt``, lines 2-5 the x, y, z, t axes, rows
  ``x y z t ux uy uz`` (:func:`read_current_profile_4d`).

:func:`water_from_options` turns ``WaveKin`` 0/1/2/3/7 and ``Currents`` 0/1/2/5 into
:class:`~moorline.model.water.Waves` and :class:`~moorline.model.water.Current` descriptions that
reproduce MoorDyn-C's kinematics (spec 4), including its quirks:

* WaveKin 7 reads the amplitudes **sine**-phased, WaveKin 2 **cosine**-phased (gotcha 28): the
  same file gives waves a quarter period apart; WaveKin 7 has no dynamic pressure;
* WaveKin 2 resamples the spectrum to the smallest frequency gap d_omega (amplitude and heading
  linear in omega), with half weight on the 0 rad/s and the last component, on a record of
  2 (n_w - 1) samples that repeats every 2 pi / d_omega (spec 4.4);
* WaveKin 3 resamples the record at ``dtWave``, trims it to an even length and drops every
  component above 0.5 Hz (pi rad/s) (spec 4.5);
* grid records repeat with MoorDyn-C's wrap (first sample held over the last interval, 4.7);
* current profiles are not zeroed above the surface; currents have zero acceleration; time tables
  are resampled at their smallest interval (4.8);
* ``UnifyCurrentGrid = 1``: with a wave grid the current is sampled onto it (4.8);
* the 4-D current file: MoorDyn-C ignores line 6, the first data row (``skip_first_row``).

Deliberate differences, each turning a silent surprise of MoorDyn-C into a located
:class:`~moorline.errors.DeckError` (file, line, row, what was expected) or a warning:

* blank lines and everything after a ``#`` are ignored in data rows (C rejects blank rows);
* a ``wave_frequencies.txt`` row with 5 or more values is an error (C silently sets beta = 0);
* a dynamic-profile row must hold exactly 1 + nz, 1 + 2 nz or 1 + 3 nz values (C ignores extras);
* water-grid axes must be strictly increasing and a type-2 axis needs n >= 2 (C: n = 1 gives two
  points); 4-D axes must hold exactly n values;
* a 4-D row whose coordinate text is not an axis token is matched by value; one that matches no
  grid node is an error (C files it at index 0); unlisted 4-D nodes stay 0 as in C, with a warning;
* time tables must be strictly increasing (C would divide by a zero or negative interval);
* the z levels of the dynamic profile are read in double precision (C: single precision);
* the number of resampled times floor(t_last / dt) + 1 tolerates a relative round-off of 1e-12
  in t_last / dt (C can lose the last time to it).
"""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import NamedTuple

import numpy as np

from ..errors import DeckError
from ..model.types import ModelError
from ..model.water import Current, WaveGrid, Waves

# the row and number helpers of the bathymetry readers (same conventions: 1-based line numbers,
# blank lines and '#' comments dropped, located DeckErrors)
from .bathymetry import _data_rows, _end_of_file, _float_or_nan, _number, _read_lines, _Row

log = logging.getLogger("moorline.io")

__all__ = ["FILES", "FrequencyTable", "read_current_profile", "read_current_profile_4d",
           "read_current_profile_dynamic", "read_wave_elevation", "read_wave_frequencies", "read_water_grid",
           "water_from_options", "waves_fft_grid", "waves_summed"]

#: file names MoorDyn-C reads from the deck's folder
FILES = {
    "frequencies": "wave_frequencies.txt",
    "elevation": "wave_elevation.txt",
    "grid": "water_grid.txt",
    "profile": "current_profile.txt",
    "dynamic": "current_profile_dynamic.txt",
    "grid4d": "current_profile_4d.txt",
}
#: MoorDyn-C's WaveKin 3 low-pass: components above 0.5 Hz are dropped [rad/s]
ELEVATION_CUTOFF = math.pi
#: MoorDyn-C's default ``dtWave`` [s]
DT_WAVE = 0.25


# ------------------------------------------------------------------------------------ helpers
def _whole(tok: str, row: _Row, path: Path, what: str, minimum: int) -> int:
    v = _float_or_nan(tok)
    if not (math.isfinite(v) and v.is_integer() and v >= minimum):
        raise DeckError(f"{what}: expected a whole number >= {minimum}, got {tok!r}", file=path, line=row[0],
                        row=row[1], field=what)
    return int(v)


def _ascending(values: np.ndarray, rows: list[_Row], path: Path, what: str) -> None:
    """DeckError at the first value that does not exceed its predecessor (one row per value, or
    one row for all)."""
    bad = np.nonzero(np.diff(values) <= 0.0)[0]
    if bad.size:
        k = int(bad[0]) + 1
        row = rows[k] if len(rows) > 1 else rows[0]
        raise DeckError(f"{what} must be strictly increasing: {values[k]:g} does not exceed {values[k - 1]:g}",
                        file=path, line=row[0], row=row[1], field=what)


def _numbers(tokens: list[str], row: _Row, path: Path, what: str) -> np.ndarray:
    return np.array([_number(t, row, path, what) for t in tokens], dtype=float)


def _model(path: Path, fn, *args, **kwargs):
    """Call a model constructor, turning its ModelError into a DeckError naming the file."""
    try:
        return fn(*args, **kwargs)
    except ModelError as e:
        raise DeckError(str(e), file=path) from None


# --------------------------------------------------------------------------- wave frequencies
class FrequencyTable(NamedTuple):
    """Rows of ``wave_frequencies.txt`` as listed: omega [rad/s], complex amplitude a [m], heading
    beta [rad], and the 1-based line number of each row."""

    omega: np.ndarray
    amplitude: np.ndarray
    heading: np.ndarray
    lines: np.ndarray


def read_wave_frequencies(path) -> FrequencyTable:
    """Read ``wave_frequencies.txt`` (spec 4.4, item 1).

    One component per row: ``omega Re(a) Im(a) [beta]`` (3 or 4 numbers; beta in radians within
    +/- 2 pi, default 0), no header; at least 2 rows; the first omega must be 0 (MoorDyn-C
    requires it for WaveKin 2 and 7); omega >= 0.

    Raises
    ------
    DeckError
        Naming the file, line, row and what was expected.
    """
    path = Path(path)
    lines = _read_lines(path, "wave frequencies file")
    rows = _data_rows(lines)
    if len(rows) < 2:
        raise DeckError(f"expected at least 2 frequency rows 'omega Re(a) Im(a) [beta]' (the first at 0 rad/s), "
                        f"found {len(rows)}", file=path, line=len(lines) or None)
    out = np.zeros((len(rows), 4))
    for i, row in enumerate(rows):
        tokens = row[2]
        if len(tokens) not in (3, 4):
            raise DeckError(f"expected 'omega Re(a) Im(a) [beta]' (3 or 4 numbers: rad/s, m, m, rad), got "
                            f"{len(tokens)} value(s)", file=path, line=row[0], row=row[1], field="omega Re Im beta")
        names = ("omega", "Re(a)", "Im(a)", "beta")[: len(tokens)]
        vals = [_number(t, row, path, name) for t, name in zip(tokens, names, strict=True)]
        if vals[0] < 0.0:
            raise DeckError(f"omega must be >= 0 rad/s, got {tokens[0]}", file=path, line=row[0], row=row[1],
                            field="omega")
        if len(vals) == 4 and abs(vals[3]) > 2.0 * math.pi:
            raise DeckError(f"beta = {tokens[3]} is outside +/- 2 pi: the heading is in radians", file=path,
                            line=row[0], row=row[1], field="beta")
        out[i, : len(vals)] = vals
    if out[0, 0] != 0.0:
        raise DeckError(f"the first frequency must be 0 rad/s (MoorDyn requires a zero row first), got "
                        f"{rows[0][2][0]}", file=path, line=rows[0][0], row=rows[0][1], field="omega")
    return FrequencyTable(out[:, 0], out[:, 1] + 1j * out[:, 2], out[:, 3], np.array([r[0] for r in rows]))


def waves_summed(table: FrequencyTable, *, source: str = "") -> Waves:
    """MoorDyn's WaveKin 7 reading of a frequency table (spec 4.3): every row a component as
    listed, sine-phased (zeta = sum |a| sin(theta + arg a)), summed at each point, no dynamic
    pressure."""
    return Waves.from_components(table.omega, table.amplitude, np.degrees(table.heading), phasing="sine",
                                 evaluation="sum", dynamic_pressure=False,
                                 source=source or f"WaveKin 7: {table.omega.size} components")


def waves_fft_grid(table: FrequencyTable, grid: WaveGrid, *, path=None, source: str = "") -> Waves:
    """MoorDyn's WaveKin 2 reading of a frequency table (spec 4.4) on the axes of ``grid``.

    The spectrum is resampled to d_omega = the smallest gap between consecutive frequencies:
    n_w = floor(omega_max / d_omega) + 1 components at j d_omega, complex amplitude and heading
    linear in omega; the grid record has n_t = 2 (n_w - 1) samples over 2 pi / d_omega; the 0 rad/s
    and the last component enter with half weight (MoorDyn's inverse real FFT); cosine phasing.

    Raises
    ------
    DeckError
        When the frequencies are not strictly increasing (``path`` names the file).
    """
    w = table.omega
    gaps = np.diff(w)
    if np.any(gaps <= 0.0):
        k = int(np.nonzero(gaps <= 0.0)[0][0]) + 1
        raise DeckError(f"WaveKin 2 needs strictly increasing frequencies: {w[k]:g} rad/s does not exceed "
                        f"{w[k - 1]:g}", file=path, line=int(table.lines[k]), field="omega")
    dw = float(gaps.min())
    nw = int(math.floor(w[-1] / dw)) + 1
    wj = np.arange(nw) * dw
    a = np.interp(wj, w, table.amplitude.real) + 1j * np.interp(wj, w, table.amplitude.imag)
    beta = np.interp(wj, w, table.heading)
    a[0] *= 0.5
    a[-1] *= 0.5
    spec = WaveGrid(x=grid.x, y=grid.y, z=grid.z, nt=2 * (nw - 1), margin=grid.margin, time_wrap="moordyn")
    return Waves(omega=wj, amplitude=a, heading=np.degrees(beta), evaluation="grid", grid=spec, base_omega=dw,
                 source=source or f"WaveKin 2: {nw} components every {dw:g} rad/s")


# ------------------------------------------------------------------------------- wave grid
def read_water_grid(path) -> WaveGrid:
    """Read ``water_grid.txt`` (spec 4.6): the x, y and z axes of a wave grid.

    Lines 1-3 are free; lines 4-9 are three pairs (type line, values line) for x, y and z. Type 0:
    the single coordinate 0 (the values line must exist but is ignored); 1: the listed values,
    strictly increasing; 2: ``first last n``, n >= 2 equally spaced values. Lines are counted as
    in the file (blank lines count).

    Returns
    -------
    WaveGrid
        Axes set, ``time_wrap='moordyn'``.

    Raises
    ------
    DeckError
        Naming the file, line, row and what was expected.
    """
    path = Path(path)
    lines = _read_lines(path, "water grid file")
    if len(lines) < 9:
        raise _end_of_file(path, lines, "the 9 lines of a water grid (3 header lines, then a type line and a values "
                                        "line for each of x, y and z)")
    axes = []
    for i, name in enumerate("xyz"):
        k = 3 + 2 * i
        type_row = (k + 1, lines[k], lines[k].split("#", 1)[0].split())
        vals_row = (k + 2, lines[k + 1], lines[k + 1].split("#", 1)[0].split())
        if not type_row[2]:
            raise DeckError(f"expected the {name} axis type (0 single point at 0, 1 list, 2 'first last n')",
                            file=path, line=type_row[0], row=type_row[1], field=f"{name} type")
        kind = _whole(type_row[2][0], type_row, path, f"{name} axis type", 0)
        tokens = vals_row[2]
        if kind == 0:
            axes.append(np.zeros(1))
        elif kind == 1:
            if not tokens:
                raise DeckError(f"expected the list of {name} values (type 1)", file=path, line=vals_row[0],
                                row=vals_row[1], field=name)
            v = _numbers(tokens, vals_row, path, f"{name} value")
            _ascending(v, [vals_row], path, f"{name} values")
            axes.append(v)
        elif kind == 2:
            if len(tokens) != 3:
                raise DeckError(f"expected '{name}_first {name}_last n' (type 2), got {len(tokens)} value(s)",
                                file=path, line=vals_row[0], row=vals_row[1], field=name)
            first = _number(tokens[0], vals_row, path, f"first {name}")
            last = _number(tokens[1], vals_row, path, f"last {name}")
            n = _whole(tokens[2], vals_row, path, f"number of {name} values", 2)
            if last <= first:
                raise DeckError(f"type 2 {name} axis: last ({tokens[1]}) must exceed first ({tokens[0]})", file=path,
                                line=vals_row[0], row=vals_row[1], field=name)
            v = first + np.arange(n) * ((last - first) / (n - 1))
            v[-1] = last
            axes.append(v)
        else:
            raise DeckError(f"{name} axis type must be 0 (single point at 0), 1 (list) or 2 (first last n), got "
                            f"{type_row[2][0]}", file=path, line=type_row[0], row=type_row[1], field=f"{name} type")
    return _model(path, WaveGrid, x=axes[0], y=axes[1], z=axes[2], time_wrap="moordyn")


# ---------------------------------------------------------------------------- wave elevation
def read_wave_elevation(path) -> tuple[np.ndarray, np.ndarray]:
    """Read ``wave_elevation.txt`` (spec 4.5): rows ``t zeta`` [s, m] (further values ignored, as
    in MoorDyn), times strictly increasing from >= 0; at least 2 rows.

    Returns
    -------
    t, zeta : numpy.ndarray
    """
    path = Path(path)
    lines = _read_lines(path, "wave elevation file")
    rows = _data_rows(lines)
    if len(rows) < 2:
        raise DeckError(f"expected at least 2 rows 't zeta', found {len(rows)}", file=path, line=len(lines) or None)
    t = np.empty(len(rows))
    z = np.empty(len(rows))
    for i, row in enumerate(rows):
        if len(row[2]) < 2:
            raise DeckError(f"expected a row 't zeta' (2 numbers: s, m), got {len(row[2])} value(s)", file=path,
                            line=row[0], row=row[1], field="t zeta")
        t[i] = _number(row[2][0], row, path, "t")
        z[i] = _number(row[2][1], row, path, "zeta")
    if t[0] < 0.0:
        raise DeckError(f"times must be >= 0 s (the record is resampled from t = 0), got {rows[0][2][0]}", file=path,
                        line=rows[0][0], row=rows[0][1], field="t")
    _ascending(t, rows, path, "times")
    return t, z


# ---------------------------------------------------------------------------------- currents
def read_current_profile(path) -> Current:
    """Read ``current_profile.txt`` (spec 4.8, Currents = 1): lines 1-3 free, then rows
    ``z ux [uy [uz]]`` [m, m/s] (missing components 0, further values ignored as in MoorDyn),
    z strictly increasing; at least one row. Steady, uniform in x and y, linear in z, clamped."""
    path = Path(path)
    lines = _read_lines(path, "current profile file")
    rows = _data_rows(lines, start=3)
    if not rows:
        raise _end_of_file(path, lines, "the first profile row 'z ux [uy [uz]]' (after 3 header lines)")
    z = np.empty(len(rows))
    u = np.zeros((len(rows), 3))
    for i, row in enumerate(rows):
        tokens = row[2]
        if len(tokens) < 2:
            raise DeckError(f"expected a profile row 'z ux [uy [uz]]' (at least 2 numbers), got {len(tokens)} "
                            "value(s)", file=path, line=row[0], row=row[1], field="z ux")
        z[i] = _number(tokens[0], row, path, "z")
        for c, (tok, name) in enumerate(zip(tokens[1:4], ("ux", "uy", "uz"), strict=False)):
            u[i, c] = _number(tok, row, path, name)
    _ascending(z, rows, path, "z levels")
    return _model(path, Current.profile, z, u[:, 0], u[:, 1], u[:, 2], time_wrap="moordyn",
                  source=f"{path.name} ({z.size} levels)")


def read_current_profile_dynamic(path) -> Current:
    """Read ``current_profile_dynamic.txt`` (spec 4.8, Currents = 2).

    Lines 1-4 free; line 5 the z levels (strictly increasing); line 6 free; then rows
    ``t ux(z_1..z_nz) [uy(z_1..z_nz) [uz(z_1..z_nz)]]`` (exactly 1 + nz, 1 + 2 nz or 1 + 3 nz
    numbers), times strictly increasing from >= 0. Resampled in time at the smallest interval
    when built; linear in z and t, clamped in z, repeating in t as MoorDyn-C; acceleration 0.
    """
    path = Path(path)
    lines = _read_lines(path, "dynamic current profile file")
    if len(lines) < 5:
        raise _end_of_file(path, lines, "line 5, the z levels (lines 1-4 are free)")
    zrow = (5, lines[4], lines[4].split("#", 1)[0].split())
    if not zrow[2]:
        raise DeckError("expected the z levels on line 5 (lines 1-4 are free)", file=path, line=5, row=lines[4],
                        field="z")
    z = _numbers(zrow[2], zrow, path, "z level")
    _ascending(z, [zrow], path, "z levels")
    nz = z.size
    rows = _data_rows(lines, start=6)
    if not rows:
        raise _end_of_file(path, lines, "the first row 't ux(z_1..z_nz) ...' (from line 7; line 6 is free)")
    t = np.empty(len(rows))
    u = np.zeros((3, len(rows), nz))
    for i, row in enumerate(rows):
        tokens = row[2]
        ncomp, rest = divmod(len(tokens) - 1, nz)
        if rest or not 1 <= ncomp <= 3:
            raise DeckError(f"expected 't' then ux (and optionally uy, uz) at the {nz} levels of line 5: "
                            f"{1 + nz}, {1 + 2 * nz} or {1 + 3 * nz} numbers, got {len(tokens)}", file=path,
                            line=row[0], row=row[1], field="t u")
        t[i] = _number(tokens[0], row, path, "t")
        for c in range(ncomp):
            u[c, i] = _numbers(tokens[1 + c * nz: 1 + (c + 1) * nz], row, path, ("ux", "uy", "uz")[c])
    if t[0] < 0.0:
        raise DeckError(f"times must be >= 0 s, got {rows[0][2][0]}", file=path, line=rows[0][0], row=rows[0][1],
                        field="t")
    _ascending(t, rows, path, "times")
    return _model(path, Current.dynamic_profile, t, z, u[0], u[1], u[2], time_wrap="moordyn",
                  source=f"{path.name} ({t.size} times x {nz} levels)")


def _index_of(tok: str, names: dict[str, int], axis: np.ndarray, row: _Row, path: Path, what: str) -> int:
    """Grid index of a coordinate token: by its text (MoorDyn-C), else by value."""
    if tok in names:
        return names[tok]
    v = _number(tok, row, path, what)
    tol = 1e-9 * max(1.0, float(np.max(np.abs(axis))))
    hit = np.nonzero(np.abs(axis - v) <= tol)[0]
    if hit.size == 0:
        shown = ", ".join(f"{a:g}" for a in axis[:8]) + (", ..." if axis.size > 8 else "")
        raise DeckError(f"{what} = {tok} is not one of the {axis.size} {what} values of the axis ({shown})",
                        file=path, line=row[0], row=row[1], field=what)
    return int(hit[0])


def read_current_profile_4d(path, *, skip_first_row: bool = True) -> Current:
    """Read ``current_profile_4d.txt`` (spec 4.8, Currents = 5).

    Line 1 ``nx ny nz nt``; lines 2-5 exactly nx x values, ny y values, nz z values and nt times
    (each strictly increasing); then rows ``x y z t ux uy uz``, one per grid node in any order,
    matched to the axes by the text of the coordinates (as written on lines 2-5) or, failing that,
    by value. Nodes never listed stay 0 (MoorDyn-C), with a warning.

    Parameters
    ----------
    path : str or Path
        The file.
    skip_first_row : bool
        Ignore line 6, the first data row, as MoorDyn-C v2.7.1 does (spec 4.8, (bug?)); the
        warning names that row when it is a grid node listed nowhere else. False reads it.

    Raises
    ------
    DeckError
        Naming the file, line, row and what was expected.
    """
    path = Path(path)
    lines = _read_lines(path, "4-D current file")
    if len(lines) < 5:
        raise _end_of_file(path, lines, "the 5 header lines (nx ny nz nt, then the x, y, z and t values)")
    head = (1, lines[0], lines[0].split("#", 1)[0].split())
    if len(head[2]) != 4:
        raise DeckError(f"expected 'nx ny nz nt' (4 whole numbers), got {len(head[2])} value(s)", file=path, line=1,
                        row=lines[0], field="nx ny nz nt")
    counts = [_whole(tok, head, path, name, 1) for tok, name in zip(head[2], ("nx", "ny", "nz", "nt"), strict=True)]
    axes, names = [], []
    for k, (name, n) in enumerate(zip("xyzt", counts, strict=True)):
        row = (k + 2, lines[k + 1], lines[k + 1].split("#", 1)[0].split())
        if len(row[2]) != n:
            raise DeckError(f"expected exactly {n} {name} values (n{name} = {n} on line 1), got {len(row[2])}",
                            file=path, line=row[0], row=row[1], field=name)
        v = _numbers(row[2], row, path, f"{name} value")
        _ascending(v, [row], path, f"{name} values")
        if name == "t" and v[0] < 0.0:
            raise DeckError(f"times must be >= 0 s, got {row[2][0]}", file=path, line=row[0], row=row[1], field="t")
        axes.append(v)
        names.append({tok: i for i, tok in enumerate(row[2])})
    vel = np.zeros(tuple(counts) + (3,))
    where = np.zeros(tuple(counts), dtype=int)
    all_rows = _data_rows(lines, start=5)
    skipped = None
    if skip_first_row and all_rows and all_rows[0][0] == 6:
        skipped, all_rows = all_rows[0], all_rows[1:]
    for row in all_rows:
        tokens = row[2]
        if len(tokens) != 7:
            raise DeckError(f"expected a grid row 'x y z t ux uy uz' (7 numbers), got {len(tokens)} value(s)",
                            file=path, line=row[0], row=row[1], field="x y z t ux uy uz")
        idx = tuple(_index_of(tokens[c], names[c], axes[c], row, path, "xyzt"[c]) for c in range(4))
        if where[idx]:
            log.warning("%s, line %d: grid node (x, y, z, t) = (%s) already given on line %d; the later row wins "
                        "(as MoorDyn-C)", path, row[0], ", ".join(tokens[:4]), where[idx])
        where[idx] = row[0]
        vel[idx] = [_number(tokens[4 + c], row, path, name) for c, name in enumerate(("ux", "uy", "uz"))]
    missing = int(np.count_nonzero(where == 0))
    if missing:
        note = ""
        if skipped is not None:
            note = (f"; line 6 ('{skipped[1].strip()}') was skipped as MoorDyn-C v2.7.1 does "
                    "(read_current_profile_4d(..., skip_first_row=False) reads it)")
        log.warning("%s: %d of %d grid nodes are not listed and get zero velocity (MoorDyn-C)%s", path, missing,
                    where.size, note)
    return _model(path, Current.grid, axes[0], axes[1], axes[2], axes[3], vel, time_wrap="moordyn",
                  source=f"{path.name} ({' x '.join(map(str, counts))})")


# ------------------------------------------------------------------------------------ options
def _file(deck_dir: Path, key: str, option: str) -> Path:
    p = deck_dir / FILES[key]
    if not p.is_file():
        raise DeckError(f"{option} needs the file {FILES[key]} in the deck's folder ({deck_dir}); it is missing",
                        field=option.split()[0])
    return p


def _check_grid_depth(grid: WaveGrid, path: Path, depth) -> None:
    if depth is not None and grid.z[0] > -float(depth):
        log.warning("%s: the z axis starts at %g m, above the seabed at %g m: deeper points get the values at %g m",
                    path, grid.z[0], -float(depth), grid.z[0])
    if grid.z[-1] < 0.0:
        log.warning("%s: the z axis ends at %g m, below the still-water level: points above it get the values at "
                    "%g m", path, grid.z[-1], grid.z[-1])


def water_from_options(wave_kin: int, currents: int, deck_dir, depth=None, *, dt_wave: float = DT_WAVE,
                       unify_current_grid: bool = True) -> tuple[Waves | None, Current | None]:
    """The waves and current of MoorDyn's ``WaveKin`` and ``Currents`` options (spec 4.1).

    ==========  =====================================================================
    WaveKin     0 none; 1 external (set per node by the coupling program);
                2 FFT grid from ``wave_frequencies.txt`` on ``water_grid.txt``;
                3 FFT grid from ``wave_elevation.txt`` (resampled at ``dt_wave``, low-passed
                at 0.5 Hz) on ``water_grid.txt``; 7 ``wave_frequencies.txt`` summed at the
                points (sine-phased, no dynamic pressure); 4-6 reserved (error)
    Currents    0 none; 1 ``current_profile.txt``; 2 ``current_profile_dynamic.txt``;
                5 ``current_profile_4d.txt``; 3-4 reserved (error)
    ==========  =====================================================================

    MoorDyn has no ramp-up (the waves act fully from t = 0) and turns the waves off (currents on)
    during its initial-condition solve; both are the caller's business.

    Parameters
    ----------
    wave_kin, currents : int
        Option values.
    deck_dir : str or Path
        Folder of the input deck (the files are read from it).
    depth : float or None
        Water depth [m], to warn about a wave grid that does not reach the seabed.
    dt_wave : float
        MoorDyn's ``dtWave`` [s], the resampling step of WaveKin 3.
    unify_current_grid : bool
        MoorDyn's ``UnifyCurrentGrid`` (default 1): with a wave grid (WaveKin 2 or 3), sample the
        current onto it (:attr:`Current.on_wave_grid`).

    Returns
    -------
    (Waves or None, Current or None)

    Raises
    ------
    DeckError
        For an unknown or unimplemented option value, a missing file, or a malformed file.
    """
    deck_dir = Path(deck_dir)
    waves = None
    if wave_kin in (4, 5, 6):
        raise DeckError(f"WaveKin = {wave_kin} is reserved and not implemented (in MoorDyn either); use 0, 1, 2, 3 "
                        "or 7", field="WaveKin")
    if wave_kin == 1:
        waves = Waves.external()
    elif wave_kin == 7:
        path = _file(deck_dir, "frequencies", "WaveKin 7")
        waves = waves_summed(read_wave_frequencies(path), source=f"WaveKin 7: {path}")
    elif wave_kin == 2:
        fpath = _file(deck_dir, "frequencies", "WaveKin 2")
        gpath = _file(deck_dir, "grid", "WaveKin 2")
        grid = read_water_grid(gpath)
        _check_grid_depth(grid, gpath, depth)
        waves = waves_fft_grid(read_wave_frequencies(fpath), grid, path=fpath, source=f"WaveKin 2: {fpath}")
    elif wave_kin == 3:
        epath = _file(deck_dir, "elevation", "WaveKin 3")
        gpath = _file(deck_dir, "grid", "WaveKin 3")
        grid = read_water_grid(gpath)
        _check_grid_depth(grid, gpath, depth)
        t, zeta = read_wave_elevation(epath)
        if not (math.isfinite(dt_wave) and dt_wave > 0.0):
            raise DeckError(f"dtWave must be > 0 s, got {dt_wave!r}", field="dtWave")
        waves = _model(epath, Waves.from_elevation, t, zeta, dt=dt_wave, heading=0.0, cutoff=ELEVATION_CUTOFF,
                       evaluation="grid", grid=grid, source=f"WaveKin 3: {epath}")
    elif wave_kin != 0:
        raise DeckError(f"WaveKin must be 0 (none), 1 (external), 2 (FFT grid), 3 (elevation grid) or 7 (summed "
                        f"components), got {wave_kin!r}", field="WaveKin")

    current = None
    if currents in (3, 4):
        raise DeckError(f"Currents = {currents} is reserved and not implemented (in MoorDyn either); use 0, 1, 2 or 5",
                        field="Currents")
    if currents == 1:
        current = read_current_profile(_file(deck_dir, "profile", "Currents 1"))
    elif currents == 2:
        current = read_current_profile_dynamic(_file(deck_dir, "dynamic", "Currents 2"))
    elif currents == 5:
        current = read_current_profile_4d(_file(deck_dir, "grid4d", "Currents 5"))
    elif currents != 0:
        raise DeckError(f"Currents must be 0 (none), 1 (profile), 2 (dynamic profile) or 5 (4-D grid), got "
                        f"{currents!r}", field="Currents")
    if current is not None and unify_current_grid and waves is not None and waves.evaluation == "grid":
        current.on_wave_grid = True
    return waves, current
