"""Wave-flume case files: a paddle in constant depth, gauges along the flume and a
damping zone at the far end, laid out in wavelengths of the target wave.

``python -m post.wave_cases --kh 1.2 --out input/waves/regular_kh12.nml`` writes one;
the tests of tests/test_waves.py build theirs with :func:`flume_case`.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

G = 9.81
# the solver's smoothing length / dp in a case with a wavemaker that leaves it out (doc/input.md,
# "Wave defaults"): the walls' thickness follows it
WAVE_H_OVER_DP = 1.6


def period_for_kh(kh: float, depth: float, g: float = G) -> float:
    k = kh / depth
    return 2.0 * math.pi / math.sqrt(g * k * math.tanh(kh))


def biesel_transfer(kh: float, paddle: str) -> float:
    """Biesel's H/S of a piston, or of a flap hinged at the bed (S at the still-water level)."""
    if paddle == "piston":
        return 2.0 * (math.cosh(2.0 * kh) - 1.0) / (math.sinh(2.0 * kh) + 2.0 * kh)
    return 4.0 * math.sinh(kh) / kh * (kh * math.sinh(kh) - math.cosh(kh) + 1.0) / (math.sinh(2.0 * kh) + 2.0 * kh)


@dataclass
class Flume:
    """Layout of a flume case, in metres and seconds."""

    text: str
    period: float
    group_speed: float
    length: float          # wavelength L
    height: float
    depth: float
    x0: float              # paddle face at rest
    gauges: list[float]    # x of the elevation gauges
    t_end: float
    damping: tuple[float, float]


def paddle_modes(kh: float, depth: float, paddle: str, x: float, g: float = G) -> tuple[float, float, float]:
    """omega, the progressive elevation per unit face velocity P (in phase with the
    velocity) and q, the evanescent modes' elevation i q at x in front of the face
    (Havelock), of a wave of kh: the solver's wave_theory paddle_mode, summed as
    wave_paddle paddle_absorb_tune does."""
    omega = 2.0 * math.pi / period_for_kh(kh, depth, g)
    P = biesel_transfer(kh, paddle) / omega
    c = omega * omega * depth / g
    q = 0.0
    n = 0
    while True:
        n += 1
        lo, hi = 0.0, 0.5 * math.pi          # kappa_n d = n pi - dl, (n pi - dl) tan dl = omega^2 d / g
        while hi - lo > 4e-16 * hi:
            dl = 0.5 * (lo + hi)
            lo, hi = (lo, dl) if (n * math.pi - dl) * math.tan(dl) > c else (dl, hi)
        y = n * math.pi - 0.5 * (lo + hi)
        kn = y / depth
        proj = (y * math.sin(y) + math.cos(y) - 1.0) / (kn * kn * depth) if paddle == "flap" else math.sin(y) / kn
        cn = proj / (0.5 * depth + math.sin(2.0 * y) / (4.0 * kn))
        term = -omega / (g * kn) * cn * math.cos(y) * math.exp(-kn * max(x, 0.0))
        q += term
        if abs(term) < 1e-12 * P and n > 10:
            return omega, P, q


def absorber_tuning(kh: float, paddle: str, depth: float, x_gauge: float, tau_periods: float = 5.0,
                    g: float = G) -> tuple[float, float, float]:
    """The solver's absorber tuned to a wave of kh (wave_paddle paddle_absorb_tune): its
    gain G [1/s], the lag t_l [s] with which it reads the wave coming in, and its near
    field q (per unit of its own wave), for a gauge x_gauge in front of the wave's source
    and filters of tau_periods periods."""
    omega, P, q = paddle_modes(kh, depth, paddle, x_gauge, g)
    tau = tau_periods * 2.0 * math.pi / omega
    K = (1.0 + 1j / (omega * tau)) ** 2 / (P * complex(math.cos(kh / depth * x_gauge), -math.sin(kh / depth * x_gauge))
                                         - 1j * q)
    return abs(K), (math.atan2(K.imag, K.real) % (2.0 * math.pi)) / omega, q / P


