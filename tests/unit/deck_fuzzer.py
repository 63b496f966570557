"""A seeded deck fuzzer: mutations of the repository's example decks, each read, built and run.

    python -m tests.unit.deck_fuzzer --cases 200 --seed 1

Each case takes one of the decks below and applies one to three mutations (a line deleted,
duplicated or swapped with another, the text truncated, a number replaced by an extreme value, a
token by garbage, a reference by one to an object that does not exist, a section header mangled),
then reads the deck, builds the System, and simulates 0.2 s (after the initial conditions) when
the run's time-step estimate is within a budget (:data:`STEP_BUDGET`: the fuzzer looks for
crashes and hangs, not for long runs; anything beyond the package's own limits is refused by
the package itself).

One JSON line per case on stdout: ``{"case": i, "deck": name, "mutations": [...], "outcome": ...}``
with outcome ``ok``, ``budget``, ``package: <error type>`` (one of moorline's own errors) or
``other: <error type>: <message>`` (a bug); a line ``{"start": i}`` is printed before each case
so that a driver can name a case that hangs. ``tests/unit/test_fuzz.py`` runs it in a
subprocess with a timeout per case.
"""

from __future__ import annotations

import argparse
import json
import logging
import random
import shutil
import sys
import tempfile
import warnings
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
#: decks mutated (with the files they refer to, copied beside them)
DECKS = [
    (ROOT / "examples" / "catenary_3line" / "catenary_3line.dat", []),
    (ROOT / "examples" / "wec_cable" / "wec_cable.dat", []),
    (ROOT / "examples" / "slope_friction" / "slope_chain.dat", ["slope_bathymetry.txt"]),
    (ROOT / "benchmarks" / "decks" / "buoy_body.dat", []),
    (ROOT / "benchmarks" / "decks" / "bending_cable.dat", []),
    (ROOT / "tests" / "studies" / "tiny_cable.dat", []),
]
#: time steps (dynamics and initial conditions) a case may take; larger ones are counted, not run
STEP_BUDGET = 2e5
#: simulated time of a case [s]
DURATION = 0.2
EXTREMES = ["0", "-0", "-1", "1e-308", "1e308", "nan", "inf", "-inf", "1e20", "-1e20", "1e-12", "2147483648",
            "99999999999", "0.5", "3"]
GARBAGE = ["abc", "#", "@@", "1,2", "--", "1e", "0x10", "None", "1/0", "Body", "R", "Point99"]
BAD_REFS = ["99", "0", "-1", "R9", "R1C", "Body7", "Body1Pinned", "Point0", "Fixed", "Coupled", "nosuch"]


def _numbers(line: str) -> list[int]:
    toks = line.split()
    out = []
    for k, t in enumerate(toks):
        try:
            float(t)
            out.append(k)
        except ValueError:
            pass
    return out


def mutate(text: str, rng: random.Random) -> tuple[str, list[str]]:
    """Apply 1 to 3 random mutations; returns the new text and their names."""
    lines = text.splitlines()
    done = []
    for _ in range(rng.randint(1, 3)):
        if not lines:
            break
        kind = rng.choice(["delete", "duplicate", "swap", "truncate", "extreme", "extreme", "extreme", "garbage",
                           "reference", "header"])
        i = rng.randrange(len(lines))
        if kind == "delete":
            del lines[i]
        elif kind == "duplicate":
            lines.insert(i, lines[i])
        elif kind == "swap":
            j = rng.randrange(len(lines))
            lines[i], lines[j] = lines[j], lines[i]
        elif kind == "truncate":
            joined = "\n".join(lines)
            lines = joined[:rng.randrange(len(joined) + 1)].splitlines()
        elif kind in ("extreme", "garbage"):
            cand = [k for k, ln in enumerate(lines) if _numbers(ln)] if kind == "extreme" else \
                [k for k, ln in enumerate(lines) if ln.split()]
            if not cand:
                continue
            i = rng.choice(cand)
            toks = lines[i].split()
            k = rng.choice(_numbers(lines[i])) if kind == "extreme" else rng.randrange(len(toks))
            toks[k] = rng.choice(EXTREMES if kind == "extreme" else GARBAGE)
            lines[i] = "  ".join(toks)
        elif kind == "reference":
            cand = [k for k, ln in enumerate(lines) if len(ln.split()) >= 4 and ln.split()[0].isdigit()]
            if not cand:
                continue
            i = rng.choice(cand)
            toks = lines[i].split()
            toks[rng.randrange(1, min(4, len(toks)))] = rng.choice(BAD_REFS)
            lines[i] = "  ".join(toks)
        elif kind == "header":
            cand = [k for k, ln in enumerate(lines) if ln.lstrip().startswith("---")]
            if not cand:
                continue
            i = rng.choice(cand)
            lines[i] = lines[i].replace("LINE", "LINEZ", 1) if rng.random() < 0.5 else lines[i].replace("-", "", 6)
        done.append(kind)
    return "\n".join(lines) + "\n", done


def run_case(deck: Path, budget: float) -> str:
    """Read, build and run ``deck``; the outcome as a short string (see the module docstring)."""
    import moorline
    from moorline.errors import CheckpointError, DeckError, SimulationError
    from moorline.io import read_deck
    from moorline.model import ModelError
    from moorline.system import System
    from moorline.system.limits import estimated_steps

    own = (DeckError, ModelError, SimulationError, CheckpointError)
    try:
        system = System(read_deck(deck))
        dyn, ic = estimated_steps(system, DURATION, solve_ic=True)
        if dyn + ic > budget:
            return "budget"
        moorline.simulate(system, DURATION, dt_out=0.1, progress=False, compile_notice=False)
        return "ok"
    except own as e:
        return f"package: {type(e).__name__}"
    except Exception as e:  # noqa: BLE001 - what the fuzzer looks for
        return f"other: {type(e).__name__}: {e}"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", type=int, default=200)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--first", type=int, default=0, help="skip the cases before this one")
    ap.add_argument("--budget", type=float, default=STEP_BUDGET)
    a = ap.parse_args(argv)
    logging.disable(logging.CRITICAL)
    warnings.simplefilter("ignore")
    rng = random.Random(a.seed)
    tmp = Path(tempfile.mkdtemp(prefix="moorline_fuzz_"))
    for deck, extra in DECKS:
        for name in extra:
            shutil.copy(deck.parent / name, tmp / name)
    # the unmutated decks first: they compile the kernels the cases use (minutes on a busy machine
    # with a cold cache), so that a case's time is its own and a hang can be told from a compile
    for deck, _ in DECKS:
        shutil.copy(deck, tmp / deck.name)
        print(json.dumps({"warmup": deck.name}), flush=True)
        print(json.dumps({"warmed": deck.name, "outcome": run_case(tmp / deck.name, a.budget)}), flush=True)
    for i in range(a.cases):
        deck, _ = DECKS[rng.randrange(len(DECKS))]
        text, kinds = mutate(deck.read_text(), rng)
        if i < a.first:
            continue
        path = tmp / deck.name
        path.write_text(text)
        print(json.dumps({"start": i}), flush=True)
        outcome = run_case(path, a.budget)
        print(json.dumps({"case": i, "deck": deck.name, "mutations": kinds, "outcome": outcome}), flush=True)
    shutil.rmtree(tmp, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
