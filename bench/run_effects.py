"""Effects cost nothing when they are off: the dam-break benchmark of bench/run_bench.py
in three versions, and the pair-loop time per particle-step of each.

  (a) the fluid-only case, as run_bench.py runs it;
  (b) the same plus a floating box resting on a solid shelf near the top of the domain,
      far from the water (the water stays below y = 2.1 m in the steps run; the shelf is
      at y = 3.25 m): bodies, contact and friction are in the case but never meet the fluid;
  (c) every optional model on: (b), laminar viscosity + SPS turbulence, kernel gradient
      correction, Fourtakas density diffusion (already on in (a)), an oscillating solid
      block (a moving boundary) beside the shelf, a damping zone over the right quarter
      of the tank and three gauges (two elevation, one pressure, sampled every 0.01 s).
      The wavemaker is left out: its paddle would replace the wall behind the column,
      i.e. change the flow.

Each version runs --repeat times; the minimum is kept (the run least disturbed by other
processes). --reference BINARY also runs (a) with another build, e.g. the foundation's,
so that both are measured on the same machine at the same time.

    .venv/bin/python bench/run_effects.py [--dp 0.01] [--steps 2000] [--repeat 3]
                                          [--reference path/to/old/mbsph]
"""
from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(Path(__file__).resolve().parent))
from run_bench import make_case  # noqa: E402


def body_far(dp: float) -> str:
    """Shelf (three rows thick) and a 0.2 x 0.1 m box of density 2400 resting on it."""
    top = 3.25
    return (f"&box role = 'solid', xmin = 1.6, xmax = 2.4, ymin = {top - 3 * dp!r}, ymax = {top!r} /\n"
            f"&body shape = 'box', x = 2.0, y = {top + 0.05!r}, width = 0.2, height = 0.1, "
            f"density = 2400.0, mu = 0.5 /\n")


def every_model(text: str, dp: float) -> str:
    text = text.replace("viscosity = 'artificial', alpha = 0.02",
                        "viscosity = 'laminar_sps', nu = 1.0e-6, alpha = 0.02, kernel_correction = 'gradient'")
    assert "laminar_sps" in text, "the benchmark case file changed: update every_model()"
    return text + body_far(dp) + (
        f"&box role = 'solid', xmin = 0.3, xmax = 0.5, ymin = {3.25 - 3 * dp!r}, ymax = 3.25, "
        "motion = 'oscillate', amplitude = 0.02, 0.0, period = 1.0 /\n"
        "&damping x0 = 3.0, x1 = 4.0, strength = 10.0 /\n"
        "&gauge kind = 'elevation', x = 0.5 /\n&gauge kind = 'elevation', x = 2.0 /\n"
        "&gauge kind = 'pressure', x = 0.5, y = 0.1 /\n")


def run(binary: Path, case: Path) -> dict[str, float]:
    proc = subprocess.run([str(binary), str(case)], capture_output=True, text=True, stdin=subprocess.DEVNULL)
    if proc.returncode != 0:
        sys.exit(f"benchmark run failed ({binary} {case}):\n{proc.stdout[-3000:]}\n{proc.stderr[-2000:]}")
    out = proc.stdout
    m = re.search(r"cost: ([\d.]+) microseconds per particle-step \((\d+) particle-steps in ([\d.]+) s\)", out)
    psteps = int(m.group(2))
    pair = float(re.search(r"pair loop\s+([\d.]+)", out).group(1))
    return {"particles": int(re.search(r"particles: (\d+)", out).group(1)),
            "steps": int(re.search(r"after (\d+) steps", out).group(1)),
            "us": float(m.group(1)), "pair_us": 1e6 * pair / psteps}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--dp", type=float, default=0.01, help="particle spacing (m), default 0.01")
    ap.add_argument("--steps", type=int, default=2000, help="steps per run, default 2000")
    ap.add_argument("--repeat", type=int, default=3, help="runs per version; the minimum is kept")
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "mbsph")
    ap.add_argument("--reference", type=Path, default=None, help="another build to run (a) with")
    args = ap.parse_args()
    load = os.getloadavg()[0]
    print(f"load average (1 min) before: {load:.2f}" + ("  -- not quiet: the figures are upper bounds" if load >= 1 else ""))
    template = (ROOT / "bench" / "dambreak_bench.nml").read_text()
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        a = make_case(template, args.dp, args.steps, tmp / "out", None)
        versions = {"(a) fluid only": (args.binary, a),
                    "(b) + body far from the water": (args.binary, a + body_far(args.dp)),
                    "(c) every optional model on": (args.binary, every_model(a, args.dp))}
        if args.reference is not None:
            versions["(a) with the reference build"] = (args.reference, a)
        best: dict[str, dict[str, float]] = {}
        for k in range(args.repeat):
            for name, (binary, text) in versions.items():  # interleaved, so a slow spell hits all alike
                case = tmp / "case.nml"
                case.write_text(text)
                r = run(binary, case)
                if name not in best or r["pair_us"] < best[name]["pair_us"]:
                    best[name] = {**r, "us": min(r["us"], best.get(name, r)["us"])}
    ref = best["(a) fluid only"]["pair_us"]
    print(f"dp = {args.dp} m, {args.steps} steps, minimum of {args.repeat} runs; "
          f"load average (1 min) after: {os.getloadavg()[0]:.2f}")
    print(f"{'version':32s} {'particles':>9s} {'pair loop [us/particle-step]':>29s} {'vs (a)':>8s} "
          f"{'whole step [us/particle-step]':>30s}")
    for name, r in best.items():
        print(f"{name:32s} {r['particles']:9d} {r['pair_us']:29.4f} {100 * (r['pair_us'] / ref - 1):+7.1f}% "
              f"{r['us']:30.4f}")


if __name__ == "__main__":
    main()
