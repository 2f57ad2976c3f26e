"""Where a generated regular wave loses its height: a flume run with eleven gauges
from 0.5 to 3 wavelengths (L) from the paddle (--x-max for farther), a quarter wavelength apart, and its
analysis (doc/waves.md, "Where the height goes").

    .venv/bin/python tools/wave_loss.py run NAME --kh 1.2 --n 15 [--steepness 0.03]
        [--viscosity laminar_sps | --alpha 0.005] [--paddle flap] [--second-order]
        [--dt-out T_FRACTION] [--t-end S] [--x-max 4] [--plain-continuity] [--numerics "..."] [--dry-run]
    .venv/bin/python tools/wave_loss.py heights NAME     # per gauge, last three periods, and the fit below
    .venv/bin/python tools/wave_loss.py history NAME     # per gauge, two-period windows through the run
    .venv/bin/python tools/wave_loss.py drift NAME       # mean (Lagrangian) drift in front of the paddle
    .venv/bin/python tools/wave_loss.py surface NAME     # gauge surface against the top particle
    .venv/bin/python tools/wave_loss.py paddle NAME      # pressure of the paddle's particles
    .venv/bin/python tools/wave_loss.py theory --kh 1.2 --n 15 [--alpha 0.005]

A run writes OUT/waves_loss/NAME.nml and its output to OUT/waves_loss/NAME/ (one
run at a time: `nice -n 10`). `heights` fits, to the complex first-harmonic
amplitudes a(x) of all gauges, an incident wave that decays and a reflected one,
a(x) = A exp(-(kappa + i k) x) + B exp(i k x) (post.waves.decaying_wave_fit, as the
wave-height tests): A at the paddle (x = 0), the decay rate kappa and Kr = |B|/|A|;
the incident height at 2, 3 and 4 L is printed as a first harmonic and crest to trough
(times the mean ratio of the crest-to-trough to the first-harmonic height of the
gauges from 2 L). `theory` gives the spatial
decay rate of a linear wave under a kinematic viscosity nu (the one that artificial
viscosity alpha stands for, nu = alpha h c0 / 8): interior 2 nu k^2 / cg and the
laminar bed boundary layer 2 k^2 sqrt(nu / 2 omega) / (2kd + sinh 2kd).
"""

from __future__ import annotations

import argparse
import glob
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from post.wave_cases import flume_case  # noqa: E402
from post.io import read_snapshot  # noqa: E402
from post.waves import decaying_wave_fit, read_gauges, regular_wave_height  # noqa: E402

DIR = ROOT / "OUT" / "waves_loss"
DEPTH = 0.25
G = 9.81


def gauge_positions(x_max: float) -> tuple[float, ...]:
    """Gauges from 0.5 L to x_max L, a quarter wavelength apart (11 up to 3 L)."""
    return tuple(0.5 + 0.25 * i for i in range(int(round((x_max - 0.5) / 0.25)) + 1))


def cmd_run(a: argparse.Namespace) -> None:
    visc = (f"  viscosity = 'laminar_sps'" if a.viscosity == "laminar_sps"
            else f"  viscosity = 'artificial', alpha = {a.alpha}")
    numerics = "  kernel_correction = 'gradient'" + ("\n  kgc_continuity = .false." if a.plain_continuity else "")
    if a.numerics:
        numerics += "\n  " + a.numerics
    f = flume_case(a.kh, depth=DEPTH, dp=DEPTH / a.n, steepness=a.steepness, paddle=a.paddle,
                   out_dir=str(DIR / a.name), gauges_at=gauge_positions(a.x_max), extra_numerics=numerics,
                   case_name=a.name, second_order=a.second_order, t_end=a.t_end, h_over_dp=a.h_over_dp,
                   damping_len=a.damping_len)
    text = f.text.replace("  viscosity = 'artificial', alpha = 0.01", visc)
    if a.dt_out:
        text = text.replace(f"dt_out = {max(f.period / 2.0, 0.1):.6f}", f"dt_out = {a.dt_out * f.period:.6f}")
    DIR.mkdir(parents=True, exist_ok=True)
    (DIR / f"{a.name}.nml").write_text(text)
    meta = dict(T=f.period, L=f.length, H=f.height, x0=f.x0, gauges=f.gauges, t_end=f.t_end, kh=a.kh,
                depth=DEPTH, paddle=a.paddle, dp=DEPTH / a.n, h_over_dp=a.h_over_dp)
    (DIR / f"{a.name}.json").write_text(json.dumps(meta))
    if not a.dry_run:
        subprocess.run(["nice", "-n", "10", str(ROOT / "build" / "mbsph"), str(DIR / f"{a.name}.nml")], check=True)


