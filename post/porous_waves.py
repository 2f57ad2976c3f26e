"""Regular waves on a porous breakwater: a rectangular block of stones (vertical faces,
emerging from the water) across a flume of constant depth, its reflection and
transmission coefficients against the long-wave theory of Madsen (1974) (doc/porous.md).

    .venv/bin/python -m post.porous_waves --write OUT/porous_waves.nml    # the case file
    build/mbsph OUT/porous_waves.nml
    .venv/bin/python -m post.porous_waves OUT/porous_waves                    # table

or `make porous_waves`. The theory (Madsen 1974; the algorithm of the US Army Corps of
Engineers' ACES program for wave transmission through permeable structures, MADSN1 and
EQBWTRCO, for a rectangular homogeneous structure): inside the stones the water obeys
n d(eta)/dt + h du/dx = 0 and (S/n) du/dt + (f omega/n) u = -g d(eta)/dx in the discharge
velocity u, with the inertia coefficient S = 1 + c_A and the friction factor f of the
Forchheimer resistance linearised by Lorentz's equivalent work; matching the water level
and the discharge at both faces gives, with eps = n / sqrt(S - i f) and
theta = i k b sqrt(S - i f),

    K_T = |4 eps / D|,  K_R = |(1 - eps^2)(e^theta - e^-theta) / D|,
    D = (1 + eps)^2 e^theta - (1 - eps)^2 e^-theta.

The resistance is the one the solver uses (Van Gent's, `&porous` alpha, beta, gamma:
per unit mass of pore water kl V + kq |V| V in the pore velocity V = u / n), so that
f = (kl + 8/(3 pi) kq U / n) / omega for a discharge amplitude U, taken as ACES takes it
from the thin-structure estimate U = (H_i/2) sqrt(g/h) / (1 + lambda), lambda = k b f / (2 n),
iterated to a fixed point. k is the wave number of linear dispersion.
"""

from __future__ import annotations

import argparse
import cmath
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from post.porous_cases import coefficients
from post.wave_cases import flume_case
from post.waves import read_gauges, reflection_two_gauge, regular_wave_height, wavenumber

G = 9.81

# The flume: depth, kh, wave steepness, the structure (width, porosity, stone size)
DEPTH = 0.3
KH = 0.5
STEEPNESS = 0.008
WIDTH = 0.5
POROSITY = 0.45
D50 = 0.03
DP = 0.015
FRONT = 1.5                     # structure's front face, wavelengths from the paddle
GAUGES = (1.0, 1.25)            # the pair in front (dx = L/4), wavelengths from the paddle


@dataclass(frozen=True)
class Theory:
    KR: float
    KT: float
    f: float                    # linearised friction factor
    S: float                    # inertia coefficient 1 + c_A


def madsen(period: float, depth: float, width: float, n: float, d50: float, H: float) -> Theory:
    """K_R and K_T of a rectangular porous breakwater (module docstring)."""
    omega = 2.0 * math.pi / period
    k = float(wavenumber(omega, depth))
    kl, kq, ca = coefficients(n, d50)
    S = 1.0 + ca
    lam, f = 1.0, 0.0
    for _ in range(200):
        U = 0.5 * H * math.sqrt(G / depth) / (1.0 + lam)
        f_new = (kl + 8.0 / (3.0 * math.pi) * kq * U / n) / omega
        lam = k * width * f_new / (2.0 * n)
        if abs(f_new - f) <= 1e-12 * f_new:
            f = f_new
            break
        f = f_new
    root = cmath.sqrt(S - 1j * f)
    eps = n / root
    theta = 1j * k * width * root
    D = (1 + eps) ** 2 * cmath.exp(theta) - (1 - eps) ** 2 * cmath.exp(-theta)
    KT = abs(4 * eps / D)
    KR = abs((1 - eps ** 2) * (cmath.exp(theta) - cmath.exp(-theta)) / D)
    return Theory(KR=KR, KT=KT, f=f, S=S)


def case(out_dir: str = "OUT/porous_waves", dp: float = DP, periods_after: float = 5.0, porosity: float = POROSITY,
         d50: float = D50, structure: bool = True):
    """The flume (post.wave_cases.flume_case) with the structure and a third gauge half a
    wavelength behind it; h = 2 dp, as the pores need. Without the structure: the same
    flume and gauges, whose heights give the flume's own decay (`corrected`)."""
    k = KH / DEPTH
    L = 2.0 * math.pi / k
    behind = FRONT + WIDTH / L + 0.5
    fl = flume_case(KH, depth=DEPTH, steepness=STEEPNESS, dp=dp, out_dir=out_dir, case_name="porous_waves",
                    gauges_at=(*GAUGES, behind), damping_len=1.0, periods_after=periods_after,
                    h_over_dp=2.0)
    x_s = fl.x0 + FRONT * L
    thick = math.ceil(4.0 - 1e-9) * dp
    if not structure:
        return fl, fl.text + "! no structure: the flume's own decay from the gauges in front to the one behind\n"
    text = fl.text + (f"! the porous breakwater: {WIDTH} m wide, n = {porosity}, D50 = {d50} m, from the bed "
                      f"to above the waves\n&porous porosity = {porosity}, d50 = {d50}, xmin = {x_s:.6f}, "
                      f"xmax = {x_s + WIDTH:.6f}, ymin = {-thick:.6f}, ymax = {2.0 * DEPTH:.6f} /\n")
    return fl, text


