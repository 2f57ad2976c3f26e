"""Readers for the files MBSPH writes into its output folder (see doc/output.md).

One reader per file kind:

- :func:`list_snapshots` and :func:`read_snapshot` for ``snap_NNNNN.h5``,
- :func:`snapshot_time` and :func:`closest_snapshots` to pick snapshots by time
  without loading their particle arrays,
- :func:`read_csv` for ``energy.csv`` (or any one-header-line CSV file),
- :func:`read_case` for the effective namelist ``case.nml``, and
  :func:`fluid_box` for the first ``&box`` group with ``role = 'fluid'``.
"""

from __future__ import annotations

import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import f90nml
import h5py
import numpy as np

__all__ = [
    "Snapshot",
    "list_snapshots",
    "read_snapshot",
    "snapshot_time",
    "closest_snapshots",
    "read_csv",
    "complete_lines",
    "note_end",
    "case_t_end",
    "read_case",
    "fluid_box",
]

_SNAP_RE = re.compile(r"^snap_(\d+)\.h5$")

#: Particle kinds stored in ``/kind``.
FLUID, FIXED_BOUNDARY, MOVING_BOUNDARY, FLOATING_BODY, FILTER = 1, 2, 3, 4, 5


@dataclass(frozen=True)
class Snapshot:
    """One particle snapshot: the datasets and root attributes of ``snap_NNNNN.h5``.

    Vector fields have shape ``(N, 2)`` (``(N, 3)`` from the 3D build), scalar fields shape ``(N,)``. ``gravity`` is
    kept as stored (a scalar or a vector, possibly signed); :attr:`g` is its magnitude.
    ``attrs`` holds every root attribute as read, including any not listed here, and
    ``datasets`` every other dataset as stored (``body_pose``: x, y, angle of each body,
    ``body_outline``: the outline vertices of the bodies, ...; doc/output.md).
    """

    path: Path
    position: np.ndarray
    velocity: np.ndarray
    density: np.ndarray
    pressure: np.ndarray
    mass: np.ndarray
    kind: np.ndarray
    body: np.ndarray
    id: np.ndarray
    time: float
    dt: float
    step: int
    n_particles: int
    dp: float
    h: float
    rho0: float
    c0: float
    gravity: float | np.ndarray
    case_name: str
    case_nml: str
    attrs: dict[str, Any] = field(default_factory=dict, repr=False)
    datasets: dict[str, np.ndarray] = field(default_factory=dict, repr=False)

    @property
    def fluid(self) -> np.ndarray:
        """Boolean mask of the fluid particles (``kind == 1``)."""
        return self.kind == FLUID

    @property
    def volume(self) -> np.ndarray:
        """Particle volume ``m / rho`` (m2 in 2D, per metre of width)."""
        return self.mass / self.density

    @property
    def g(self) -> float:
        """Magnitude of the gravity acceleration (m/s2)."""
        return float(np.linalg.norm(np.atleast_1d(self.gravity)))


def _decode(value: Any) -> str:
    """Return an HDF5 string attribute (bytes, numpy bytes or str) as ``str``.

    Fortran writes fixed-length strings, padded with NULs or blanks: both are stripped.
    """
    if isinstance(value, np.ndarray):
        value = value.reshape(-1)[0] if value.size == 1 else b"".join(value.reshape(-1))
    if isinstance(value, (bytes, np.bytes_)):
        value = bytes(value).decode("utf-8", errors="replace")
    return str(value).rstrip("\x00 ")


def _number(value: Any, default: float = float("nan")) -> Any:
    """Return a numeric attribute as a Python scalar, or as an array if it has several values."""
    if value is None:
        return default
    arr = np.asarray(value)
    return arr.reshape(-1)[0].item() if arr.size == 1 else arr.astype(float)


def _vectors(values: np.ndarray, name: str) -> np.ndarray:
    """Return a vector dataset as ``(N, 2)`` (2D) or ``(N, 3)`` (3D) floats; a ``(2, N)`` or
    ``(3, N)`` layout is transposed."""
    arr = np.asarray(values, dtype=float)
    if arr.ndim == 2 and arr.shape[1] in (2, 3):
        return arr
    if arr.ndim == 2 and arr.shape[0] in (2, 3):
        return arr.T.copy()
    raise ValueError(f"/{name} has shape {arr.shape}, expected (N, 2) or (N, 3)")


