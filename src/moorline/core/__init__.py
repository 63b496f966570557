"""Compiled (numba) kernels: arrays in, arrays out.

numba's on-disk cache (``cache=True``) checks only the source file of the function it compiled,
not the modules whose functions were compiled into it: after an edit of ``lines.py`` the cached
``rhs`` would still run the old line kernel. On import we therefore hash all kernel sources and
drop the cache files when the hash changed.
"""

from __future__ import annotations

import hashlib
from pathlib import Path


def _drop_stale_kernel_cache() -> None:
    here = Path(__file__).resolve().parent
    cache = here / "__pycache__"
    try:
        digest = hashlib.sha256(b"".join(p.read_bytes() for p in sorted(here.glob("*.py")))).hexdigest()
        stamp = cache / "kernel-sources.sha256"
        if stamp.is_file() and stamp.read_text() == digest:
            return
        for f in list(cache.glob("*.nbi")) + list(cache.glob("*.nbc")):
            f.unlink(missing_ok=True)
        cache.mkdir(exist_ok=True)
        stamp.write_text(digest)
    except OSError:  # read-only installation: numba then cannot cache either
        pass


_drop_stale_kernel_cache()
