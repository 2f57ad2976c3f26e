"""Still-water tank: settled bed pressure against rho0 g H for several settings.

Runs the tank of tests/cases/tank.nml (H = 0.5 m, 1 m wide, dp = H/25) for 5 s
(22 sqrt(H/g)) with each setting and prints, from the snapshots of the last
second, the bed pressure (linear fit of the interpolated mid-tank profile,
extrapolated to the bed) as an error against rho0 g H, and the mean fluid speed.

    .venv/bin/python tools/validation_tank.py
    .venv/bin/python tools/validation_tank.py --boundary repulsive   # one run at a time

With --boundary repulsive the settings are those the repulsive-force boundary
accepts (no density diffusion, no kernel correction), with the dynamic boundary
under the same settings for comparison; with --boundary mdbc those of the modified
dynamic boundary (doc/mdbc.md).
"""
from __future__ import annotations

import argparse
import math
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path[:0] = [str(ROOT), str(ROOT / "tests")]

from conftest import run_case, snapshots, tank_text  # noqa: E402
from post import hydrostatic  # noqa: E402
from post.io import read_snapshot  # noqa: E402

H, WIDTH, G, RHO0 = 0.5, 1.0, 9.81, 1000.0
BASE = {"kernel": "wendland", "integrator": "symplectic", "viscosity": "artificial", "alpha": 0.02,
        "diffusion": "fourtakas", "delta": 0.1}
SETTINGS = {
    "h/dp = sqrt(2) (default)": {},
    "h/dp = 1.7": {"h_over_dp": 1.7},
    "h/dp = 2": {"h_over_dp": 2.0},
    "h/dp = sqrt(2), gradient correction": {"kernel_correction": "gradient"},
    "h/dp = sqrt(2), Shepard filter": {"kernel_correction": "shepard"},
    "h/dp = sqrt(2), hydrostatic mass": {"particle_mass": "hydrostatic"},
    "h/dp = sqrt(2), gradient correction, hydrostatic mass": {"kernel_correction": "gradient",
                                                              "particle_mass": "hydrostatic"},
}
REPULSIVE = {
    "repulsive, h/dp = sqrt(2)": {"boundary": "repulsive", "diffusion": "none"},
    "repulsive, h/dp = 2": {"boundary": "repulsive", "diffusion": "none", "h_over_dp": 2.0},
    "dynamic, h/dp = sqrt(2), no diffusion": {"diffusion": "none"},
}
MDBC = {
    "mdbc, h/dp = sqrt(2)": {"boundary": "mdbc"},
    "mdbc, h/dp = 1.7": {"boundary": "mdbc", "h_over_dp": 1.7},
    "mdbc, h/dp = sqrt(2), gradient correction": {"boundary": "mdbc", "kernel_correction": "gradient"},
    "mdbc, h/dp = sqrt(2), no slip": {"boundary": "mdbc", "mdbc_slip": "noslip"},
    "mdbc, h/dp = sqrt(2), hydrostatic mass": {"boundary": "mdbc", "particle_mass": "hydrostatic"},
    "mdbc, h/dp = sqrt(2), gradient correction, hydrostatic mass": {"boundary": "mdbc",
                                                                    "kernel_correction": "gradient",
                                                                    "particle_mass": "hydrostatic"},
}


def run(name: str, tmp: Path) -> tuple[str, list[float], float]:
    numerics = dict(BASE, **SETTINGS[name])
    folder = tmp / f"case{list(SETTINGS).index(name)}"
    folder.mkdir()
    text = tank_text(depth=H, width=WIDTH, dp=H / 25, t_end=5.0, dt_out=0.25, numerics=numerics)
    proc, out = run_case(text, folder, binary=ROOT / "build" / "mbsph")
    if proc.returncode != 0:
        raise SystemExit(proc.stderr)
    errors, speeds = [], []
    for path in snapshots(out):
        snap = read_snapshot(path)
        if snap.time < 4.0 - 1e-9:
            continue
        ys = hydrostatic.sample_heights(snap, 0.0, H, n=10)
        fit = hydrostatic.bed_pressure(ys, hydrostatic.profile(snap, 0.5 * WIDTH, ys), 0.0)
        errors.append((fit.p_bed - RHO0 * G * H) / (RHO0 * G * H))
        speeds.append(float(np.hypot(*snap.velocity[snap.fluid].T).mean()))
    return name, errors, float(np.mean(speeds))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--boundary", choices=["dynamic", "repulsive", "mdbc"], default="dynamic")
    args = ap.parse_args()
    workers = 2
    if args.boundary == "repulsive":
        SETTINGS.clear()
        SETTINGS.update(REPULSIVE)
        workers = 1
    elif args.boundary == "mdbc":
        SETTINGS.clear()
        SETTINGS.update(MDBC)
    with tempfile.TemporaryDirectory() as tmp, ThreadPoolExecutor(max_workers=workers) as pool:
        rows = list(pool.map(lambda n: run(n, Path(tmp)), SETTINGS))
    print(f"{'setting':56s} {'bed error, mean [%]':>20s} {'range [%]':>16s} {'mean speed / sqrt(gH)':>22s}")
    for name, errors, speed in rows:
        e = 100 * np.array(errors)
        print(f"{name:56s} {e.mean():20.2f} {e.min():7.2f} .. {e.max():5.2f} {speed / math.sqrt(G * H):22.1e}")


if __name__ == "__main__":
    main()