@dataclass(frozen=True)
class Measured:
    Hi: float
    KR: float
    KT: float
    t0: float
    t1: float


def measure(out: Path, periods: float = 4.0, porosity: float = POROSITY, d50: float = D50) -> tuple[Measured, Theory]:
    """The incident and reflected waves from the pair in front (first harmonic, least
    squares over whole periods) and the transmitted height behind, over the last
    ``periods`` periods of the run; the theory at the measured incident height."""
    fl, _ = case()
    gauges, t, cols = read_gauges(out)
    T = fl.period
    t1 = float(t[-1])
    t0 = t1 - periods * T
    w = t >= t0 - 1e-9
    dx = fl.gauges[1] - fl.gauges[0]
    r = reflection_two_gauge(t[w], cols["eta_1"][w], cols["eta_2"][w], dx, DEPTH, frequency=1.0 / T)
    Hi = 2.0 * math.sqrt(2.0 * r.E_i)
    Ht = regular_wave_height(t[w], cols["eta_3"][w], T).H
    th = madsen(T, DEPTH, WIDTH, porosity, d50, Hi)
    return Measured(Hi=Hi, KR=r.Kr, KT=Ht / Hi, t0=t0, t1=t1), th


def corrected(m: Measured, empty: Measured) -> tuple[float, float]:
    """K_R and K_T of the structure with the flume's own decay taken out: the empty
    flume's height behind over its incident height, empty.KT, is the decay over the
    transmitted wave's path from the pair of gauges in front (their mid-point) to the gauge
    behind; the reflected wave travels from that mid-point to the front face and back,
    and decays as much per wavelength (exponential decay with distance)."""
    fl, _ = case()
    mid = 0.5 * (GAUGES[0] + GAUGES[1])
    behind = FRONT + WIDTH / fl.length + 0.5
    path_t, path_r = behind - mid, 2.0 * (FRONT - mid)
    return m.KR / empty.KT ** (path_r / path_t), m.KT / empty.KT


def table(m: Measured, th: Theory, porosity: float = POROSITY, d50: float = D50,
          empty: Measured | None = None) -> str:
    fl, _ = case()
    head = (f"kh = {KH}, depth {DEPTH} m, T = {fl.period:.3f} s, L = {fl.length:.3f} m; structure {WIDTH} m "
            f"wide, n = {porosity}, D50 = {d50} m; t = {m.t0:.1f} to {m.t1:.1f} s; incident H {m.Hi * 1000:.1f} mm "
            f"(f = {th.f:.3f}, S = {th.S:.3f})\n\n")
    if empty is None:
        rows = "| | SPH | Madsen (1974) | difference |\n|---|---|---|---|\n"
        rows += f"| K_R | {m.KR:.3f} | {th.KR:.3f} | {100 * (m.KR / th.KR - 1):+.1f} % |\n"
        rows += f"| K_T | {m.KT:.3f} | {th.KT:.3f} | {100 * (m.KT / th.KT - 1):+.1f} % |\n"
        return head + rows
    kr, kt = corrected(m, empty)
    head += (f"the flume without the structure: height behind / incident {empty.KT:.3f}, "
             f"reflection {empty.KR:.3f}\n\n")
    rows = ("| | SPH | SPH, the flume's decay taken out | Madsen (1974) | difference |\n"
            "|---|---|---|---|---|\n")
    rows += f"| K_R | {m.KR:.3f} | {kr:.3f} | {th.KR:.3f} | {100 * (kr / th.KR - 1):+.1f} % |\n"
    rows += f"| K_T | {m.KT:.3f} | {kt:.3f} | {th.KT:.3f} | {100 * (kt / th.KT - 1):+.1f} % |\n"
    return head + rows


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("out", nargs="?", type=Path, help="output folder of the case: print the table")
    ap.add_argument("--write", type=Path, help="write the case file here (its run goes to the same path without .nml)")
    ap.add_argument("--dp", type=float, default=DP)
    ap.add_argument("--porosity", type=float, default=POROSITY)
    ap.add_argument("--d50", type=float, default=D50)
    ap.add_argument("--no-structure", action="store_true",
                    help="with --write: the flume without the structure (its own decay)")
    ap.add_argument("--empty", type=Path, help="output folder of the flume without the structure: "
                    "the table with the flume's own decay taken out")
    a = ap.parse_args(argv)
    if a.write:
        # the run's folder beside the case file (a run writes its effective case.nml into its folder)
        _, text = case(out_dir=str(a.write.with_suffix("")), dp=a.dp, porosity=a.porosity, d50=a.d50,
                       structure=not a.no_structure)
        a.write.parent.mkdir(parents=True, exist_ok=True)
        a.write.write_text(text)
        print(a.write)
    if a.out:
        m, th = measure(a.out, porosity=a.porosity, d50=a.d50)
        empty = measure(a.empty)[0] if a.empty else None
        print(table(m, th, a.porosity, a.d50, empty))
    if not (a.write or a.out):
        fl, _ = case()
        th = madsen(fl.period, DEPTH, WIDTH, POROSITY, D50, fl.height)
        print(f"theory at the target height {fl.height:.4f} m: K_R = {th.KR:.3f}, K_T = {th.KT:.3f}, f = {th.f:.3f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
