"""Seabed bathymetry grid files: MoorDyn-C SeafloorFile and MoorDyn-F WtrDpth layouts."""

from __future__ import annotations

import logging
import random
from pathlib import Path

import numpy as np
import pytest

from moorline.errors import DeckError
from moorline.io.bathymetry import find_seafloor_file, read_depth_grid, read_seafloor_grid
from moorline.model.types import Bathymetry

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
CORPUS = SHARED / "conformance" / "inputs" / "seafloor3d_slope" / "seafloor_profile_3d.txt"


def _write(tmp_path: Path, text: str, name: str = "grid.txt") -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _raises(reader, path: Path, line: int | None, *fragments: str) -> DeckError:
    with pytest.raises(DeckError) as info:
        reader(path)
    e = info.value
    assert e.line == line, str(e)
    assert e.file == str(path)
    msg = str(e)
    for f in fragments:
        assert f in msg, f"{f!r} not in {msg!r}"
    return e


def _c_grid(x, y, zfun, order=None, extra_head="") -> str:
    """Text of a MoorDyn-C grid file with rows in the given order (list of (i, j))."""
    nodes = order or [(i, j) for i in range(len(x)) for j in range(len(y))]
    out = [extra_head + f"{len(x)} {len(y)}", " ".join(repr(v) for v in x), " ".join(repr(v) for v in y)]
    out += [f"{x[i]!r} {y[j]!r} {zfun(x[i], y[j])!r}" for i, j in nodes]
    return "\n".join(out) + "\n"


# ------------------------------------------------------------------------------ corpus file
@pytest.fixture(scope="module")
def corpus() -> Bathymetry:
    if not CORPUS.is_file():
        pytest.skip(f"shared conformance corpus not available ({CORPUS})")
    return read_seafloor_grid(CORPUS)


def test_corpus_grid_plane(corpus):
    b = corpus
    assert b.z.shape == (5, 100)
    assert b.x.shape == (100,) and b.y.shape == (5,)
    assert b.x[0] == -50.0 and b.x[-1] == 50.0
    np.testing.assert_array_equal(b.y, [-2.0, -1.0, 0.0, 1.0, 2.0])
    expected = -30.0 + 0.2 * b.x[None, :] * np.ones((5, 1))
    np.testing.assert_allclose(b.z, expected, rtol=0, atol=1e-12)
    assert b.source == str(CORPUS)


def test_corpus_mean_depth(corpus):
    # MoorDyn: sum of the z values / (nx*ny), as a positive depth
    assert corpus.mean_depth == pytest.approx(30.0, abs=1e-12)
    assert -corpus.z.sum() / (100 * 5) == pytest.approx(30.0, abs=1e-12)


def test_corpus_bilinear_exact_on_plane_and_clamped(corpus):
    rng = np.random.default_rng(3)
    xs = rng.uniform(-50, 50, 200)
    ys = rng.uniform(-2, 2, 200)
    np.testing.assert_allclose(corpus.height(xs, ys), -30.0 + 0.2 * xs, rtol=0, atol=1e-12)
    # outside the grid the height is clamped to the edge values
    assert corpus.height(80.0, 0.3) == pytest.approx(-20.0, abs=1e-12)
    assert corpus.height(-75.0, -9.0) == pytest.approx(-40.0, abs=1e-12)
    assert corpus.height(10.0, 40.0) == pytest.approx(-28.0, abs=1e-12)


# --------------------------------------------------------------------- MoorDyn-C layout: good
def test_c_grid_shuffled_rows_comments_tabs(tmp_path):
    x = [0.0, 10.0, 25.0, 40.0]
    y = [-5.0, 0.0, 5.0]

    def zf(a, b):
        return -50.0 + 0.1 * a - 0.3 * b + 0.01 * a * b

    order = [(i, j) for i in range(4) for j in range(3)]
    random.Random(7).shuffle(order)
    text = _c_grid(x, y, zf, order, extra_head="# a bathymetry grid\n\n")
    text = text.replace(" ", "\t", 5) + "\n# trailing comment\n"
    b = read_seafloor_grid(_write(tmp_path, text))
    assert b.z.shape == (3, 4)
    for i, xv in enumerate(x):
        for j, yv in enumerate(y):
            assert b.z[j, i] == zf(xv, yv)
    # bilinear reproduces the bilinear function exactly inside each cell
    assert b.height(17.0, 2.0) == pytest.approx(zf(17.0, 2.0), abs=1e-12)


