"""The absorbing paddle's tuning at kh 1.2 (doc/waves.md, "Active absorption at the
paddle"): for 15 particles over the depth (both boundaries) and 12.5 (mDBC), piston and
flap, the near field q, the lag beyond x_g/c (the evanescent modes' share alone, with
filters of infinite time, and all, each also in dp of travel) and the gain over Biesel's,
from post.wave_cases.absorber_tuning (the solver's paddle_absorb_tune).

    .venv/bin/python tools/absorber_tuning.py
"""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from post.wave_cases import absorber_tuning, biesel_transfer, paddle_modes  # noqa: E402


d = 0.25
for n, bs in ((15, ('dynamic', 'mdbc')), (12.5, ('mdbc',))):
    dp = d / n
    h = 1.6 * dp
    for b in bs:
        xg = 2 * h + dp - (h - 0.5 * dp if b == 'dynamic' else 0.0)
        for p in ('piston', 'flap'):
            G, tl, q = absorber_tuning(1.2, p, d, xg)
            w = paddle_modes(1.2, d, p, xg)[0]
            c = w * d / 1.2
            _, tl_modes, _ = absorber_tuning(1.2, p, d, xg, tau_periods=1e12)
            print(f"{n} per depth, {b}, {p}: q {q:.3f}, t_l - x_g/c {tl - xg / c:.4f} s "
                  f"(modes {tl_modes - xg / c:.4f} s = {(tl_modes - xg / c) * c / dp:.2f} dp, "
                  f"all {(tl - xg / c) * c / dp:.2f} dp), G / Biesel {G * biesel_transfer(1.2, p) / w:.3f}")
