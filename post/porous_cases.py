"""The porous-region cases of doc/porous.md, each defined once (the tests of
tests/test_porous.py run the same texts), with what each is measured against.

- ``drain``: a block of water falling through stones, free on every side: the
  momentum equation of the pore water with Van Gent's resistance and added mass,
  (1 + c_A) dV/dt = g - kl V - kq V^2, solved exactly here.
- ``stones_tank``: still water in a tank filled (``full``) or half filled (``half``)
  with stones: hydrostatic pressure, one level inside and outside the stones.
- ``column``: water ponded above a layer of stones in a channel drains through it
  and falls out below: the flow rate against the Forchheimer law over the layer
  (quasi-steady, the porosity's transition included), for the three stone sizes of
  ``drain`` (the Darcy, the transitional and the turbulent regime).
- ``steady``: a piston pushes water at a constant rate up a channel through a layer of
  stones held between open water below and above: the head loss across the layer
  against the Forchheimer law integrated over the smooth porosity profile, with no
  entry or exit head (the water is at the piston's speed on both sides), in the three
  regimes of ``drain``.

    .venv/bin/python -m post.porous_cases [--bin build/mbsph] [--out OUT/porous]

runs them all (about 2 minutes on one core) and prints the table of doc/porous.md.

    .venv/bin/python -m post.porous_cases --liu OUT/porous_dambreak --liu-data DIR

compares the run of input/porous/dambreak_liu1999.nml with the free surfaces measured by
Liu et al. (1999), digitised as DIR/data_<10 t>.dat (x, y in m; doc/porous.md says where
to find them), and prints that table instead.
"""
from __future__ import annotations

import argparse
import math
import shutil
import subprocess
import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from . import hydrostatic
from .io import FLUID, list_snapshots, read_snapshot

__all__ = ["G", "NU", "ALPHA", "BETA", "GAMMA", "N", "coefficients", "terminal_velocity", "drain_velocity",
           "drain_case", "REGIMES", "H", "WIDTH", "TANK_DP", "T_SETTLE", "stones_tank_case", "surface",
           "column_case", "column_law", "STEADY", "STEADY_DP", "steady_case", "steady_law", "steady_loss"]

G = 9.81
NU = 1.0e-6
# Van Gent (1995): the defaults of &porous
ALPHA, BETA, GAMMA = 1000.0, 1.1, 0.34
N = 0.4


def coefficients(n: float, d50: float) -> tuple[float, float, float]:
    """kl [1/s], kq [1/m] and c_A of the pore water's momentum in the pore velocity V (doc/porous.md)."""
    a = ALPHA * (1 - n) ** 2 / n ** 3 * NU / (G * d50 ** 2)   # Van Gent's a [s/m], in the Darcy velocity
    b = BETA * (1 - n) / n ** 3 / (G * d50)                  # and b [s2/m2]
    return G * a * n, G * b * n * n, GAMMA * (1 - n) / n


def terminal_velocity(n: float, d50: float) -> float:
    """The pore velocity at which the resistance carries the water's weight (I = 1)."""
    kl, kq, _ = coefficients(n, d50)
    return (-kl + math.sqrt(kl * kl + 4 * kq * G)) / (2 * kq)


def drain_velocity(n: float, d50: float, t: np.ndarray) -> np.ndarray:
    """V(t) from rest of (1 + c_A) dV/dt = g - kl V - kq V^2."""
    kl, kq, ca = coefficients(n, d50)
    sol = solve_ivp(lambda _t, v: [(G - kl * v[0] - kq * v[0] ** 2) / (1 + ca)], (0.0, float(t[-1])), [0.0],
                    t_eval=t, rtol=1e-10, atol=1e-12)
    return sol.y[0]


# Stone sizes whose terminal flow is Darcy (linear share of the resistance 0.98),
# transitional (0.42) and turbulent (0.05).
REGIMES = {"darcy": 0.002, "transitional": 0.01, "turbulent": 0.05}


