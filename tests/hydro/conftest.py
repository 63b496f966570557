"""Shared fixtures for the hydro tests: the public reference data in ../shared/data (skipped when absent)."""

from __future__ import annotations

from pathlib import Path

import pytest

DATA = Path(__file__).resolve().parents[2].parent / "shared" / "data"


def data_file(rel: str) -> Path:
    path = DATA / rel
    if not path.exists():
        pytest.skip(f"reference data {path} not available")
    return path


@pytest.fixture(scope="session")
def rm3():
    from moorline.hydro import read_wamit
    stem = data_file("rm3/rm3.1").with_suffix("")
    return read_wamit(stem, rho=1000.0, g=9.81)