def absorber_linear_kr(kh: float, gain_kh: float, paddle: str, depth: float, x_gauge: float,
                       tau_periods: float = 5.0, g: float = G) -> float:
    """The reflection coefficient of linear theory for the solver's absorbing paddle
    (doc/waves.md, "Active absorption at the paddle"): tuned at gain_kh (absorber_tuning),
    met by a wave of kh. The gauge reads the wave coming in, its reflection by the paddle
    at rest and the correction's own wave and modes; Kr = |I + U P| / |I|."""
    gain, lag, _ = absorber_tuning(gain_kh, paddle, depth, x_gauge, tau_periods, g)
    tau = tau_periods * period_for_kh(gain_kh, depth, g)
    w, P, q = paddle_modes(kh, depth, paddle, x_gauge, g)
    kx = kh / depth * x_gauge
    Kc = gain * complex(math.cos(w * lag), math.sin(w * lag)) / (1.0 + 1j / (w * tau)) ** 2
    e_in, e_out = complex(math.cos(kx), -math.sin(kx)), complex(math.cos(kx), math.sin(kx))
    U = -Kc * (e_in + e_out) / (1.0 + Kc * (P * e_out + 1j * q))
    return abs(1.0 + U * P)


def _run_to_numerics(case_name: str, t_end: float, T: float, out_dir: str, extra_run: str, xmax: float,
                     thick: float, top: float, dp: float, h_over_dp: float | None, extra_numerics: str,
                     viscosity: str | None = "artificial") -> str:
    """The &run, &domain, &fluid and &numerics groups every flume of this module shares;
    ``viscosity = None`` leaves the viscosity to the solver (its wave default)."""
    visc = {"artificial": "\n  viscosity = 'artificial', alpha = 0.01", None: ""}.get(
        viscosity, f"\n  viscosity = '{viscosity}'")
    return f"""&run
  case_name = '{case_name}'
  t_end = {t_end:.6f}
  dt_out = {max(T / 2.0, 0.1):.6f}
  out_dir = '{out_dir}'
  overwrite = .true.
  gauge_interval = {T / 40.0:.6f}
{extra_run}
/
&domain
  xmin = 0.0, xmax = {xmax:.6f}, ymin = {-thick - 0.01:.6f}, ymax = {top + 0.05:.6f}
/
&fluid
  rho0 = 1000.0, gamma = 7.0, coef = 10.0, gravity = {G}
/
&numerics
  dp = {dp}{"" if h_over_dp is None else f"{chr(10)}  h_over_dp = {h_over_dp}"}{visc}
  diffusion = 'fourtakas', delta = 0.1
{extra_numerics}
/
"""