def drain_case(d50: float, out_dir: str = "OUT", n: float = N) -> str:
    """The block falls through still air, not water: Molteni's density diffusion, whose
    reference is no hydrostatic column; h_swl = 0.01 m starts it at the pressure of 1 cm
    of water, c0 from the same depth."""
    return f"""\
&run case_name = 'drain', t_end = 0.6, dt_out = 0.05, out_dir = '{out_dir}' /
&domain xmin = -0.05, xmax = 0.45, ymin = -0.05, ymax = 1.05 /
&fluid h_swl = 0.01, coef = 20.0 /
&numerics dp = 0.01, integrator = 'symplectic', diffusion = 'molteni' /
&porous porosity = {n}, d50 = {d50}, xmin = 0.0, xmax = 0.4, ymin = 0.0, ymax = 1.0 /
&box role = 'fluid', xmin = 0.1, xmax = 0.3, ymin = 0.6, ymax = 0.8 /
"""


FILTER_Y = 0.15               # top of the stones and the filter on them (m)
FILTER_BOX = (0.1, 0.05, 2000.0)   # width, height (m) and density (kg/m3) of the body on the filter


def filter_case(wet: bool = True, out_dir: str = "OUT", t_end: float = 2.0) -> str:
    """A block resting on a permeable filter (``&slope role = 'filter'``) laid on a bed of
    stones (n = 0.4, D = 0.02 m) FILTER_Y thick, under still water 0.3 m deep in a tank
    0.4 m wide; the block starts 1 cm above the filter. The stones' outline lies h (half
    the porosity's transition) below the filter, so that the stones begin at the filter
    (as &breakwater lays its core). ``wet = False``: the same block and filter without
    water or stones, the dry reference of its resting height."""
    w, hgt, rho = FILTER_BOX
    water = f"""\
&box role = 'fluid', xmin = 0.0, xmax = 0.4, ymin = 0.0, ymax = 0.3 /
&porous porosity = 0.4, d50 = 0.02, xmin = -0.04, xmax = 0.44, ymin = -0.04, ymax = {FILTER_Y - 0.02} /
""" if wet else ""
    return f"""\
&run case_name = 'filter', t_end = {t_end}, dt_out = 0.5, energy_interval = 0.05, out_dir = '{out_dir}' /
&domain xmin = -0.05, xmax = 0.45, ymin = -0.05, ymax = 0.5 /
&fluid coef = 10.0 /
&numerics dp = 0.01, h_over_dp = 2.0, integrator = 'symplectic' /
{water}&box role = 'solid', xmin = -0.04, xmax = 0.44, ymin = -0.04, ymax = 0.0 /
&box role = 'solid', xmin = -0.04, xmax = 0.0, ymin = 0.0, ymax = 0.45 /
&box role = 'solid', xmin = 0.4, xmax = 0.44, ymin = 0.0, ymax = 0.45 /
&slope role = 'filter', x0 = 0.0, y0 = {FILTER_Y}, x1 = 0.4, y1 = {FILTER_Y} /
&body shape = 'box', x = 0.2, y = {FILTER_Y + 0.5 * hgt + 0.01}, width = {w}, height = {hgt}, density = {rho}, mu = 0.5 /
"""


H = 0.5                       # still-water depth of the tanks (m)
WIDTH = 1.0                   # tank width (m)
TANK_DP = H / 25              # 25 particles over the depth, as the open-water tank of tests/test_cases.py
T_SETTLE = 20.0 * math.sqrt(H / G)


