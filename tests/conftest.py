"""Shared helpers of the integration tests: where the binaries are, how to run a
case, and the case templates of tests/cases/.

The tests build nothing: `make test` (or `make build/mbsph build/debug/mbsph`)
builds before pytest runs. A test that needs a binary that is missing is skipped.
MBSPH_BINARY and MBSPH_DEBUG_BINARY (environment) point the tests at another
build of the release and the debug binary.

Every run happens in the test's own ``tmp_path``: the case file is written
there and the binary runs with ``tmp_path`` as its working folder, so a
relative ``out_dir`` lands in ``tmp_path`` too.
"""

from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path
from typing import Any

import h5py
import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
CASES = Path(__file__).resolve().parent / "cases"
sys.path.insert(0, str(ROOT))  # the package post/ at the repository root

RELEASE = Path(os.environ.get("MBSPH_BINARY", ROOT / "build" / "mbsph"))
DEBUG = Path(os.environ.get("MBSPH_DEBUG_BINARY", ROOT / "build" / "debug" / "mbsph"))
RELEASE_3D = Path(os.environ.get("MBSPH3D_BINARY", ROOT / "build" / "mbsph3d"))

#: exit code of the solver for bad input (src/errors.f90)
EXIT_INPUT = 2
#: wall-clock limit of one run of the solver, so that a hung run fails instead of blocking the suite
RUN_TIMEOUT = 300.0
#: names of the datasets of a snapshot (doc/output.md)
SNAPSHOT_DATASETS = ("position", "velocity", "density", "pressure", "mass", "kind", "body", "id",
                     "connectivity")


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line("markers", "long: a run of several minutes (the wave-height flumes); collected "
                            "first, so that the workers of `pytest -n 2` share them and end together")


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    # long runs first, each followed by one short test: with --maxschedchunk=1 (Makefile)
    # pytest-xdist starts each worker with the next two tests in order, so each of the
    # first workers starts with a long run of its own
    long_runs = [item for item in items if item.get_closest_marker("long") is not None]
    rest = [item for item in items if item.get_closest_marker("long") is None]
    order: list[pytest.Item] = []
    for item in long_runs:
        order.append(item)
        if rest:
            order.append(rest.pop(0))
    items[:] = order + rest


def _binary_or_skip(path: Path, make_target: str) -> Path:
    if not (path.is_file() and os.access(path, os.X_OK)):
        pytest.skip(f"{path} is missing: build it first with `make {make_target}` "
                    "(the tests do not build the solver)")
    return path


@pytest.fixture(scope="session")
def mbsph() -> Path:
    """The release binary build/mbsph; skips the test when it has not been built."""
    return _binary_or_skip(RELEASE, "build/mbsph")


@pytest.fixture(scope="session")
def mbsph3d() -> Path:
    """The 3D release binary build/mbsph3d; skips the test when it has not been built."""
    return _binary_or_skip(RELEASE_3D, "mbsph3d")


@pytest.fixture(scope="session")
def mbsph_debug() -> Path:
    """The debug binary build/debug/mbsph (traps FP exceptions); skips when it has not been built."""
    return _binary_or_skip(DEBUG, "build/debug/mbsph")


# A small water column on the floor of a domain 0.6 m wide, one step (the bad-input
# tests edit it; the removal test lets it spill off the floor's ends).
COLUMN_ON_FLOOR = """\
&run
  case_name = 'bad_input'
  t_end = 0.01
  dt_out = 0.01
  out_dir = 'OUT'
  max_steps = 1
/
&domain
  xmin = -0.1, xmax = 0.5, ymin = -0.1, ymax = 0.5
/
&fluid
  rho0 = 1000.0, gamma = 7.0
/
&numerics
  dp = 0.02
  kernel = 'wendland'
  integrator = 'symplectic'
  cfl = 0.2
/
&box role = 'fluid', xmin = 0.0, xmax = 0.1, ymin = 0.0, ymax = 0.2 /
&box role = 'solid', xmin = -0.06, xmax = 0.46, ymin = -0.06, ymax = 0.0 /
"""

_OUT_DIR_RE = re.compile(r"""\bout_dir\s*=\s*(['"])(.*?)\1""", re.IGNORECASE)