def flume_case(kh: float, *, depth: float = 0.25, steepness: float = 0.03, dp: float = 0.0125,
               paddle: str = "piston", out_dir: str = "OUT/waves", gauges_at=(2.0, 2.25, 2.5, 2.75, 3.0),
               damping_len: float = 1.5, periods_after: float = 4.0, extra_run: str = "",
               extra_numerics: str = "", case_name: str = "waves", second_order: bool = False,
               ramp_periods: float = 2.0, t_end: float | None = None, h_over_dp: float | None = None,
               extra_wavemaker: str = "", viscosity: str | None = "artificial") -> Flume:
    """A regular-wave flume: the paddle, then gauges at the given multiples of the
    wavelength L, then a damping zone damping_len L long. The run lasts until the
    wave front (group speed) has passed the last gauge and periods_after more periods.
    ``h_over_dp`` is written to ``&numerics`` when given (else the solver's default for
    a case with a wavemaker, 1.6, doc/input.md "Wave defaults"); the bed and end wall are
    as thick as its kernel's reach. ``viscosity``: 'artificial' (alpha 0.01), another
    model's name, or None for the solver's wave default. With ``damping_len = 0``
    the flume ends in a bare vertical wall (no &damping group); ``extra_wavemaker`` goes
    into the &wavemaker group."""
    T = period_for_kh(kh, depth)
    k = kh / depth
    L = 2.0 * math.pi / k
    H = steepness * L
    n1 = 0.5 * (1.0 + 2.0 * kh / math.sinh(2.0 * kh))
    cg = n1 * L / T
    # bed and end wall as thick as the kernel's reach (2h), so no water leaks through them
    layers = math.ceil(2.0 * (WAVE_H_OVER_DP if h_over_dp is None else h_over_dp) - 1e-9)
    thick = layers * dp
    x0 = 0.11 + thick          # room for the paddle moving max_stroke/2 = 0.1 m back
    x_end = x0 + (max(gauges_at) + 0.25 + damping_len) * L
    x_end = x0 + math.ceil((x_end - x0) / dp) * dp
    gx = [x0 + a * L for a in gauges_at]
    if t_end is None:
        t_end = ramp_periods * T + (max(gauges_at) * L) / cg + periods_after * T
    damp = (x0 + (max(gauges_at) + 0.25) * L, x_end)
    top = 2.0 * depth
    gauges = "\n".join(f"&gauge kind = 'elevation', x = {x:.6f} /" for x in gx)
    text = f"""! Regular waves from a {paddle} paddle in constant depth: kh = {kh}, depth {depth} m,
! T = {T:.6f} s, L = {L:.6f} m, H = {H:.6f} m (steepness H/L = {steepness}).
! Gauges at {', '.join(str(a) for a in gauges_at)} wavelengths from the paddle; damping zone
! over the last {damping_len} L. Made by post/wave_cases.py.
{_run_to_numerics(case_name, t_end, T, out_dir, extra_run, x_end + thick + 0.01, thick, top, dp, h_over_dp, extra_numerics, viscosity)}&box role = 'solid', xmin = 0.0, xmax = {x_end + thick:.6f}, ymin = {-thick:.6f}, ymax = 0.0 /
&box role = 'solid', xmin = {x_end:.6f}, xmax = {x_end + thick:.6f}, ymin = 0.0, ymax = {top:.6f} /
&box role = 'fluid', xmin = {x0:.6f}, xmax = {x_end:.6f}, ymin = 0.0, ymax = {depth:.6f} /
&wavemaker
  paddle = '{paddle}', wave = 'regular', x0 = {x0:.6f}, depth = {depth}
  height = {H:.6f}, period = {T:.6f}, ramp_periods = {ramp_periods}, max_stroke = 0.2
  second_order = {'.true.' if second_order else '.false.'}{chr(10) + extra_wavemaker if extra_wavemaker else ''}
/
{gauges}
"""
    if damping_len > 0.0:
        text += f"&damping x0 = {damp[0]:.6f}, x1 = {damp[1]:.6f}, strength = {max(10.0, 10.0 / T):.3f} /\n"
    return Flume(text, T, cg, L, H, depth, x0, gx, t_end, damp)


@dataclass
class AbsorptionFlume:
    """A flume whose far end is a piston making a regular wave that runs to the paddle,
    which makes no wave of its own (it rests) and absorbs (or not). Two gauges a quarter
    wavelength apart in front of the paddle separate the wave that comes in from the
    wave the paddle returns; :func:`paddle_reflection_coefficient` reads Kr from them."""

    text: str
    period: float
    length: float          # wavelength L
    height: float
    depth: float
    x0: float              # paddle face at rest
    gauges: list[float]    # the two gauges [m]
    window: tuple[float, float]   # the time window of the separation [s]


