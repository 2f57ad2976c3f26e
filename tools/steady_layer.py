"""The pore water in the middle of the steady-flow layer (post.porous_cases.steady_case):
its mean velocity against u/n, the scatter of its particles' speeds, and the mass below,
in and above the layer at every snapshot (doc/porous.md, what does not work yet).

    .venv/bin/python tools/steady_layer.py OUT/porous/steady_turbulent_mdbc/OUT --u 0.24 --from 0.25 --to 0.5
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from post.io import FLUID, list_snapshots, read_snapshot  # noqa: E402
from post.porous_cases import COLUMN_L, N, STEADY_YL  # noqa: E402


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path, help="the run's output folder")
    ap.add_argument("--u", type=float, required=True, help="the piston's Darcy velocity [m/s]")
    ap.add_argument("--from", dest="t0", type=float, default=0.25, help="start of the window [s]")
    ap.add_argument("--to", dest="t1", type=float, default=0.5, help="end of the window [s]")
    a = ap.parse_args()
    lo, hi = STEADY_YL, STEADY_YL + COLUMN_L
    print("| t [s] | mass below / in / above the layer [kg/m] |")
    print("|---|---|")
    rows = []
    for path in list_snapshots(a.out):
        s = read_snapshot(path)
        f = s.kind == FLUID
        y, v, m = s.position[f, 1], s.velocity[f], s.mass[f]
        band = [m[y < lo - 0.02].sum(), m[(y >= lo - 0.02) & (y < hi + 0.02)].sum(), m[y >= hi + 0.02].sum()]
        print(f"| {s.time:.2f} | {band[0]:.3f} / {band[1]:.3f} / {band[2]:.3f} |")
        if a.t0 - 1e-9 <= s.time <= a.t1 + 1e-9:
            mid = (y > lo + 0.2 * COLUMN_L) & (y < hi - 0.2 * COLUMN_L)
            vy = v[mid, 1]
            rows.append((vy.mean() / (a.u / N), (v[mid] ** 2).sum(axis=1).mean() / vy.mean() ** 2))
    if not rows:
        print(f"no snapshot from {a.t0} to {a.t1} s")
        return 1
    vel, scatter = np.array(rows).mean(axis=0)
    print(f"\nmiddle of the layer, {a.t0} to {a.t1} s ({len(rows)} snapshots): mean V_y = {vel:.3f} u/n, "
          f"<|V|^2> = {scatter:.3f} <V_y>^2")
    return 0


if __name__ == "__main__":
    sys.exit(main())
