"""Perspective views of a 3D run (build/mbsph3d), one panel per output time.

Usage::

    python -m post.plot_3d OUT [--times t1 t2 ...] [--out file.png] [--max-fluid N]

For each requested time the snapshot closest to it is drawn (default: 4 times spread
evenly over the run). The water is drawn as its particles coloured by speed (at most
``--max-fluid`` of them, a fixed random subset, so that the picture stays legible).
Each body's particles are drawn in one colour, and the walls as a light grey cloud. The
vertical axis of the picture is y, the solver's up. The PNG goes to ``OUT/view_3d.png``
by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Sequence

import numpy as np

from .io import Snapshot, closest_snapshots, list_snapshots, read_snapshot
from .plotting import Figure, plt, save_figure

__all__ = ["view_figure", "main"]

_BODY_COLOURS = ["tab:red", "tab:orange", "tab:purple", "tab:brown", "tab:pink", "tab:olive"]


def _panel(ax, snap: Snapshot, vmax: float, max_fluid: int, rng: np.random.Generator):
    """One perspective view of a snapshot on a 3D axis."""
    x = snap.position
    # a body's particles carry its number, after the objects' numbers: the last
    # len(body_pose) numbers; the walls are drawn first, the water, then the bodies on top
    n_bodies = int(np.asarray(snap.datasets.get("body_pose", np.zeros((0, 1)))).shape[0])
    first_body = int(snap.body.max()) - n_bodies + 1 if n_bodies else int(snap.body.max()) + 1
    walls = np.nonzero((~snap.fluid) & (snap.body < first_body))[0]
    if walls.size:
        w = walls[::max(1, walls.size // 4000)]
        ax.scatter(x[w, 0], x[w, 2], x[w, 1], s=0.3, color="0.8", depthshade=False)
    fluid = np.nonzero(snap.fluid)[0]
    if fluid.size > max_fluid:
        fluid = np.sort(rng.choice(fluid, max_fluid, replace=False))
    speed = np.linalg.norm(snap.velocity[fluid], axis=1)
    sc = ax.scatter(x[fluid, 0], x[fluid, 2], x[fluid, 1], c=speed, s=1.0, cmap="viridis", vmin=0.0, vmax=vmax,
                    depthshade=False)
    for k, b in enumerate(range(first_body, first_body + n_bodies)):
        sel = snap.body == b
        ax.scatter(x[sel, 0], x[sel, 2], x[sel, 1], s=8.0, color=_BODY_COLOURS[k % len(_BODY_COLOURS)],
                   depthshade=False, zorder=3)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(plt.MaxNLocator(4))
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m)")
    ax.set_zlabel("y (m)")
    ax.set_title(f"t = {snap.time:.2f} s")
    span = np.ptp(x, axis=0)
    ax.set_box_aspect((span[0], span[2], span[1]))
    ax.view_init(elev=22, azim=-58)
    return sc


def view_figure(snapshots: Sequence[Snapshot], max_fluid: int = 30000) -> Figure:
    """Perspective views of 3D snapshots, one colour scale of speed for all panels."""
    if any(s.position.shape[1] != 3 for s in snapshots):
        raise ValueError("post.plot_3d draws 3D runs (build/mbsph3d); use post.plot_field for 2D ones")
    speeds = np.concatenate([np.linalg.norm(s.velocity[s.fluid], axis=1) for s in snapshots])
    vmax = float(np.percentile(speeds, 99.5)) if speeds.size else 1.0
    vmax = vmax if vmax > 0 else 1.0
    ncol = min(2, len(snapshots))
    nrow = (len(snapshots) + ncol - 1) // ncol
    fig = plt.figure(figsize=(6.0 * ncol + 1.0, 4.6 * nrow))
    rng = np.random.default_rng(1)
    sc = None
    for k, snap in enumerate(snapshots):
        # drawn in the order given (walls, water, bodies on top), not sorted by depth
        ax = fig.add_subplot(nrow, ncol, k + 1, projection="3d", computed_zorder=False)
        sc = _panel(ax, snap, vmax, max_fluid, rng)
    if sc is not None:
        fig.colorbar(sc, ax=fig.axes, shrink=0.6, pad=0.06, label="speed |u| (m/s)")
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    parser = argparse.ArgumentParser(prog="python -m post.plot_3d", description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", type=Path, help="output folder of a 3D run")
    parser.add_argument("--times", type=float, nargs="+", help="output times (s); default: 4 spread over the run")
    parser.add_argument("--out", type=Path, help="PNG file (default OUT/view_3d.png)")
    parser.add_argument("--max-fluid", type=int, default=30000, help="most water particles drawn per panel")
    args = parser.parse_args(argv)
    if args.times:
        paths = closest_snapshots(args.out_dir, args.times)
    else:
        paths = list_snapshots(args.out_dir)
        if not paths:
            raise FileNotFoundError(f"no snapshot snap_NNNNN.h5 in {args.out_dir}")
        paths = [paths[i] for i in np.unique(np.linspace(0, len(paths) - 1, 4).round().astype(int))]
    fig = view_figure([read_snapshot(p) for p in paths], args.max_fluid)
    out = args.out_dir / "view_3d.png" if args.out is None else args.out
    print(f"wrote {save_figure(fig, out)}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.plot_3d"))