def load(name: str):
    m = json.loads((DIR / f"{name}.json").read_text())
    _, _, d = read_gauges(DIR / name)
    return m, d


def harmonics(t, y, omega, t0, t1):
    """Mean and complex amplitudes of harmonics 1..3 (eta = Re(a e^{i w t})) over [t0, t1)."""
    s = (t >= t0) & (t < t1)
    t, y = t[s], y[s]
    cols = [np.ones_like(t)]
    for j in (1, 2, 3):
        cols += [np.cos(j * omega * t), np.sin(j * omega * t)]
    c, *_ = np.linalg.lstsq(np.column_stack(cols), y, rcond=None)
    return c[0], c[1] - 1j * c[2], c[3] - 1j * c[4]


def cmd_heights(a: argparse.Namespace) -> None:
    m, d = load(a.name)
    T, L, H, x0 = m["T"], m["L"], m["H"], m["x0"]
    t = d["time"]
    t1 = t[-1]
    t0 = t1 - 3.0 * T
    xs = np.array(m["gauges"]) - x0
    print(f"{a.name}: kh {m['kh']}, {m.get('paddle', 'piston')}, T {T:.4f} s, L {L:.4f} m, H {H:.5f} m; "
          f"window {t0:.2f} to {t1:.2f} s")
    print("  x/L   H error   T error   H2/H1   crest-to-trough H error")
    ratios = []
    for j, x in enumerate(xs):
        y = d[f"eta_{j + 1}"]
        _, c1, c2 = harmonics(t, y, 2.0 * math.pi / T, t0, t0 + 3.0 * T)
        r = regular_wave_height(t, y, T, t_start=t0, t_end=t1)
        if x >= 2.0 * L - 1e-9:
            ratios.append(r.H_crest_trough / r.H)
        print(f"  {x / L:4.2f}  {100 * (r.H / H - 1):+6.2f} %  {100 * (r.T_fit / T - 1):+6.2f} %  {abs(c2) / abs(c1):5.3f}"
              f"   {100 * (r.H_crest_trough / H - 1):+6.2f} %")
    fit = decaying_wave_fit(t, [d[f"eta_{j + 1}"] for j in range(len(xs))], xs, T, 2.0 * math.pi / L,
                            t_start=t0, t_end=t1)
    print(f"  fit: A at the paddle {100 * (fit.H0 / H - 1):+.2f} %, decay {fit.kappa:.4f} /m "
          f"({100 * (1 - math.exp(-fit.kappa * L)):.2f} % per L), Kr {fit.Kr:.3f}, "
          f"k/k_linear {fit.k * L / (2.0 * math.pi):.4f}")
    # crest to trough: the first harmonic times the mean ratio of the gauges from 2 L (as the tests)
    for xl in (x for x in (2.0, 3.0, 4.0, 5.0, 6.0) if x * L <= xs.max() + 0.01 * L):
        print(f"  incident wave at {xl} L: {100 * (fit.height(xl * L) / H - 1):+.2f} % (first harmonic), "
              f"{100 * (fit.height(xl * L) * float(np.mean(ratios)) / H - 1):+.2f} % (crest to trough)")


def cmd_history(a: argparse.Namespace) -> None:
    m, d = load(a.name)
    T, H, L, x0 = m["T"], m["H"], m["L"], m["x0"]
    t = d["time"]
    print(f"{a.name}: height error [%] over two periods from t0; columns x/L")
    print("  t0/T " + " ".join(f"{(x - x0) / L:6.2f}" for x in m["gauges"]))
    for t0 in np.arange(3.0 * T, t[-1] - 2.0 * T + 1e-9, 0.5 * T):
        row = []
        for j in range(len(m["gauges"])):
            _, c1, _ = harmonics(t, d[f"eta_{j + 1}"], 2.0 * math.pi / T, t0, t0 + 2.0 * T)
            row.append(100.0 * (2.0 * abs(c1) / H - 1.0))
        print(f"  {t0 / T:4.1f} " + " ".join(f"{v:+6.1f}" for v in row))


def snapshot(path: str):
    s = read_snapshot(path)  # particles in id order
    return s.time, s.kind, s.position, s.velocity, s.pressure, s.dp


