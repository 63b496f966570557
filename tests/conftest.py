"""Test-suite settings.

Every system in the tests is compiled with every feature (``MOORLINE_ALL_FEATURES=1``, see
:mod:`moorline.core.features`): the suite meets rods, bodies, waves, bending and every scheme, and
one compiled specialisation for all of them is cheaper than one per combination met. Results are
identical (``tests/kernels/test_jit.py`` checks it); the tests of the per-deck specialisation unset
the variable. Subprocesses started by tests inherit it.

BLAS and OpenMP run single-threaded (``OMP_NUM_THREADS`` and the like, unless set): the suite runs
on two pytest-xdist workers, and with OpenBLAS's default of a thread per core each worker ran two
threads on the two cores. Measured under load 5 (benchmarks/RESULTS.md section 7):
tests/floating/test_decay.py took 28.7-29.2 s with OpenBLAS's threads against 5.8-7.8 s without
(the hydrodynamic state-space fits' SVDs and eigenvalue problems). The xdist workers are started
after this file is read, so they load their BLAS with these settings.

The workers of a whole-suite run share the compilation of the big kernels (the derivative and the
two time loops, some 310 s of CPU from an empty cache) through numba's cache instead of each
compiling all of it: tests/shared_compile.py.
"""

from __future__ import annotations

import os

import pytest

from .shared_compile import compile_shared

os.environ.setdefault("MOORLINE_ALL_FEATURES", "1")
for _k in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS", "VECLIB_MAXIMUM_THREADS",
           "NUMEXPR_NUM_THREADS"):
    os.environ.setdefault(_k, "1")


@pytest.fixture(scope="session", autouse=True)
def _shared_compilation(request, tmp_path_factory):
    """The suite's big kernels compiled once for all pytest-xdist workers, not once by each
    (tests/shared_compile.py)."""
    compile_shared(len(request.session.items), tmp_path_factory.getbasetemp().parent)