def test_c_grid_tick_tolerance(tmp_path):
    text = "2 2\n0 100\n0 50\n0 0 -10\n100.00000000001 0 -12\n0 50 -11\n100 49.99999999999 -13\n"
    b = read_seafloor_grid(_write(tmp_path, text))
    np.testing.assert_array_equal(b.z, [[-10, -12], [-11, -13]])


@pytest.mark.parametrize("nx, ny", [(1, 1), (1, 4), (4, 1)])
def test_c_grid_degenerate_shapes(tmp_path, nx, ny):
    x = [float(3 * i) for i in range(nx)]
    y = [float(-2 + 2 * j) for j in range(ny)]

    def zf(a, b):
        return -20.0 - 0.5 * a + 0.25 * b

    b = read_seafloor_grid(_write(tmp_path, _c_grid(x, y, zf)))
    assert b.z.shape == (ny, nx)
    # a single tick in a direction: constant along it
    for xv in (-10.0, x[0], 1.3, 50.0):
        for yv in (-7.0, y[0], 0.4, 9.0):
            xc = min(max(xv, x[0]), x[-1])
            yc = min(max(yv, y[0]), y[-1])
            assert b.height(xv, yv) == pytest.approx(zf(xc, yc), abs=1e-12)


def test_c_grid_single_node_is_flat(tmp_path):
    b = read_seafloor_grid(_write(tmp_path, "1 1\n7.5\n-3\n7.5 -3 -42.0\n"))
    assert b.z.shape == (1, 1)
    pts = np.array([[-1e3, -1e3], [0, 0], [7.5, -3], [1e4, 55.0]])
    np.testing.assert_array_equal(b.height(pts[:, 0], pts[:, 1]), -42.0)
    assert b.mean_depth == 42.0


def test_c_grid_warns_on_positive_heights(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        read_seafloor_grid(_write(tmp_path, "1 2\n0\n0 1\n0 0 40\n0 1 40\n"))
    assert "not a depth" in caplog.text


# -------------------------------------------------------------------- MoorDyn-C layout: errors
def test_c_err_header_count(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "\n# c\n3 2 1\n"), 3, "'nx ny'", "got 3 value(s)")


def test_c_err_header_not_whole(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "0 2\n"), 1, "nx", "whole number >= 1", "'0'")
    _raises(read_seafloor_grid, _write(tmp_path, "2 2.5\n"), 1, "ny", "whole number >= 1", "'2.5'")


def test_c_err_x_count(tmp_path):
    p = _write(tmp_path, "3 2\n# ticks\n0 1\n0 1\n")
    e = _raises(read_seafloor_grid, p, 3, "expected exactly 3 x values", "nx = 3 on line 1", "got 2")
    assert "0 1" in str(e)  # the row text


def test_c_err_y_count(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "2 3\n0 1\n\n0 1 2 3\n"), 4, "expected exactly 3 y values",
            "got 4")


def test_c_err_x_not_ascending(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "3 1\n0 5 5\n0\n"), 2, "x values must be strictly ascending",
            "value 3 (5)")


def test_c_err_y_not_ascending(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "1 3\n0\n2 1 3\n"), 3, "y values must be strictly ascending")


def test_c_err_row_with_two_values(tmp_path):
    p = _write(tmp_path, "2 1\n0 1\n0\n0 0 -5\n1 0\n")
    _raises(read_seafloor_grid, p, 5, "'x y z' (3 numbers)", "got 2 value(s)")


def test_c_err_row_off_x_tick(tmp_path):
    p = _write(tmp_path, "2 2\n0 10\n0 5\n0 0 -5\n0 5 -5\n\n7.5 0 -5\n10 5 -5\n")
    _raises(read_seafloor_grid, p, 7, "x = 7.5 is not one of the 2 x ticks of line 2", "0, 10")


def test_c_err_row_off_y_tick(tmp_path):
    p = _write(tmp_path, "2 2\n0 10\n0 5\n0 0 -5\n0 5.001 -5\n")
    _raises(read_seafloor_grid, p, 5, "y = 5.001 is not one of the 2 y ticks of line 3")


def test_c_err_duplicate_node(tmp_path):
    p = _write(tmp_path, "2 2\n0 10\n0 5\n0 0 -5\n10 5 -6\n0 5 -7\n10 5.0 -8\n10 0 -9\n")
    _raises(read_seafloor_grid, p, 7, "(x = 10, y = 5) is listed twice", "first on line 5", "exactly once")