def out_dir_of(text: str, default: str = "OUT") -> str:
    """The ``out_dir`` of a case text (the solver's default 'OUT' when it is not set)."""
    found = _OUT_DIR_RE.search(text)
    return found.group(2).strip() if found else default


def run_case(text: str, tmp_path: Path, binary: Path | str = RELEASE, name: str = "case.nml",
             timeout: float = RUN_TIMEOUT) -> tuple[subprocess.CompletedProcess, Path]:
    """Write ``text`` to ``tmp_path/name`` and run ``binary`` on it from ``tmp_path``.

    Returns the finished process (stdout and stderr as text) and the output folder
    ``tmp_path/<out_dir of the text>``, which may not exist (bad input).
    """
    tmp_path = Path(tmp_path)
    case = tmp_path / name
    case.write_text(text)
    proc = subprocess.run([str(binary), name], cwd=tmp_path, capture_output=True, text=True,
                          timeout=timeout, stdin=subprocess.DEVNULL)
    return proc, tmp_path / out_dir_of(text)


def straight_and_restarted(text, tmp_path: Path, binary: Path | str, steps: int) -> tuple[Path, Path]:
    """One run of ``text(steps)`` in tmp_path/a, and one of ``text(steps // 2)`` in tmp_path/b
    continued by ``text(steps, restart=True)``: their output folders, every run ended normally."""
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    proc, out_a = run_case(text(steps), tmp_path / "a", binary=binary)
    assert_ok(proc)
    proc, out_b = run_case(text(steps // 2), tmp_path / "b", binary=binary)
    assert_ok(proc)
    proc, _ = run_case(text(steps, restart=True), tmp_path / "b", binary=binary)
    assert_ok(proc)
    return out_a, out_b


def describe(proc: subprocess.CompletedProcess) -> str:
    """Exit code and the ends of stdout and stderr, for assertion messages."""
    return (f"exit code {proc.returncode}\n--- stdout (end) ---\n{proc.stdout[-2000:]}"
            f"\n--- stderr (start) ---\n{proc.stderr[:2000]}")


def assert_ok(proc: subprocess.CompletedProcess) -> None:
    """The run ended normally."""
    assert proc.returncode == 0, f"the solver failed\n{describe(proc)}"


# ------------------------------------------------------------------ namelists


def nml_value(value: Any) -> str:
    """A Python value as a namelist value: strings quoted, logicals as .true./.false."""
    if isinstance(value, bool):
        return ".true." if value else ".false."
    if isinstance(value, str):
        return f"'{value}'"
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, (list, tuple)):
        return ", ".join(nml_value(v) for v in value)
    return str(value)


def nml_lines(values: dict[str, Any]) -> str:
    """``name = value`` lines, indented, for the body of a namelist group."""
    return "\n".join(f"  {key} = {nml_value(val)}" for key, val in values.items())


def case_text(template: str, run: dict[str, Any] | None = None,
              numerics: dict[str, Any] | None = None, **fields: Any) -> str:
    """Fill the template ``tests/cases/<template>.nml``.

    ``run`` and ``numerics`` are extra variables of &run and &numerics; every other
    field replaces ``{field}`` in the template (floats written with repr, so exactly).
    """
    text = (CASES / f"{template}.nml").read_text()
    values = {key: (repr(val) if isinstance(val, float) else val) for key, val in fields.items()}
    values["run"] = nml_lines(run or {})
    values["numerics"] = nml_lines(numerics or {})
    values.setdefault("out_dir", "OUT")
    return text.format(**values)


def walls(dp: float, left: float, right: float, layers: int = 3) -> dict[str, float]:
    """Fields of a tank from x = left to x = right with floor and walls ``layers`` dp thick."""
    w = layers * dp
    return {"wall_left": left - w, "wall_right": right + w, "floor_bottom": -w}


def dambreak_text(a: float = 0.1, dp: float = 0.1 / 15, t_end: float = 1.0, dt_out: float = 0.1,
                  run: dict[str, Any] | None = None, numerics: dict[str, Any] | None = None,
                  out_dir: str = "OUT") -> str:
    """The dam break of tests/cases/dambreak.nml: column a x 2a, tank 4a wide, walls 3 dp thick."""
    tank = 4.0 * a
    margin = 3.0 * dp + 0.1 * a  # the walls and some room around them
    return case_text("dambreak", run=run, numerics=numerics, out_dir=out_dir, t_end=t_end,
                     dt_out=dt_out, dp=dp, a=a, column_top=2.0 * a, tank=tank, wall_top=3.0 * a,
                     dom_xmin=-margin, dom_xmax=tank + margin, dom_ymin=-margin, dom_ymax=4.0 * a,
                     **walls(dp, 0.0, tank))


def tank_text(depth: float, width: float, dp: float, t_end: float, dt_out: float,
              run: dict[str, Any] | None = None, numerics: dict[str, Any] | None = None,
              out_dir: str = "OUT") -> str:
    """Still water of tests/cases/tank.nml: ``depth`` deep, ``width`` wide, walls 3 dp thick."""
    margin = 3.0 * dp + 0.05 * width  # the walls and some room around them
    return case_text("tank", run=run, numerics=numerics, out_dir=out_dir, t_end=t_end, dt_out=dt_out,
                     dp=dp, depth=depth, width=width, wall_top=1.4 * depth,
                     dom_xmin=-margin, dom_xmax=width + margin, dom_ymin=-margin,
                     dom_ymax=1.6 * depth, **walls(dp, 0.0, width))


def paddle_text(amplitude_x: float, period: float, t_end: float, dt_out: float, dp: float = 0.01,
                run: dict[str, Any] | None = None, numerics: dict[str, Any] | None = None,
                out_dir: str = "OUT") -> str:
    """The oscillating paddle of tests/cases/paddle.nml."""
    return case_text("paddle", run=run, numerics=numerics, out_dir=out_dir, t_end=t_end,
                     dt_out=dt_out, dp=dp, amplitude_x=amplitude_x, period=period,
                     **walls(dp, 0.0, 0.6))


# -------------------------------------------------------------------- output


def snapshots(out_dir: Path) -> list[Path]:
    """The snapshots of an output folder, in output order."""
    from post.io import list_snapshots
    return list_snapshots(out_dir)


def read_datasets(path: Path) -> dict[str, np.ndarray]:
    """Every dataset of an HDF5 file, as stored (no conversion)."""
    with h5py.File(path, "r") as f:
        return {name: f[name][()] for name in f.keys()}


def read_attrs(path: Path) -> dict[str, Any]:
    """The root attributes of an HDF5 file."""
    with h5py.File(path, "r") as f:
        return {key: f.attrs[key] for key in f.attrs}


def assert_same_datasets(a: Path, b: Path) -> None:
    """Both snapshots hold the same datasets, bit for bit, and the same time and step."""
    da, db = read_datasets(a), read_datasets(b)
    assert sorted(da) == sorted(db), f"{a.name} and {b.name} hold different datasets"
    differ = []
    for name in da:
        if da[name].shape != db[name].shape or not np.array_equal(da[name], db[name]):
            if da[name].shape == db[name].shape and da[name].dtype.kind == "f":
                diff = float(np.max(np.abs(da[name].astype(float) - db[name].astype(float))))
                differ.append(f"/{name} (max abs difference {diff:.3e})")
            else:
                differ.append(f"/{name} (shapes {da[name].shape} and {db[name].shape})")
    assert not differ, f"{a} and {b} differ in " + ", ".join(differ)
    aa, ab = read_attrs(a), read_attrs(b)
    for key in ("time", "step", "n_particles"):
        assert np.array_equal(aa[key], ab[key]), f"attribute {key}: {aa[key]!r} != {ab[key]!r}"


def wait_for_checkpoint(path: Path, step: int, timeout: float = 60.0) -> None:
    """Wait until the checkpoint at path holds a step of at least ``step`` (a running
    run writes it; a read of a file being renamed is retried)."""
    import time
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if path.is_file():
            try:
                with h5py.File(path, "r") as f:
                    if int(f.attrs["istep"]) >= step:
                        return
            except OSError:
                pass
        time.sleep(0.05)
