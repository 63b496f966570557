"""Helpers shared by the validation studies (``validation/<study>/run.py``): where the shared data
sit, steady amplitudes, spectra, statistics, and writing ``results.json``.

The studies import this module by putting ``validation/`` on ``sys.path``; it uses only numpy, the
standard library and moorline's public API.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import platform
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
#: ../shared/data beside the repository (never copied into it)
SHARED_DATA = ROOT.parent / "shared" / "data"


def shared_file(*parts: str) -> Path:
    """A file of ``../shared/data``; exits with a clear message when it is absent.

    Parameters
    ----------
    *parts : str
        Path components below ``shared/data``.

    Returns
    -------
    pathlib.Path
    """
    p = SHARED_DATA.joinpath(*parts)
    if not p.exists():
        sys.exit(f"missing shared data: {p} (the studies read the public reference data from ../shared/data "
                 "beside the repository; see its PROVENANCE.md)")
    return p


def steady_amplitude(t, x, omega: float, periods: float) -> complex:
    """Complex first-harmonic amplitude of the last ``periods`` periods of ``x``.

    Least squares on mean + drift + cos + sin, so that ``x ~ Re(c exp(-i omega t))`` (Capytaine's
    convention, as :func:`moorline.hydro.rao`).

    Parameters
    ----------
    t, x : array_like
        Times [s] and the signal.
    omega : float
        Angular frequency [rad/s].
    periods : float
        Number of periods at the end of the record to fit.

    Returns
    -------
    complex
    """
    t = np.asarray(t, dtype=float)
    x = np.asarray(x, dtype=float)
    T = 2 * np.pi / omega
    sel = t >= t[-1] - periods * T - 1e-9
    X = np.column_stack([np.ones(sel.sum()), t[sel], np.cos(omega * t[sel]), np.sin(omega * t[sel])])
    coef, *_ = np.linalg.lstsq(X, x[sel], rcond=None)
    return complex(coef[2] + 1j * coef[3])


def spectrum(t, x, *, segment: float | None = None):
    """One-sided power spectral density by Welch's method (Hann window, 50 % overlap).

    Parameters
    ----------
    t, x : array_like
        Uniformly sampled record.
    segment : float, optional
        Segment length [s]; default a quarter of the record.

    Returns
    -------
    f : ndarray
        Frequencies [Hz].
    S : ndarray
        Density [unit^2/Hz].
    """
    from scipy.signal import welch

    t = np.asarray(t, dtype=float)
    dt = float(np.median(np.diff(t)))
    n = len(t) if segment is None else int(round(segment / dt))
    n = min(len(t), n if segment is not None else max(16, len(t) // 4))
    f, S = welch(np.asarray(x, dtype=float) - np.mean(x), fs=1.0 / dt, window="hann", nperseg=n)
    return f, S


def peak_period(t, x, *, segment: float | None = None) -> float:
    """Period [s] of the peak of the spectrum of ``x``."""
    f, S = spectrum(t, x, segment=segment)
    k = int(np.argmax(S[1:])) + 1
    return float(1.0 / f[k])


def to_builtin(v):
    """numpy scalars and arrays to plain Python for JSON."""
    if isinstance(v, dict):
        return {str(k): to_builtin(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [to_builtin(x) for x in v]
    if isinstance(v, np.ndarray):
        return to_builtin(v.tolist())
    if isinstance(v, (np.floating, float)):
        x = float(v)
        return x if math.isfinite(x) else str(x)
    if isinstance(v, (np.integer,)):
        return int(v)
    if isinstance(v, (np.bool_,)):
        return bool(v)
    return v


def write_results(path: Path, results: dict, *, quick: bool, started: float) -> dict:
    """Write ``results.json`` (headline numbers in SI units, the mode, wall time and versions).

    Parameters
    ----------
    path : pathlib.Path
        Where to write (``results.json`` beside the study's script).
    results : dict
        The study's numbers.
    quick : bool
        Whether the run was the shortened ``--quick`` version.
    started : float
        ``time.perf_counter()`` at the start of the run.

    Returns
    -------
    dict
        What was written.
    """
    import moorline

    out = dict(results)
    out["mode"] = "quick" if quick else "full"
    out["wall_time_s"] = round(time.perf_counter() - started, 1)
    out["versions"] = {"moorline": moorline.__version__, "python": platform.python_version(),
                       "numpy": np.__version__}
    out = to_builtin(out)
    path.write_text(json.dumps(out, indent=2) + "\n")
    return out


class Checks:
    """Named pass/fail checks of a run: each states its value, its tolerance and why."""

    def __init__(self):
        self.items: list[dict] = []
        self.comparisons: list[dict] = []

    def compare(self, name: str, value: float, published: float, source: str, *, note: str = "") -> None:
        """Record ours beside a published number (reported, not a pass/fail check: where the paper
        leaves inputs unstated the difference is explained in the study's README)."""
        diff = (value - published) / published if published else float("nan")
        self.comparisons.append({"name": name, "ours": float(value), "published": float(published),
                                 "relative_difference": float(diff), "source": source, "note": note})

    def add(self, name: str, value: float, reference: float, tol: float, *, relative: bool = True,
            why: str = "") -> bool:
        """Record ``|value - reference| <= tol`` (relative to ``|reference|`` when ``relative``)."""
        err = abs(value - reference) / abs(reference) if relative and reference != 0 else abs(value - reference)
        ok = bool(np.isfinite(err) and err <= tol)
        self.items.append({"name": name, "value": float(value), "reference": float(reference),
                           "error": float(err), "tolerance": float(tol), "relative": relative, "passed": ok,
                           "why": why})
        return ok

    def bound(self, name: str, value: float, *, lo: float = -np.inf, hi: float = np.inf, why: str = "") -> bool:
        """Record ``lo <= value <= hi``."""
        ok = bool(np.isfinite(value) and lo <= value <= hi)
        self.items.append({"name": name, "value": float(value), "lo": float(lo), "hi": float(hi), "passed": ok,
                           "why": why})
        return ok

    @property
    def passed(self) -> bool:
        return all(c["passed"] for c in self.items)

    def report(self) -> str:
        lines = [f"  [cmp ] {c['name']}: ours {c['ours']:.4g}, published {c['published']:.4g} ({c['source']}), "
                 f"{100 * c['relative_difference']:+.0f} %" for c in self.comparisons]
        for c in self.items:
            mark = "ok  " if c["passed"] else "FAIL"
            if "tolerance" in c:
                kind = "rel" if c["relative"] else "abs"
                lines.append(f"  [{mark}] {c['name']}: {c['value']:.5g} vs {c['reference']:.5g} "
                             f"({kind} error {c['error']:.3g}, tolerance {c['tolerance']:.3g})")
            else:
                lines.append(f"  [{mark}] {c['name']}: {c['value']:.5g} in [{c['lo']:.5g}, {c['hi']:.5g}]")
        return "\n".join(lines)


def study_command(doc: str, quick_help: str, here: Path, argv=None) -> tuple[argparse.Namespace, Path]:
    """The command line the gallery-I studies share: ``--quick`` and ``--out``; makes the output
    folder (default: beside the script, ``here``), sets up logging; returns (arguments, folder)."""
    ap = argparse.ArgumentParser(description=doc, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--out", type=Path, default=None, help="folder for results.json and the figures (default: beside "
                    "this script)")
    a = ap.parse_args(argv)
    out = a.out or here
    out.mkdir(parents=True, exist_ok=True)
    logging.basicConfig(level=logging.WARNING, format="%(levelname)s %(name)s: %(message)s")
    return a, out
