"""Cost of a step: the 2D dam-break benchmark at dp, dp/2 and dp/4.

Runs build/mbsph on bench/dambreak_bench.nml at each size and prints, per
size, the particles, steps, microseconds per particle-step (the solver's own
end-of-run figure: wall time of the stepping loop / particle-steps) and the
peak resident memory per particle, both raw (RSS / N) and marginal (the
slope of RSS against N between sizes, which leaves out the fixed cost of
the MPI and HDF5 libraries).

    .venv/bin/python bench/run_bench.py [--sizes 1 2 4] [--steps 0 800 200] [--t-end T]

--steps gives max_steps per size (0: the whole 0.5 s of flow); --t-end runs
every size for the same simulated time instead (no step limit).
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def make_case(template: str, dp: float, steps: int, out_dir: Path, t_end: float | None) -> str:
    wall = 3 * dp  # three particle layers: more than the kernel support 2h
    text = template.replace("dp = 0.01,", f"dp = {dp!r},")
    if t_end is not None:
        text = text.replace("t_end = 0.5", f"t_end = {t_end!r}")
    text = text.replace("out_dir = 'OUT/bench'", f"out_dir = '{out_dir}'")
    text = text.replace("-0.03", repr(-wall)).replace("4.03", repr(4.0 + wall))
    if steps > 0:
        text = text.replace("  overwrite = .true.", f"  overwrite = .true.\n  max_steps = {steps}")
    return text


def run(case: Path) -> tuple[str, int]:
    """Run the solver; return its output and its peak RSS in bytes."""
    proc = subprocess.Popen([str(ROOT / "build" / "mbsph"), str(case)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit(f"benchmark run failed:\n{out}")
    return out, usage.ru_maxrss * 1024


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 4], help="refinements: dp = 0.01 / size")
    ap.add_argument("--steps", type=int, nargs="+", default=[0, 800, 200],
                    help="max_steps per size (0 = the whole 0.5 s)")
    ap.add_argument("--t-end", type=float, default=None, help="simulated time for every size (overrides --steps)")
    args = ap.parse_args()
    template = (ROOT / "bench" / "dambreak_bench.nml").read_text()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for k, size in enumerate(args.sizes):
            dp = 0.01 / size
            steps = args.steps[k] if k < len(args.steps) else 0
            if args.t_end is not None:
                steps = 0
            case = Path(tmp) / f"bench_{size}.nml"
            case.write_text(make_case(template, dp, steps, Path(tmp) / f"out_{size}", args.t_end))
            out, rss = run(case)
            n = int(re.search(r"particles: (\d+)", out).group(1))
            us = float(re.search(r"cost: ([\d.]+) microseconds", out).group(1))
            nsteps = int(re.search(r"after (\d+) steps", out).group(1))
            pair = float(re.search(r"pair loop\s+([\d.]+)", out).group(1))
            wall = float(re.search(r"particle-steps in ([\d.]+) s", out).group(1))
            rows.append((dp, n, nsteps, us, rss, pair / wall))
    print(f"{'dp [m]':>8} {'particles':>10} {'steps':>7} {'us/particle-step':>17} "
          f"{'pair loop share':>16} {'RSS/N [B]':>10} {'marginal [B]':>13}")
    for k, (dp, n, nsteps, us, rss, share) in enumerate(rows):
        marginal = ""
        if k > 0:
            marginal = f"{(rss - rows[k - 1][4]) / (n - rows[k - 1][1]):.0f}"
        print(f"{dp:8.4f} {n:10d} {nsteps:7d} {us:17.3f} {100 * share:15.1f}% {rss / n:10.0f} {marginal:>13}")


if __name__ == "__main__":
    main()