def test_c_err_missing_node(tmp_path):
    p = _write(tmp_path, "2 2\n0 10\n0 5\n0 0 -5\n10 5 -6\n0 5 -7\n# end\n")
    _raises(read_seafloor_grid, p, 6, "expected nx*ny = 4 node rows", "found 3", "(x = 10, y = 0)",
            "z = 0", "seabed at the still-water surface")


def test_c_err_bad_number(tmp_path):
    p = _write(tmp_path, "2 1\n0 1\n0\n0 0 -5\n1 0 -5,5\n")
    _raises(read_seafloor_grid, p, 5, "z: expected a finite number", "'-5,5'")
    p = _write(tmp_path, "2 1\n0 abc\n0\n")
    _raises(read_seafloor_grid, p, 2, "x value: expected a finite number", "'abc'")
    p = _write(tmp_path, "1 1\n0\n0\n0 0 nan\n")
    _raises(read_seafloor_grid, p, 4, "expected a finite number", "'nan'")


def test_c_err_comma_separated(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "2,2\n"), 1, "'nx ny'", "got 1 value(s)")


def test_c_err_truncated_and_empty(tmp_path):
    _raises(read_seafloor_grid, _write(tmp_path, "2 2\n0 1\n"), 2, "file ends before the line of 2 y values")
    _raises(read_seafloor_grid, _write(tmp_path, "# nothing\n\n"), 2, "empty seafloor grid file")


def test_c_err_no_such_file(tmp_path):
    p = tmp_path / "absent.txt"
    _raises(read_seafloor_grid, p, None, "cannot read seafloor grid file")


# --------------------------------------------------------------------- MoorDyn-F layout: good
F_TEXT = """--- MoorDyn bathymetry: 40 m at x = -100 to 20 m at x = 100 ---
nGridX 3
NGRIDY 2   ! trailing words are ignored
        -100   0    100
-10      40    30   20
 10      40    30   20
"""


def test_f_grid(tmp_path):
    b = read_depth_grid(_write(tmp_path, F_TEXT))
    assert b.z.shape == (2, 3)
    np.testing.assert_array_equal(b.x, [-100, 0, 100])
    np.testing.assert_array_equal(b.y, [-10, 10])
    np.testing.assert_array_equal(b.z, [[-40, -30, -20], [-40, -30, -20]])
    assert b.height(50.0, 3.0) == pytest.approx(-25.0)
    assert b.mean_depth == pytest.approx(30.0)


def test_f_grid_title_verbatim_blank_and_comment_lines(tmp_path):
    text = "nGridX 5 looks like a key but is the title\n\nngridx\t2\n# c\nnGridY 1\n0 10\n\n5 12.5 17.5 # d\n"
    b = read_depth_grid(_write(tmp_path, text))
    np.testing.assert_array_equal(b.z, [[-12.5, -17.5]])
    np.testing.assert_array_equal(b.y, [5.0])


def test_f_grid_single_node_is_flat(tmp_path):
    b = read_depth_grid(_write(tmp_path, "t\nnGridX 1\nnGridY 1\n0\n0 55\n"))
    np.testing.assert_array_equal(b.height(np.array([-500.0, 0.0, 800.0]), np.array([3.0, 0.0, -90.0])), -55.0)


def test_f_and_c_layouts_agree(tmp_path):
    x = [-100.0, 0.0, 100.0]
    y = [-10.0, 10.0]
    c = read_seafloor_grid(_write(tmp_path, _c_grid(x, y, lambda a, b: -30.0 + 0.1 * a), "c.txt"))
    f = read_depth_grid(_write(tmp_path, F_TEXT, "f.txt"))
    np.testing.assert_array_equal(c.z, f.z)


# -------------------------------------------------------------------- MoorDyn-F layout: errors
def test_f_err_ngridx_missing(tmp_path):
    p = _write(tmp_path, "title\nnGridY 2\nnGridX 3\n")
    _raises(read_depth_grid, p, 2, "expected 'nGridX <n>'", "'nGridY'")
    p = _write(tmp_path, "title\n")
    _raises(read_depth_grid, p, 1, "file ends before the 'nGridX <n>' line")


def test_f_err_ngridy_value(tmp_path):
    _raises(read_depth_grid, _write(tmp_path, "t\nnGridX 2\nnGridY\n"), 3, "nGridY", "value is missing")
    _raises(read_depth_grid, _write(tmp_path, "t\nnGridX 2\nnGridY 1.5\n"), 3, "whole number >= 1", "'1.5'")


