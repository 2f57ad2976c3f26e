"""Measured Hm0 and Tp of an irregular-wave run against the wave it was asked for, over
the same window: the solver's target elevation at the paddle (``signal.csv`` of
``build/jonswap_signal``, the solver's own synthesis) is carried to each elevation gauge
component by component (linear dispersion, k_i at the still-water depth) and analysed
exactly like the measured record (``post.waves.spectrum`` over ``--fmin``..``--fmax`` Hz).
A window shorter than the signal does not hold exactly Hs: this compares like with like.

Usage (doc/waves.md)::

    python tools/jonswap_target.py OUT/waves_irregular signal.csv --x0 0.17 --depth 0.25 --t-start 8

``--window-spread W`` prints instead how far Hm0 of a window of W seconds strays from Hs
for the signal's amplitudes with random phases (5 and 95 % of 400 draws).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from post import waves  # noqa: E402
from post.io import read_csv  # noqa: E402


def target_at(t: np.ndarray, x: float, signal: dict, x0: float, depth: float) -> np.ndarray:
    """The periodic target elevation of ``signal`` (at the paddle, x0) carried to x."""
    return waves.target_elevation_at(t, x, signal["time"], signal["eta"], x0, depth)


def window_spread(signal: dict, window: float, fmin: float, fmax: float, draws: int = 400) -> None:
    """Hm0 / Hs of a ``window`` s record of the signal's components with random phases."""
    n = len(signal["time"])
    dt = signal["time"][1] - signal["time"][0]
    amp = 2.0 * np.abs(np.fft.rfft(signal["eta"]) / n)[1:]
    f = np.arange(1, len(amp) + 1) / (n * dt)
    keep = amp > 1e-6 * amp.max()
    f, amp = f[keep], amp[keep]
    hs = 4.0 * math.sqrt(np.sum(amp**2) / 2.0)
    t = np.arange(0.0, window, 0.025)
    rng = np.random.default_rng(1)
    ratio, tp = [], []
    for _ in range(draws):
        eta = np.cos(2.0 * math.pi * f[None, :] * t[:, None] + rng.uniform(0.0, 2.0 * math.pi, len(f))[None, :]) @ amp
        sp = waves.spectrum(t, eta, fmin=fmin, fmax=fmax)
        ratio.append(sp.Hm0 / hs)
        tp.append(sp.Tp)
    print(f"window of {window:g} s out of a signal of {n * dt:g} s ({draws} random-phase draws): Hm0/Hs "
          f"{np.percentile(ratio, 5):.2f} to {np.percentile(ratio, 95):.2f}, Tp {np.percentile(tp, 5):.3f} to "
          f"{np.percentile(tp, 95):.3f} s (5 to 95 %)")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", type=Path, help="run folder holding gauges.csv")
    ap.add_argument("signal", type=Path, help="time,x,eta of build/jonswap_signal")
    ap.add_argument("--x0", type=float, default=None, help="paddle face at rest (m)")
    ap.add_argument("--depth", type=float, default=None, help="still-water depth (m)")
    ap.add_argument("--t-start", type=float, default=None, help="start of the window (s), after the slowest component arrived")
    ap.add_argument("--window-spread", type=float, default=None, metavar="W", help="spread of Hm0 over windows of W s")
    ap.add_argument("--fmin", type=float, default=0.5, help="band of Hm0 (Hz); default the signal's 0.5 fp at Tp = 1 s")
    ap.add_argument("--fmax", type=float, default=3.0, help="band of Hm0 (Hz)")
    a = ap.parse_args(argv)
    sig = read_csv(a.signal)
    if a.window_spread is not None:
        window_spread(sig, a.window_spread, a.fmin, a.fmax)
        return 0
    if a.x0 is None or a.depth is None or a.t_start is None:
        ap.error("--x0, --depth and --t-start are needed to compare with a run")
    gauges, t, cols = waves.read_gauges(a.out)
    sel = t >= a.t_start
    tt = t[sel]
    print(f"window {tt[0]:.2f} to {tt[-1]:.2f} s; Hm0 over {a.fmin:g} to {a.fmax:g} Hz; target Hm0 of the whole signal "
          f"{4.0 * np.std(sig['eta']):.4f} m")
    for g in gauges:
        if g.kind != "elevation":
            continue
        y = cols[g.column][sel]
        ref = target_at(tt, g.x, sig, a.x0, a.depth)
        m = waves.spectrum(tt, y, fmin=a.fmin, fmax=a.fmax)
        r = waves.spectrum(tt, ref, fmin=a.fmin, fmax=a.fmax)
        zm, zr = waves.zero_crossing(tt, y), waves.zero_crossing(tt, ref)
        rho = np.corrcoef(y - y.mean(), ref)[0, 1]
        print(f"gauge {g.id} at x = {g.x:.3f} m ({g.x - a.x0:.3f} m from the paddle): "
              f"Hm0 {m.Hm0:.4f} m against {r.Hm0:.4f} m ({m.Hm0 / r.Hm0 - 1.0:+.1%}), "
              f"Tp {m.Tp:.3f} s against {r.Tp:.3f} s (bins of {m.df:.4f} Hz), "
              f"T_mean {zm.T_mean:.3f} s against {zr.T_mean:.3f} s, correlation {rho:.2f}, "
              f"mean level {1e3 * y.mean():+.1f} mm")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