def _snapshot_index(path: Path) -> int:
    """Output index NNNNN of ``snap_NNNNN.h5`` (-1 for another name)."""
    match = _SNAP_RE.match(path.name)
    return int(match.group(1)) if match else -1


def list_snapshots(out_dir: str | Path) -> list[Path]:
    """Return the snapshot files ``snap_NNNNN.h5`` of an output folder, in output order."""
    paths = [p for p in Path(out_dir).iterdir() if _SNAP_RE.match(p.name)]
    return sorted(paths, key=_snapshot_index)


def read_snapshot(path: str | Path) -> Snapshot:
    """Read one snapshot file into a :class:`Snapshot`, particles in id order."""
    path = Path(path)
    with _open_h5(path) as f:
        data = {
            name: f[name][()]
            for name in ("position", "velocity", "density", "pressure", "mass", "kind", "body", "id")
        }
        attrs = {key: f.attrs[key] for key in f.attrs}
        others = {name: f[name][()] for name in f if name not in data and isinstance(f[name], h5py.Dataset)}
    for name in ("position", "velocity"):
        data[name] = _vectors(data[name], name)
    for name in ("density", "pressure", "mass"):
        data[name] = np.asarray(data[name], dtype=float).reshape(-1)
    for name in ("kind", "body", "id"):
        data[name] = np.asarray(data[name], dtype=np.int64).reshape(-1)
    # a run on several ranks writes each rank's particles in turn: put them in id order
    if np.any(np.diff(data["id"]) < 0):
        order = np.argsort(data["id"], kind="stable")
        for name in ("position", "velocity", "density", "pressure", "mass", "kind", "body", "id"):
            data[name] = data[name][order]
    n = data["position"].shape[0]
    return Snapshot(
        path=path,
        time=float(_number(attrs.get("time"))),
        dt=float(_number(attrs.get("dt"))),
        step=int(_number(attrs.get("step"), -1)),
        n_particles=int(_number(attrs.get("n_particles"), n)),
        dp=float(_number(attrs.get("dp"))),
        h=float(_number(attrs.get("h"))),
        rho0=float(_number(attrs.get("rho0"))),
        c0=float(_number(attrs.get("c0"))),
        gravity=_number(attrs.get("gravity")),
        case_name=_decode(attrs.get("case_name", "")),
        case_nml=_decode(attrs.get("case_nml", "")),
        attrs=attrs,
        datasets=others,
        **data,
    )


def _open_h5(path: Path) -> h5py.File:
    """An HDF5 file open for reading; a file cut short (a run stopped while writing it) or
    not HDF5 at all is an OSError that names it (post.cli turns it into one line)."""
    try:
        return h5py.File(path, "r")
    except OSError as exc:
        if getattr(exc, "filename", None):
            raise
        raise OSError(0, f"not a whole HDF5 file ({exc})", str(path)) from exc


def snapshot_time(path: str | Path) -> float:
    """Return the ``time`` attribute of a snapshot without reading its particle data."""
    with _open_h5(Path(path)) as f:
        return float(_number(f.attrs["time"]))


def closest_snapshots(out_dir: str | Path, times: Sequence[float] | None = None,
                      count: int = 4) -> list[Path]:
    """Return the snapshots whose times are closest to ``times``, in order, without repeats.

    Without ``times``, ``count`` times evenly spread from the first to the last snapshot
    are used.
    """
    paths = list_snapshots(out_dir)
    if not paths:
        raise FileNotFoundError(f"no snapshot snap_NNNNN.h5 in {out_dir}")
    stored = np.array([snapshot_time(p) for p in paths])
    wanted = np.linspace(stored[0], stored[-1], count) if times is None else np.asarray(times, float)
    chosen: list[Path] = []
    for t in np.atleast_1d(wanted):
        path = paths[int(np.argmin(np.abs(stored - t)))]
        if path not in chosen:
            chosen.append(path)
    return chosen


def _parse_column(values: list[str]) -> np.ndarray:
    """Return a CSV column as int64 when every entry is an integer, else float64."""
    try:
        return np.array([int(v) for v in values], dtype=np.int64)
    except ValueError:
        return np.array([float(v) for v in values], dtype=float)