def stones_tank_case(stones: str, out_dir: str = "OUT", h_over_dp: float = 2.0) -> str:
    """Still water H deep in a tank WIDTH wide, walls the kernel's support thick (2h), the stones (n = 0.4,
    D = 0.02 m) reaching into the walls and the floor: over the whole tank (``full``) or
    its right half (``half``); ``open``: a region of porosity 1 over the whole tank, the
    open-water reference run through the same code. h = 2 dp: the pores at n = 0.4 hold one particle per
    dp^2/n, and h = 2 dp keeps the kernel 1.26 of their spacing wide."""
    w = math.ceil(2 * h_over_dp - 1e-9) * TANK_DP
    x0 = {"full": -w, "half": 0.5 * WIDTH, "open": -w}[stones]
    n = 1.0 if stones == "open" else N
    t_end = math.ceil(T_SETTLE * 10.0) / 10.0
    return f"""\
&run case_name = 'stones_tank_{stones}', t_end = {t_end}, dt_out = 0.5, out_dir = '{out_dir}' /
&domain xmin = {-w - 0.05 * WIDTH}, xmax = {WIDTH + w + 0.05 * WIDTH}, ymin = {-w - 0.05 * WIDTH}, ymax = {1.6 * H} /
&fluid rho0 = 1000.0, gamma = 7.0, coef = 10.0, gravity = 9.81 /
&numerics dp = {TANK_DP}, h_over_dp = {h_over_dp}, kernel = 'wendland', integrator = 'symplectic',
  viscosity = 'artificial', alpha = 0.02, diffusion = 'fourtakas', delta = 0.1 /
&box role = 'fluid', xmin = 0.0, xmax = {WIDTH}, ymin = 0.0, ymax = {H} /
&box role = 'solid', xmin = {-w}, xmax = {WIDTH + w}, ymin = {-w}, ymax = 0.0 /
&box role = 'solid', xmin = {-w}, xmax = 0.0, ymin = 0.0, ymax = {1.4 * H} /
&box role = 'solid', xmin = {WIDTH}, xmax = {WIDTH + w}, ymin = 0.0, ymax = {1.4 * H} /
&porous porosity = {n}, d50 = 0.02, xmin = {x0}, xmax = {WIDTH + w}, ymin = {-w}, ymax = {1.4 * H} /
"""


def surface(snap, x0: float, x1: float) -> float:
    """The water level between x0 and x1: the highest particles' centres plus half their spacing."""
    f = snap.kind == FLUID
    x = snap.position[f]
    m = (x[:, 0] > x0) & (x[:, 0] < x1)
    top = np.sort(x[m, 1])[-5:].mean()
    near = m & (x[:, 1] > top - TANK_DP)
    spacing = np.sqrt(np.mean(snap.mass[f][near]) / np.mean(snap.density[f][near]))
    return float(top + 0.5 * spacing)


COLUMN_L = 0.1                # layer thickness (m)
COLUMN_W = 0.1                # channel width (m)


def column_case(d50: float, out_dir: str = "OUT", dp: float = 0.005, h_over_dp: float = 2.0) -> str:
    """A channel COLUMN_W wide: water 0.3 m deep above a layer of stones COLUMN_L thick,
    nothing below the layer; the water drains through and leaves the domain. h = 2 dp
    by default, as in the tanks; the walls the kernel's support thick (2h)."""
    w = math.ceil(2 * h_over_dp - 1e-9) * dp
    return f"""\
&run case_name = 'column', t_end = 0.9, dt_out = 0.01, out_dir = '{out_dir}', max_lost_fraction = 1.0 /
&domain xmin = -0.03, xmax = 0.13, ymin = -0.05, ymax = 0.5 /
&fluid coef = 10.0 /
&numerics dp = {dp}, h_over_dp = {h_over_dp}, integrator = 'symplectic' /
&porous porosity = {N}, d50 = {d50}, xmin = {-w}, xmax = {COLUMN_W + w}, ymin = 0.0, ymax = {COLUMN_L} /
&box role = 'fluid', xmin = 0.0, xmax = {COLUMN_W}, ymin = 0.0, ymax = 0.4 /
&box role = 'solid', xmin = {-w}, xmax = 0.0, ymin = 0.0, ymax = 0.45 /
&box role = 'solid', xmin = {COLUMN_W}, xmax = {COLUMN_W + w}, ymin = 0.0, ymax = 0.45 /
"""


def layer_profile(d50: float, width: float) -> tuple[np.ndarray, ...]:
    """Across a layer of stones COLUMN_L thick (y = 0 at its outline's bottom): heights y,
    the solver's porosity n(y) (the smooth step over ``width``, a step at 0), and its
    resistance rates kl(y) [1/s] and kq(y) [1/m] in the pore velocity, each region's
    coefficients weighted by the step as in the solver's porosity field."""
    y = np.linspace(-width, COLUMN_L + width, 20001)
    d = np.minimum(y, COLUMN_L - y)
    t = np.clip(d / width + 0.5, 0, 1) if width > 0 else (d > 0).astype(float)
    s = t * t * (3 - 2 * t) if width > 0 else t
    n = 1 - s * (1 - N)
    kl = s * ALPHA * NU * (1 - n) ** 2 / (n * n * d50 * d50)
    kq = s * BETA * (1 - n) / (n * d50)
    return y, n, kl, kq


