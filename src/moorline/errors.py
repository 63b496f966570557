"""Exception types shared by the whole package."""

from __future__ import annotations


class DeckError(ValueError):
    """A malformed input deck or auxiliary file.

    The message names the file, the 1-based line number, the row text, the field and what was
    expected, e.g.::

        lines.txt, line 18, field 'NumSegs' of LINES: expected a whole number >= 1, got '0'
            1   main   1   4   902.2   0   p
    """

    def __init__(self, message: str, *, file=None, line: int | None = None, row: str | None = None,
                 field: str | None = None):
        self.file = str(file) if file is not None else None
        self.line = line
        self.row = row
        self.field = field
        where = []
        if self.file:
            where.append(self.file)
        if line is not None:
            where.append(f"line {line}")
        head = ", ".join(where)
        text = f"{head}: {message}" if head else message
        if row is not None:
            text += f"\n    {row.strip()}"
        super().__init__(text)


class SimulationError(RuntimeError):
    """A simulation that cannot go on (instability, non-finite state, failed solve).

    Attributes give where it happened: ``time`` [s], ``line`` and ``node`` (1-based line number,
    0-based node index, or None), ``point`` (1-based) and ``suggested_dtM`` [s].
    """

    def __init__(self, message: str, *, time=None, line=None, node=None, point=None, suggested_dtM=None):
        self.time = time
        self.line = line
        self.node = node
        self.point = point
        self.suggested_dtM = suggested_dtM
        super().__init__(message)


class StudyError(ValueError):
    """A study file that cannot be run (unknown key or parameter, missing file, bad value)."""


class SweepError(RuntimeError):
    """Some cases of a sweep failed (the others are stored; running the sweep again retries them)."""


class CheckpointError(ValueError):
    """A checkpoint that cannot be loaded into this system (another model, scheme or time step, a
    damaged file, or outputs of the interrupted run that are missing)."""


class InputLimitError(DeckError):
    """Input that parses but would make a run endless or meaningless (an astronomical number of
    time steps, a water density or time step of 1e-308); the message says which value and what
    would be reasonable. ``force`` (``--force`` on the command line) skips the checks that are
    only estimates."""
