"""MoorDyn-C's saved state files (``MoorDyn_SaveState``; the deck option ``fileIC``).

The layout, as MoorDyn-C 2.7 writes it (read from its files, checked against the live ``moordyn``
package in tests/conformance/test_oracle_file_ic.py), all numbers little-endian:

- the 7 bytes ``MoorDyn``, then the major and minor version (one byte each);
- the number of 8-byte words that follow (uint64);
- the number of objects (uint64), then for each object, in the order bodies, rods, points, lines:
  its rows and columns (uint64 each) and rows x columns float64 values, row by row. A body or rod
  is one row of 13 (position, quaternion, velocity, angular velocity; zero for objects without a
  state of their own), a point one row of 6 (position, velocity; zero unless free), a line N - 1
  rows of 6 (position and velocity of each internal node), with one more column for VIV lines and
  one more row and column for viscoelastic and Syrope lines (what each value is:
  :mod:`moorline.system.moordyn_start`, which puts them into a system).

Schemes that carry more than the state (MoorDyn's multi-step schemes) write more objects;
:func:`read_moordyn_state` returns whatever is there and the system checks the shapes it needs.
"""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np

from ..errors import DeckError

MAGIC = b"MoorDyn"


def read_moordyn_state(path) -> tuple[tuple[int, int], list[np.ndarray]]:
    """((major, minor) version, the objects' arrays in the file's order) of MoorDyn state file
    ``path``. Raises :class:`~moorline.errors.DeckError` naming the file and what was expected."""
    path = Path(path)
    try:
        b = path.read_bytes()
    except OSError as e:
        raise DeckError(f"cannot read the MoorDyn state file: {e.strerror or e}", file=str(path),
                        field="fileIC") from None
    if b[:7] != MAGIC or len(b) < 25:
        raise DeckError("not a MoorDyn state file (expected one written by MoorDyn's SaveState, starting with "
                        "'MoorDyn')", file=str(path), field="fileIC")
    version = (b[7], b[8])
    words, count = struct.unpack_from("<QQ", b, 9)
    if 17 + 8 * words != len(b):
        raise DeckError(f"MoorDyn state file of {len(b)} bytes announces {words} words after its 17-byte header; "
                        f"the file is truncated or not a MoorDyn {version[0]}.{version[1]} state", file=str(path),
                        field="fileIC")
    o = 25
    out = []
    for k in range(count):
        if o + 16 > len(b):
            raise DeckError(f"MoorDyn state file ends inside object {k + 1} of {count}", file=str(path),
                            field="fileIC")
        rows, cols = struct.unpack_from("<QQ", b, o)
        o += 16
        n = rows * cols
        if o + 8 * n > len(b):
            raise DeckError(f"MoorDyn state file ends inside object {k + 1} of {count} ({rows} x {cols} values)",
                            file=str(path), field="fileIC")
        out.append(np.frombuffer(b, dtype="<f8", count=n, offset=o).reshape(rows, cols).copy())
        o += 8 * n
    if o != len(b):
        raise DeckError(f"MoorDyn state file has {len(b) - o} bytes after its {count} objects", file=str(path),
                        field="fileIC")
    return version, out
