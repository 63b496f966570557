"""Compiled (numba) kernels: arrays in, arrays out.

numba's on-disk cache (``cache=True``) checks only the source file of the function it compiled,
not the modules whose functions were compiled into it: after an edit of ``lines.py`` the cached
``rhs`` would still run the old line kernel. On import we therefore hash all kernel sources and
drop the cache files of this folder when the hash changed, wherever numba keeps them: beside the
sources (``__pycache__``) or, when ``NUMBA_CACHE_DIR`` is set, in the subfolder numba makes there
for this folder (``core_<sha1 of the folder path>``; ``tests/kernels/test_jit.py`` checks that
numba still names it so).
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path

from numba import config


def kernel_cache_dirs() -> list[Path]:
    """The folders where numba may keep the cache of the kernels in this package folder."""
    here = os.path.abspath(os.path.dirname(__file__))
    dirs = [Path(here) / "__pycache__"]
    if config.CACHE_DIR:
        sub = f"{os.path.basename(here)}_{hashlib.sha1(here.encode()).hexdigest()}"
        dirs.append(Path(os.path.abspath(config.CACHE_DIR)) / sub)
    return dirs


def _drop_stale_kernel_cache() -> None:
    here = Path(__file__).resolve().parent
    digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(here.glob("*.py")))).hexdigest()
    for cache in kernel_cache_dirs():
        try:
            stamp = cache / "kernel-sources.sha256"
            if stamp.is_file() and stamp.read_text() == digest:
                continue
            for f in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
                f.unlink(missing_ok=True)
            cache.mkdir(parents=True, exist_ok=True)
            stamp.write_text(digest)
        except OSError:  # a read-only folder: numba cannot cache there either
            pass


_drop_stale_kernel_cache()