def column_law(head: float, d50: float, width: float) -> float:
    """The Darcy velocity u [m/s] of steady flow through the layer under the water depth
    ``head`` above it (pressure zero at the exit below): g (head + L) equals the integral
    of the resistance kl(n) V + kq(n) V^2, V = u / n, over the smooth porosity profile of
    transition ``width``."""
    y, n, kl, kq = layer_profile(d50, width)

    def excess(u: float) -> float:
        v = u / n
        return float(np.trapezoid(kl * v + kq * v * v, y)) - G * (head + COLUMN_L)
    return brentq(excess, 1e-6, 10.0)


def liu_dambreak(out: Path, data: Path, dp: float = 0.004) -> list[str]:
    """Rows of the table of the porous dam break against the measured free surfaces: at
    each time, the RMS of the elevation difference at the measured points, upstream of
    the block, in it and downstream. The simulated surface at a point is the highest
    fluid particle within 1.5 dp of it plus half its spacing (dp/sqrt(n) in the stones)."""
    snaps = {round(read_snapshot(p).time, 2): p for p in list_snapshots(out)}
    rows = []
    for t10 in range(2, 23, 2):
        t = t10 / 10
        key = min(snaps, key=lambda k: abs(k - t))
        snap = read_snapshot(snaps[key])
        f = snap.kind == FLUID
        x, n = snap.position[f], snap.datasets["porosity"][f]
        d = np.loadtxt(data / f"data_{t10}.dat")
        eta = np.full(len(d), np.nan)
        for k, (xd, _) in enumerate(d):
            m = np.abs(x[:, 0] - xd) < 1.5 * dp
            if m.any():
                top = np.argmax(np.where(m, x[:, 1], -1.0))
                eta[k] = x[top, 1] + 0.5 * dp / math.sqrt(n[top])
        e = eta - d[:, 1]
        parts = {"all": np.ones(len(d), bool), "upstream": d[:, 0] <= 0.30,
                 "in the block": (d[:, 0] > 0.30) & (d[:, 0] < 0.59), "downstream": d[:, 0] >= 0.59}
        rms = {k: 1000 * math.sqrt(np.nanmean(e[m] ** 2)) for k, m in parts.items()}
        # the water the measured profile holds, per metre of width (n = 0.49 in the block)
        xs = np.linspace(0.0, 0.892, 2000)
        held = np.trapezoid(np.where((xs > 0.30) & (xs < 0.59), 0.49, 1.0) * np.interp(xs, d[:, 0], d[:, 1]), xs)
        rows.append(f"| {t:.1f} | {rms['all']:.1f} | {rms['upstream']:.1f} | {rms['in the block']:.1f} | "
                    f"{rms['downstream']:.1f} | {1000 * np.nanmax(np.abs(e)):.1f} | {1000 * held:.1f} |")
    return rows


STEADY_YL, STEADY_W, STEADY_TOP = 0.2, 0.1, 0.5     # layer's bottom, channel width, water's top (m)
STEADY_DP = 0.005                                    # particle spacing (m), h = 2 dp: the transition 2h = 4 dp
# the three regimes of drain, each at a Darcy velocity that makes the hydraulic gradient
# about 1.3 (a head loss of 1 to 1.3 kPa over the layer): linear shares 0.96, 0.44, 0.04
STEADY = {"darcy": (0.002, 0.0103), "transitional": (0.01, 0.07), "turbulent": (0.05, 0.24)}


