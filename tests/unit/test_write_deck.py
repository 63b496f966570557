"""``write_deck`` (v2 and v1) and ``moorline convert``: every deck read, written and read again
gives the same model (field by field, floats exactly: ``repr``), over every public MoorDyn deck,
the conformance and example decks and a Python-built model with every section; v1 <-> v2; v1
refuses what it cannot express; and a converted deck runs to the same tensions, in moorline
(bitwise) and in MoorDyn (the live oracle reads our v2 decks as it reads the originals)."""

from __future__ import annotations

import os
import shutil
from pathlib import Path

import numpy as np
import pytest

from moorline.cli import main as cli_main
from moorline.io import read_deck, read_deck_text, write_deck
from moorline.model import Curve, Model, SyropeCurve
from moorline.model.water import Waves

from .model_compare import diff
from .test_deck import V1

ROOT = Path(__file__).resolve().parents[2]
SHARED = ROOT.parent / "shared"
PUBLIC = SHARED / "public_decks"
TEMPLATES = ("tests/Mooring/time_schemes.txt",)  # @DT@ placeholders: invalid in MoorDyn too


def _public() -> list[str]:
    lst = PUBLIC / "decks.txt"
    if not lst.is_file():
        return []
    return [ln.strip() for ln in lst.read_text().splitlines() if ln.strip() and not ln.strip().endswith(TEMPLATES)]


def _own() -> list[Path]:
    decks = sorted((ROOT / "examples").glob("*/*.dat"))
    inputs = SHARED / "conformance" / "inputs"
    if inputs.is_dir():
        decks += sorted(inputs.glob("*/*.txt")) + sorted(inputs.glob("*/*.dat"))
    # decks, not the data files beside them: a dashed LINE TYPES (or LINE DICTIONARY) header
    return [p for p in decks if "---" in (t := p.read_text(errors="replace").upper()) and
            ("LINE TYPES" in t or "LINE DICTIONARY" in t)]


def _run_dir(deck: Path) -> Path:
    """MoorDyn's tests run from the folder holding Mooring/ (SeafloorFile is relative to it)."""
    parts = deck.parts
    if "Mooring" in parts:
        return Path(*parts[:len(parts) - 1 - parts[::-1].index("Mooring")])
    return deck.parent


def _read_in_run_dir(deck: Path):
    """The deck read from the folder MoorDyn runs it from (it names its files relative to that)."""
    cwd = os.getcwd()
    os.chdir(_run_dir(deck))
    try:
        return read_deck(deck)
    finally:
        os.chdir(cwd)


def _round_trip(deck: Path, tmp_path: Path, version="v2"):
    a = _read_in_run_dir(deck)
    out = write_deck(a, tmp_path / "written.txt", version=version)
    b = read_deck(out)
    return a, b


def test_compare_sees_differences():
    a = read_deck_text(V1)
    b = read_deck_text(V1)
    assert diff(a, b) == []
    b.line_types["main"].Cd += 1e-12
    b.points[2].r[0] = 1.0
    b.options.dtWave = 0.3
    d = diff(a, b)
    assert len(d) == 3 and "Cd" in d[0] and "points[2].r" in d[1] and "dtWave" in d[2]


@pytest.mark.parametrize("name", _public() or ["(no ../shared)"])
def test_public_decks_round_trip(name, tmp_path):
    if not _public():
        pytest.skip("../shared/public_decks not available")
    a, b = _round_trip(PUBLIC / name, tmp_path)
    assert diff(a, b) == []


@pytest.mark.parametrize("deck", _own(), ids=lambda p: f"{p.parent.name}/{p.name}")
def test_own_decks_round_trip(deck, tmp_path):
    a, b = _round_trip(deck, tmp_path)
    assert diff(a, b) == []


