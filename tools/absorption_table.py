"""Reflection coefficient of the absorbing paddle: a regular wave made by a piston wall at
the far end of a flume runs to the paddle, which rests; two gauges a quarter wavelength
in front of it separate the wave coming in from the wave it returns (Goda and Suzuki).
The layout is post/wave_cases.py's absorption_case; the test is tests/test_waves.py's
test_absorbing_paddle_reflection.

    .venv/bin/python tools/absorption_table.py               # the table of doc/waves.md

Each row: the paddle, the wave's kh, the kh the absorber is tuned to (the wave's own for
a regular wave, the peak's for a JONSWAP sea), Kr of linear theory for that absorber (0
where it is tuned to the wave; its gain and delay at another kh), and Kr measured with and
without absorption.
"""
from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from post.wave_cases import absorber_linear_kr, absorption_case  # noqa: E402
from post.waves import paddle_reflection_coefficient, read_gauges  # noqa: E402

H_OVER_DP = 1.6   # absorption_case's h / dp


def linear_kr(kh: float, gain_kh: float, paddle: str, depth: float, over_depth: float,
              boundary: str = "dynamic") -> float:
    """Kr of linear theory for the solver's absorber tuned to gain_kh and met by a wave of
    kh (post.wave_cases.absorber_linear_kr): the gauge stands 2h + dp in front of the
    face, and the dynamic boundary makes the wave h - dp/2 in front of it (the others at
    the face)."""
    dp = depth / over_depth
    h = H_OVER_DP * dp
    source = h - 0.5 * dp if boundary == "dynamic" else 0.0
    return absorber_linear_kr(kh, gain_kh, paddle, depth, 2.0 * h + dp - source)


def measure(kh: float, gain_kh: float, paddle: str, absorb: bool, over_depth: float, depth: float,
            binary: str, boundary: str = "") -> float:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "OUT"
        f = absorption_case(kh, depth=depth, dp=depth / over_depth, paddle=paddle, absorb=absorb,
                            gain_kh=gain_kh, out_dir=str(out),
                            extra_numerics=f"  boundary = '{boundary}'" if boundary else "")
        case = Path(tmp) / "case.nml"
        case.write_text(f.text)
        subprocess.run([binary, str(case)], check=True, capture_output=True, cwd=tmp)
        _, t, c = read_gauges(out / "gauges.csv")
        m = (t >= f.window[0]) & (t <= f.window[1])
        r = paddle_reflection_coefficient(t[m], c["eta_1"][m], c["eta_2"][m], f.gauges[1] - f.gauges[0], depth,
                                          f.period)
        return r.Kr


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--over-depth", type=float, default=15.0, help="particles over the depth")
    ap.add_argument("--depth", type=float, default=0.25)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--binary", default=str(ROOT / "build" / "mbsph"), help="the solver (another build: "
                    "its absorber against this one's)")
    ap.add_argument("--boundary", default="", choices=["", "dynamic", "mdbc"],
                    help="boundary of both runs (default: the wave defaults, dynamic with an absorbing paddle)")
    a = ap.parse_args()
    a.binary = str(Path(a.binary).resolve())
    rows = [("piston", 1.2, 1.2), ("piston", 0.7, 0.7), ("piston", 1.7, 1.7), ("piston", 0.7, 1.2),
            ("piston", 1.7, 1.2), ("flap", 1.2, 1.2)]
    jobs = []
    with ThreadPoolExecutor(a.workers) as ex:
        for paddle, kh, gkh in rows:
            jobs.append((ex.submit(measure, kh, gkh, paddle, True, a.over_depth, a.depth, a.binary, a.boundary),
                         ex.submit(measure, kh, gkh, paddle, False, a.over_depth, a.depth, a.binary, a.boundary)))
        print(f"depth {a.depth} m, {a.over_depth:g} particles over the depth, steepness 0.02")
        print("| paddle | kh of the wave | absorber tuned to kh | Kr, linear theory | Kr measured | Kr, paddle not absorbing |")
        print("|---|---|---|---|---|---|")
        for (paddle, kh, gkh), (j1, j0) in zip(rows, jobs):
            print(f"| {paddle} | {kh} | {gkh} | {linear_kr(kh, gkh, paddle, a.depth, a.over_depth, a.boundary or 'dynamic'):.3f} | {j1.result():.3f} | "
                  f"{j0.result():.3f} |", flush=True)


if __name__ == "__main__":
    main()
