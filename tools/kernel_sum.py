"""Does the density a run carries still match the particles' packing?

For the fluid particles at mid-depth of a flume (0.6 < x < 1.6 m, 0.05 < y < 0.15 m),
the kernel sum sum_j m_j W_ij over the fluid (`post.interp.mass_sum`) against the density
the continuity equation carried, in the first, the middle and the last snapshot
(doc/waves.md, "The corrected continuity equation").

    .venv/bin/python tools/kernel_sum.py OUT/waves_irregular
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from post.interp import mass_sum  # noqa: E402
from post.io import Snapshot, list_snapshots, read_snapshot  # noqa: E402


def packing(snap: Snapshot) -> tuple[float, float, float]:
    """Mean carried density, mean kernel sum of the fluid at mid-depth, and the mean height
    of the water between x = 0.6 and 1.6 m."""
    x = snap.position
    mid = snap.fluid & (x[:, 0] > 0.6) & (x[:, 0] < 1.6)
    sel = mid & (x[:, 1] > 0.05) & (x[:, 1] < 0.15)
    return float(snap.density[sel].mean()), float(mass_sum(snap, x[sel]).mean()), float(x[mid, 1].mean())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    a = ap.parse_args()
    paths = list_snapshots(a.out)
    for path in (paths[0], paths[len(paths) // 2], paths[-1]):
        snap = read_snapshot(path)
        rho, ksum, ymid = packing(snap)
        print(f"t = {snap.time:6.2f} s  carried density {rho:8.2f}  kernel sum {ksum:8.2f}  "
              f"({ksum / rho - 1.0:+.2%})  mean height of the water at mid-flume {ymid:.4f} m")


if __name__ == "__main__":
    main()