def test_v1_round_trip_and_v1_v2_v1(tmp_path):
    m1 = read_deck_text(V1)
    p1 = write_deck(m1, tmp_path / "a_v1.txt", version="v1")
    text = p1.read_text()
    for head in ("LINE DICTIONARY", "NODE PROPERTIES", "LINE PROPERTIES", "SOLVER OPTIONS", "OUTPUTS"):
        assert head in text
    assert "\nEND\n" in text and "rhoW" in text
    # the v1 layouts: 9-column line types, length before the end points
    assert "main    0.0766  113.35        753600000.0  -1.0      0.8  0.25  2.0  0.4" in text
    assert "1     main      835.35    20       1         2         plt" in text
    assert "FrictionModel" not in text and "mu_kT" not in text  # v2-only keys at their defaults
    assert diff(read_deck(p1), m1) == []
    p2 = write_deck(read_deck(p1), tmp_path / "b_v2.txt")
    assert "LINE TYPES" in p2.read_text() and "CONNECTION" not in p2.read_text()
    p3 = write_deck(read_deck(p2), tmp_path / "c_v1.txt", version="v1")
    assert diff(read_deck(p3), m1) == []
    assert p3.read_text().splitlines()[2:] == text.splitlines()[2:]  # same text but the "written from" line


@pytest.mark.parametrize("name", ["NREL+MoorPy/tests/case1.dat",
                                  "FloatingArrayDesign+MoorDyn/example/lines.txt",
                                  "FloatingArrayDesign+MoorDyn/tests/Mooring/wavekin_2/wavekin_2.txt"])
def test_public_decks_to_v1(name, tmp_path):
    if not (PUBLIC / name).is_file():
        pytest.skip("../shared/public_decks not available")
    if "wavekin_2" in name:
        with pytest.raises(ValueError, match="MoorDyn v1 cannot express"):
            _round_trip(PUBLIC / name, tmp_path, "v1")
        return
    a, b = _round_trip(PUBLIC / name, tmp_path, "v1")
    assert diff(a, b) == []


def _everything(tmp_path: Path) -> Model:
    """A Python-built model with every section a deck can hold."""
    m = Model()
    m.env.depth = 120.0
    m.env.mu, m.env.kShear, m.env.contact = 0.3, 2e5, "vertical"
    m.options.dtM, m.options.tScheme, m.options.ICNewton = 1e-3, "RK4", 0
    m.add_line_type("chain", d=0.15, w=140.0, EA=Curve([0.0, 0.01, 0.02], [0.0, 1e7, 2.5e7]), BA=-0.8,
                    EI=Curve([0.0, 0.1], [0.0, 40.0]), Cd=2.4, Ca=1.0, CdAx=1.15, CaAx=0.5)
    m.add_line_type("visco", d=0.2, w=30.0, EA=5e8, BA=1e7, EA_D=9e8, BA_D=2e6, Cd=1.2, Ca=1.0)
    m.add_line_type("visco_mean", d=0.2, w=30.0, EA=5e8, BA=-0.5, EA_D=3e8, EA_D_Lm=20.0, BA_D=0.0)
    owc = Curve([0.0, 0.02, 0.05, 0.1], [0.0, 1e6, 4e6, 1.2e7])
    m.add_line_type("poly", d=0.2, w=30.0, EA=0.0, BA=1e8, BA_D=1e5, EA_D=1.5e8, EA_D_Lm=20.0,
                    syrope=SyropeCurve(owc, "QUADRATIC", 0.3, 0.7))
    m.add_line_type("viv", d=0.3, w=50.0, EA=1e9, EI=1e4, Cl=0.8, dF=0.1, cF=0.2)
    m.add_rod_type("can", d=2.0, w=1000.0, Cd=0.8, Ca=1.0, CdEnd=0.6, CaEnd=0.6)
    b1 = m.add_body("free", (1.0, 2.0, -3.0), (1.0, 2.0, 3.0), m=1e5, rCG=(0.1, 0.2, -1.0), I=(1e6, 2e6, 3e6),
                    V=120.0, CdA=(1.0, 1.0, 2.0, 3.0, 3.0, 3.0), Ca=(1.0, 0.5, 0.7))
    b2 = m.add_body("coupled", (0.0, 0.0, 0.0), m=0.0, rCG=(0.0, 0.0, -2.0), I=5.0, CdA=(4.0,) * 3 + (5.0,) * 3)
    m.add_body("coupledpinned", (0.0, 30.0, -5.0), m=1e4, I=(1e3, 1e3, 1e3), V=10.0, CdA=1.0, Ca=1.0)
    ra, rb = m.add_rod("can", "body", (0.0, 0.0, 0.0), (0.0, 0.0, -10.0), N=4, outputs="p", body=b1)
    za, _ = m.add_rod("can", "free", (20.0, 0.0, -40.0), (21.0, 0.0, -40.0), N=0)  # zero-length, end B unused
    m.add_rod("can", "bodypinned", (1.0, 0.0, 0.0), (1.0, 0.0, -5.0), N=2, body=b2)
    m.add_rod("can", "coupledpinned", (50.0, 0.0, -10.0), (50.0, 0.0, -20.0), N=3)
    anchors = [m.add_point("fixed", (x, y, -120.0)) for x, y in ((400.0, 0.0), (-400.0, 0.0), (0.0, 400.0))]
    fair = m.add_point("body", (5.0, 0.0, -2.0), body=b2)
    clump = m.add_point("free", (200.0, 0.0, -100.0), m=5e3, V=1.0, CdA=2.0, Ca=1.0, F_ext=(0.0, 10.0, -20.0))
    m.add_line("chain", anchors[0], clump, L=210.0, N=10, outputs="pt")
    m.add_line("visco", clump, fair, L=-1.05, N=8)
    m.add_line("visco_mean", anchors[1], rb, L=390.0, N=12)
    ln = m.add_line("poly", anchors[2], za, L=360.0, N=6)
    ln.syrope_ic = (2e6, 1.5e6)
    m.add_line("viv", za, ra, L=50.0, N=5)
    m.outputs = ["FairTen1", "Body1Pz", "Rod1NAPZ"]
    m.options.not_acted_on = {"inertialF": "1"}
    m.validate()
    return m


