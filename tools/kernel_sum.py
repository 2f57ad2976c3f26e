"""Does the density a run carries still match the particles' packing?

For the fluid particles at mid-depth of a flume (0.6 < x < 1.6 m, 0.05 < y < 0.15 m),
the kernel sum sum_j m_j W_ij over the fluid (Wendland C2, h = sqrt(2) dp) against the
density the continuity equation carried, in the first, the middle and the last
snapshot (doc/waves.md, "The corrected continuity equation").

    .venv/bin/python tools/kernel_sum.py OUT/waves_irregular [--dp 0.02]
"""

from __future__ import annotations

import argparse
from pathlib import Path

import h5py
import numpy as np


def kernel_sum_ratio(snap: Path, dp: float) -> tuple[float, float, float, float]:
    """Time, mean carried density, mean kernel sum and mean height of the fluid at mid-tank."""
    h = np.sqrt(2.0) * dp
    a = 7.0 / (4.0 * np.pi * h * h)
    with h5py.File(snap, "r") as s:
        x, kind, rho, mass = s["position"][:], s["kind"][:], s["density"][:], s["mass"][:]
        t = float(s.attrs["time"])
    fluid = kind == 1
    sel = np.where(fluid & (x[:, 0] > 0.6) & (x[:, 0] < 1.6) & (x[:, 1] > 0.05) & (x[:, 1] < 0.15))[0]
    xf, mf = x[fluid], mass[fluid]
    ksum = np.empty(sel.size)
    for n, i in enumerate(sel):
        q = np.hypot(*(xf - x[i]).T) / h
        ksum[n] = np.sum(mf * np.where(q < 2.0, a * (1.0 - q / 2.0) ** 4 * (2.0 * q + 1.0), 0.0))
    mid = fluid & (x[:, 0] > 0.6) & (x[:, 0] < 1.6)
    return t, float(rho[sel].mean()), float(ksum.mean()), float(x[mid, 1].mean())


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=Path)
    ap.add_argument("--dp", type=float, default=0.02)
    a = ap.parse_args()
    snaps = sorted(a.out.glob("snap_*.h5"))
    for snap in (snaps[0], snaps[len(snaps) // 2], snaps[-1]):
        t, rho, ksum, ymid = kernel_sum_ratio(snap, a.dp)
        print(f"t = {t:6.2f} s  carried density {rho:8.2f}  kernel sum {ksum:8.2f}  "
              f"({ksum / rho - 1.0:+.2%})  mean height of the water at mid-flume {ymid:.4f} m")


if __name__ == "__main__":
    main()
