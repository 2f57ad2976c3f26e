"""Cost of a step on the two workloads of doc/performance.md.

- The 2D dam break (bench/dambreak_bench.nml) at dp, dp/2 and dp/4: fluid and
  walls only, the Verlet integrator (one force evaluation a step).
- The 3D dam break (bench/dambreak3d_bench.nml, about 170 000 particles) with
  build/mbsph3d, the whole 0.5 s of flow (or --steps-3d steps): its cost per
  particle-step against the 2D dam break's of the same run (doc/3d.md).
- The breakwater workload: the settling case of input/breakwater/regular.nml
  (gradient correction, density diffusion, the paddle, eleven armour units in
  contact, the symplectic integrator: two force evaluations a step) at its dp
  and at dp/2, each a fixed number of steps.

Runs build/mbsph on each case and prints, per size, the particles, steps,
microseconds per particle-step (the solver's own end-of-run figure: wall time
of the stepping loop / particle-steps), the share of the pair loop and the
peak resident memory per particle, both raw (RSS / N) and marginal (the
slope of RSS against N between sizes, which leaves out the fixed cost of the
MPI and HDF5 libraries). It ends with one line per workload, the smallest size:

    dam break 2D: 0.173 us per particle-step (23018 particles)
    breakwater 2D: 0.411 us per particle-step (14344 particles)
    dam break 3D: 0.605 us per particle-step (172674 particles); 3.49 times the 2D dam break's

    .venv/bin/python bench/run_bench.py [--sizes 1 2 4] [--steps 0 800 200] [--t-end T]
                                        [--bw-sizes 1 2] [--bw-steps 400 100] [--steps-3d 200]
                                        [--only dambreak|breakwater|dambreak3d]

--steps gives max_steps per size of the dam break (0: the whole 0.5 s of flow);
--t-end runs every size for the same simulated time instead (no step limit).
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


def run(case: Path, binary: str = "mbsph") -> tuple[str, int]:
    """Run the solver (build/<binary>); return its output and its peak RSS in bytes."""
    proc = subprocess.Popen([str(ROOT / "build" / binary), str(case)],
                            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    out = proc.stdout.read()
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    if proc.returncode != 0:
        sys.exit(f"benchmark run failed:\n{out}")
    return out, usage.ru_maxrss * 1024


def make_breakwater(template: str, size: int, steps: int, out_dir: Path) -> str:
    """The settling case at dp = 0.01 / size, max_steps steps, no progress lines."""
    assert "  dp = 0.01\n" in template and "out_dir = 'OUT/breakwater_regular'" in template
    text = template.replace("  dp = 0.01\n", f"  dp = {0.01 / size!r}\n")
    return text.replace("out_dir = 'OUT/breakwater_regular'",
                        f"out_dir = '{out_dir}'\n  max_steps = {steps}\n  progress_interval = 1.0e9")


def measure(case: Path, binary: str = "mbsph") -> tuple[int, int, float, int, float]:
    """Particles, steps, us per particle-step, peak RSS [B] and pair-loop share of one run."""
    out, rss = run(case, binary)
    n = int(re.search(r"particles: (\d+)", out).group(1))
    us = float(re.search(r"cost: ([\d.]+) microseconds", out).group(1))
    nsteps = int(re.search(r"after (\d+) steps", out).group(1))
    pair = float(re.search(r"pair loop\s+([\d.]+)", out).group(1))
    wall = float(re.search(r"particle-steps in ([\d.]+) s", out).group(1))
    return n, nsteps, us, rss, pair / wall


def table(title: str, rows: list) -> None:
    print(title)
    print(f"{'dp [m]':>8} {'particles':>10} {'steps':>7} {'us/particle-step':>17} "
          f"{'pair loop share':>16} {'RSS/N [B]':>10} {'marginal [B]':>13}")
    for k, (dp, n, nsteps, us, rss, share) in enumerate(rows):
        marginal = ""
        if k > 0:
            marginal = f"{(rss - rows[k - 1][4]) / (n - rows[k - 1][1]):.0f}"
        print(f"{dp:8.4f} {n:10d} {nsteps:7d} {us:17.3f} {100 * share:15.1f}% {rss / n:10.0f} {marginal:>13}")
    print()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--sizes", type=int, nargs="+", default=[1, 2, 4], help="dam break refinements: dp = 0.01 / size")
    ap.add_argument("--steps", type=int, nargs="+", default=[0, 800, 200],
                    help="dam break max_steps per size (0 = the whole 0.5 s)")
    ap.add_argument("--t-end", type=float, default=None, help="simulated time for every size (overrides --steps)")
    ap.add_argument("--bw-sizes", type=int, nargs="+", default=[1, 2], help="breakwater refinements: dp = 0.01 / size")
    ap.add_argument("--bw-steps", type=int, nargs="+", default=[400, 100], help="breakwater max_steps per size")
    ap.add_argument("--steps-3d", type=int, default=0, help="3D dam break max_steps (0 = the whole 0.5 s)")
    ap.add_argument("--only", choices=["dambreak", "breakwater", "dambreak3d"], default=None, help="run one workload")
    args = ap.parse_args()
    summary = []
    with tempfile.TemporaryDirectory() as tmp:
        if args.only in (None, "dambreak"):
            template = (ROOT / "bench" / "dambreak_bench.nml").read_text()
            rows = []
            for k, size in enumerate(args.sizes):
                dp = 0.01 / size
                steps = args.steps[k] if k < len(args.steps) else 0
                if args.t_end is not None:
                    steps = 0
                case = Path(tmp) / f"bench_{size}.nml"
                case.write_text(make_case(template, dp, steps, Path(tmp) / f"out_{size}", args.t_end))
                n, nsteps, us, rss, share = measure(case)
                rows.append((dp, n, nsteps, us, rss, share))
            table("dam break 2D (bench/dambreak_bench.nml)", rows)
            rows2d = rows
            summary.append(f"dam break 2D: {rows[0][3]:.3f} us per particle-step ({rows[0][1]} particles)")
        if args.only in (None, "breakwater"):
            template = (ROOT / "input" / "breakwater" / "regular.nml").read_text()
            rows = []
            for k, size in enumerate(args.bw_sizes):
                steps = args.bw_steps[k] if k < len(args.bw_steps) else args.bw_steps[-1]
                case = Path(tmp) / f"breakwater_{size}.nml"
                case.write_text(make_breakwater(template, size, steps, Path(tmp) / f"bw_{size}"))
                n, nsteps, us, rss, share = measure(case)
                rows.append((0.01 / size, n, nsteps, us, rss, share))
            table("breakwater 2D (input/breakwater/regular.nml, settling)", rows)
            summary.append(f"breakwater 2D: {rows[0][3]:.3f} us per particle-step ({rows[0][1]} particles)")
        if args.only in (None, "dambreak3d"):
            text = (ROOT / "bench" / "dambreak3d_bench.nml").read_text()
            assert "out_dir = 'OUT/bench3d'" in text
            case = Path(tmp) / "bench3d.nml"
            limit = f"\n  max_steps = {args.steps_3d}" if args.steps_3d > 0 else ""
            case.write_text(text.replace("out_dir = 'OUT/bench3d'", f"out_dir = '{Path(tmp) / 'out3d'}'{limit}"))
            n, nsteps, us, rss, share = measure(case, "mbsph3d")
            table("dam break 3D (bench/dambreak3d_bench.nml, build/mbsph3d)", [(0.01, n, nsteps, us, rss, share)])
            line = f"dam break 3D: {us:.3f} us per particle-step ({n} particles)"
            if args.only is None:
                line += f"; {us / rows2d[0][3]:.2f} times the 2D dam break's"
            summary.append(line)
    for line in summary:
        print(line)


if __name__ == "__main__":
    main()