def test_python_model_with_every_section(tmp_path):
    m = _everything(tmp_path)
    out = write_deck(m, tmp_path / "all.txt")
    text = out.read_text()
    assert "SYROPE:all_poly_syrope.txt|150000000.0|20.0" in text
    assert "500000000.0|900000000.0" in text and "10000000.0|2000000.0" in text  # EA_s|EA_d, BA_s|BA_d
    assert "R1B" in text and "Body2" in text and "Body1Pinned" not in text and "Body2Pinned" in text
    assert (tmp_path / "all_chain_EA.txt").is_file() and (tmp_path / "all_poly_OWC.txt").is_file()
    sections = [ln.split()[1] for ln in text.splitlines() if ln.startswith("-----") and len(ln.split()) > 2]
    assert sections[1:9] == ["LINE", "ROD", "BODIES", "RODS", "POINTS", "LINES", "SYROPE", "OPTIONS"]
    back = read_deck(out)
    assert diff(m, back) == []


def test_v1_refuses_what_it_cannot_express(tmp_path):
    m = _everything(tmp_path)
    with pytest.raises(ValueError, match="3 bodies and 4 rods: MoorDyn v1 has neither"):
        write_deck(m, tmp_path / "x.txt", version="v1")
    cases = [
        (lambda m: setattr(m.line_types["main"], "EI", 10.0), "bending stiffness"),
        (lambda m: setattr(m.line_types["main"], "Cl", 0.8), "VIV"),
        (lambda m: setattr(m.line_types["main"], "EA", Curve([0.0, 0.1], [0.0, 1e7])), "EA or BA curve"),
        (lambda m: setattr(m.env, "mu", 0.5), "seabed friction"),
        (lambda m: setattr(m.lines[0], "L", -1.02), "fraction of the end-to-end distance"),
        (lambda m: setattr(m.options, "WaveKin", 7), "wave kinematics"),
    ]
    for change, message in cases:
        m1 = read_deck_text(V1)
        change(m1)
        with pytest.raises(ValueError, match=message):
            write_deck(m1, tmp_path / "x.txt", version="v1")