def steady_case(d50: float, u: float, out_dir: str = "OUT", dp: float = STEADY_DP, h_over_dp: float = 2.0,
                t_end: float = 0.6, boundary: str = "dynamic") -> str:
    """A channel STEADY_W wide, walls 2h thick; a layer of stones COLUMN_L thick from
    STEADY_YL, reaching into the walls; water from 0 to STEADY_TOP; a piston (a prescribed
    body as wide as the channel) at its bottom pushes it up at u from t = 0 (u = 0: the
    still reference). Pressure gauges in mid-channel half the transition and the kernel
    support (plus dp) below and above the layer, where the water is open and moves at u.
    boundary: the walls' and piston's treatment, ``&numerics boundary``."""
    h = h_over_dp * dp
    w = math.ceil(2 * h_over_dp - 1e-9) * dp
    off = 0.5 * 2.0 * h + 2.0 * h + dp
    yl, wc = STEADY_YL, STEADY_W
    return f"""\
&run case_name = 'steady', t_end = {t_end}, dt_out = 0.05, gauge_interval = 0.002, out_dir = '{out_dir}' /
&domain xmin = {-w - 0.01}, xmax = {wc + w + 0.01}, ymin = {-w - 0.01}, ymax = {STEADY_TOP + 0.25} /
&fluid coef = 20.0, h_swl = {STEADY_TOP} /
&numerics dp = {dp}, h_over_dp = {h_over_dp}, integrator = 'symplectic', boundary = '{boundary}' /
&porous porosity = {N}, d50 = {d50}, xmin = {-w}, xmax = {wc + w}, ymin = {yl}, ymax = {yl + COLUMN_L} /
&box role = 'fluid', xmin = 0.0, xmax = {wc}, ymin = 0.0, ymax = {STEADY_TOP} /
&box role = 'solid', xmin = {-w}, xmax = 0.0, ymin = {-w}, ymax = {STEADY_TOP + 0.2} /
&box role = 'solid', xmin = {wc}, xmax = {wc + w}, ymin = {-w}, ymax = {STEADY_TOP + 0.2} /
&body shape = 'box', motion = 'prescribed', x = {0.5 * wc}, y = {-0.5 * w}, width = {wc}, height = {w}, v = {u} /
&gauge kind = 'pressure', x = {0.5 * wc}, y = {yl - off} /
&gauge kind = 'pressure', x = {0.5 * wc}, y = {yl + COLUMN_L + off} /
"""


def steady_t_end(u: float) -> float:
    """The end of the steady run at Darcy velocity u [s]: 0.6 s, or earlier, so that the
    piston stays below the lower gauge's kernel support. The head loss is the mean of the
    last 0.25 s."""
    return min(0.6, 0.12 / u)


def steady_law(u: float, d50: float, width: float) -> tuple[float, float]:
    """The head loss [Pa] of steady flow at Darcy velocity u through the layer: rho0 times
    the integral of kl(n) V + kq(n) V^2, V = u / n, over the smooth porosity profile of
    transition ``width`` (the convective and added-mass terms integrate to zero between
    two points of open water at the same velocity); and the linear term's share."""
    y, n, kl, kq = layer_profile(d50, width)
    v = u / n
    lin, tot = float(np.trapezoid(kl * v, y)), float(np.trapezoid(kl * v + kq * v * v, y))
    return 1000.0 * tot, lin / tot


def steady_loss(moving: Path, still: Path, t0: float, t1: float) -> float:
    """The measured head loss [Pa]: the mean pressure difference of the two gauges from t0
    to t1 with the piston moving, less the same in still water (the hydrostatic difference
    as the discrete pressure gradient has it)."""
    from .waves import read_gauges

    def diff(out: Path) -> float:
        _, t, c = read_gauges(out)
        m = (t >= t0) & (t <= t1)
        return float(c["p_1"][m].mean() - c["p_2"][m].mean())
    return diff(moving) - diff(still)


