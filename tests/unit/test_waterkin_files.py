"""MoorDyn-C water-kinematics files (spec 1.11.3, 4) and the WaveKin / Currents options.

Small files of our own under ``tests/data/waterkin/`` check what each reader gives; files written
to tmp_path check every located error (file, 1-based line, what was expected). The conformance
corpus' inputs (../shared/conformance/inputs, MoorDyn's own data, read-only) are read where
present.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np
import pytest

from moorline.core.waterkin import (
    CURRENT_GRID,
    WAVES_EXTERNAL,
    WAVES_GRID,
    WAVES_SUM,
    WRAP_MOORDYN,
    build_water_kinematics,
    fluid_kinematics,
    wave_numbers,
)
from moorline.errors import DeckError
from moorline.io.waterkin import (
    read_current_profile,
    read_current_profile_4d,
    read_current_profile_dynamic,
    read_water_grid,
    read_wave_elevation,
    read_wave_frequencies,
    water_from_options,
    waves_fft_grid,
    waves_summed,
)

DATA = Path(__file__).resolve().parents[1] / "data" / "waterkin"
SHARED = Path(__file__).resolve().parents[2].parent / "shared"
INPUTS = SHARED / "conformance" / "inputs"

G, RHO, DEPTH = 9.80665, 1025.0, 30.0


def _write(tmp_path: Path, name: str, text: str) -> Path:
    p = tmp_path / name
    p.write_text(text, encoding="utf-8")
    return p


def _raises(reader, path: Path, line: int | None, *fragments: str) -> DeckError:
    with pytest.raises(DeckError) as info:
        reader(path)
    e = info.value
    assert e.line == line, str(e)
    assert e.file == str(path), str(e)
    for f in fragments:
        assert f in str(e), f"{f!r} not in {str(e)!r}"
    return e


def _build(waves, current=None, **kw):
    return build_water_kinematics(waves, current, depth=DEPTH, g=G, rho=RHO, **kw)


# ------------------------------------------------------------------------- wave_frequencies.txt
def test_wave_frequencies_rows():
    tab = read_wave_frequencies(DATA / "wave_frequencies.txt")
    np.testing.assert_array_equal(tab.omega, [0.0, 0.4, 0.6, 1.0])
    np.testing.assert_array_equal(tab.amplitude, [0.0, 0.5, 0.25j, 0.1 - 0.1j])
    np.testing.assert_array_equal(tab.heading, [0.0, 0.0, 0.5236, 0.0])
    np.testing.assert_array_equal(tab.lines, [1, 2, 3, 6])  # a comment and a blank line skipped


def test_wavekin7_is_sine_phased_without_pressure():
    """WaveKin 7: zeta = sum |a| sin(omega t - k l + arg a) (spec 4.3); at the origin at t = 0
    that is sum Im(a) = 0.25 - 0.1; the heading column is read in radians."""
    tab = read_wave_frequencies(DATA / "wave_frequencies.txt")
    w = waves_summed(tab)
    assert w.evaluation == "sum" and not w.dynamic_pressure
    np.testing.assert_allclose(w.heading[2], math.degrees(0.5236))
    K = _build(w)
    assert K.wave_mode == WAVES_SUM
    o = fluid_kinematics(K, 0.0, [0.0, 0.0, -5.0])
    assert o[6] == pytest.approx(0.15, abs=1e-15)
    assert o[7] == 0.0
    # and elsewhere, against the sine formula written out
    x, y, t = 13.0, -4.0, 2.7
    k = wave_numbers(tab.omega, G, DEPTH)
    th = tab.omega * t - k * (x * np.cos(tab.heading) + y * np.sin(tab.heading))
    expect = np.sum(np.abs(tab.amplitude) * np.sin(th + np.angle(tab.amplitude)))
    assert fluid_kinematics(K, t, [x, y, -5.0])[6] == pytest.approx(expect, abs=1e-14)


def test_wavekin2_resamples_the_spectrum():
    """WaveKin 2 (spec 4.4): d_omega = smallest gap, n_w = floor(omega_max / d_omega) + 1,
    amplitude and heading linear in omega, half weight on the first and last component,
    n_t = 2 (n_w - 1) samples."""
    tab = read_wave_frequencies(DATA / "wave_frequencies.txt")
    grid = read_water_grid(DATA / "water_grid.txt")
    w = waves_fft_grid(tab, grid)
    dw = 0.6 - 0.4  # the smallest gap, as computed in floating point
    np.testing.assert_allclose(w.omega, np.arange(6) * dw, rtol=0, atol=1e-15)
    assert w.grid.nt == 10 and w.grid.time_wrap == "moordyn"
    expect = np.array([0.0, 0.25, 0.5, 0.25j, 0.05 + 0.075j, 0.5 * (0.1 - 0.1j)])
    np.testing.assert_allclose(w.amplitude, expect, atol=1e-12)
    np.testing.assert_allclose(w.heading, np.degrees([0, 0, 0, 0.5236, 0.2618, 0]), atol=1e-9)


def test_wavekin2_grid_is_the_half_weighted_cosine_sum():
    """At the grid's nodes and sample times the FFT grid equals the cosine sum with half weight on
    the first and last component (MoorDyn's inverse real FFT), to round-off."""
    tab = read_wave_frequencies(DATA / "wave_frequencies.txt")
    w = waves_fft_grid(tab, read_water_grid(DATA / "water_grid.txt"))
    K = _build(w)
    assert K.wave_mode == WAVES_GRID and K.wg_wrap == WRAP_MOORDYN
    k = wave_numbers(w.omega, G, DEPTH)
    beta = np.radians(w.heading)
    for n in (0, 3, 7):
        t = n * K.wg_dt
        for x in (-20.0, 0.0, 10.0):
            th = w.omega * t - k * x * np.cos(beta)
            expect = np.sum(np.abs(w.amplitude) * np.cos(th + np.angle(w.amplitude)))
            assert fluid_kinematics(K, t, [x, 0.0, -10.0])[6] == pytest.approx(expect, abs=1e-13)


def test_wavekin2_and_7_are_a_quarter_period_apart(tmp_path):
    """The same file read by WaveKin 2 (cosine) and WaveKin 7 (sine): zeta_2(t) = zeta_7(t + T/4)
    for a single component (gotcha 28)."""
    _write(tmp_path, "wave_frequencies.txt", "0 0 0\n0.25 0 0\n0.5 0.8 0.3\n0.75 0 0\n")
    _write(tmp_path, "water_grid.txt", "a\nb\nc\n1\n-40 0 40\n0\n0\n2\n-30 0 4\n")
    w2, _ = water_from_options(2, 0, tmp_path, DEPTH)
    w7, _ = water_from_options(7, 0, tmp_path, DEPTH)
    K2, K7 = _build(w2), _build(w7)
    quarter = 0.25 * 2.0 * math.pi / 0.5
    assert w2.grid.nt == 6
    for n in range(5):  # sample times, all but the last (below)
        t = n * K2.wg_dt
        for x in (-40.0, 0.0, 40.0):
            z2 = fluid_kinematics(K2, t, [x, 0.0, -3.0])[6]
            z7 = fluid_kinematics(K7, t + quarter, [x, 0.0, -3.0])[6]
            assert z2 == pytest.approx(z7, abs=1e-13)
    assert abs(fluid_kinematics(K2, 0.0, [0, 0, -3])[6] - 0.8) < 1e-13  # cosine: Re(a) at the origin
    # MoorDyn-C's wrap (spec 4.7): from the last sample time on, the first sample is held
    z_first = fluid_kinematics(K2, 0.0, [40.0, 0.0, -3.0])[6]
    for t in (5 * K2.wg_dt, 5.5 * K2.wg_dt):
        assert fluid_kinematics(K2, t, [40.0, 0.0, -3.0])[6] == pytest.approx(z_first, abs=1e-14)
    assert abs(fluid_kinematics(K7, 5 * K2.wg_dt + quarter, [40.0, 0.0, -3.0])[6] - z_first) > 0.1


@pytest.mark.parametrize("text, line, fragments", [
    ("0 0 0\n", 1, ["at least 2 frequency rows"]),
    ("0 0 0\n0.5 1.0\n", 2, ["3 or 4 numbers"]),
    ("0 0 0\n0.5 1.0 0 0 0\n", 2, ["3 or 4 numbers"]),
    ("0 0 0\n0.5 x 0\n", 2, ["Re(a)", "finite number", "'x'"]),
    ("0 0 0\n0.5 1 0 7.0\n", 2, ["beta", "radians"]),
    ("0.1 0 0\n0.5 1 0\n", 1, ["first frequency must be 0"]),
    ("0 0 0\n-0.5 1 0\n", 2, ["omega must be >= 0"]),
])
def test_wave_frequencies_errors(tmp_path, text, line, fragments):
    _raises(read_wave_frequencies, _write(tmp_path, "wave_frequencies.txt", text), line, *fragments)


def test_wavekin2_needs_increasing_frequencies(tmp_path):
    p = _write(tmp_path, "wave_frequencies.txt", "0 0 0\n0.5 1 0\n0.5 0 1 1.0\n")
    _write(tmp_path, "water_grid.txt", "a\nb\nc\n0\n\n0\n\n0\n\n")
    with pytest.raises(DeckError) as info:
        water_from_options(2, 0, tmp_path, DEPTH)
    assert info.value.line == 3 and info.value.file == str(p) and "strictly increasing" in str(info.value)
    water_from_options(7, 0, tmp_path, DEPTH)  # WaveKin 7 takes repeated frequencies


# -------------------------------------------------------------------------------- water_grid.txt
def test_water_grid_types():
    g = read_water_grid(DATA / "water_grid.txt")
    np.testing.assert_array_equal(g.x, [-20.0, -10.0, 0.0, 10.0, 20.0])
    np.testing.assert_array_equal(g.y, [0.0])
    np.testing.assert_allclose(g.z, np.linspace(-30.0, 0.0, 7), atol=1e-14)
    assert g.z[-1] == 0.0


@pytest.mark.parametrize("text, line, fragments", [
    ("a\nb\nc\n1\n1 2\n0\n\n", 7, ["9 lines"]),
    ("a\nb\nc\n3\n1 2\n0\n\n0\n\n", 4, ["x axis type must be 0", "got 3"]),
    ("a\nb\nc\n0\n\n2\n-1 1 1\n0\n\n", 7, ["number of y values", ">= 2"]),
    ("a\nb\nc\n0\n\n0\n\n1\n-5 -1 -3\n", 9, ["z values must be strictly increasing"]),
    ("a\nb\nc\n2\n-5 5\n0\n\n0\n\n", 5, ["'x_first x_last n'", "got 2"]),
    ("a\nb\nc\n0\n\n0\n\n\n\n", 8, ["z axis type"]),
    ("a\nb\nc\n1\n\n0\n\n0\n\n", 5, ["list of x values"]),
])
def test_water_grid_errors(tmp_path, text, line, fragments):
    _raises(read_water_grid, _write(tmp_path, "water_grid.txt", text), line, *fragments)


# ------------------------------------------------------------------------------ wave_elevation.txt
def test_wavekin3_reproduces_the_low_passed_record(caplog):
    """WaveKin 3 (spec 4.5): resampled at dtWave from 0 (41 samples at 0.5 s, trimmed to 40),
    components above 0.5 Hz dropped; at the origin the grid replays that record exactly at its
    samples (but the last, see below), and it repeats with period 40 x 0.5 s. Reference: numpy's
    FFT of the same samples."""
    t, z = read_wave_elevation(DATA / "wave_elevation.txt")
    assert t.size == 41 and t[-1] == 20.0
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        w, c = water_from_options(3, 0, DATA, DEPTH, dt_wave=0.5)
    assert c is None and w.evaluation == "grid" and w.grid.nt == 40
    n, dt = 40, 0.5
    X = np.fft.rfft(np.interp(np.arange(n) * dt, t, z))
    X[np.arange(X.size) * 2 * np.pi / (n * dt) > np.pi] = 0.0
    expect = np.fft.irfft(X, n)
    assert np.max(np.abs(expect - np.interp(np.arange(n) * dt, t, z))) > 1e-3  # the low-pass bites
    K = _build(w)
    assert K.wg_dt == pytest.approx(dt, rel=1e-14)
    # MoorDyn-C's wrap (spec 4.7) holds the first sample from the last sample time on
    replay = np.append(expect[:-1], expect[0])
    got = np.array([fluid_kinematics(K, i * dt, [0.0, 0.0, -1.0])[6] for i in range(n)])
    np.testing.assert_allclose(got, replay, atol=1e-13)
    later = np.array([fluid_kinematics(K, i * dt + n * dt, [0.0, 0.0, -1.0])[6] for i in range(n)])
    np.testing.assert_allclose(later, replay, atol=1e-13)


@pytest.mark.parametrize("text, line, fragments", [
    ("0 0.1\n", 1, ["at least 2 rows"]),
    ("0 0.1\n1\n", 2, ["'t zeta'"]),
    ("0 0.1\n1 0.2\n1 0.3\n", 3, ["times must be strictly increasing"]),
    ("-1 0.1\n1 0.2\n", 1, ["times must be >= 0"]),
])
def test_wave_elevation_errors(tmp_path, text, line, fragments):
    _raises(read_wave_elevation, _write(tmp_path, "wave_elevation.txt", text), line, *fragments)


# ------------------------------------------------------------------------------------- currents
def test_current_profile():
    c = read_current_profile(DATA / "current_profile.txt")
    assert c.velocity.shape == (1, 1, 3, 1, 3) and c.time_wrap == "moordyn"
    np.testing.assert_array_equal(c.z, [-30.0, -10.0, 0.0])
    np.testing.assert_array_equal(c.velocity[0, 0, :, 0], [[0.1, 0.0, 0.0], [0.5, 0.2, 0.0], [0.8, -0.1, 0.01]])


def test_current_profile_dynamic():
    c = read_current_profile_dynamic(DATA / "current_profile_dynamic.txt")
    np.testing.assert_array_equal(c.z, [-30.0, -10.0, 0.0])
    np.testing.assert_array_equal(c.t, [0.0, 2.0, 5.0])
    v = c.velocity[0, 0]  # (nz, nt, 3)
    np.testing.assert_array_equal(v[:, 1, 0], [0.2, 0.3, 0.4])
    np.testing.assert_array_equal(v[:, 2, 1], [-0.1, -0.1, -0.1])
    assert np.all(v[..., 2] == 0.0)  # no uz columns
    # resampled at the smallest interval (2 s) from 0 to 5 s: samples at 0, 2, 4 s
    K = _build(None, c)
    assert K.current_mode == CURRENT_GRID and K.cg_vel.shape[3] == 3 and K.cg_dt == 2.0
    np.testing.assert_allclose(K.cg_vel[0, 0, 2, 2], [0.4, 0.1 - 0.2 * 2.0 / 3.0, 0.0], atol=1e-15)


def test_current_4d_skips_line_6_like_moordyn(caplog):
    """MoorDyn-C ignores line 6, the first data row (spec 4.8, (bug?)): that node keeps zero
    velocity, and a warning says so; skip_first_row=False reads it."""
    path = DATA / "current_profile_4d.txt"
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        c = read_current_profile_4d(path)
    assert "1 of 8 grid nodes are not listed" in caplog.text and "line 6" in caplog.text
    assert c.velocity.shape == (2, 1, 2, 2, 3)
    np.testing.assert_array_equal(c.velocity[0, 0, 0, 0], [0.0, 0.0, 0.0])
    np.testing.assert_allclose(c.velocity[1, 0, 0, 1], [0.3, -0.04, 0.004])
    full = read_current_profile_4d(path, skip_first_row=False)
    np.testing.assert_allclose(full.velocity[0, 0, 0, 0], [-0.1, -0.04, 0.0])
    np.testing.assert_array_equal(full.velocity[1:], c.velocity[1:])


def test_current_4d_matches_coordinates_by_value(tmp_path):
    """C matches rows by the text of their coordinates and silently files others at index 0;
    moorline matches '10' to the axis token '10.0' by value."""
    text = "2 1 1 1\n-10.0 10.0\n0\n0\n0\nskipped\n10 0 0 0 1 2 3\n-10.0 0 0 0 4 5 6\n"
    c = read_current_profile_4d(_write(tmp_path, "current_profile_4d.txt", text))
    np.testing.assert_array_equal(c.velocity[:, 0, 0, 0], [[4, 5, 6], [1, 2, 3]])


@pytest.mark.parametrize("reader, name, text, line, fragments", [
    (read_current_profile, "current_profile.txt", "a\nb\nc\n", 3, ["first profile row"]),
    (read_current_profile, "current_profile.txt", "a\nb\nc\n-5\n", 4, ["'z ux [uy [uz]]'"]),
    (read_current_profile, "current_profile.txt", "a\nb\nc\n-5 1\n-6 1\n", 5, ["z levels must be strictly"]),
    (read_current_profile, "current_profile.txt", "a\nb\nc\n-5 1 q\n", 4, ["uy", "'q'"]),
    (read_current_profile_dynamic, "d.txt", "a\nb\nc\n", 3, ["line 5, the z levels"]),
    (read_current_profile_dynamic, "d.txt", "a\nb\nc\nd\n\n", 5, ["z levels on line 5"]),
    (read_current_profile_dynamic, "d.txt", "a\nb\nc\nd\n-5 0\n\n", 6, ["first row"]),
    (read_current_profile_dynamic, "d.txt", "a\nb\nc\nd\n-5 0\n\n0 1 2 3\n", 7, ["3, 5 or 7 numbers, got 4"]),
    (read_current_profile_dynamic, "d.txt", "a\nb\nc\nd\n-5 0\n\n0 1 2\n0 1 2\n", 8, ["times must be strictly"]),
    (read_current_profile_4d, "f.txt", "1 1 1\n0\n0\n0\n0\n", 1, ["'nx ny nz nt'"]),
    (read_current_profile_4d, "f.txt", "2 1 1 1\n0\n0\n0\n0\n", 2, ["exactly 2 x values"]),
    (read_current_profile_4d, "f.txt", "1 1 1 1\n0\n0\n0\n0\nx\n0 0 0 0 1 2\n", 7, ["7 numbers"]),
    (read_current_profile_4d, "f.txt", "1 1 1 1\n0\n0\n0\n0\nx\n3 0 0 0 1 2 3\n", 7, ["x = 3 is not one"]),
    (read_current_profile_4d, "f.txt", "1 1 1 2\n0\n0\n0\n1 1\n", 5, ["t values must be strictly"]),
])
def test_current_file_errors(tmp_path, reader, name, text, line, fragments):
    _raises(reader, _write(tmp_path, name, text), line, *fragments)


# -------------------------------------------------------------------------------------- options
def test_options_none_external_and_unify(tmp_path):
    assert water_from_options(0, 0, tmp_path) == (None, None)
    w, _ = water_from_options(1, 0, tmp_path)
    assert w.evaluation == "external"
    assert _build(w, n_external=4).wave_mode == WAVES_EXTERNAL
    # UnifyCurrentGrid only matters with a wave grid
    for name in ("wave_frequencies.txt", "water_grid.txt", "current_profile.txt"):
        (tmp_path / name).write_bytes((DATA / name).read_bytes())
    _, c = water_from_options(7, 1, tmp_path)
    assert not c.on_wave_grid
    _, c = water_from_options(2, 1, tmp_path)
    assert c.on_wave_grid
    _, c = water_from_options(2, 1, tmp_path, unify_current_grid=False)
    assert not c.on_wave_grid


@pytest.mark.parametrize("wave_kin, currents, fragment", [
    (4, 0, "WaveKin = 4 is reserved"),
    (6, 0, "WaveKin = 6 is reserved"),
    (8, 0, "WaveKin must be 0"),
    (0, 3, "Currents = 3 is reserved"),
    (0, 7, "Currents must be 0"),
    (7, 0, "needs the file wave_frequencies.txt"),
    (2, 0, "needs the file"),
    (0, 5, "needs the file current_profile_4d.txt"),
])
def test_option_errors(tmp_path, wave_kin, currents, fragment):
    with pytest.raises(DeckError, match=fragment):
        water_from_options(wave_kin, currents, tmp_path)


def test_grid_not_reaching_the_seabed_warns(tmp_path, caplog):
    (tmp_path / "wave_frequencies.txt").write_bytes((DATA / "wave_frequencies.txt").read_bytes())
    _write(tmp_path, "water_grid.txt", "a\nb\nc\n0\n\n0\n\n1\n-10 -5\n")
    with caplog.at_level(logging.WARNING, logger="moorline.io"):
        water_from_options(2, 0, tmp_path, depth=30.0)
    assert "above the seabed" in caplog.text and "below the still-water level" in caplog.text


# --------------------------------------------------------------------- conformance corpus inputs
def _corpus(name: str) -> Path:
    d = INPUTS / name
    if not d.is_dir():
        pytest.skip(f"shared conformance corpus not available ({d})")
    return d


@pytest.mark.conformance
def test_corpus_wavekin7():
    d = _corpus("wavekin7_spectrum")
    tab = read_wave_frequencies(d / "wave_frequencies.txt")
    np.testing.assert_array_equal(tab.omega, [0.0, 0.35, 0.4, 0.6])
    np.testing.assert_array_equal(tab.amplitude, [0.0, 1.0, 1.0j, 0.0])
    np.testing.assert_array_equal(tab.heading, [0.0, 0.0, 1.57, 0.0])  # last row has no heading: 0
    w, c = water_from_options(7, 0, d, 50.0)
    assert c is None and w.evaluation == "sum" and w.n_components == 4
    np.testing.assert_array_equal(w.amplitude, [0.0, -1.0j, 1.0, 0.0])  # sine -> cosine: a -> -i a


@pytest.mark.conformance
def test_corpus_wavekin2_and_profile():
    d = _corpus("wavekin2_waves_current")
    grid = read_water_grid(d / "water_grid.txt")
    assert (grid.x.size, grid.y.size, grid.z.size) == (501, 5, 57)
    assert grid.x[0] == -450.0 and grid.z[-1] == 5.0
    w, c = water_from_options(2, 1, d, 50.0)
    assert w.n_components == 121 and w.grid.nt == 240  # floor(6.0 / 0.05) + 1, 2 (n_w - 1)
    assert w.amplitude[4] == pytest.approx(0.5, rel=1e-12) and w.amplitude[-1] == 0.0  # the row 0.2 0.5 0.0
    assert c.on_wave_grid and c.velocity.shape == (1, 1, 57, 1, 3)
    np.testing.assert_allclose(c.velocity[0, 0, [0, 2, 33], 0, 0], [0.0, 0.03125, 1.0], rtol=1e-14)


@pytest.mark.conformance
def test_corpus_current_dynamic():
    """CRLF file, lines 3-4 hold stray numbers (free lines), 42 levels, 60 times, ux and uy."""
    d = _corpus("current_dynamic")
    w, c = water_from_options(0, 2, d, 400.0)
    assert w is None
    assert c.z.size == 42 and c.z[0] == -41.0 and c.z[-1] == 0.0
    np.testing.assert_array_equal(c.t, np.arange(60.0))
    v = c.velocity[0, 0]
    np.testing.assert_allclose(v[:, 15, 0], 1.0)
    np.testing.assert_allclose(v[:, :, 0], v[:, :, 1])
    np.testing.assert_allclose(v[0, :, 0], np.sin(2 * np.pi * np.arange(60) / 60), atol=1e-12)
    assert np.all(v[..., 2] == 0.0)
