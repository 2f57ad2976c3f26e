"""Do two runs of the same case give the same answers?

Compares two output folders written by two builds of the solver on the same case:
every snapshot (each float dataset, the ones post.io.read_snapshot does not read too, particles matched by id, as the largest difference
relative to the dataset's largest magnitude; integer datasets exactly) and the CSV series
energy.csv, bodies.csv and gauges.csv (column by column, relative to the column's
largest magnitude). Prints one line per file and the largest relative difference, and
exits 1 when it exceeds --tol (default 1e-10: the bar for a change that reorders sums).

    .venv/bin/python tools/compare_runs.py OUT/before OUT/after [--tol 1e-10]
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import h5py
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from post.io import read_csv  # noqa: E402
from post.waves import read_gauges  # noqa: E402


def by_id(f: h5py.File, name: str) -> np.ndarray:
    """Dataset `name` of a snapshot with its particles in the order of their ids."""
    data = f[name][()]
    order = np.argsort(f["id"][()], kind="stable")
    # vectors are stored (N, 2) as h5py reads them
    return data[order] if data.shape and data.shape[0] == order.size else data


def compare_snapshot(a: Path, b: Path) -> float:
    worst = 0.0
    with h5py.File(a) as fa, h5py.File(b) as fb:
        for name in fa:
            # connectivity numbers the particles in the file's order, which the ranks change
            if not isinstance(fa[name], h5py.Dataset) or name not in fb or name == "connectivity":
                continue
            x, y = by_id(fa, name), by_id(fb, name)
            if x.shape != y.shape:
                print(f"{a.name}: {name}: shapes differ {x.shape} {y.shape}")
                return float("inf")
            if x.dtype.kind == "f":
                scale = float(np.max(np.abs(x))) if x.size else 0.0
                d = float(np.max(np.abs(x - y))) / scale if scale > 0 else 0.0
                worst = max(worst, d)
            elif not np.array_equal(x, y):
                print(f"{a.name}: {name}: integer data differ")
                return float("inf")
    return worst


def read_series(path: Path) -> dict[str, np.ndarray]:
    """The columns of a CSV series, by the post package's reader of that file."""
    if path.name == "gauges.csv":
        return read_gauges(path)[2]
    return read_csv(path)


def compare_csv(a: Path, b: Path) -> float:
    x, y = read_series(a), read_series(b)
    if list(x) != list(y) or any(x[k].shape != y[k].shape for k in x):
        print(f"{a.name}: columns or lengths differ")
        return float("inf")
    worst = 0.0
    for name in x:
        u, v = x[name].astype(float), y[name].astype(float)
        if u.size == 0:
            continue
        scale = float(np.nanmax(np.abs(u)))
        if scale > 0:
            worst = max(worst, float(np.nanmax(np.abs(u - v))) / scale)
    return worst


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("a", type=Path)
    ap.add_argument("b", type=Path)
    ap.add_argument("--tol", type=float, default=1e-10)
    args = ap.parse_args()
    worst = 0.0
    snaps = sorted(args.a.glob("snap_*.h5"))
    if not snaps:
        print(f"error: no snapshots in {args.a}", file=sys.stderr)
        return 2
    for sa in snaps:
        sb = args.b / sa.name
        if not sb.is_file():
            print(f"{sa.name}: missing in {args.b}")
            return 1
        d = compare_snapshot(sa, sb)
        identical = d == 0.0
        print(f"{sa.name}: {'identical' if identical else f'largest relative difference {d:.3g}'}")
        worst = max(worst, d)
    for name in ("energy.csv", "bodies.csv", "gauges.csv"):
        fa, fb = args.a / name, args.b / name
        if not fa.is_file():
            continue
        same = fa.read_bytes() == fb.read_bytes()
        d = 0.0 if same else compare_csv(fa, fb)
        print(f"{name}: {'identical' if same else f'largest relative difference {d:.3g}'}")
        worst = max(worst, d)
    print(f"largest relative difference: {worst:.3g} (bar {args.tol:g})")
    return 0 if worst <= args.tol else 1


if __name__ == "__main__":
    sys.exit(main())
