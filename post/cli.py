"""How every post tool ends when what it reads is not there or not whole.

A post tool run on a missing or empty output folder, a missing CSV series, or a snapshot
cut short (a run killed while writing it, a full disk) stops with one line on standard
error, naming the file it needed and what writes it, and exit code 2, never with a
Python traceback:

    python -m post.waves: error: OUT/x/gauges.csv: no such file (written by a run of
    build/mbsph on a case with &gauge groups)

Each tool's ``if __name__ == "__main__"`` block calls :func:`run`.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Callable

#: exit code of a post tool that could not read its input (as the solver's for bad input)
EXIT_INPUT = 2

#: what writes each file of an output folder (doc/output.md)
_WRITER = {
    "gauges.csv": "a run of build/mbsph on a case with &gauge groups",
    "armour.csv": "a run of build/mbsph on a case with &armour",
    "bodies.csv": "a run of build/mbsph on a case with bodies",
    "energy.csv": "a run of build/mbsph",
    "case.nml": "a run of build/mbsph",
}


def _writer(path: str) -> str:
    name = Path(path).name
    if name in _WRITER:
        return _WRITER[name]
    if name.startswith("snap_") and name.endswith(".h5"):
        return "a run of build/mbsph"
    return "a run of build/mbsph (the output folder is the case's out_dir)"


def message(exc: BaseException) -> str | None:
    """The one-line message for an exception of unreadable input, or None for any other."""
    if isinstance(exc, FileNotFoundError):
        if exc.filename:
            return f"{exc.filename}: no such file or folder (written by {_writer(str(exc.filename))})"
        return f"{exc} (output folders and their files are written by a run of build/mbsph)"
    if isinstance(exc, IsADirectoryError) and exc.filename:
        return f"{exc.filename}: a folder, where a file was expected"
    if isinstance(exc, OSError) and exc.filename:
        # h5py's error for a file cut short or still being written
        return (f"{exc.filename}: unreadable ({exc.strerror or exc}): truncated or partly written? "
                "A run that stopped while writing it leaves the previous snapshot whole")
    if isinstance(exc, OSError) and "truncated" in str(exc).lower():
        return f"truncated HDF5 file: {exc}"
    if isinstance(exc, (ValueError, KeyError)):
        text = str(exc).strip("'\"")
        return text.splitlines()[0] if text else type(exc).__name__
    return None


def run(main: Callable[[], int | None], prog: str) -> int:
    """Call a tool's main(); unreadable input ends in one line on stderr and exit code 2."""
    try:
        code = main()
    except (OSError, ValueError, KeyError) as exc:
        text = message(exc)
        if text is None:
            raise
        print(f"{prog}: error: {text}", file=sys.stderr)
        return EXIT_INPUT
    return int(code or 0)
