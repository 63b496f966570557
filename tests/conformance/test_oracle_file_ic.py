"""``fileIC``: a run starts from MoorDyn's saved state (a MoorDyn-C SaveState file), against
MoorDyn-C 2.7.2 live (issue 18).

MoorDyn runs the clump-on-two-lines deck (tests/conformance/test_oracle_failure.py) for 0.7 s,
saves its state and runs on for 1 s. moorline, given a deck with ``fileIC`` naming that file (and
TmaxIC 0), must start with every internal node and the clump where MoorDyn left them, moving as they
were (exactly: the file holds the numbers), and then run as MoorDyn ran on (node tensions within
1e-6 of the largest; measured 3e-12). Malformed files are refused with the file named.

MoorDyn-C 2.7.2 itself reads the ``fileIC`` option and does not act on it (observed: its Init starts
from its own initial conditions, without a message); docs/moordyn_differences.md says so.
"""

from __future__ import annotations

import numpy as np
import pytest

from moorline.errors import DeckError
from moorline.io import read_deck
from moorline.system import System

from .test_oracle_failure import VEE

md = pytest.importorskip("moordyn")
pytestmark = pytest.mark.oracle

DT = 0.1


def _state(m):
    lines = [md.GetLine(m, i) for i in (1, 2)]
    pos = np.array([md.GetLineNodePos(ln, j) for ln in lines for j in range(11)])
    vel = np.array([md.GetLineNodeVel(ln, j) for ln in lines for j in range(11)])
    p3 = md.GetPoint(m, 3)
    return pos, vel, np.array(md.GetPointPos(p3)), np.array(md.GetPointVel(p3))


@pytest.fixture(scope="module")
def saved(tmp_path_factory):
    d = tmp_path_factory.mktemp("file_ic")
    (d / "vee.txt").write_text(VEE.format(failure=""))
    m = md.Create(str(d / "vee.txt"))
    md.SetVerbosity(m, md.LEVEL_ERR)
    md.Init(m, [], [])
    for k in range(7):
        md.Step(m, [], [], k * DT, DT)
    md.SaveState(m, str(d / "vee.state"))
    ref = _state(m)
    tensions = []
    for k in range(7, 17):
        md.Step(m, [], [], k * DT, DT)
        tensions.append([np.array([np.linalg.norm(md.GetLineNodeTen(md.GetLine(m, i), j)) for j in range(11)])
                         for i in (1, 2)])
    md.Close(m)
    deck = d / "vee_ic.txt"
    deck.write_text(VEE.format(failure="").replace("0             TmaxIC", "0             TmaxIC\nvee.state  fileIC"))
    return d, deck, ref, tensions


def test_moorline_starts_from_moordyn_state(saved):
    _, deck, ref, tensions = saved
    s = System(read_deck(deck), loads_at="last_stage")
    s.init()
    pos = np.vstack([ln.node_positions() for ln in s.lines])
    vel = np.vstack([ln.node_velocities() for ln in s.lines])
    assert np.array_equal(pos, ref[0])
    assert np.array_equal(vel, ref[1])
    assert np.array_equal(s.points[2].position(), ref[2]) and np.array_equal(s.points[2].velocity(), ref[3])
    assert s.ic_report["file_ic"].endswith("vee.state")
    # and runs on as MoorDyn ran on from there
    worst = 0.0
    for k, ten in enumerate(tensions):
        s.step(None, None, k * DT, DT)
        for i in (0, 1):
            worst = max(worst, float(np.max(np.abs(ten[i] - s.lines[i].node_tensions()))) / 20e3)
    assert worst < 1e-6


def test_bad_state_files(saved, tmp_path):
    d, deck, _, _ = saved
    good = (d / "vee.state").read_bytes()
    for name, data, msg in (("short", good[:-8], "truncated"), ("text", b"hello world" * 4, "not a MoorDyn state")):
        p = tmp_path / "x.state"
        p.write_bytes(data)
        text = deck.read_text().replace("vee.state", str(p))
        q = tmp_path / f"{name}.txt"
        q.write_text(text)
        s = System(read_deck(q))
        with pytest.raises(DeckError, match=msg) as e:
            s.init()
        assert str(p) in str(e.value)
    # a state of another deck (one line fewer)
    other = tmp_path / "one.txt"
    other.write_text(VEE.format(failure="").replace("2     main       2        3         58.0      10      -\n", "")
                     .replace("0             TmaxIC", f"0             TmaxIC\n{d / 'vee.state'}  fileIC"))
    with pytest.raises(DeckError, match="state file with 5 objects; this deck has 0 bodies, 0 rods, 3 points and 1"):
        System(read_deck(other)).init()