def _run(binary: str, text: str, out: Path) -> Path:
    out.mkdir(parents=True, exist_ok=True)
    if (out / "OUT").exists():
        shutil.rmtree(out / "OUT")          # this tool's own earlier run
    (out / "case.nml").write_text(text)
    subprocess.run([binary, "case.nml"], cwd=out, check=True, capture_output=True, text=True)
    return out / "OUT"


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--bin", default="build/mbsph")
    ap.add_argument("--out", default="OUT/porous")
    ap.add_argument("--column-dp", type=float, default=0.005, help="spacing of the column case [m]")
    ap.add_argument("--column-h-over-dp", type=float, default=2.0, help="h/dp of the column case")
    ap.add_argument("--liu", help="output folder of input/porous/dambreak_liu1999.nml: compare it instead")
    ap.add_argument("--liu-data", help="folder of the digitised measurements data_<10 t>.dat")
    ap.add_argument("--liu-dp", type=float, default=0.004, help="the particle spacing of that run [m]")
    a = ap.parse_args()
    if a.liu:
        print("| t [s] | RMS, all [mm] | upstream | in the block | downstream | largest [mm] | "
              "water in the measured profile [L/m] |")
        print("|---|---|---|---|---|---|---|")
        for row in liu_dambreak(Path(a.liu), Path(a.liu_data), dp=a.liu_dp):
            print(row)
        return 0
    binary = str(Path(a.bin).resolve())
    root = Path(a.out)
    print("| case | measured | against | difference |")
    print("|---|---|---|---|")
    for name, d50 in REGIMES.items():
        out = _run(binary, drain_case(d50), root / f"drain_{name}")
        snaps = [read_snapshot(p) for p in list_snapshots(out)]
        t = np.array([s.time for s in snaps[1:]])
        v = np.array([-s.velocity[s.kind == FLUID, 1].mean() for s in snaps[1:]])
        exact = drain_velocity(N, d50, t)
        vt = terminal_velocity(N, d50)
        late = v[t >= 0.4].mean()
        print(f"| drainage, D = {d50} m ({name}) | V(t) from rest; V at t >= 0.4 s: {late:.5f} m/s | "
              f"the momentum equation; terminal {vt:.5f} m/s | largest {100 * np.max(np.abs(v / exact - 1)):.3f} %; "
              f"terminal {100 * (late / vt - 1):+.3f} % |")
    for stones in ("open", "full", "half"):
        out = _run(binary, stones_tank_case(stones), root / f"tank_{stones}")
        snap = read_snapshot(list_snapshots(out)[-1])
        ys = hydrostatic.sample_heights(snap, 0.0, H, n=10)
        fl = snap.kind == FLUID
        pore_speed = np.hypot(*snap.velocity[fl].T)
        speed = pore_speed.mean() / math.sqrt(G * H)
        darcy = (snap.datasets["porosity"][fl] * pore_speed).mean() / math.sqrt(G * H)
        if stones in ("open", "full"):
            p = hydrostatic.profile(snap, 0.5 * WIDTH, ys)
            fit = hydrostatic.bed_pressure(ys, p, 0.0)
            dev = np.nanmax(np.abs(p - 1000.0 * G * (H - ys))) / (1000.0 * G * H)
            what = "open water (porosity 1)" if stones == "open" else "filled with stones"
            print(f"| still tank, {what}, t = {snap.time:.1f} s | bed pressure {fit.p_bed:.0f} Pa, "
                  f"mean speed {speed:.1e} sqrt(gH) (Darcy {darcy:.1e}) | rho g H = {1000 * G * H:.0f} Pa | "
                  f"{100 * (fit.p_bed / (1000 * G * H) - 1):+.2f} %, profile within {100 * dev:.2f} % |")
        else:
            lo, li = surface(snap, 0.1, 0.3), surface(snap, 0.7, 0.9)
            p_out = hydrostatic.profile(snap, 0.2, ys)
            p_in = hydrostatic.profile(snap, 0.8, ys)
            dp_max = np.nanmax(np.abs(p_in - p_out)) / (1000.0 * G * H)
            print(f"| still tank half filled with stones, t = {snap.time:.1f} s | level inside {li:.4f} m, "
                  f"outside {lo:.4f} m; mean speed {speed:.1e} sqrt(gH) (Darcy {darcy:.1e}) | one level, one pressure at one depth | "
                  f"{1000 * (li - lo):+.1f} mm ({(li - lo) / TANK_DP:+.2f} dp); pressures within "
                  f"{100 * dp_max:.2f} % of rho g H |")
    cdp, chd = a.column_dp, a.column_h_over_dp
    for name, d50 in REGIMES.items():
        column_rows(binary, root / f"column_{name}", d50, cdp, chd)
    for boundary in ("dynamic", "mdbc"):
        tag = "" if boundary == "dynamic" else "_mdbc"
        still = _run(binary, steady_case(0.01, 0.0, boundary=boundary), root / f"steady_still{tag}")
        for name, (d50, u) in STEADY.items():
            t_end = steady_t_end(u)
            out = _run(binary, steady_case(d50, u, t_end=t_end, boundary=boundary), root / f"steady_{name}{tag}")
            loss = steady_loss(out, still, t_end - 0.25, t_end)
            law, lin = steady_law(u, d50, 4.0 * STEADY_DP)
            # the head a sudden expansion from the pore velocity to u would lose (Borda-Carnot),
            # which the smooth volume-averaged equations do not have
            exit_head = 0.5 * 1000.0 * (u / N - u) ** 2
            print(f"| steady flow through a layer, {boundary} boundary, D = {d50} m ({name}, linear share {lin:.2f}), "
                  f"Darcy velocity {u} m/s, dp = {STEADY_DP} m, h = 2 dp, t = {t_end - 0.25:.2f} to {t_end:.2f} s | "
                  f"head loss {loss:.0f} Pa | Forchheimer law over the porosity profile: {law:.0f} Pa "
                  f"(an exit head rho (u/n - u)^2 / 2 would add {exit_head:.0f} Pa) | {100 * (loss / law - 1):+.1f} % "
                  f"({100 * (loss / (law + exit_head) - 1):+.1f} % with the exit head) |")
    return 0