def test_f_err_x_count(tmp_path):
    p = _write(tmp_path, "t\nnGridX 3\nnGridY 1\n0 1\n0 5 5 5\n")
    _raises(read_depth_grid, p, 4, "expected exactly 3 x values", "nGridX = 3 on line 2", "got 2")


def test_f_err_x_not_ascending(tmp_path):
    p = _write(tmp_path, "t\nnGridX 3\nnGridY 1\n0 2 1\n0 5 5 5\n")
    _raises(read_depth_grid, p, 4, "x values must be strictly ascending")


def test_f_err_depth_row_count(tmp_path):
    p = _write(tmp_path, "t\nnGridX 3\nnGridY 2\n0 1 2\n0 5 5 5\n1 5 5\n")
    _raises(read_depth_grid, p, 6, "'y D_1 ... D_3'", "4 numbers", "got 3 value(s)")


def test_f_err_y_not_ascending(tmp_path):
    p = _write(tmp_path, "t\nnGridX 1\nnGridY 2\n0\n4 5\n\n4 6\n")
    _raises(read_depth_grid, p, 7, "y values must be strictly ascending", "line 5")


def test_f_err_bad_depth(tmp_path):
    p = _write(tmp_path, "t\nnGridX 2\nnGridY 1\n0 1\n0 5 deep\n")
    _raises(read_depth_grid, p, 5, "depth: expected a finite number", "'deep'")


def test_f_err_too_few_rows(tmp_path):
    p = _write(tmp_path, "t\nnGridX 1\nnGridY 3\n0\n0 5\n1 5\n")
    _raises(read_depth_grid, p, 6, "file ends before all 3 depth rows", "nGridY = 3 on line 3", "found 2")


def test_f_err_too_many_rows(tmp_path):
    p = _write(tmp_path, "t\nnGridX 1\nnGridY 1\n0\n0 5\n1 5\n")
    _raises(read_depth_grid, p, 6, "expected exactly 1 depth rows", "row 2")


def test_f_warns_on_non_positive_depth(tmp_path, caplog):
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        read_depth_grid(_write(tmp_path, "t\nnGridX 1\nnGridY 1\n0\n0 -3\n"))
    assert "depths in this layout are positive" in caplog.text


# ------------------------------------------------------------------------- find_seafloor_file
def test_find_prefers_deck_folder(tmp_path, monkeypatch, caplog):
    deck_dir = tmp_path / "deck"
    work = tmp_path / "work"
    deck_dir.mkdir()
    work.mkdir()
    (deck_dir / "sea.txt").write_text("1 1\n0\n0\n0 0 -1\n")
    (work / "sea.txt").write_text("1 1\n0\n0\n0 0 -2\n")
    monkeypatch.chdir(work)
    with caplog.at_level(logging.INFO, logger="moorline.io"):
        p = find_seafloor_file("sea.txt", deck_dir)
    assert p == deck_dir / "sea.txt"
    assert "deck's folder" in caplog.text
    assert read_seafloor_grid(p).z[0, 0] == -1.0


def test_find_falls_back_to_cwd(tmp_path, monkeypatch, caplog):
    deck_dir = tmp_path / "deck"
    work = tmp_path / "work"
    deck_dir.mkdir()
    (work / "sub").mkdir(parents=True)
    (work / "sub" / "sea.txt").write_text("1 1\n0\n0\n0 0 -2\n")
    monkeypatch.chdir(work)
    with caplog.at_level(logging.INFO, logger="moorline.io"):
        p = find_seafloor_file("sub/sea.txt", str(deck_dir))
    assert p.resolve() == (work / "sub" / "sea.txt").resolve()
    assert "working directory" in caplog.text


def test_find_absolute_and_none(tmp_path, monkeypatch):
    f = tmp_path / "abs.txt"
    f.write_text("x")
    assert find_seafloor_file(f, tmp_path / "elsewhere") == f
    monkeypatch.chdir(tmp_path)
    assert find_seafloor_file("abs.txt", None).resolve() == f.resolve()


def test_find_error_names_both(tmp_path, monkeypatch):
    deck_dir = tmp_path / "deck"
    work = tmp_path / "work"
    deck_dir.mkdir()
    work.mkdir()
    monkeypatch.chdir(work)
    with pytest.raises(DeckError) as info:
        find_seafloor_file("nowhere.txt", deck_dir)
    msg = str(info.value)
    assert str(deck_dir / "nowhere.txt") in msg and "deck's folder" in msg
    assert str(work / "nowhere.txt") in msg and "working directory" in msg
