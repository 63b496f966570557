"""Field-by-field comparison of two models (or any nesting of dataclasses, dicts, lists, numpy
arrays and plain objects), for round-trip tests. Attributes named ``source`` (which file a thing
was read from) are not compared: a deck written elsewhere names other files."""

from __future__ import annotations

import dataclasses
from enum import Enum
from pathlib import Path

import numpy as np

SKIP = {"source"}


def diff(a, b, where: str = "model", out: list | None = None) -> list[str]:
    """Every difference between ``a`` and ``b`` as 'path: a != b' strings (empty when equal)."""
    out = [] if out is None else out
    if isinstance(a, np.ndarray) or isinstance(b, np.ndarray):
        a2, b2 = np.asarray(a), np.asarray(b)
        same = a2.shape == b2.shape and (np.array_equal(a2, b2, equal_nan=a2.dtype.kind == "f" and b2.dtype.kind == "f")
                                         if a2.dtype.kind in "fc" else np.array_equal(a2, b2))
        if not same:
            out.append(f"{where}: {a2!r} != {b2!r}"[:300])
        return out
    if type(a) is not type(b) and not (isinstance(a, int | float) and isinstance(b, int | float)
                                       and not isinstance(a, Enum) and not isinstance(b, Enum)):
        out.append(f"{where}: type {type(a).__name__} != {type(b).__name__}")
        return out
    if dataclasses.is_dataclass(a):
        for f in dataclasses.fields(a):
            if f.name not in SKIP:
                diff(getattr(a, f.name), getattr(b, f.name), f"{where}.{f.name}", out)
    elif isinstance(a, dict):
        if list(a) != list(b):
            out.append(f"{where}: keys {list(a)} != {list(b)}")
        else:
            for k in a:
                diff(a[k], b[k], f"{where}[{k!r}]", out)
    elif isinstance(a, list | tuple):
        if len(a) != len(b):
            out.append(f"{where}: length {len(a)} != {len(b)}")
        else:
            for i, (x, y) in enumerate(zip(a, b, strict=True)):
                diff(x, y, f"{where}[{i}]", out)
    elif isinstance(a, float):
        if not (a == b or (np.isnan(a) and np.isnan(b))):
            out.append(f"{where}: {a!r} != {b!r}")
    elif isinstance(a, str | int | bool | Enum | type(None) | Path):
        if a != b:
            out.append(f"{where}: {a!r} != {b!r}")
    elif hasattr(a, "__dict__"):
        for k in vars(a):
            if k not in SKIP and not k.startswith("_"):
                diff(getattr(a, k), getattr(b, k, None), f"{where}.{k}", out)
    elif a != b:
        out.append(f"{where}: {a!r} != {b!r}")
    return out
