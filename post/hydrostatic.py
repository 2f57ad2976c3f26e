"""Pressure profile of a still tank against the hydrostatic pressure.

Usage::

    python -m post.hydrostatic OUT --x X [--depth H] [--y-bed YB] [--time T] [--out file.png]

The pressure is interpolated on a vertical line at ``x`` in the snapshot closest
to ``--time`` (default: the last one) and compared with ``rho0 g (y_bed + H - y)``.
``H`` is the water depth above the bed at ``y_bed`` (default 0); without
``--depth`` it is measured from the free surface of the snapshot. A straight line
fitted to the profile, away from the bed and the surface by ``2h``, gives the
pressure extrapolated to the bed, to compare with ``rho0 g H``. The figure goes
to ``OUT/hydrostatic.png`` by default.
"""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import NamedTuple, Sequence

import numpy as np

from .interp import free_surface_height, interpolate, line_points
from .io import Snapshot, closest_snapshots, list_snapshots, read_snapshot
from .plotting import Figure, plt, save_figure

__all__ = ["profile", "sample_heights", "BedFit", "bed_pressure", "main"]

_N_POINTS = 40


def profile(snapshot: Snapshot, x: float, ys: Sequence[float] | np.ndarray, z: float | None = None) -> np.ndarray:
    """SPH-interpolated pressure (Pa) at the points ``(x, y)`` for ``y`` in ``ys`` (NaN out of the water);
    in a 3D snapshot at ``(x, y, z)``, ``z`` by default mid-width."""
    ys = np.asarray(ys, dtype=float)
    return interpolate(snapshot, "pressure", line_points(snapshot, np.full(ys.shape, x), ys, z))


def sample_heights(snapshot: Snapshot, y_bed: float, depth: float, n: int = _N_POINTS) -> np.ndarray:
    """``n`` heights between the bed and the surface, ``2h`` away from both when the depth allows."""
    margin = 2.0 * snapshot.h
    if depth <= 2.0 * margin + snapshot.dp:
        margin = 0.5 * snapshot.dp
    return np.linspace(y_bed + margin, y_bed + depth - margin, n)


class BedFit(NamedTuple):
    """Straight line ``p = p_bed + slope (y - y_bed)`` fitted to a pressure profile."""

    p_bed: float
    """pressure extrapolated to the bed (Pa)"""
    slope: float
    """dp/dy (Pa/m); ``-rho0 g`` for a hydrostatic profile"""


def bed_pressure(ys: np.ndarray, p: np.ndarray, y_bed: float = 0.0) -> BedFit:
    """Least-squares straight line through the finite values of ``p(ys)``, evaluated at ``y_bed``."""
    ok = np.isfinite(p)
    if np.count_nonzero(ok) < 2:
        return BedFit(float("nan"), float("nan"))
    slope, intercept = np.polyfit(np.asarray(ys)[ok] - y_bed, np.asarray(p)[ok], 1)
    return BedFit(float(intercept), float(slope))


def _figure(snapshot: Snapshot, x: float, ys: np.ndarray, p: np.ndarray, y_bed: float,
            depth: float, fit: BedFit) -> Figure:
    """p(y) of the run, the hydrostatic line and the fitted line with its bed value."""
    rho_g = snapshot.rho0 * snapshot.g
    fig, ax = plt.subplots(figsize=(5.0, 5.5))
    y_ref = np.array([y_bed, y_bed + depth])
    ax.plot(rho_g * (y_bed + depth - y_ref), y_ref, "k-", lw=1, label=r"$\rho_0 g (H - y)$")
    ax.plot(p, ys, "o", ms=3, color="C0", label="MBSPH")
    ax.plot(fit.p_bed + fit.slope * (y_ref - y_bed), y_ref, "--", color="C1", lw=1, label="linear fit")
    ax.plot([fit.p_bed], [y_bed], "D", color="C1", label=f"bed: {fit.p_bed:.1f} Pa")
    ax.set_xlabel("pressure p (Pa)")
    ax.set_ylabel("y (m)")
    ax.set_title(f"x = {x:g} m, t = {snapshot.time:.3f} s, H = {depth:.4g} m")
    ax.grid(True, alpha=0.3)
    ax.legend()
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    parser = argparse.ArgumentParser(prog="python -m post.hydrostatic", description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", type=Path, help="output folder of a run")
    parser.add_argument("--x", type=float, required=True, help="horizontal position of the profile (m)")
    parser.add_argument("--z", type=float, help="3D runs: position across the width (m); default mid-width")
    parser.add_argument("--depth", type=float, help="water depth H above the bed (m); default: measured")
    parser.add_argument("--y-bed", type=float, default=0.0, help="bed elevation (m), default 0")
    parser.add_argument("--time", type=float, help="time (s) of the snapshot; default: the last one")
    parser.add_argument("--out", type=Path, help="PNG file (default OUT/hydrostatic.png)")
    args = parser.parse_args(argv)

    paths = list_snapshots(args.out_dir) if args.time is None else closest_snapshots(args.out_dir, [args.time])
    if not paths:
        raise FileNotFoundError(f"no snapshot snap_NNNNN.h5 in {args.out_dir}")
    snap = read_snapshot(paths[-1])
    depth = args.depth
    if depth is None:
        depth = float(free_surface_height(snap, args.x, z=args.z)) - args.y_bed
        if not np.isfinite(depth):
            raise ValueError(f"no water at x = {args.x} in {args.out_dir}")
    ys = sample_heights(snap, args.y_bed, depth)
    p = profile(snap, args.x, ys, args.z)
    rho_g = snap.rho0 * snap.g
    p_ref = rho_g * (args.y_bed + depth - ys)
    fit = bed_pressure(ys, p, args.y_bed)

    print(f"{snap.path.name}: t = {snap.time:.4f} s, x = {args.x:g} m, depth H = {depth:.5g} m")
    print(f"{'y (m)':>10} {'p (Pa)':>12} {'rho0 g (H-y)':>13} {'rel. diff':>10}")
    for y, pv, pr in zip(ys, p, p_ref):
        print(f"{y:10.5f} {pv:12.3f} {pr:13.3f} {(pv - pr) / pr:10.2e}")
    print(f"fitted dp/dy = {fit.slope:.4g} Pa/m, -rho0 g = {-rho_g:.4g} Pa/m")
    print(f"bed pressure (linear fit) = {fit.p_bed:.4g} Pa, rho0 g H = {rho_g * depth:.4g} Pa, "
          f"rel. error = {(fit.p_bed - rho_g * depth) / (rho_g * depth):.2e}")
    out = args.out_dir / "hydrostatic.png" if args.out is None else args.out
    print(f"wrote {save_figure(_figure(snap, args.x, ys, p, args.y_bed, depth, fit), out)}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.hydrostatic"))
