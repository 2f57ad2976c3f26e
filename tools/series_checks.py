"""Numbers doc/damage.md quotes from a series' output folder: Hm0 (all waves, 4 std) at
each elevation gauge per step, the mean level per 4 s window at one gauge, each unit's
displacement at the step ends, and the paddle face and particle packing in the last
snapshot.

    .venv/bin/python tools/series_checks.py OUT/series/trial study/series/trial.toml
"""
from __future__ import annotations

import glob
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from post import armour, series  # noqa: E402
from post.io import read_csv  # noqa: E402
from post.waves import read_gauges  # noqa: E402


def main() -> None:
    out, ser = Path(sys.argv[1]) / "run", series.load_series(sys.argv[2])
    times = series.schedule(ser)
    gs, t, c = read_gauges(out)
    print("Hm0 (4 std) per step at each elevation gauge")
    for g in gs:
        if g.kind == "elevation":
            e = c[g.column]
            print(f"  x = {g.x}: " + ", ".join(
                f"{4 * np.nanstd(e[(t >= s.start) & (t <= s.end)]):.4f}" for s in times if s.start <= t[-1]))
    g = next(g for g in gs if g.kind == "elevation")
    e = c[g.column]
    print(f"mean level at x = {g.x} per 4 s [mm]: " + ", ".join(
        f"{1000 * np.nanmean(e[(t >= a) & (t < a + 4)]):.1f}" for a in np.arange(0.0, t[-1], 4.0)))
    lay = armour.read_armour(out)
    b = read_csv(out / "bodies.csv")
    ends = [ser.settle] + [s.end for s in times]
    print("displacement / dn at t = " + ", ".join(f"{x:.2f}" for x in ends))
    for body in lay.body:
        m = armour.unit_motion(b, int(body))
        print(f"  body {body}: " + ", ".join(f"{np.interp(x, m.time, m.displacement) / lay.dn:.2f}" for x in ends))
    with h5py.File(sorted(glob.glob(str(out / "snap_*.h5")))[-1]) as f:
        x, k, tt = f["position"][:], f["kind"][:], float(f.attrs["time"])
    pad, fl = x[k == 3], x[k == 1]
    col = fl[(fl[:, 0] >= 0.8) & (fl[:, 0] < 0.9)]
    print(f"last snapshot t = {tt:.2f} s: paddle x {pad[:, 0].min():.3f} to {pad[:, 0].max():.3f} m; column "
          f"x 0.8-0.9 m: {len(col)} particles, water {col[:, 1].min():.3f} to {col[:, 1].max():.3f} m")


if __name__ == "__main__":
    main()
