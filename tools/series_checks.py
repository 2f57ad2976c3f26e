"""Numbers doc/damage.md quotes from a series' output folder: Hm0 (all waves, 4 std) at
each elevation gauge per step, the mean level per 4 s window at one gauge, each unit's
displacement at the step ends, the reflection a slope of the same steepness gives by
Seelig and Ahrens' formula beside the measured Kr, and the paddle face and particle
packing in the last snapshot.

    .venv/bin/python tools/series_checks.py OUT/series/trial study/series/trial.toml
"""
from __future__ import annotations

import glob
import sys
from pathlib import Path

import f90nml
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
    # the reflection a slope of this steepness gives (Seelig and Ahrens 1981, as the Coastal
    # Engineering Manual tabulates it: Kr = a xi^2 / (b + xi^2), a smooth impermeable slope
    # a = 1.0, b = 5.5, a permeable rubble mound a = 0.6, b = 6.6), at each step's incident
    # Hm0 at the toe and the deep-water wave length of Tp
    csv_path = out.parent / "series.csv"
    if csv_path.is_file():
        rows = read_csv(csv_path)
        nml = f90nml.read(str(out / "case.nml"))
        tan_a = 1.0 / float(nml["breakwater"]["slope_cot"])
        l0 = 9.81 * ser.tp ** 2 / (2.0 * np.pi)
        for step, hm0, kr in zip(rows["step"], rows["Hm0_i"], rows["Kr"]):
            xi = tan_a / np.sqrt(hm0 / l0)
            print(f"step {step}: xi_0p {xi:.2f}, Kr measured {kr:.2f}; Seelig-Ahrens smooth impermeable "
                  f"{xi ** 2 / (5.5 + xi ** 2):.2f}, rubble mound {0.6 * xi ** 2 / (6.6 + xi ** 2):.2f}")
    with h5py.File(sorted(glob.glob(str(out / "snap_*.h5")))[-1]) as f:
        x, k, tt = f["position"][:], f["kind"][:], float(f.attrs["time"])
    pad, fl = x[k == 3], x[k == 1]
    col = fl[(fl[:, 0] >= 0.8) & (fl[:, 0] < 0.9)]
    print(f"last snapshot t = {tt:.2f} s: paddle x {pad[:, 0].min():.3f} to {pad[:, 0].max():.3f} m; column "
          f"x 0.8-0.9 m: {len(col)} particles, water {col[:, 1].min():.3f} to {col[:, 1].max():.3f} m")


if __name__ == "__main__":
    main()