def column_rows(binary: str, root: Path, d50: float, cdp: float, chd: float) -> None:
    """Run the column with stones of size d50 and print its rows of the table."""
    out = _run(binary, column_case(d50, dp=cdp, h_over_dp=chd), root)
    kl, kq, _ = coefficients(N, d50)
    snaps = [read_snapshot(p) for p in list_snapshots(out)]
    # windows of 0.1 s (ten snapshots) from 0.2 s on: the means of each window
    for w0 in range(20, len(snaps) - 9, 30):
        rows = []
        for snap in snaps[w0:w0 + 10]:
            f = snap.kind == FLUID
            x, v, p = snap.position[f], snap.velocity[f], snap.pressure[f]
            above = x[:, 1] > COLUMN_L + 0.02
            head = (x[:, 1] > COLUMN_L).sum() * cdp ** 2 / COLUMN_W
            # the head loss inside the layer, away from its edges: a straight line through
            # the pressure of seven bands, and the pore velocity there
            band = (x[:, 0] > 0.1 * COLUMN_W) & (x[:, 0] < 0.9 * COLUMN_W)
            ys = np.linspace(0.2, 0.8, 7) * COLUMN_L
            pm = [p[band & (np.abs(x[:, 1] - y) < 0.05 * COLUMN_L)].mean() for y in ys]
            inner = band & (x[:, 1] > 0.2 * COLUMN_L) & (x[:, 1] < 0.8 * COLUMN_L)
            rows.append((snap.time, -v[above, 1].mean(), head, np.polyfit(ys, pm, 1)[0], -v[inner, 1].mean(),
                         inner.sum() / (0.6 * COLUMN_L / 0.01)))
        t0, u, head, grad, vin, per_cm = np.array(rows).mean(axis=0)
        law = column_law(head, d50, 2.0 * chd * cdp)
        grad_law = 1000.0 * (kl * vin + kq * vin * vin - G)
        nominal = 0.8 * COLUMN_W * 0.01 * N / cdp ** 2       # in the band measured
        print(f"| column, D = {d50} m, dp = {cdp} m, h = {chd:.3g} dp, t = {rows[0][0]:.2f} to {rows[-1][0]:.2f} s "
              f"({per_cm:.1f} particles per cm of the layer away from its walls, {nominal:.1f} nominal) | Darcy velocity {u:.4f} m/s "
              f"under {head:.3f} m; in the layer dp/dy {grad:.0f} Pa/m at V = {vin:.3f} m/s | Forchheimer law, "
              f"quasi-steady: {law:.4f} m/s; rho (kl V + kq V^2 - g) = {grad_law:.0f} Pa/m | "
              f"{100 * (u / law - 1):+.1f} %; {100 * (grad / grad_law - 1):+.1f} % |")


if __name__ == "__main__":
    sys.exit(main())
