"""The README's Python snippets run as pasted (from the repository's root folder, where its paths
point), and its command-line synopsis names only options the command has."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from moorline.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]
README = (ROOT / "README.md").read_text()
SNIPPETS = re.findall(r"```python\n(.*?)```", README, flags=re.S)


def test_readme_has_python_snippets():
    assert len(SNIPPETS) >= 2


@pytest.mark.parametrize("index", range(len(SNIPPETS)))
def test_readme_python_snippet_runs_as_pasted(index, monkeypatch, capsys):
    monkeypatch.chdir(ROOT)
    exec(compile(SNIPPETS[index], f"README.md python snippet {index + 1}", "exec"), {"__name__": "__readme__"})
    assert capsys.readouterr().out.strip(), "the snippet prints what it shows"


def test_readme_command_synopsis_matches_the_parser():
    synopsis = README[README.index("## Command line"):]
    synopsis = synopsis[synopsis.index("```") + 3:]
    synopsis = synopsis[:synopsis.index("```")]
    parser = build_parser()
    sub = next(a for a in parser._actions if a.dest == "command").choices
    command = None
    for line in synopsis.strip().splitlines():
        words = line.split()
        if words[0] == "moorline":
            command = words[1]
        for opt in re.findall(r"(--[a-zA-Z][\w-]*)", line):
            known = {o for a in sub[command]._actions for o in a.option_strings}
            assert opt in known, f"README names moorline {command} {opt}, which the command does not have"