def cmd_drift(a: argparse.Namespace) -> None:
    """Lagrangian mean velocity: the displacement of each fluid particle over the last
    three periods (whole periods, so the orbital motion cancels), binned by where it started."""
    m = json.loads((DIR / f"{a.name}.json").read_text())
    T, L, x0 = m["T"], m["L"], m["x0"]
    snaps = sorted(glob.glob(str(DIR / a.name / "snap_*.h5")))
    times = np.array([snapshot(s)[0] for s in snaps])
    j1 = len(snaps) - 1
    j0 = int(np.argmin(abs(times - (times[j1] - 3.0 * T))))
    ta, ka, xa, *_ = snapshot(snaps[j0])
    tb, _, xb, *_ = snapshot(snaps[j1])
    f = ka == 1
    u = (xb[f, 0] - xa[f, 0]) / (tb - ta)
    xm = xa[f]
    xe = x0 + np.arange(0.0, 2.01, 0.25) * L
    ye = np.linspace(0.0, DEPTH, 6)
    print(f"{a.name}: Lagrangian drift [mm/s] from t = {ta:.2f} to {tb:.2f} s ({(tb - ta) / T:.2f} T); "
          f"rows from the surface down, columns x/L from the paddle")
    print("                  " + " ".join(f"{(x - x0) / L:6.2f}" for x in xe[:-1]))
    for r in range(len(ye) - 2, -1, -1):
        row = []
        for c in range(len(xe) - 1):
            s = (xm[:, 0] >= xe[c]) & (xm[:, 0] < xe[c + 1]) & (xm[:, 1] >= ye[r]) & (xm[:, 1] < ye[r + 1])
            row.append(1000.0 * u[s].mean() if s.any() else math.nan)
        print(f"  y {ye[r]:.3f}-{ye[r + 1]:.3f} m " + " ".join(f"{v:+6.1f}" for v in row))
    k = 2.0 * math.pi / L
    amp = m["H"] / 2.0
    om = 2.0 * math.pi / T
    us = amp * amp * om * k * math.cosh(2.0 * k * DEPTH) / (2.0 * math.sinh(k * DEPTH) ** 2)
    print(f"  Stokes drift at the surface (linear theory): {1000.0 * us:.1f} mm/s")


def cmd_surface(a: argparse.Namespace) -> None:
    """The gauge's kernel-sum surface minus (top fluid particle within dp/2 of the gauge + dp/2)."""
    m, d = load(a.name)
    t = d["time"]
    diffs = []
    for s in sorted(glob.glob(str(DIR / a.name / "snap_*.h5")))[1:]:
        ts, k, x, _, _, dp = snapshot(s)
        xf = x[k == 1]
        for j, xg in enumerate(m["gauges"]):
            sel = np.abs(xf[:, 0] - xg) < 0.5 * dp
            if sel.any():
                top = xf[sel, 1].max() + 0.5 * dp - DEPTH
                eg = np.interp(ts, t, d[f"eta_{j + 1}"])
                diffs.append(((eg - top) / dp, eg / m["H"]))
    diffs, phase = np.array(diffs).T
    print(f"{a.name}: gauge - top particle, {len(diffs)} samples: median {np.median(diffs):+.3f} dp, "
          f"90 % within [{np.percentile(diffs, 5):+.3f}, {np.percentile(diffs, 95):+.3f}] dp; "
          f"median near crests (eta > H/4) {np.median(diffs[phase > 0.25]):+.3f} dp, "
          f"near troughs (eta < -H/4) {np.median(diffs[phase < -0.25]):+.3f} dp")


