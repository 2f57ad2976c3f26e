"""Time series of columns of a CSV file such as ``OUT/energy.csv``.

Usage::

    python -m post.plot_series OUT/energy.csv col1 [col2 ...] [--out file.png]

The columns are drawn against ``time``; columns sharing a unit (kinetic and
potential energy, say) share a panel, and panels are stacked over a common time
axis. The PNG goes next to the CSV file, as ``<csv name>_<col1>_<col2>....png``,
by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Sequence

import numpy as np

from .io import read_csv
from .plotting import Figure, plt, save_figure

__all__ = ["UNITS", "series_figure", "plot_series", "main"]

#: Units of the energy.csv columns (doc/output.md); other columns are drawn without a unit.
UNITS: dict[str, str] = {
    "time": "s",
    "step": "-",
    "kinetic": "J/m",
    "potential": "J/m",
    "total_mass": "kg/m",
    "n_fluid": "-",
    "lost": "-",
}


def _panels(columns: Sequence[str]) -> list[list[str]]:
    """Group columns by unit, in order of first appearance; unknown units get a panel each."""
    panels: dict[str, list[str]] = {}
    for col in columns:
        key = UNITS.get(col, f"?{col}")
        panels.setdefault(key, []).append(col)
    return list(panels.values())


def series_figure(data: dict[str, np.ndarray], columns: Sequence[str], x: str = "time") -> Figure:
    """Draw ``data[col]`` against ``data[x]`` for each column; return the figure."""
    missing = [c for c in [x, *columns] if c not in data]
    if missing:
        raise KeyError(f"no column {', '.join(missing)}; columns are {', '.join(data)}")
    panels = _panels(columns)
    fig, axes = plt.subplots(len(panels), 1, sharex=True, squeeze=False,
                             figsize=(7.0, 1.0 + 2.6 * len(panels)))
    for ax, cols in zip(axes[:, 0], panels):
        for col in cols:
            ax.plot(data[x], data[col], label=col)
        unit = UNITS.get(cols[0])
        ax.set_ylabel(f"{', '.join(cols)} ({unit})" if unit else ", ".join(cols))
        ax.grid(True, alpha=0.3)
        if len(cols) > 1:
            ax.legend()
    axes[-1, 0].set_xlabel(f"{x} ({UNITS[x]})" if x in UNITS else x)
    fig.tight_layout()
    return fig


def plot_series(csv_path: str | Path, columns: Sequence[str], out: str | Path | None = None) -> Path:
    """Plot ``columns`` of a CSV file against time; return the PNG path."""
    csv_path = Path(csv_path)
    fig = series_figure(read_csv(csv_path), columns)
    if out is None:
        out = csv_path.with_name(f"{csv_path.stem}_{'_'.join(columns)}.png")
    return save_figure(fig, out)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    parser = argparse.ArgumentParser(prog="python -m post.plot_series", description=__doc__.split("\n")[0])
    parser.add_argument("csv", type=Path, help="CSV file with a header line, e.g. OUT/energy.csv")
    parser.add_argument("columns", nargs="+", help="columns to draw against time")
    parser.add_argument("--out", type=Path, help="PNG file (default: next to the CSV file)")
    args = parser.parse_args(argv)
    try:
        path = plot_series(args.csv, args.columns, args.out)
    except KeyError as err:
        parser.error(err.args[0])
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.plot_series"))
