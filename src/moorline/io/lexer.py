"""Lexer for MoorDyn v2 input decks: text -> sections -> rows of tokens.

The rules follow MoorDyn-C (spec section 1.1) with the moorline choices:

* tokens are split on any whitespace (MoorDyn-C splits on spaces only);
* the first token that *contains* ``#`` ends the row (that token is dropped too);
* a line is a section header when it contains ``---`` and, upper-cased, one of the section
  keywords of :data:`SECTION_KEYWORDS`; any other line containing ``---`` only ends the current
  section;
* the two lines after a table header (column titles and units) are skipped unread, except that a
  line containing ``---`` is never skipped (it ends the section, so an empty table written
  without titles does not swallow the next header);
* blank and comment-only rows are skipped everywhere (MoorDyn-C rejects them inside tables);
* everything before the first header is front matter and is ignored.

Nothing here knows what the columns mean; :mod:`moorline.io.deck` does.
"""

from __future__ import annotations

import logging
import math
import re
from dataclasses import dataclass, field

log = logging.getLogger("moorline.io")

#: Canonical section names with the header keywords that select them (upper-case substrings).
#: Order matters: the more specific keywords come first, so that ``LINE TYPES`` is never taken for
#: ``LINES`` and ``ROD TYPES`` never for ``RODS``.
SECTION_KEYWORDS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("LINE TYPES", ("LINE DICTIONARY", "LINE TYPES")),
    ("ROD TYPES", ("ROD DICTIONARY", "ROD TYPES")),
    ("BODIES", ("BODIES", "BODY LIST", "BODY PROPERTIES")),
    ("RODS", ("ROD LIST", "ROD PROPERTIES", "RODS")),
    ("POINTS", ("POINT LIST", "POINT PROPERTIES", "POINTS", "CONNECTION PROPERTIES", "NODE PROPERTIES")),
    ("LINES", ("LINE LIST", "LINE PROPERTIES", "LINES")),
    ("SYROPE IC", ("SYROPE IC",)),
    ("FAILURE", ("FAILURE",)),
    ("EXTERNAL LOADS", ("EXTERNAL LOADS",)),
    ("CONTROL", ("CONTROL",)),
    ("OPTIONS", ("OPTIONS",)),
    ("OUTPUTS", ("OUTPUT",)),
)

#: Sections whose two lines after the header are column titles and units (not read).
TABLE_SECTIONS = frozenset({"LINE TYPES", "ROD TYPES", "BODIES", "RODS", "POINTS", "LINES", "SYROPE IC",
                            "FAILURE", "CONTROL", "EXTERNAL LOADS"})

_LINE_BREAK = re.compile(r"\r\n|\r|\n")
_NUMBER = re.compile(r"[+-]?(?:\d+\.?\d*|\.\d+)(?:[eE][+-]?\d+)?")


@dataclass(frozen=True)
class Row:
    """One data row of a section.

    Attributes
    ----------
    line : int
        1-based line number in the file.
    text : str
        The raw line (trailing whitespace removed), for error messages.
    tokens : tuple of str
        The tokens before any comment.
    """

    line: int
    text: str
    tokens: tuple[str, ...]


@dataclass
class Section:
    """A section of a deck: its canonical name, header line and data rows."""

    name: str
    line: int
    header: str
    rows: list[Row] = field(default_factory=list)


def tokenize(text: str) -> tuple[str, ...]:
    """Split one line into tokens; the first token containing ``#`` and all after it are dropped."""
    out = []
    for tok in text.split():
        if "#" in tok:
            break
        out.append(tok)
    return tuple(out)


def section_name(line: str) -> str | None:
    """Canonical section name if ``line`` is a section header, else None."""
    if "---" not in line:
        return None
    up = line.upper()
    for name, keywords in SECTION_KEYWORDS:
        if any(k in up for k in keywords):
            return name
    return None


def split_lines(text: str) -> list[str]:
    """Split text into lines on ``\\n``, ``\\r\\n`` or ``\\r`` (and only those), trailing blanks removed."""
    return [s.rstrip() for s in _LINE_BREAK.split(text)]


def lex(text: str, *, file: str = "<deck>") -> list[Section]:
    """Cut a deck into sections, in file order.

    Parameters
    ----------
    text : str
        The whole deck.
    file : str
        Name used in log messages.

    Returns
    -------
    list of Section
        One entry per header found (a section may in principle appear twice; the builder decides).
    """
    sections: list[Section] = []
    current: Section | None = None
    skip = 0
    for lineno, raw in enumerate(split_lines(text), 1):
        if "---" in raw:
            name = section_name(raw)
            if name is None:
                current = None
                skip = 0
            else:
                current = Section(name, lineno, raw)
                sections.append(current)
                skip = 2 if name in TABLE_SECTIONS else 0
            continue
        if current is None:
            continue
        if skip:
            skip -= 1
            toks = tokenize(raw)
            if sum(1 for t in toks if is_number(t)) >= 3:
                log.warning("%s, line %d: this line follows the %s header and is skipped as column "
                            "titles/units, but it looks like data (is a title or units row missing?)",
                            file, lineno, current.name)
            continue
        toks = tokenize(raw)
        if toks:
            current.rows.append(Row(lineno, raw, toks))
    return sections


def is_number(token: str) -> bool:
    """True if ``token`` is a plain, finite decimal number (no ``nan``, ``inf``, ``_``, Fortran ``D``)."""
    return parse_number(token) is not None


def parse_number(token: str) -> float | None:
    """Strictly parse a decimal number; None if ``token`` is not one."""
    if _NUMBER.fullmatch(token) is None:
        return None
    v = float(token)
    return v if math.isfinite(v) else None


def parse_whole(token: str) -> int | None:
    """Parse a whole number (``20``, also ``20.0`` or ``2e1``); None if not a whole number."""
    v = parse_number(token)
    if v is None or v != int(v):
        return None
    return int(v)
