"""Deck fuzzing (tests/unit/deck_fuzzer.py): mutated example decks give a result or one of the
package's own errors, never another exception and never a hang.

The fuzzer runs in a subprocess that first runs the unmutated decks (they compile the kernels, which
may take minutes with a cold cache: :data:`WARMUP_TIMEOUT`), then prints a line before and after
each case; a case that gives no answer within :data:`CASE_TIMEOUT` seconds is a hang. The default
suite runs :data:`CASES` cases of one seed; the ``slow`` part runs more with other seeds.
"""

from __future__ import annotations

import json
import os
import selectors
import subprocess
import sys
import time
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
#: cases of the default suite (about 30 s) and of the slow part, per seed
CASES = 200
SLOW_CASES = 1000
#: seconds a case may take before it counts as a hang
CASE_TIMEOUT = 240.0
#: seconds for each unmutated deck the fuzzer runs first: it compiles the kernels the cases use
#: (a cold compile of every feature; minutes when other tests compile in parallel on 2 cores)
WARMUP_TIMEOUT = 1800.0


def run_fuzzer(cases: int, seed: int) -> list[dict]:
    proc = subprocess.Popen([sys.executable, "-m", "tests.unit.deck_fuzzer", "--cases", str(cases), "--seed",
                             str(seed)], cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True,
                            env=dict(os.environ))
    sel = selectors.DefaultSelector()
    sel.register(proc.stdout, selectors.EVENT_READ)
    results, current, warming = [], None, None
    try:
        while True:
            wait = WARMUP_TIMEOUT if warming else CASE_TIMEOUT
            deadline = time.monotonic() + wait
            line = None
            while time.monotonic() < deadline:
                if sel.select(timeout=1.0):
                    line = proc.stdout.readline()
                    break
            if line is None:
                if warming:
                    pytest.fail(f"seed {seed}: the unmutated deck {warming} gave no answer in {wait:g} s")
                pytest.fail(f"seed {seed}: case {current} gave no answer in {wait:g} s (a hang); reproduce "
                            f"with python -m tests.unit.deck_fuzzer --seed {seed} --first {current} --cases "
                            f"{(current or 0) + 1}")
            if not line:
                break
            row = json.loads(line)
            if "warmup" in row:
                warming = row["warmup"]
            elif "warmed" in row:
                # "budget": the deck's steps exceed the fuzzer's budget, so its cases are not run either
                assert row["outcome"] in ("ok", "budget"), \
                    f"the unmutated deck {row['warmed']} did not run: {row['outcome']}"
                warming = None
            elif "start" in row:
                current = row["start"]
            else:
                results.append(row)
    finally:
        proc.kill()
        proc.wait()
    assert proc.returncode is not None
    return results


def _check(results: list[dict], cases: int, seed: int) -> None:
    assert len(results) == cases, f"seed {seed}: the fuzzer stopped after {len(results)} of {cases} cases"
    bad = [r for r in results if not (r["outcome"] in ("ok", "budget") or r["outcome"].startswith("package: "))]
    assert not bad, f"seed {seed}: exceptions that are not moorline's own:\n" + "\n".join(map(json.dumps, bad))
    # the fuzzer exercises the runs too, not only the reader
    assert sum(r["outcome"] == "ok" for r in results) >= cases // 10


def test_fuzzed_decks_give_results_or_package_errors():
    _check(run_fuzzer(CASES, 1), CASES, 1)


@pytest.mark.slow
@pytest.mark.parametrize("seed", [2, 3])
def test_fuzzed_decks_more_seeds(seed):
    _check(run_fuzzer(SLOW_CASES, seed), SLOW_CASES, seed)
