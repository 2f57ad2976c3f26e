"""The still tank of tests/test_3d.py on the repulsive boundary (doc/3d.md, "Wall surfaces"):
the 2D section (`2d`), a strip N particles wide with periodic sides (`stripN`), or a tank
N particles wide between side walls (`wallsN`). For each it prints the bed pressure
against rho0 g H (the tests' linear fit at mid-tank, last snapshot), the mean speed, the
water past a wall surface, the least distance of the water from a side wall's surface
and the mean speed within dp of the side walls and away from every wall.

    .venv/bin/python tools/repulsive_tank3d.py 2d strip3 walls20 [--out /tmp/rep]
"""
from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))

import test_3d as T  # noqa: E402
from conftest import run_case  # noqa: E402


def report(name: str, out: Path, seconds: float, width: float) -> str:
    err, snap = T.bed_error(out)
    x = snap.position[snap.fluid]
    speed = np.linalg.norm(snap.velocity[snap.fluid], axis=1)
    scale = math.sqrt(T.G * T.H)
    past = int(np.sum((x[:, 0] <= 0.0) | (x[:, 0] >= T.LENGTH) | (x[:, 1] <= 0.0)))
    line = (f"{name}: bed {100 * err:+.2f} % of rho0 g H, mean speed {speed.mean() / scale:.2e} sqrt(gH), "
            f"past a wall {past}, fluid {int(snap.fluid.sum())}, t = {snap.time:.2f} s, {seconds:.0f} s")
    if name.startswith("walls"):
        dz = np.minimum(x[:, 2], width - x[:, 2])
        dx = np.minimum(x[:, 0], T.LENGTH - x[:, 0])
        line += (f"; least distance from a side wall {dz.min() / T.DP:.2f} dp, mean speed within dp of the "
                 f"side walls {speed[dz < T.DP].mean() / scale:.2e}, 4 dp from every wall "
                 f"{speed[(dz > 4 * T.DP) & (dx > 4 * T.DP)].mean() / scale:.2e} sqrt(gH)")
        # where it runs: the vertical corners (within dp of a side wall, 3 dp of an end wall) at mid-depth,
        # against the side walls' middles
        mid = (x[:, 1] > 0.3 * T.H) & (x[:, 1] < 0.7 * T.H)
        corner = (dz < T.DP) & (dx < 3 * T.DP) & mid
        middle = (dz < T.DP) & (dx > 3 * T.DP) & mid
        v = snap.velocity[snap.fluid]
        line += (f"; at mid-depth the mean vertical velocity in the vertical corners {v[corner, 1].mean():+.4f} m/s, "
                 f"along the side walls' middles {v[middle, 1].mean():+.4f} m/s")
    return line


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("cases", nargs="+", help="2d, stripN or wallsN (N particles across)")
    ap.add_argument("--out", default="/tmp/rep", help="folder for the runs")
    args = ap.parse_args()
    for case in args.cases:
        run_dir = Path(args.out) / case
        run_dir.mkdir(parents=True, exist_ok=True)
        width = 0.0
        if case == "2d":
            text, binary = T.repulsive(T.tank2d_text()), ROOT / "build" / "mbsph"
        elif case.startswith("strip"):
            width = int(case[5:]) * T.DP
            text, binary = T.repulsive(T.strip_tank_text(width)), ROOT / "build" / "mbsph3d"
        elif case.startswith("walls"):
            width = int(case[5:]) * T.DP
            T.WIDTH = width                     # tank3d_text reads the module's width
            text, binary = T.repulsive(T.tank3d_text()), ROOT / "build" / "mbsph3d"
        else:
            sys.exit(f"unknown case {case!r}: 2d, stripN or wallsN")
        t0 = time.time()
        proc, out = run_case(text, run_dir, binary=binary, timeout=7200.0)
        if proc.returncode != 0:
            sys.exit(f"{case} failed:\n{proc.stderr[-2000:]}")
        print(report(case, out, time.time() - t0, width), flush=True)


if __name__ == "__main__":
    main()
