"""Hard limits on absurd input and the command line's exit codes.

Inputs found by fuzzing that read without error and then ran without end (water density 1e-308,
CFL 1e-308, dtIC 0 with dynamic relaxation) must be refused before anything runs, with the
package's own error (exit code 2 on the command line) and a message naming the value; a
stiff seabed must show in the pre-run stability check; bad argument values give exit code 2
and one line, never a traceback.
"""

from __future__ import annotations

import logging
from pathlib import Path

import pytest

from moorline.cli import main as cli_main
from moorline.errors import DeckError, InputLimitError
from moorline.io import read_deck
from moorline.system import System
from moorline.system.limits import MAX_STEPS, WARN_STEPS, check_run

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "catenary_3line" / "catenary_3line.dat"
CABLE = ROOT / "examples" / "wec_cable" / "wec_cable.dat"


def _deck(tmp_path, source: Path, replace: dict[str, str]) -> Path:
    text = source.read_text()
    for old, new in replace.items():
        assert old in text, old
        text = text.replace(old, new)
    p = tmp_path / source.name
    p.write_text(text)
    return p


def _one_line(err: str) -> str:
    lines = [ln for ln in err.strip().splitlines() if ln.strip()]
    assert "Traceback" not in err
    assert len(lines) == 1, err
    return lines[0]


@pytest.mark.parametrize("replace, words", [
    ({"1025.0     rho": "1e-308     rho"}, ["water density rho = 1e-308", "1025"]),
    ({"0.002      dtM": "1e-308     CFL"}, ["CFL = 1e-308"]),
    ({"0.002      dtM": "1e-12      dtM"}, ["dtM = 1e-12 s is below"]),
    ({"1.0        dtIC": "0          dtIC"}, ["dtIC", "> 0"]),  # (the deck reader already refuses this one)
], ids=["rho", "cfl", "dtM", "dtIC"])
def test_absurd_values_are_refused_before_the_run(tmp_path, capsys, replace, words):
    deck = _deck(tmp_path, EXAMPLE, replace)
    with pytest.raises(DeckError):  # InputLimitError is a DeckError
        System(read_deck(deck))
    assert cli_main(["run", str(deck), "--duration", "1", "--out", str(tmp_path / "o"), "--quiet-progress"]) == 2
    err = capsys.readouterr().err
    assert "Traceback" not in err
    line = err.splitlines()[0]  # (a deck error quotes the row on a second line)
    assert all(w in line for w in words), line


def test_the_same_limits_for_models_built_in_python():
    model = read_deck(EXAMPLE)
    model.options.dtIC = 0.0
    with pytest.raises(InputLimitError, match="dtIC = 0.0"):
        System(model)
    model = read_deck(EXAMPLE)
    model.env.g = float("inf")
    with pytest.raises(InputLimitError, match="gravity g = inf"):
        System(model)


def test_astronomical_step_counts_are_refused_unless_forced(tmp_path, capsys, caplog):
    assert cli_main(["run", str(EXAMPLE), "--dtM", "1e-8", "--duration", "1e6", "--out", str(tmp_path),
                     "--quiet-progress"]) == 2
    assert "--force" in _one_line(capsys.readouterr().err)
    s = System.from_file(EXAMPLE, dtM=1e-6)
    with pytest.raises(InputLimitError, match="--force"):
        check_run(s, MAX_STEPS * 1e-6 * 10, solve_ic=False)
    with caplog.at_level(logging.WARNING, logger="moorline"):
        assert check_run(s, MAX_STEPS * 1e-6 * 10, solve_ic=False, force=True) > MAX_STEPS
    assert "time steps" in caplog.text
    caplog.clear()
    with caplog.at_level(logging.WARNING, logger="moorline"):
        check_run(s, WARN_STEPS * 1e-6 * 2, solve_ic=True)
    assert "hours of wall time" in caplog.text


@pytest.mark.parametrize("args, words", [
    (["--duration", "-5"], ["--duration", "-5"]),
    (["--duration", "inf"], ["--duration"]),
    (["--dt-out", "0"], ["--dt-out", "'0'"]),
    (["--dtM", "abc"], ["--dtM", "expected a number"]),
    (["--checkpoint-every", "0"], ["--checkpoint-every"]),
], ids=["negative-duration", "infinite-duration", "zero-dt-out", "text-dtM", "zero-checkpoint"])
def test_bad_argument_values_exit_2_with_one_line(capsys, args, words):
    with pytest.raises(SystemExit) as e:
        cli_main(["run", str(EXAMPLE), *args])
    assert e.value.code == 2
    line = _one_line(capsys.readouterr().err)
    assert all(w in line for w in words), line


def test_output_folder_that_cannot_be_made_exits_2(tmp_path, capsys):
    blocker = tmp_path / "file"
    blocker.write_text("a file where the folder should go")
    assert cli_main(["run", str(EXAMPLE), "--duration", "1", "--out", str(blocker / "out"), "--quiet-progress"]) == 2
    assert "cannot create the output folder" in _one_line(capsys.readouterr().err)


def test_missing_motion_file_exits_2(tmp_path, capsys):
    assert cli_main(["run", str(EXAMPLE), "--duration", "1", "--motion", str(tmp_path / "none.csv"), "--out",
                     str(tmp_path), "--quiet-progress"]) == 2
    assert "none.csv" in _one_line(capsys.readouterr().err)


def test_check_warns_and_strict_fails(tmp_path, capsys):
    """``moorline check`` exits 0 for a valid deck, with stability advice as a warning on stderr;
    ``--strict`` makes the warning an exit code 1. A stiff seabed under a cable that only reaches
    the seabed in motion is in the check (it once blew up unannounced)."""
    assert cli_main(["check", str(EXAMPLE)]) == 0
    assert "warning" not in capsys.readouterr().err
    stiff = _deck(tmp_path, CABLE, {"1.0e5      kBot": "3.0e14     kBot"})
    assert cli_main(["check", str(stiff)]) == 0
    cap = capsys.readouterr()
    assert "seabed contact stiffness" in cap.out
    assert "moorline: warning: dtM = 0.004 s is above the estimated stability limit" in cap.err
    assert cli_main(["check", str(stiff), "--strict"]) == 1


def test_a_dtic_longer_than_tmaxic_ends_the_relaxation_at_tmaxic(monkeypatch):
    """Fuzzer seed 2, case 63: the wave-energy cable example with dtIC 1e11 s. Newton did not
    converge from its catenary start, and the implicit relaxation then integrated towards t = dtIC
    (1e11 one-second steps, a hang) instead of stopping at TmaxIC. Newton is cut to one iteration
    here so that the relaxation runs whatever Newton's iteration budget, and the seabed-blend
    continuation before it and the relaxation-Newton alternation after it are switched off (this
    test is about the deck's own relaxation budget)."""
    import moorline.system.initial as initial

    monkeypatch.setattr(initial, "NEWTON_FIRST_IT", 1)
    monkeypatch.setattr(initial, "NEWTON_FIRST_IT_EXPLICIT", 1)
    monkeypatch.setattr(initial, "BLEND_WIDTHS", ())
    monkeypatch.setattr(initial, "RELAX_BUDGET", 0.0)
    model = read_deck(ROOT / "examples" / "wec_cable" / "wec_cable.dat")
    model.options.dtIC = 1.0e11
    s = System(model)
    s.init()  # returns (within TmaxIC of pseudo time), converged or not
    assert 0.0 < s.ic_report["pseudo_time"] <= model.options.TmaxIC + 1e-9
