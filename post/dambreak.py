"""Dam-break surge front against the experiment of Martin and Moyce (1952).

A water column of width ``a`` and height ``2a`` (``n^2 = 2``) stands against a
wall at ``x_wall`` and collapses on a dry horizontal bed. The front position is
made dimensionless as ``Z = (x_front - x_wall) / a`` and the time as
``T = t sqrt(2 g / a)``.

Usage::

    python -m post.dambreak OUT [--a A] [--x-wall X] [--out OUT/dambreak_front.png]

Without ``--a`` / ``--x-wall`` the first ``&box`` group of ``OUT/case.nml`` with
``role = 'fluid'`` gives them: ``a = xmax - xmin`` and ``x_wall = xmin``. The
figure shows the run, the experiment and the Ritter shallow-water front; the
maximum relative error of the run over ``1 <= T <= 3`` is printed.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import NamedTuple, Sequence

import numpy as np
from scipy.spatial import cKDTree

from .io import Snapshot, fluid_box, list_snapshots, read_case, read_snapshot
from .cli import message
from .plotting import Figure, plt, save_figure

__all__ = [
    "experiment",
    "ritter_front",
    "front_position",
    "FrontComparison",
    "compare",
    "main",
]

# Martin, J. C. and Moyce, W. J. (1952), "Part IV. An experimental study of the
# collapse of liquid columns on a rigid horizontal plane", Phil. Trans. R. Soc.
# Lond. A 244 (882), 312-324: Table 2, surge front of the square-based column,
# n^2 = 2, a = 2.25 in. The front was read at steps of a/9 (0.25 in), hence the
# Z values 10/9, 11/9, 13/9, ... The same values are the reference of many later
# validations of particle and free-surface methods (e.g. the n^2 = 2 comparisons
# after Koshizuka and Oka, Nucl. Sci. Eng. 123 (1996) 421-434). The values were
# not read from a scan of the original paper: they were taken from several
# independent reproductions of its Table 2, which agree with each other to
# within 0.01 in T.
# Koshizuka and Oka's front-position figure shows these same points (two public
# digitisations of it fall on them within 0.04 in T): it is not a second
# experiment (doc/validation.md).
_MM_T = (0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98, 3.11, 3.33)
_MM_Z = (1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67, 3.89, 4.11)

#: Dimensionless time window of the error measure.
ERROR_WINDOW = (1.0, 3.0)


def experiment() -> tuple[np.ndarray, np.ndarray]:
    """Return ``(T, Z)`` of the surge front measured by Martin and Moyce (1952), ``n^2 = 2``."""
    return np.array(_MM_T), np.array(_MM_Z)


def ritter_front(T: np.ndarray | float, n2: float = 2.0) -> np.ndarray:
    """Ritter's shallow-water dry-bed front in the variables of Martin and Moyce.

    The front runs at ``2 sqrt(g h0)`` with ``h0 = n^2 a``:
    ``Z = 1 + 2 sqrt(g n^2 a) t / a = 1 + sqrt(2 n^2) T``, i.e. ``Z = 1 + 2T`` for ``n^2 = 2``.
    """
    return 1.0 + np.sqrt(2.0 * n2) * np.asarray(T, dtype=float)


def front_position(snapshot: Snapshot, x_wall: float, bed_layers: float = 3.0,
                   min_neighbours: int = 3, y_bed: float | None = None) -> float:
    """Distance of the surge front from the wall (m).

    The front is the foremost fluid particle near the bed (``y < y_bed + bed_layers dp``)
    that has at least ``min_neighbours`` other fluid particles within ``2 dp``, so that
    isolated spray drops ahead of the surge are ignored. Its position plus ``dp/2``
    (the front face of its volume, so that the still column gives exactly its width)
    minus ``x_wall`` is returned. ``y_bed`` defaults to the lowest fluid particle
    minus ``dp/2``. NaN when no particle qualifies. (The tip of a tongue one particle
    thick has only two neighbours that close, so the front is then read one particle
    behind it; lower ``min_neighbours`` for such runs.)
    """
    pos = snapshot.position[snapshot.fluid]
    dp = snapshot.dp
    if pos.size == 0:
        return float("nan")
    y_bed = pos[:, 1].min() - 0.5 * dp if y_bed is None else y_bed
    radius = 2.0 * dp * (1.0 + 1e-9)
    pool = pos[pos[:, 1] < y_bed + bed_layers * dp + radius]
    candidates = pos[pos[:, 1] < y_bed + bed_layers * dp]
    candidates = candidates[np.argsort(-candidates[:, 0])]
    if candidates.size == 0:
        return float("nan")
    # neighbours within the radius, the particle itself left out
    count = cKDTree(pool).query_ball_point(candidates, radius, return_length=True) - 1
    ok = np.nonzero(count >= min_neighbours)[0]
    if ok.size:
        return float(candidates[ok[0], 0] + 0.5 * dp - x_wall)
    return float("nan")


class FrontComparison(NamedTuple):
    """Front of a run against the experiment, at the snapshot times."""

    T: np.ndarray
    """dimensionless time ``t sqrt(2 g / a)``"""
    Z_sim: np.ndarray
    """dimensionless front of the run ``(x_front - x_wall) / a``"""
    Z_exp: np.ndarray
    """experiment interpolated linearly at ``T`` (NaN outside the measured range)"""
    max_rel_error: float
    """max of ``|Z_sim - Z_exp| / Z_exp`` over ``1 <= T <= 3`` (NaN without a snapshot there)"""


def compare(out_dir: str | Path, a: float, x_wall: float, g: float | None = None) -> FrontComparison:
    """Front of every snapshot of ``out_dir`` against Martin and Moyce (1952).

    ``g`` defaults to the magnitude of the snapshots' ``gravity`` attribute.
    """
    T, Z = [], []
    for path in list_snapshots(out_dir):
        snap = read_snapshot(path)
        grav = snap.g if g is None else g
        T.append(snap.time * np.sqrt(2.0 * grav / a))
        Z.append(front_position(snap, x_wall) / a)
    T_sim, Z_sim = np.array(T), np.array(Z)
    T_exp, Z_exp = experiment()
    Z_at = np.interp(T_sim, T_exp, Z_exp, left=np.nan, right=np.nan)
    tol = 1e-9  # keep a snapshot exactly at an end of the window despite rounding of T
    window = (T_sim >= ERROR_WINDOW[0] - tol) & (T_sim <= ERROR_WINDOW[1] + tol) & np.isfinite(Z_sim)
    rel = np.abs(Z_sim[window] - Z_at[window]) / Z_at[window]
    return FrontComparison(T_sim, Z_sim, Z_at, float(rel.max()) if rel.size else float("nan"))


def front_difference(run: FrontComparison, ref: FrontComparison, t_from: float = 0.5) -> float:
    """Largest |Z_run - Z_ref| / Z_ref over the snapshots of ``ref`` from ``t_from`` on (``run``
    interpolated at them: the snapshots fall on the first step after each output time)."""
    w = (ref.T >= t_from) & (ref.T <= run.T[-1]) & np.isfinite(ref.Z_sim)
    z = np.interp(ref.T[w], run.T, run.Z_sim)
    return float(np.max(np.abs(z - ref.Z_sim[w]) / ref.Z_sim[w]))


def _geometry(out_dir: Path, a: float | None, x_wall: float | None) -> tuple[float, float]:
    """Column width and wall position: the given values, else the first fluid &box of case.nml."""
    if a is None or x_wall is None:
        box = fluid_box(read_case(out_dir))
        if box is None:
            raise ValueError("give --a and --x-wall: case.nml has no &box with role = 'fluid'")
        a = box[1] - box[0] if a is None else a
        x_wall = box[0] if x_wall is None else x_wall
    return float(a), float(x_wall)


def _figure(result: FrontComparison, a: float, other: FrontComparison | None = None,
            labels: tuple[str, str] = ("MBSPH", "")) -> Figure:
    """Z(T) of the run (and of another one), the experiment and the Ritter front."""
    T_exp, Z_exp = experiment()
    t_max = max(float(np.nanmax(result.T, initial=0.0)), float(T_exp[-1])) * 1.05
    z_max = max(float(np.nanmax(result.Z_sim, initial=0.0)), float(Z_exp[-1])) * 1.1
    fig, ax = plt.subplots(figsize=(6.5, 4.5))
    T_line = np.linspace(0.0, t_max, 200)
    ax.plot(T_line, ritter_front(T_line), "k--", lw=1, label="Ritter shallow water, Z = 1 + 2T")
    ax.plot(T_exp, Z_exp, "s", mfc="none", color="C3", label="Martin & Moyce (1952), $n^2 = 2$")
    ax.plot(result.T, result.Z_sim, "-o", ms=3, color="C0", label=f"{labels[0]}, a = {a:g} m")
    if other is not None:
        ax.plot(other.T, other.Z_sim, "-x", ms=4, color="C2", label=labels[1])
    ax.axvspan(*ERROR_WINDOW, color="0.9", zorder=0)
    ax.set_xlim(0.0, t_max)
    ax.set_ylim(0.8, z_max)
    ax.set_xlabel(r"$T = t\,\sqrt{2g/a}$")
    ax.set_ylabel(r"$Z = (x_{front} - x_{wall})\,/\,a$")
    err = result.max_rel_error
    ax.set_title(f"Surge front; max rel. error on T in [1, 3]: {100 * err:.1f} %" if np.isfinite(err)
                 else "Surge front")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper left")
    fig.tight_layout()
    return fig


def main(argv: Sequence[str] | None = None) -> int:
    """Command line entry point."""
    parser = argparse.ArgumentParser(prog="python -m post.dambreak", description=__doc__.split("\n")[0])
    parser.add_argument("out_dir", type=Path, help="output folder of a dam-break run")
    parser.add_argument("--a", type=float, help="column width a (m); default from case.nml")
    parser.add_argument("--x-wall", type=float, help="wall position behind the column (m); default from case.nml")
    parser.add_argument("--out", type=Path, help="PNG file (default OUT/dambreak_front.png)")
    parser.add_argument("--vs", type=Path, help="another run of the same dam break (e.g. the 2D one of a 3D run): "
                        "its front too, and the largest relative difference of the two from T = 0.5 on")
    parser.add_argument("--labels", nargs=2, default=("MBSPH", "MBSPH, --vs"), metavar=("RUN", "VS"),
                        help="legend labels of the run and of the --vs run")
    args = parser.parse_args(argv)
    try:
        a, x_wall = _geometry(args.out_dir, args.a, args.x_wall)
    except (ValueError, FileNotFoundError) as err:
        # one line, as every post tool (post.cli), and exit code 2
        print(f"{parser.prog}: error: {message(err)}", file=sys.stderr)
        raise SystemExit(2) from err
    result = compare(args.out_dir, a, x_wall)
    print(f"a = {a:g} m, x_wall = {x_wall:g} m")
    print(f"{'T':>8} {'Z_sim':>8} {'Z_exp':>8}")
    for T, zs, ze in zip(result.T, result.Z_sim, result.Z_exp):
        print(f"{T:8.3f} {zs:8.3f} {ze:8.3f}")
    if np.isfinite(result.max_rel_error):
        print(f"max relative error for 1 <= T <= 3: {100 * result.max_rel_error:.2f} %")
        lo, hi = ERROR_WINDOW
        w = (result.T >= lo - 1e-9) & (result.T <= hi + 1e-9) & np.isfinite(result.Z_exp)
        if np.count_nonzero(w) >= 2:
            s_sim = np.polyfit(result.T[w], result.Z_sim[w], 1)[0]
            s_exp = np.polyfit(result.T[w], result.Z_exp[w], 1)[0]
            print(f"front speed dZ/dT for 1 <= T <= 3: {s_sim:.3f}, experiment {s_exp:.3f} "
                  f"({100 * (s_sim - s_exp) / s_exp:+.1f} %); mean lead {np.mean(result.Z_sim[w] - result.Z_exp[w]):.3f} a")
    else:
        print("max relative error for 1 <= T <= 3: no snapshot in that range")
    other = None
    if args.vs is not None:
        other = compare(args.vs, a, x_wall)
        print(f"largest relative difference from the --vs run for T >= 0.5: "
              f"{100 * front_difference(result, other):.2f} %")
    out = args.out_dir / "dambreak_front.png" if args.out is None else args.out
    print(f"wrote {save_figure(_figure(result, a, other, tuple(args.labels)), out)}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.dambreak"))
