"""Test-suite settings.

Every system in the tests is compiled with every feature (``MOORLINE_ALL_FEATURES=1``, see
:mod:`moorline.core.features`): the suite meets rods, bodies, waves, bending and every scheme, and
one compiled specialisation for all of them is cheaper than one per combination met. Results are
identical (``tests/kernels/test_jit.py`` checks it); the tests of the per-deck specialisation unset
the variable. Subprocesses started by tests inherit it.
"""

from __future__ import annotations

import os

os.environ.setdefault("MOORLINE_ALL_FEATURES", "1")