def test_writer_refuses_python_waves_and_floating(tmp_path):
    m = read_deck_text(V1)
    m.env.waves = Waves.regular(2.0, 8.0)
    with pytest.raises(ValueError, match="waves were set in Python"):
        write_deck(m, tmp_path / "x.txt")
    with pytest.raises(ValueError, match="version must be"):
        write_deck(read_deck_text(V1), tmp_path / "x.txt", version="v3")


def test_failures_round_trip_and_v1_refuses_them(tmp_path):
    """The FAILURE section: a time, a load, both (rows keep their order, 0 for a trigger not set)."""
    m = read_deck_text(V1)
    m.add_failure(m.lines[0].end_b, [0], time=5.0)
    m.add_failure(m.lines[1].end_a, [1], tension=2.5e6)
    m.add_failure(m.lines[0].end_a, [0], time=1.25, tension=3.0e5)
    out = write_deck(m, tmp_path / "failing.txt")
    assert "FAILURE" in out.read_text()
    back = read_deck(out)
    assert len(back.failures) == 3
    assert diff(m.failures, back.failures) == []
    assert diff(m, back) == []
    with pytest.raises(ValueError, match="MoorDyn v1 has no FAILURE section"):
        write_deck(m, tmp_path / "x.txt", version="v1")


def test_water_files_are_copied(tmp_path):
    deck = PUBLIC / "FloatingArrayDesign+MoorDyn/tests/Mooring/wavekin_2/wavekin_2_curr2.txt"
    if not deck.is_file():
        pytest.skip("../shared/public_decks not available")
    a, b = _round_trip(deck, tmp_path)
    assert diff(a, b) == []
    assert (a.options.WaveKin, a.options.Currents) == (2, 2)
    for name in ("wave_frequencies.txt", "water_grid.txt", "current_profile_dynamic.txt"):
        assert (tmp_path / name).read_bytes() == (deck.parent / name).read_bytes()


def test_cli_convert(tmp_path, capsys):
    src = tmp_path / "v1.txt"
    src.write_text(V1)
    assert cli_main(["convert", str(src), str(tmp_path / "v2.txt")]) == 0
    assert cli_main(["convert", str(tmp_path / "v2.txt"), str(tmp_path / "back.txt"), "--to", "v1"]) == 0
    assert diff(read_deck(tmp_path / "back.txt"), read_deck(src)) == []
    assert "MoorDyn v1 layout" in capsys.readouterr().out
    assert cli_main(["convert", str(src), str(src)]) == 2
    m = _everything(tmp_path)
    write_deck(m, tmp_path / "all.txt")
    assert cli_main(["convert", str(tmp_path / "all.txt"), str(tmp_path / "all_v1.txt"), "--to", "v1"]) == 2
    assert "cannot be written as a MoorDyn v1 deck" in capsys.readouterr().err
    assert not (tmp_path / "all_v1.txt").exists()


# ----------------------------------------------------------------------------- converted decks run the same
SAME_RUN = ["FloatingArrayDesign+MoorDyn/tests/Mooring/syrope/linear_wc/line.txt",
            "FloatingArrayDesign+MoorDyn/tests/Mooring/BodiesAndRods.dat",
            "FloatingArrayDesign+MoorDyn/tests/Mooring/polyester/visco.txt",
            "FloatingArrayDesign+MoorDyn/tests/Mooring/seafloor.txt",
            "NREL+MoorPy/tests/case4.dat"]


def _copy_converted(name: str, tmp_path: Path) -> tuple[Path, Path]:
    """The deck's repository copied to tmp_path (MoorDyn writes outputs beside decks) and the
    converted v2 deck beside the copy of the original."""
    repo = name.split("/")[0]
    shutil.copytree(PUBLIC / repo, tmp_path / repo)
    orig = tmp_path / name
    model = _read_in_run_dir(orig)
    conv = write_deck(model, orig.with_name("converted_" + orig.name))
    return orig, conv