def complete_lines(path: str | Path) -> list[str]:
    """The lines of a series the solver writes row by row, without a last row cut short.

    The solver writes every row whole, newline included. A file that does not end with
    a newline was cut while a row was being written (a run killed, a full disk): that
    row may hold a number cut to its first digits (a pressure of 1.96 Pa for 1957), so it
    is left out, with a note on standard error.
    """
    text = Path(path).read_text()
    lines = text.splitlines()
    if text and not text.endswith("\n") and lines:
        print(f"post: {path}: the last line {lines[-1][:40]!r}... is incomplete (the run stopped while "
              "writing it): left out", file=sys.stderr)
        lines = lines[:-1]
    return lines


def note_end(path: str | Path, times: np.ndarray, t_end: float | None) -> None:
    """Say on standard error when a series ends before the case's t_end.

    A run that stopped early (or is still running) leaves series that end before t_end;
    figures from them describe the time they cover, which is stated.
    """
    if t_end is None or len(times) == 0 or not np.isfinite(t_end):
        return
    last = float(times[-1])
    step = float(np.median(np.diff(times))) if len(times) > 2 else 0.0
    if last < t_end - max(1.5 * step, 1.0e-9 * max(abs(t_end), 1.0)):
        print(f"post: {path}: the records end at t = {last:.6g} s, before the case's t_end = {t_end:.6g} s "
              f"(the run stopped early or is still running): the results describe t <= {last:.6g} s",
              file=sys.stderr)


def case_t_end(nml: Any) -> float | None:
    """``&run t_end`` of a case namelist, or None."""
    try:
        return float(nml["run"]["t_end"])
    except (KeyError, TypeError, ValueError):
        return None


def read_csv(path: str | Path) -> dict[str, np.ndarray]:
    """Read a comma-separated file with one header line into ``{column name: array}``.

    Blank lines are skipped, and a last line cut short (complete_lines). Columns of
    integers come back as int64, others as float64.
    """
    lines = [ln.strip() for ln in complete_lines(path)]
    lines = [ln for ln in lines if ln]
    if not lines:
        raise ValueError(f"{path}: empty file, no header line")
    names = [name.strip() for name in lines[0].split(",")]
    rows = [[v.strip() for v in ln.split(",")] for ln in lines[1:]]
    for number, row in enumerate(rows, start=2):
        if len(row) != len(names):
            raise ValueError(f"{path}: data line {number} has {len(row)} fields, header has {len(names)}")
    columns = list(zip(*rows)) if rows else [()] * len(names)
    return {name: _parse_column(list(col)) for name, col in zip(names, columns)}


def read_case(out_dir: str | Path) -> f90nml.Namelist:
    """Return the effective namelist of a run.

    ``out_dir`` is the output folder (its ``case.nml`` is read) or a namelist file.
    Without ``case.nml`` the ``case_nml`` attribute of the first snapshot is used.
    """
    path = Path(out_dir)
    if path.is_file():
        return f90nml.read(str(path))
    if (path / "case.nml").is_file():
        return f90nml.read(str(path / "case.nml"))
    snapshots = list_snapshots(path)
    if snapshots:
        with h5py.File(snapshots[0], "r") as f:
            if "case_nml" in f.attrs:
                return f90nml.reads(_decode(f.attrs["case_nml"]))
    raise FileNotFoundError(f"no case.nml and no snapshot with a case_nml attribute in {path}")


def fluid_box(nml: f90nml.Namelist) -> tuple[float, float, float, float] | None:
    """Return ``(xmin, xmax, ymin, ymax)`` of the first ``&box`` with ``role = 'fluid'``, or None.

    A bound missing from the group is returned as NaN.
    """
    groups = nml.get("box")
    if groups is None:
        return None
    if isinstance(groups, f90nml.Namelist):
        groups = [groups]
    for group in groups:
        if str(group.get("role", "")).strip().lower() == "fluid":
            xmin, xmax, ymin, ymax = (float(group.get(key, np.nan)) for key in ("xmin", "xmax", "ymin", "ymax"))
            return xmin, xmax, ymin, ymax
    return None