def cmd_paddle(a: argparse.Namespace) -> None:
    """Pressure of the paddle's boundary particles less hydrostatic (rho0 g (d - y)) over the
    snapshots from the third period on: standard deviation and mean, by row from the bed,
    for the face column and the one behind it."""
    m = json.loads((DIR / f"{a.name}.json").read_text())
    snaps = sorted(glob.glob(str(DIR / a.name / "snap_*.h5")))
    dev, x_rest = [], None
    for s in snaps:
        t, k, x, _, p, dp = snapshot(s)
        if t < 3.0 * m["T"] - 1e-9:
            continue
        pad = k == 3
        if x_rest is None:
            x_rest = x[pad].copy()
        dev.append(p[pad] - 1000.0 * G * (DEPTH - x[pad, 1]))
    dev = np.array(dev)
    col = np.rint((x_rest[:, 0] - x_rest[:, 0].max()) / dp).astype(int)
    row = np.rint((x_rest[:, 1] - x_rest[:, 1].min()) / dp).astype(int)
    print(f"{a.name}: paddle pressure - hydrostatic over {len(dev)} snapshots: std (mean) [Pa]; "
          f"rho0 g d = {1000.0 * G * DEPTH:.0f} Pa")
    print("  row  y [m]     face column        one behind")
    for r in range(int(round(DEPTH / dp))):
        out = []
        for c in (0, -1):
            s = (col == c) & (row == r)
            out.append(f"{dev[:, s].std():7.0f} ({dev[:, s].mean():+6.0f})" if s.any() else "   -")
        y = x_rest[row == r][0, 1]
        print(f"  {r:3d}  {y:.4f}  " + "   ".join(out))


def decay_rates(kh: float, nu: float, depth: float = DEPTH) -> tuple[float, float, float]:
    """Spatial amplitude decay rates [1/m] of a linear wave under viscosity nu: interior and
    laminar bed boundary layer; and the wavelength."""
    k = kh / depth
    om = math.sqrt(G * k * math.tanh(kh))
    cg = 0.5 * (1.0 + 2.0 * kh / math.sinh(2.0 * kh)) * om / k
    interior = 2.0 * nu * k * k / cg
    bed = 2.0 * k * k * math.sqrt(nu / (2.0 * om)) / (2.0 * kh + math.sinh(2.0 * kh))
    return interior, bed, 2.0 * math.pi / k


def cmd_theory(a: argparse.Namespace) -> None:
    dp = DEPTH / a.n
    c0 = 10.0 * math.sqrt(G * DEPTH)
    nu = a.alpha * math.sqrt(2.0) * dp * c0 / 8.0 if a.alpha > 0 else 1.0e-6
    interior, bed, L = decay_rates(a.kh, nu)
    tot = interior + bed
    print(f"kh {a.kh}, dp = d/{a.n}: nu = {nu:.3g} m2/s; decay: interior {interior:.4f} /m, bed {bed:.4f} /m, "
          f"total {tot:.4f} /m; height lost at 2 L {100 * (1 - math.exp(-2 * tot * L)):.1f} %, "
          f"at 3 L {100 * (1 - math.exp(-3 * tot * L)):.1f} %")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    r = sub.add_parser("run")
    r.add_argument("name")
    r.add_argument("--kh", type=float, required=True)
    r.add_argument("--n", type=int, default=15, help="particles over the depth")
    r.add_argument("--steepness", type=float, default=0.03)
    r.add_argument("--paddle", choices=("piston", "flap"), default="piston")
    r.add_argument("--viscosity", choices=("artificial", "laminar_sps"), default="artificial")
    r.add_argument("--alpha", type=float, default=0.005)
    r.add_argument("--second-order", action="store_true")
    r.add_argument("--damping-len", type=float, default=1.5, help="damping zone length in wavelengths (default 1.5)")
    r.add_argument("--h-over-dp", type=float, default=None, help="smoothing length / dp (default: the solver's)")
    r.add_argument("--dt-out", type=float, default=0.0, help="snapshot interval in periods (default T/2)")
    r.add_argument("--t-end", type=float, default=None)
    r.add_argument("--x-max", type=float, default=3.0, help="farthest gauge in wavelengths (default 3)")
    r.add_argument("--plain-continuity", action="store_true",
                   help="kgc_continuity = .false.: the plain kernel gradient in the continuity equation")
    r.add_argument("--numerics", default="", help="more &numerics settings, e.g. \"boundary = 'mdbc', shifting = 'fickian'\"")
    r.add_argument("--dry-run", action="store_true", help="write the case only")
    for c in ("heights", "history", "drift", "surface", "paddle"):
        sub.add_parser(c).add_argument("name")
    t = sub.add_parser("theory")
    t.add_argument("--kh", type=float, required=True)
    t.add_argument("--n", type=int, default=15)
    t.add_argument("--alpha", type=float, default=0.005, help="0: water's nu = 1e-6")
    a = ap.parse_args()
    {"run": cmd_run, "heights": cmd_heights, "history": cmd_history, "drift": cmd_drift,
     "surface": cmd_surface, "paddle": cmd_paddle, "theory": cmd_theory}[a.cmd](a)


if __name__ == "__main__":
    main()