def absorption_case(kh: float, *, depth: float = 0.25, steepness: float = 0.02, dp: float = 0.0125,
                    paddle: str = "piston", absorb: bool = True, gain_kh: float | None = None,
                    flume_waves: float = 3.5, periods: float = 4.0, out_dir: str = "OUT/absorb",
                    case_name: str = "absorb", h_over_dp: float | None = 1.6, extra_numerics: str = "") -> AbsorptionFlume:
    """The paddle (at rest: its wave starts after the run) at x0, gauges at 0.5 and
    0.75 L in front of it, and ``flume_waves`` wavelengths away a piston wall oscillating
    with the Biesel stroke of a wave of steepness ``steepness``. ``gain_kh`` tunes the
    absorber to another period than the wave's (its kh in this depth). The separation
    window is ``periods`` periods long and starts two periods after the wave the paddle
    returns has passed the far gauge (at the group speed), and the run ends with it: the
    wave that the far end returns in its turn comes to the gauges after the window, so a
    paddle that does not absorb is measured too (Kr near 1)."""
    T = period_for_kh(kh, depth)
    k = kh / depth
    L = 2.0 * math.pi / k
    H = steepness * L
    cg = 0.5 * (1.0 + 2.0 * kh / math.sinh(2.0 * kh)) * L / T
    hs = biesel_transfer(kh, "piston")
    amp = 0.5 * H / hs
    h = (WAVE_H_OVER_DP if h_over_dp is None else h_over_dp) * dp
    layers = math.ceil(2.0 * h / dp - 1e-9)
    thick = layers * dp
    x0 = 0.11 + thick
    x_far = x0 + math.ceil(flume_waves * L / dp) * dp
    gx = [x0 + 0.5 * L, x0 + 0.75 * L]
    t_back = (x_far - x0) / cg + (gx[1] - x0) / cg
    t_end = t_back + (periods + 2.0) * T
    top = 2.0 * depth
    T_gain = T if gain_kh is None else period_for_kh(gain_kh, depth)
    text = f"""! Absorption at the paddle: a regular wave (kh = {kh}, depth {depth} m, T = {T:.6f} s,
! L = {L:.6f} m, H = {H:.6f} m) made by a piston wall at the far end, {flume_waves} L away,
! runs to the paddle, which rests and {"absorbs" if absorb else "does not absorb"}. Gauges at 0.5 and 0.75 L.
! Made by post/wave_cases.py (absorption_case).
{_run_to_numerics(case_name, t_end, T, out_dir, '', x_far + thick + 2.0 * amp + 0.02, thick, top, dp, h_over_dp, extra_numerics)}&box role = 'solid', xmin = 0.0, xmax = {x_far + thick + 2.0 * amp:.6f}, ymin = {-thick:.6f}, ymax = 0.0 /
&box role = 'solid', xmin = {x_far:.6f}, xmax = {x_far + thick:.6f}, ymin = 0.0, ymax = {top:.6f},
  motion = 'oscillate', amplitude = {-amp:.6f}, 0.0, period = {T:.6f} /
&box role = 'fluid', xmin = {x0:.6f}, xmax = {x_far:.6f}, ymin = 0.0, ymax = {depth:.6f} /
&wavemaker
  paddle = '{paddle}', wave = 'regular', x0 = {x0:.6f}, depth = {depth}
  height = {H:.6f}, period = {T_gain:.6f}, t_start = {t_end + 1.0:.6f}
  absorb = {'.true.' if absorb else '.false.'}
/
&gauge kind = 'elevation', x = {gx[0]:.6f} /
&gauge kind = 'elevation', x = {gx[1]:.6f} /
"""
    return AbsorptionFlume(text, T, L, H, depth, x0, gx, (t_end - periods * T, t_end))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--kh", type=float, required=True)
    ap.add_argument("--depth", type=float, default=0.25)
    ap.add_argument("--steepness", type=float, default=0.03)
    ap.add_argument("--dp", type=float, default=0.0125)
    ap.add_argument("--paddle", choices=("piston", "flap"), default="piston")
    ap.add_argument("--h-over-dp", type=float, default=None,
                    help="smoothing length / dp (default: the solver's, sqrt 2; 1.6 for wave propagation, doc/waves.md)")
    ap.add_argument("--out-dir", default="OUT/waves")
    ap.add_argument("--out", type=Path, required=True, help="case file to write")
    a = ap.parse_args()
    f = flume_case(a.kh, depth=a.depth, steepness=a.steepness, dp=a.dp, paddle=a.paddle, out_dir=a.out_dir,
                   h_over_dp=a.h_over_dp)
    a.out.parent.mkdir(parents=True, exist_ok=True)
    a.out.write_text(f.text)
    print(f"{a.out}: T = {f.period:.4f} s, L = {f.length:.4f} m, H = {f.height:.4f} m, t_end = {f.t_end:.2f} s")


if __name__ == "__main__":
    main()
