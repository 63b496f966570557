"""The markdown table and summary of a public-deck sweep (``public_sweep.py --out sweep.json``).

    python tests/conformance/sweep_table.py sweep.json [--second sweep_icnewton0.json] [--notes notes.json]

``--second`` adds the initial and dynamic columns of a second sweep of the same decks (e.g. one run
with ``--icnewton 0``); ``notes.json`` maps a deck name to the explanation put in the last column.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np


def _fmt(x) -> str:
    return "" if x is None else f"{x:.2g}" if x >= 1e-3 else f"{x:.1e}"


def _cells(r) -> tuple[str, str]:
    c = r.get("cmp", {})
    dyn = _fmt(c.get("dynamic"))
    if dyn and c.get("worst"):
        dyn += f" ({c['worst'][0]}{c['worst'][1]})"
    return _fmt(c.get("initial")), dyn


def table(rows: list[dict], notes: dict | None = None, second: list[dict] | None = None,
          labels=("", "")) -> str:
    notes = notes or {}
    other = {r["deck"]: r for r in second or []}
    head = f"| deck | MoorDyn | moorline | initial{labels[0]} | dynamic{labels[0]} |"
    rule = "|---|---|---|---|---|"
    if second:
        head += f" initial{labels[1]} | dynamic{labels[1]} |"
        rule += "---|---|"
    out = [head + " why |", rule + "---|"]
    for r in rows:
        ml, md = r["moorline"], r["moordyn"]
        md_s = "runs" if md.get("ok") else ("template" if r.get("template") else "fails")
        if ml.get("ok"):
            ml_s = "runs"
        else:
            stages = {"parse": "refused", "run": "stops", "timeout": "timeout", "crash": "crash"}
            ml_s = stages.get(ml.get("stage"), "fails")
        ini, dyn = _cells(r)
        row = f"| {r['deck']} | {md_s} | {ml_s} | {ini} | {dyn} |"
        if second:
            ini2, dyn2 = _cells(other.get(r["deck"], {}))
            row += f" {ini2} | {dyn2} |"
        out.append(row + f" {notes.get(r['deck'], '')} |")
    return "\n".join(out)


def summary(rows: list[dict]) -> str:
    n = len(rows)
    parsed = sum(1 for r in rows if r["moorline"].get("ok") or r["moorline"].get("stage") != "parse")
    ran = sum(1 for r in rows if r["moorline"].get("ok"))
    md_ran = sum(1 for r in rows if r["moordyn"].get("ok"))
    both = [r["cmp"] for r in rows if "cmp" in r and "dynamic" in r["cmp"]]
    dyn = np.array([c["dynamic"] for c in both])
    ini = np.array([c["initial"] for c in both])
    lines = [f"- decks: {n}; moorline parses {parsed}, runs {ran}; MoorDyn runs {md_ran}; both run {len(both)}"]
    if len(both):
        lines.append(f"- dynamic fairlead/anchor tension, RMS difference relative to MoorDyn's RMS, worst line end: "
                     f"within 1 % on {int(np.sum(dyn <= 0.01))}, within 5 % on {int(np.sum(dyn <= 0.05))} of "
                     f"{len(both)}; median {np.median(dyn):.2g}")
        lines.append(f"- initial tensions (after Init): within 1 % on {int(np.sum(ini <= 0.01))} of {len(both)}; "
                     f"median {np.median(ini):.2g}")
    return "\n".join(lines)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("sweep")
    ap.add_argument("--second")
    ap.add_argument("--notes")
    args = ap.parse_args(argv)
    rows = json.loads(Path(args.sweep).read_text())
    second = json.loads(Path(args.second).read_text()) if args.second else None
    notes = json.loads(Path(args.notes).read_text()) if args.notes else {}
    print(summary(rows))
    if second:
        print(summary(second))
    print()
    print(table(rows, notes, second, (" (Newton IC)", " (ICNewton 0)") if second else ("", "")))


if __name__ == "__main__":
    main()
