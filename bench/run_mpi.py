"""Parallel scaling of the dam-break benchmark (bench/dambreak_bench.nml) on MPI ranks.

    .venv/bin/python bench/run_mpi.py strong [--dp 0.0025] [--steps 200] [--ranks 1 2]
    .venv/bin/python bench/run_mpi.py weak [--dp 0.005] [--steps 400] [--ranks 1 2]
    .venv/bin/python bench/run_mpi.py agree [--steps 200] [--ranks 2]
    .venv/bin/python bench/run_mpi.py model [--ranks 64 1024]

strong: one case (dp = 0.0025 m: 332,018 particles) on each rank count; prints the wall
time of the stepping loop per step, the speed-up against the first rank count, the cost
per particle-step and the share of the 'comm' phase (rank 0's phase timers).

weak: the case widened with the rank count (P water columns side by side in a tank P
times as wide, so the particles per rank stay the same); prints the time per step.

agree: the dam break of tests/cases/dambreak.nml (coarse) on 1 rank and on each rank
count; prints the largest difference of positions, velocities and densities (particles
matched by id) relative to each field's largest magnitude.

model: the communication volume per step of the halo scheme (doc/parallel.md) for a
2D flume, against particle count and ranks; no run.

The binary is build/mbsph, or $MBSPH_BINARY. Each run is started with `mpirun -np P`
(plus --allow-run-as-root as root and --oversubscribe), one at a time. Measure on a
quiet machine: the script prints the load average before each run.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BINARY = Path(os.environ.get("MBSPH_BINARY", ROOT / "build" / "mbsph"))
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))


def mpirun(ranks: int) -> list[str]:
    cmd = [shutil.which("mpirun") or "mpirun", "-q", "--oversubscribe", "-np", str(ranks)]
    if os.geteuid() == 0:
        cmd.insert(1, "--allow-run-as-root")
    return cmd


def run(case: Path, ranks: int) -> str:
    load = os.getloadavg()[0]
    proc = subprocess.run(mpirun(ranks) + [str(BINARY), case.name], cwd=case.parent,
                          capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"run failed:\n{proc.stdout[-3000:]}\n{proc.stderr[-3000:]}")
    print(f"  ({case.name} on {ranks} rank(s), load average before: {load:.2f})", file=sys.stderr)
    return proc.stdout


def bench_case(dp: float, steps: int, out_dir: Path, columns: int = 1) -> str:
    """bench/dambreak_bench.nml at dp, `columns` water columns 1 m wide side by side in a
    tank 4 * columns m wide, walls three layers thick."""
    text = (ROOT / "bench" / "dambreak_bench.nml").read_text()
    wall = 3 * dp
    width = 4.0 * columns
    text = text.replace("dp = 0.01,", f"dp = {dp!r},")
    text = text.replace("out_dir = 'OUT/bench'", f"out_dir = '{out_dir}'")
    text = text.replace("  overwrite = .true.", f"  overwrite = .true.\n  max_steps = {steps}")
    text = text.replace("&domain xmin = -0.1, xmax = 4.1,", f"&domain xmin = -0.1, xmax = {width + 0.1!r},")
    text = text.replace("xmin = 0.0, xmax = 1.0, ymin = 0.0, ymax = 2.0", f"xmin = 0.0, xmax = {float(columns)!r}, "
                        "ymin = 0.0, ymax = 2.0")
    text = text.replace("xmin = -0.03, xmax = 4.03, ymin = -0.03", f"xmin = {-wall!r}, xmax = {width + wall!r}, "
                        f"ymin = {-wall!r}")
    text = text.replace("xmin = -0.03, xmax = 0.0,", f"xmin = {-wall!r}, xmax = 0.0,")
    text = text.replace("xmin = 4.0, xmax = 4.03,", f"xmin = {width!r}, xmax = {width + wall!r},")
    return text


def figures(out: str) -> dict:
    wall = float(re.search(r"particle-steps in ([\d.]+) s", out).group(1))
    return {
        "n": int(re.search(r"particles: (\d+)", out).group(1)),
        "steps": int(re.search(r"after (\d+) steps", out).group(1)),
        "us": float(re.search(r"cost: ([\d.]+) microseconds", out).group(1)),
        "wall": wall,
        "comm": float(re.search(r"comm\s+([\d.]+)", out).group(1)) / wall,
        "pairs": float(re.search(r"pair loop\s+([\d.]+)", out).group(1)) / wall,
    }


def scaling(args: argparse.Namespace, weak: bool) -> None:
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for p in args.ranks:
            case = Path(tmp) / f"case_{p}.nml"
            case.write_text(bench_case(args.dp, args.steps, Path(tmp) / f"out_{p}", p if weak else 1))
            rows.append((p, figures(run(case, p))))
    base = rows[0][1]["wall"] / rows[0][1]["steps"]
    print(f"{'ranks':>5} {'particles':>10} {'steps':>6} {'ms/step':>9} {'speed-up':>9} {'us/particle-step':>17} "
          f"{'pair loop':>10} {'comm':>6}")
    for p, f in rows:
        per = f["wall"] / f["steps"]
        print(f"{p:5d} {f['n']:10d} {f['steps']:6d} {1e3 * per:9.2f} {base / per:9.2f} {f['us']:17.3f} "
              f"{100 * f['pairs']:9.1f}% {100 * f['comm']:5.1f}%")


def agree(args: argparse.Namespace) -> None:
    from conftest import dambreak_text
    from post.io import read_snapshot
    text = dambreak_text(t_end=1.0, dt_out=1.0, out_dir="OUT", run={"max_steps": args.steps, "overwrite": True})
    with tempfile.TemporaryDirectory() as tmp:
        snaps = {}
        for p in [1] + list(args.ranks):
            folder = Path(tmp) / f"r{p}"
            folder.mkdir()
            (folder / "case.nml").write_text(text)
            run(folder / "case.nml", p)
            snaps[p] = read_snapshot(sorted((folder / "OUT").glob("snap_*.h5"))[-1])
    a = snaps[1]
    print(f"{'ranks':>5} {'step':>5} {'position':>10} {'velocity':>10} {'density':>10}   (max |difference| / max |value|)")
    for p in args.ranks:
        b = snaps[p]
        assert np.array_equal(a.id, b.id)
        rel = [float(np.max(np.abs(getattr(a, f) - getattr(b, f))) / np.max(np.abs(getattr(a, f))))
               for f in ("position", "velocity", "density")]
        print(f"{p:5d} {b.step:5d} {rel[0]:10.1e} {rel[1]:10.1e} {rel[2]:10.1e}")


# values per halo particle and step (doc/parallel.md, symplectic integrator): halo 16,
# refresh before the second evaluation 5, acceleration and density rate back after
# each of the two evaluations 2 x 3
HALO_VALUES = 16 + 5 + 2 * 3
MESSAGES = 11            # MPI_Sendrecv calls per step (halo 2, migration 4, refresh 1, reverse 4)
REDUCTIONS = 3           # MPI_Allreduce calls per step (dt, removals, NaN check)


def model(args: argparse.Namespace) -> None:
    """Flume aspect: the particle field is `aspect` times longer than high (water and air
    over the domain); h = sqrt(2) dp, so a cell column (2h) holds 2 sqrt(2) n_y particles."""
    aspect = 50.0
    latency, bandwidth, cost = 2e-6, 10e9, 0.17e-6     # s, B/s, s per particle-step
    print(f"flume {aspect:.0f} times longer than high, h/dp = sqrt(2); per rank and step, symplectic;")
    print(f"network {latency * 1e6:.0f} us latency, {bandwidth / 1e9:.0f} GB/s; compute {cost * 1e6:.2f} us "
          "per particle-step")
    print(f"{'particles':>11} {'ranks':>6} {'per rank':>9} {'columns':>8} {'halo':>7} {'halo %':>7} "
          f"{'kB sent':>8} {'all ranks MB':>13} {'comm us':>8} {'compute us':>11} {'comm %':>7}")
    for n in (1e6, 1e7, 1e8):
        ny = (n / aspect) ** 0.5
        nx = n / ny
        col = 2.0 * 2.0 ** 0.5 * ny               # particles per cell column
        for p in args.ranks:
            columns = nx / (2.0 * 2.0 ** 0.5) / p
            if columns < 1.0:
                continue
            mig = 0.01 * col * 20                 # about 1 % of a column crosses an edge per step
            kb = (HALO_VALUES * col + mig) * 8 / 1e3
            # neighbour messages overlap in pairs; a reduction takes log2(P) latencies
            comm = MESSAGES * latency + kb * 1e3 / bandwidth + REDUCTIONS * math.log2(p) * latency
            compute = n / p * cost
            print(f"{n:11.0e} {p:6d} {n / p:9.0f} {columns:8.1f} {col:7.0f} {100 * col * p / n:6.1f}% "
                  f"{kb:8.1f} {kb * p / 1e3:13.1f} {1e6 * comm:8.0f} {1e6 * compute:11.0f} "
                  f"{100 * comm / (comm + compute):6.1f}%")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("mode", choices=["strong", "weak", "agree", "model"])
    ap.add_argument("--dp", type=float, default=None, help="particle spacing [m]")
    ap.add_argument("--steps", type=int, default=None, help="steps per run")
    ap.add_argument("--ranks", type=int, nargs="+", default=None, help="rank counts")
    args = ap.parse_args()
    if args.mode == "strong":
        args.dp = args.dp or 0.0025
        args.steps = args.steps or 200
        args.ranks = args.ranks or [1, 2]
        scaling(args, weak=False)
    elif args.mode == "weak":
        args.dp = args.dp or 0.005
        args.steps = args.steps or 400
        args.ranks = args.ranks or [1, 2]
        scaling(args, weak=True)
    elif args.mode == "model":
        args.ranks = args.ranks or [64, 1024]
        model(args)
    else:
        args.steps = args.steps or 200
        args.ranks = args.ranks or [2]
        agree(args)


if __name__ == "__main__":
    main()