def _moorline_tensions(deck: Path) -> np.ndarray:
    from moorline.system import System

    cwd = os.getcwd()
    os.chdir(_run_dir(deck))
    try:
        s = System(read_deck(deck))
    finally:
        os.chdir(cwd)
    x0 = s.deck_coupled_positions()
    s.init(x0, np.zeros_like(x0), solve_ic=False)
    out = []
    for k in range(5):
        x = x0 + 0.01 * (k + 1)
        s.step(x, np.full_like(x0, 0.1), 0.02 * k, 0.02)
        out.append([[ln.anchor_tension(), ln.fairlead_tension()] for ln in s.lines])
    return np.array(out)


@pytest.mark.parametrize("name", SAME_RUN)
def test_converted_deck_runs_the_same_in_moorline(name, tmp_path):
    if not (PUBLIC / name).is_file():
        pytest.skip("../shared/public_decks not available")
    orig, conv = _copy_converted(name, tmp_path)
    a, b = _moorline_tensions(orig), _moorline_tensions(conv)
    assert np.all(a > 0) or np.any(a > 0)
    np.testing.assert_array_equal(a, b)


def _moordyn_tensions(deck: Path, run_dir: Path) -> np.ndarray:
    import moordyn as md

    cwd = os.getcwd()
    os.chdir(run_dir)
    try:
        s = md.Create(str(deck))
        n = md.NCoupledDOF(s)
        x0 = np.zeros(n)
        # coupled layout (bodies, rods, points) from MoorDyn itself
        xs = []
        for i in range(1, md.GetNumberBodies(s) + 1):
            b = md.GetBody(s, i)
            if md.GetBodyType(b) == md.BODY_TYPE_COUPLED:
                xs += list(md.GetBodyPos(b)) + list(md.GetBodyAngle(b))
        for i in range(1, md.GetNumberRods(s) + 1):
            r = md.GetRod(s, i)
            if md.GetRodType(r) in (md.ROD_TYPE_COUPLED, md.ROD_TYPE_CPLDPIN):
                xs += list(md.GetRodNodePos(r, 0)) + ([0.0] * 3 if md.GetRodType(r) == md.ROD_TYPE_COUPLED else [])
        for i in range(1, md.GetNumberPoints(s) + 1):
            p = md.GetPoint(s, i)
            if md.GetPointType(p) == md.POINT_TYPE_COUPLED:
                xs += list(md.GetPointPos(p))
        x0[:len(xs)] = xs
        md.Init(s, x0, np.zeros(n))
        lines = [md.GetLine(s, i) for i in range(1, md.GetNumberLines(s) + 1)]
        out = []
        for k in range(5):
            md.Step(s, x0 + 0.01 * (k + 1), np.full(n, 0.1), 0.02 * k, 0.02)
            out.append([md.GetLineFairTen(ln) for ln in lines])
        md.Close(s)
    finally:
        os.chdir(cwd)
    return np.array(out)


@pytest.mark.oracle
@pytest.mark.parametrize("name", SAME_RUN)
def test_moordyn_reads_converted_deck_the_same(name, tmp_path):
    pytest.importorskip("moordyn")
    if not (PUBLIC / name).is_file():
        pytest.skip("../shared/public_decks not available")
    orig, conv = _copy_converted(name, tmp_path)
    # MoorDyn opens SeafloorFile from its working directory: the converted deck names its grid
    # beside itself, so it runs from its own folder (the public deck names Mooring/...)
    a, b = _moordyn_tensions(orig, _run_dir(orig)), _moordyn_tensions(conv, conv.parent)
    assert np.any(a > 0)
    # MoorDyn parses numbers with atof: repr() round trips exactly, so the runs are identical
    np.testing.assert_array_equal(a, b)
