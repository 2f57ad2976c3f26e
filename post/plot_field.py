"""Particle scatter plots coloured by a field, one panel per output time.

Usage::

    python -m post.plot_field OUT [--field pressure|velocity|density]
                                  [--times t1 t2 ...] [--out file.png]

For each requested time the snapshot closest to it is drawn (default: 4 times
spread evenly over the run). Fluid particles are coloured by the field
(velocity: its magnitude) on one colour scale shared by all panels; boundary and
body particles are grey. The PNG goes to ``OUT/field_<field>.png`` by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Callable, Sequence

import numpy as np

from .io import Snapshot, closest_snapshots, read_snapshot
from .plotting import Figure, plt, save_figure

__all__ = ["FIELDS", "field_values", "field_figure", "plot_field", "main"]

#: Field name -> (colour bar label with unit, values per particle).
FIELDS: dict[str, tuple[str, Callable[[Snapshot], np.ndarray]]] = {
    "pressure": ("pressure p (Pa)", lambda s: s.pressure),
    "velocity": ("velocity magnitude |u| (m/s)", lambda s: np.hypot(s.velocity[:, 0], s.velocity[:, 1])),
    "density": (r"density $\rho$ (kg/m$^3$)", lambda s: s.density),
}

# Figure layout (inches): panel width, margins, gaps and colour bar width.
_PANEL_WIDTH = 4.5
_LEFT, _RIGHT, _BOTTOM, _TOP = 0.8, 0.9, 0.6, 0.8
_GAP, _CBAR_GAP, _CBAR_WIDTH = 0.6, 0.2, 0.15
_BOUNDARY_GREY = "0.6"


def field_values(snapshot: Snapshot, field: str) -> np.ndarray:
    """Return the plotted value of ``field`` for every particle of ``snapshot``."""
    if field not in FIELDS:
        raise ValueError(f"unknown field {field!r}; choose one of {', '.join(FIELDS)}")
    return FIELDS[field][1](snapshot)


def _colour_range(snapshots: Sequence[Snapshot], field: str) -> tuple[float, float]:
    """Shared colour range: 0.5 and 99.5 percentiles of the fluid values (robust to spikes)."""
    values = np.concatenate([field_values(s, field)[s.fluid] for s in snapshots])
    if values.size == 0:
        return 0.0, 1.0
    lo, hi = np.percentile(values, [0.5, 99.5])
    if field == "velocity":
        lo = 0.0
    if hi <= lo:
        hi = lo + max(abs(lo), 1.0) * 1e-6
    return float(lo), float(hi)


def _marker_area(fig: Figure, ax: plt.Axes, dp: float) -> float:
    """Marker area (points^2) making a particle about ``dp`` wide on screen."""
    box = ax.get_position()
    width_pt = box.width * fig.get_figwidth() * 72.0
    x0, x1 = ax.get_xlim()
    return max((dp * width_pt / (x1 - x0)) ** 2, 0.05)


def _layout(n: int, aspect: float) -> tuple[Figure, list[plt.Axes], plt.Axes]:
    """Figure with ``n`` panels of height/width ``aspect`` in a row and a colour bar axis."""
    panel_h = float(np.clip(_PANEL_WIDTH * aspect, 1.2, 8.0))
    width = _LEFT + n * _PANEL_WIDTH + (n - 1) * _GAP + _CBAR_GAP + _CBAR_WIDTH + _RIGHT
    height = _BOTTOM + panel_h + _TOP
    fig = plt.figure(figsize=(width, height))
    panels = [fig.add_axes(((_LEFT + i * (_PANEL_WIDTH + _GAP)) / width, _BOTTOM / height,
                            _PANEL_WIDTH / width, panel_h / height)) for i in range(n)]
    cax = fig.add_axes(((width - _RIGHT - _CBAR_WIDTH) / width, _BOTTOM / height,
                        _CBAR_WIDTH / width, panel_h / height))
    return fig, panels, cax


def field_figure(snapshots: Sequence[Snapshot], field: str = "pressure") -> Figure:
    """Draw one panel per snapshot, particles coloured by ``field``, and a shared colour bar."""
    if not snapshots:
        raise ValueError("no snapshot to draw")
    label = FIELDS[field][0] if field in FIELDS else field
    allpos = np.concatenate([s.position for s in snapshots])
    margin = snapshots[0].dp
    (xmin, ymin), (xmax, ymax) = allpos.min(axis=0) - margin, allpos.max(axis=0) + margin
    fig, panels, cax = _layout(len(snapshots), (ymax - ymin) / (xmax - xmin))
    vmin, vmax = _colour_range(snapshots, field)
    mappable = None
    for ax, snap in zip(panels, snapshots):
        ax.set_xlim(xmin, xmax)
        ax.set_ylim(ymin, ymax)
        ax.set_aspect("equal")
        ax.apply_aspect()
        area = _marker_area(fig, ax, snap.dp)
        solid = ~snap.fluid
        ax.scatter(snap.position[solid, 0], snap.position[solid, 1], s=area, c=_BOUNDARY_GREY,
                   marker="s", linewidths=0)
        values = field_values(snap, field)
        mappable = ax.scatter(snap.position[snap.fluid, 0], snap.position[snap.fluid, 1], s=area,
                              c=values[snap.fluid], cmap="viridis", vmin=vmin, vmax=vmax,
                              marker="o", linewidths=0)
        ax.set_title(f"t = {snap.time:.3f} s")
        ax.set_xlabel("x (m)")
    panels[0].set_ylabel("y (m)")
    box, cbox = panels[0].get_position(), cax.get_position()
    cax.set_position((cbox.x0, box.y0, cbox.width, box.height))  # as tall as the panels
    fig.colorbar(mappable, cax=cax, label=label)
    name = snapshots[0].case_name
    fig.suptitle(f"{name}: {label}" if name else label, y=1 - 0.25 / fig.get_figheight())
    return fig


def plot_field(out_dir: str | Path, field: str = "pressure", times: Sequence[float] | None = None,
               out: str | Path | None = None) -> Path:
    """Draw ``field`` at the snapshots of ``out_dir`` closest to ``times``; return the PNG path."""
    if field not in FIELDS:
        raise ValueError(f"unknown field {field!r}; choose one of {', '.join(FIELDS)}")
    snapshots = [read_snapshot(p) for p in closest_snapshots(out_dir, times)]
    out = Path(out_dir) / f"field_{field}.png" if out is None else Path(out)
    return save_figure(field_figure(snapshots, field), out)


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    parser = argparse.ArgumentParser(prog="python -m post.plot_field", description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", type=Path, help="output folder of a run (holds snap_NNNNN.h5)")
    parser.add_argument("--field", choices=list(FIELDS), default="pressure", help="field to colour by")
    parser.add_argument("--times", type=float, nargs="+", metavar="T",
                        help="times (s); the closest snapshots are drawn (default: 4 spread over the run)")
    parser.add_argument("--out", type=Path, help="PNG file (default OUT/field_<field>.png)")
    args = parser.parse_args(argv)
    path = plot_field(args.out_dir, args.field, args.times, args.out)
    print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.plot_field"))
