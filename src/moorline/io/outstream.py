"""MoorDyn-style ``.out`` tables written as a run goes (:class:`OutStream`).

The rows are collected by an :class:`~moorline.io.outputs.OutputRecorder` and appended to the
files at every :meth:`OutStream.flush` (the simulation loop flushes every few seconds of wall time,
at every checkpoint and at the end), each file with one ``write`` of whole rows, so a run that is
killed leaves every table valid up to its last flush. A run resumed from a checkpoint first cuts
the tables back to the size they had when the checkpoint was written, then appends.
"""

from __future__ import annotations

import logging
from pathlib import Path

from ..errors import CheckpointError
from .outputs import OutputRecorder

log = logging.getLogger("moorline.io")


class OutStream:
    """Streams the ``.out`` tables of a run into ``out_dir``: ``<base>.out`` and the per-line, rod
    and body files the deck asks for.

    Parameters
    ----------
    out_dir : path-like
    base : str
        File name stem (the deck's).
    resume : dict, optional
        The cursor of a checkpoint (:meth:`cursor`): ``{file name: size in bytes}``; the files are
        cut back to these sizes and appended to.
    """

    name = "out"

    def __init__(self, out_dir, base: str, *, resume: dict | None = None):
        self.out_dir = Path(out_dir)
        self.base = base
        self._resume = resume
        self.recorder: OutputRecorder | None = None
        self._flushed = 0  # rows of the recorder already written
        self._t_written = -float("inf")  # time of the last row in the files
        self._sizes: dict[str, int] = {}

    @property
    def paths(self) -> list[Path]:
        """The files written (main file first)."""
        return [self.out_dir / name for name in self._sizes]

    def start(self, system, recorder=None) -> None:
        """Prepare for ``system`` (initialised); ``recorder`` (the run's Dataset recorder) is not used."""
        self.recorder = OutputRecorder(system)
        names = list(self.recorder.texts(self.base, 0, 0))
        if self._resume is None:
            self._sizes = dict.fromkeys(names, 0)
            return
        missing = [n for n in names if n not in self._resume]
        if missing:
            raise CheckpointError(f"the checkpoint has no record of the output files {', '.join(missing)}")
        for name in names:
            path = self.out_dir / name
            size = int(self._resume[name])
            if not path.is_file() or path.stat().st_size < size:
                raise CheckpointError(f"{path} is missing or shorter than when the checkpoint was written "
                                      f"({size} bytes): the outputs of the interrupted run are needed to resume it")
            with open(path, "r+b") as f:
                f.truncate(size)
            self._sizes[name] = size
        t_last = self._resume.get("t_last")
        self._t_written = float(t_last) if t_last is not None else -float("inf")

    def record(self, system) -> None:
        """Record one row of every table at the system's current time."""
        self.recorder.record()

    def flush(self) -> None:
        """Append the rows recorded since the last flush (rows not later than the last row already
        in the files, as the first row of a resumed run, are skipped)."""
        rec = self.recorder
        n = len(rec.times)
        start = self._flushed
        while start < n and rec.times[start] <= self._t_written:
            start += 1
        self._flushed = n
        if start >= n:
            if not any(self._sizes.values()):  # nothing written yet: the headers at least
                self._append(rec.texts(self.base, 0, 0, header=True))
            return
        first = not any(self._sizes.values())
        self._append(rec.texts(self.base, start, n, header=first))
        self._t_written = rec.times[n - 1]

    def _append(self, texts: dict[str, str]) -> None:
        self.out_dir.mkdir(parents=True, exist_ok=True)
        for name, text in texts.items():
            data = text.encode("utf-8")
            with open(self.out_dir / name, "ab") as f:
                f.write(data)
            self._sizes[name] += len(data)

    def finish(self, error: BaseException | None = None, attrs: dict | None = None) -> None:
        """Write what is left; the tables are then complete up to the last recorded time."""
        self.flush()
        log.info("wrote %d output table(s) to %s", len(self._sizes), self.out_dir)

    def cursor(self) -> dict:
        """Sizes of the files now (for a checkpoint), and the time of their last row."""
        return {**self._sizes, "t_last": None if self._t_written == -float("inf") else self._t_written}

