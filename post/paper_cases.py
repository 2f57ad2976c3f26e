"""The seed paper's test cases: the dimensions chosen for them, their analytic
answers, and the paper's figures (centre of the body against time for each
contact model, with the analytic curve).

    .venv/bin/python -m post.paper_cases OUT/paper [--out doc/img]

tools/make_paper_cases.py writes the case files from the same numbers.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from post.io import read_csv
from post.plotting import plt, save_figure

G = 9.81
DP = 0.005            # 5 mm particles
H_OVER_DP = 1.3       # kernel support 2h = 13 mm, as in the paper's TC3
MODELS = ["dynamic", "repulsive", "noncohesive", "noncohesive_spring", "hertz"]

# TC1a: a solid cylinder rolling without slip drops (1/3) g sin^2(alpha) t^2; the paper's
# 0.55 m -> 0.22 m in 0.5 s fixes alpha
TC1A_Z0, TC1A_Z1, TC1A_T = 0.55, 0.22, 0.5
TC1A_ALPHA = math.asin(math.sqrt((TC1A_Z0 - TC1A_Z1) * 3.0 / (G * TC1A_T**2)))
TC1A_R, TC1A_MU, TC1A_S0 = 0.05, 0.5, 0.15     # mu > tan(alpha)/3 = 0.275: no slip
TC1A_DP = 0.0025      # R/20: a particle disc rolls on a radius that converges as dp/R
# TC1b: a block sliding with a = g (sin a - mu cos a); on the second slope mu > tan a: it sticks
TC1B_ALPHA, TC1B_MU = math.radians(30.0), 0.3
TC1B_STATIC_ALPHA, TC1B_STATIC_MU = math.radians(20.0), 0.5
TC1B_W, TC1B_H = 0.1, 0.05
# TC2: disc launched 0.2 m before the edge of a floor raised TC2_STEP above the ground
TC2_R, TC2_MU, TC2_U, TC2_STEP, TC2_EDGE = 0.05, 0.1, 2.0, 0.53, 0.4
# TC3: discs D = 3 cm; their particle rows 1 cm apart (the paper's distance between the
# boundary particles of the two bodies), support 13 mm; c0 = 15 m/s, a sound speed of
# the paper's order
TC3_R, TC3_PARTICLE_GAP, TC3_U, TC3_MU, TC3_C0 = 0.015, 0.01, 2.0, 0.2, 15.0
TC3_X_LEFT = 0.1
TC3_X_RIGHT = TC3_X_LEFT + 2 * TC3_R + TC3_PARTICLE_GAP - DP


def tc1a_height(t):
    """Centre height of the rolling cylinder (m)."""
    return TC1A_Z0 - G * math.sin(TC1A_ALPHA) ** 2 * np.asarray(t) ** 2 / 3.0


def tc1a_speed(t):
    """Speed of the centre of the rolling cylinder (m/s): a = (2/3) g sin(alpha)."""
    return 2.0 / 3.0 * G * math.sin(TC1A_ALPHA) * np.asarray(t)


def tc1b_distance(t, alpha=TC1B_ALPHA, mu=TC1B_MU):
    """Distance slid along the slope (m); zero when mu >= tan(alpha)."""
    a = max(G * (math.sin(alpha) - mu * math.cos(alpha)), 0.0)
    return 0.5 * a * np.asarray(t) ** 2


def disc_slip_roll(t, u0, mu, radius=None):
    """Travel (m) and speed of a solid disc launched at u0 without spin on a flat floor:
    it slides at -mu g while the friction spins it up (d omega/dt = 2 mu g / R), and rolls
    at u0 (2/3) once u = omega R, after t_s = u0 / (3 mu g)."""
    t = np.asarray(t, dtype=float)
    ts = u0 / (3.0 * mu * G)
    slide = t < ts
    x = np.where(slide, u0 * t - 0.5 * mu * G * t**2,
                 u0 * ts - 0.5 * mu * G * ts**2 + 2.0 / 3.0 * u0 * (t - ts))
    u = np.where(slide, u0 - mu * G * t, 2.0 / 3.0 * u0)
    return x, u


def tc2_landing():
    """Landing time (s) and x (m) of the TC2 disc: slides 0.2 m to the edge (still
    slipping), then falls TC2_STEP."""
    # 0.2 = u0 t - mu g t^2 / 2
    a = 0.5 * TC2_MU * G
    t1 = (TC2_U - math.sqrt(TC2_U**2 - 4 * a * 0.2)) / (2 * a)
    u1 = TC2_U - TC2_MU * G * t1
    t2 = math.sqrt(2 * TC2_STEP / G)
    return t1 + t2, TC2_EDGE + u1 * t2


def _series(out_root: Path, name: str, model: str, body: int = 1):
    path = out_root / f"{name}_{model}" / "bodies.csv"
    if not path.exists():
        return None
    d = read_csv(path)
    m = d["body"] == body
    return {k: v[m] for k, v in d.items()}


def figures(out_root: Path, out_dir: Path) -> list[Path]:
    """One PNG per case: the body centre against time for every model that was run."""
    written = []
    cases = [
        ("tc1a_rolling", "TC1a rolling cylinder: centre height", "y", 1,
         lambda t: tc1a_height(t), "rolling without slip"),
        ("tc1b_sliding", "TC1b sliding block: distance along the slope", "s", 1,
         lambda t: tc1b_distance(t), "g (sin a - mu cos a) t^2 / 2"),
        ("tc2_jump", "TC2 disc leaving the edge: centre height", "y", 1, None, None),
        ("tc3_receding", "TC3 receding discs: x of both centres", "x", 0,
         lambda t: TC3_X_RIGHT + disc_slip_roll(t, TC3_U, TC3_MU)[0], "right disc: slide, then roll"),
    ]
    for name, title, what, body, exact, label in cases:
        fig, ax = plt.subplots(figsize=(7, 4.5))
        any_run = False
        for model in MODELS:
            bodies = [1, 2] if body == 0 else [body]
            for b in bodies:
                s = _series(out_root, name, model, b)
                if s is None:
                    continue
                any_run = True
                if what == "s":
                    y = np.hypot(s["x"] - s["x"][0], s["y"] - s["y"][0])
                else:
                    y = s[what]
                ax.plot(s["time"], y, label=f"{model}" + (f", disc {b}" if body == 0 else ""))
        if not any_run:
            plt.close(fig)
            continue
        if exact is not None:
            t = np.linspace(0.0, 0.5, 101)
            ax.plot(t, exact(t), "k--", label=f"analytic ({label})")
        if name == "tc2_jump":
            tl, xl = tc2_landing()
            ax.axvline(tl, color="k", ls="--", label=f"analytic landing t = {tl:.3f} s")
        ax.set_xlabel("t (s)")
        ax.set_ylabel({"y": "centre y (m)", "x": "centre x (m)", "s": "distance (m)"}[what])
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
        written.append(save_figure(fig, out_dir / f"paper_{name}.png"))
    return written


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out_root", type=Path, help="folder holding the runs (OUT/paper)")
    ap.add_argument("--out", type=Path, default=None, help="folder for the PNGs (default: out_root)")
    args = ap.parse_args(argv)
    for path in figures(args.out_root, args.out or args.out_root):
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.paper_cases"))
