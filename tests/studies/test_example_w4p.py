"""Smoke run of the W4P study example (examples/w4p_study/run_study.py --quick): two designs over
the sea states of probability >= 3 %, the report and the four figures."""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

SCRIPT = Path(__file__).resolve().parents[2] / "examples" / "w4p_study" / "run_study.py"


def test_w4p_example_quick(tmp_path, capsys):
    spec = importlib.util.spec_from_file_location("w4p_run_study", SCRIPT)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    out = mod.main(["--quick", "--workers", "1", "--out", str(tmp_path / "out"), "--figures", str(tmp_path)])
    text = capsys.readouterr().out
    assert "baseline (mass 2.75 kg/m, EI 350 N m^2, 70 m)" in text
    ds = out["result"].dataset
    assert ds.sizes["sea_state"] == 11 and ds.mass.values.tolist() == [2.75, 6.0]
    assert np.all(np.isfinite(ds.life_years.values)) and np.all(ds.life_years.values > 0)
    for p in out["figures"]:
        assert p.exists() and p.stat().st_size > 10_000
