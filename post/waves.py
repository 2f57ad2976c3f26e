"""Wave analysis of the gauge records ``OUT/gauges.csv``: heights, periods, spectra, reflection.

Functions (each takes plain arrays, so tests call them on synthetic signals):

- :func:`read_gauges`: the gauge table, the time and the columns of ``gauges.csv``;
- :func:`wavenumber`: linear dispersion ``omega^2 = g k tanh(k h)`` solved for ``k``;
- :func:`target_elevation_at`: a target elevation at the paddle carried to a gauge by linear dispersion;
- :func:`zero_crossing`: zero-up-crossing wave heights and periods, ``H_1/3``, ``Hmax``, ``T_mean``;
- :func:`spectrum`: variance density by Welch's method with Hann windows, ``Hm0``, ``Tp``,
  ``Tm-1,0``, ``Tm02``;
- :func:`regular_wave_height`: height and period of a regular wave over whole periods;
- :func:`is_regular`: whether a record is a regular wave (its energy near one frequency);
- :func:`reflection_two_gauge`: incident and reflected waves of two gauges, Goda and Suzuki (1976);
- :func:`reflection_three_gauge`: the same from three gauges by least squares, Mansard and Funke (1980).

Usage::

    python -m post.waves OUT [--depth D] [--pair i,j] [--triple i,j,k] [--period T]
                             [--t-start T0] [--t-end T1] [--out DIR]

prints a table per gauge and the reflection of the chosen gauges, and draws
``gauges.png`` (elevation against time) and ``spectrum.png`` into ``DIR`` (default ``OUT``).

Conventions: waves are incident when they travel towards +x (from the wavemaker to the
structure), so in the reflection functions the gauge nearest the wavemaker comes first.
Elevations are metres above the still water level, times seconds, frequencies hertz.
"""

from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Sequence

import numpy as np
from scipy import signal

from .io import case_t_end, complete_lines, fluid_box, note_end, read_case
from .plotting import plt, save_figure

__all__ = [
    "G",
    "Gauge",
    "read_gauges",
    "gauge_column",
    "wavenumber",
    "wavelength",
    "target_elevation_at",
    "ZeroCrossing",
    "zero_crossing",
    "Spectrum",
    "spectrum",
    "is_regular",
    "RegularWave",
    "regular_wave_height",
    "Reflection",
    "reflection_two_gauge",
    "reflection_three_gauge",
    "DecayingWave",
    "decaying_wave_fit",
    "wavemaker_settings",
    "measured_height",
    "main",
]

#: gravity acceleration used by the dispersion relation (m/s2)
G = 9.81

#: band of gauge spacing over wavelength where the two-gauge separation is well conditioned
#: (Goda and Suzuki 1976): at dx/L = 0 or 1/2 the two equations coincide
DX_OVER_L_BAND = (0.05, 0.45)


# ------------------------------------------------------------------------ reading


@dataclass(frozen=True)
class Gauge:
    """One row of the gauge table of ``gauges.csv``: ``kind`` is 'elevation' or 'pressure'.

    ``column`` is the name of its column in the data (``eta_<id>`` or ``p_<id>``); ``y`` is
    NaN for an elevation gauge; ``z`` is the position across the width of a 3D run (0 in
    2D, whose table has no z column).
    """

    id: int
    kind: str
    x: float
    y: float
    z: float = 0.0

    @property
    def column(self) -> str:
        return f"{'eta' if self.kind == 'elevation' else 'p'}_{self.id}"


def read_gauges(path: str | Path) -> tuple[list[Gauge], np.ndarray, dict[str, np.ndarray]]:
    """Read ``gauges.csv`` (or the ``gauges.csv`` of an output folder).

    The file opens with comment lines (``#``): the first is the legend ``id,kind,x,y`` of
    the gauge table (``id,kind,x,y,z`` in 3D), each further one a gauge. Then comes the header line
    ``time,eta_1,...,p_k`` and one row per output time. Returns the gauges in file order,
    the time array and ``{column name: array}`` of every column (``time`` included).
    """
    path = Path(path)
    if path.is_dir():
        path = path / "gauges.csv"
    comments: list[str] = []
    data: list[str] = []
    for line in complete_lines(path):
        line = line.strip()
        if not line:
            continue
        if line.startswith("#"):
            if data:
                raise ValueError(f"{path}: comment line after the data: {line!r}")
            comments.append(line[1:].strip())
        else:
            data.append(line)
    if not comments:
        raise ValueError(f"{path}: no gauge table (comment lines starting with '#')")
    legend = [name.strip().lower() for name in comments[0].split(",")]
    if legend[:4] != ["id", "kind", "x", "y"]:
        raise ValueError(f"{path}: first comment line is {comments[0]!r}, expected 'id,kind,x,y'")
    gauges = []
    for row in comments[1:]:
        fields = [v.strip() for v in row.split(",")]
        if len(fields) < 4:
            raise ValueError(f"{path}: gauge line {row!r} has {len(fields)} fields, expected 4")
        z = float(fields[4]) if len(legend) > 4 and legend[4] == "z" and len(fields) > 4 else 0.0
        gauges.append(Gauge(int(fields[0]), fields[1].lower(), float(fields[2]), float(fields[3]), z))
    if not data:
        raise ValueError(f"{path}: no header line after the gauge table")
    names = [name.strip() for name in data[0].split(",")]
    rows = [[float(v) for v in line.split(",")] for line in data[1:]]
    for number, row in enumerate(rows, start=1):
        if len(row) != len(names):
            raise ValueError(f"{path}: data row {number} has {len(row)} fields, header has {len(names)}")
    values = np.array(rows, dtype=float).reshape(len(rows), len(names))
    columns = {name: values[:, j].copy() for j, name in enumerate(names)}
    if "time" not in columns:
        raise ValueError(f"{path}: header {data[0]!r} has no 'time' column")
    for gauge in gauges:
        if gauge.column not in columns:
            raise ValueError(f"{path}: gauge {gauge.id} ({gauge.kind}) has no column {gauge.column}")
    return gauges, columns["time"], columns


def gauge_column(gauges: Sequence[Gauge], columns: dict[str, np.ndarray], gauge_id: int) -> tuple[Gauge, np.ndarray]:
    """The gauge with id ``gauge_id`` and its data column."""
    for gauge in gauges:
        if gauge.id == gauge_id:
            return gauge, columns[gauge.column]
    raise KeyError(f"no gauge with id {gauge_id} (ids: {[g.id for g in gauges]})")


# --------------------------------------------------------------------- dispersion


def wavenumber(omega: float | np.ndarray, depth: float, g: float = G) -> np.ndarray:
    """Wave number ``k`` (rad/m) of linear waves: ``omega^2 = g k tanh(k depth)``.

    Newton iterations from the explicit approximation of Eckart (1952), to a relative
    residual of 1e-14; ``omega = 0`` gives ``k = 0``.
    """
    w = np.abs(np.asarray(omega, dtype=float))
    k0 = w * w / g  # deep water
    with np.errstate(divide="ignore", invalid="ignore"):
        k = np.where(w > 0, k0 / np.sqrt(np.tanh(k0 * depth)), 0.0)
        for _ in range(50):
            th = np.tanh(k * depth)
            f = g * k * th - w * w
            df = g * th + g * k * depth * (1.0 - th * th)
            step = np.where(w > 0, f / df, 0.0)
            k = k - step
            if np.all(np.abs(step) <= 1e-14 * np.maximum(k, 1e-300)):
                break
    return k


def wavelength(period: float | np.ndarray, depth: float, g: float = G) -> np.ndarray:
    """Linear wavelength ``L = 2 pi / k`` (m) of a wave of the given period (s)."""
    return 2.0 * np.pi / wavenumber(2.0 * np.pi / np.asarray(period, dtype=float), depth, g)


# ------------------------------------------------------------------ time domain


def target_elevation_at(t: np.ndarray, x: float, signal_time: np.ndarray, signal_eta: np.ndarray,
                        x0: float, depth: float, g: float = G) -> np.ndarray:
    """The target elevation ``signal_eta(signal_time)`` at the paddle (x0), uniformly
    sampled and taken as periodic over its length, carried to ``x`` component by
    component by linear dispersion at the still-water depth, at the times ``t``: the
    wave a perfect flume makes there, to compare a gauge with over the same window."""
    n = len(signal_time)
    dt = signal_time[1] - signal_time[0]
    c = np.fft.rfft(signal_eta) / n
    f = np.arange(1, len(c)) / (n * dt)
    k = wavenumber(2.0 * math.pi * f, depth, g)
    out = np.empty(len(t))
    for a in range(0, len(t), 2000):  # in blocks: the matrix is samples x components
        tb = t[a:a + 2000]
        ph = np.exp(1j * (2.0 * math.pi * f[None, :] * tb[:, None] - k[None, :] * (x - x0)))
        out[a:a + 2000] = 2.0 * np.real(ph @ c[1:])
    return out


def _uniform(t: np.ndarray, eta: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """The record on a uniform time grid: as given when it is uniform to 1e-6 of a step,
    else linearly interpolated at the median step."""
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float)
    if t.ndim != 1 or t.shape != eta.shape[-1:] or len(t) < 4:
        raise ValueError("need a 1-D time array and a record of the same length (at least 4 samples)")
    steps = np.diff(t)
    dt = float(np.median(steps))
    if dt <= 0:
        raise ValueError("the times must increase")
    if np.max(np.abs(steps - dt)) <= 1e-6 * dt:
        return t, eta, dt
    grid = t[0] + dt * np.arange(int(math.floor((t[-1] - t[0]) / dt + 1e-9)) + 1)
    if eta.ndim == 1:
        return grid, np.interp(grid, t, eta), dt
    return grid, np.array([np.interp(grid, t, e) for e in eta]), dt


def _extremum(y: np.ndarray, i: int, sign: float) -> float:
    """Value of the crest (sign = +1) or trough (-1) at sample ``i``, refined by the parabola
    through samples i-1, i, i+1 (sampling alone misses the peak by up to a (omega dt)^2 / 8)."""
    if 0 < i < len(y) - 1:
        ym, y0, yp = y[i - 1], y[i], y[i + 1]
        curv = ym - 2.0 * y0 + yp
        if sign * curv < 0:
            p = 0.5 * (ym - yp) / curv
            if abs(p) <= 1.0:
                return float(y0 - 0.25 * (ym - yp) * p)
    return float(y[i])


@dataclass(frozen=True)
class ZeroCrossing:
    """Zero-up-crossing statistics of a record.

    ``heights`` and ``periods`` are per wave (m, s), in time order; ``crossings`` are the
    interpolated up-crossing times (one more than the waves). ``H_1_3`` is the mean of
    the highest third of the waves and ``T_1_3`` the mean period of those waves.
    """

    heights: np.ndarray
    periods: np.ndarray
    crossings: np.ndarray
    H_mean: float
    H_rms: float
    H_1_3: float
    T_1_3: float
    H_max: float
    T_mean: float

    @property
    def count(self) -> int:
        return len(self.heights)


def zero_crossing(t: np.ndarray, eta: np.ndarray, demean: bool = True) -> ZeroCrossing:
    """Zero-up-crossing analysis of ``eta(t)``.

    The level is the record mean (``demean``) or zero. Each up-crossing time is linearly
    interpolated between the two samples that bracket it; a wave runs from one up-crossing
    to the next, its height is its highest crest minus its lowest trough (each refined by a
    parabola through the three samples around it), its period the time between the two
    crossings. The incomplete waves before the first and after the last up-crossing are
    dropped. With fewer than two up-crossings the statistics are NaN.
    """
    t, eta, _ = _uniform(t, eta)
    y = eta - np.mean(eta) if demean else eta.copy()
    up = np.nonzero((y[:-1] < 0.0) & (y[1:] >= 0.0))[0]
    crossings = t[up] + (-y[up]) / (y[up + 1] - y[up]) * (t[up + 1] - t[up])
    heights, periods = [], []
    for a, b, ta, tb in zip(up[:-1], up[1:], crossings[:-1], crossings[1:]):
        seg = slice(a + 1, b + 1)
        crest = _extremum(y, a + 1 + int(np.argmax(y[seg])), 1.0)
        trough = _extremum(y, a + 1 + int(np.argmin(y[seg])), -1.0)
        heights.append(crest - trough)
        periods.append(tb - ta)
    h = np.array(heights)
    p = np.array(periods)
    if len(h) == 0:
        nan = float("nan")
        return ZeroCrossing(h, p, crossings, nan, nan, nan, nan, nan, nan)
    order = np.argsort(h)[::-1]
    third = order[: max(1, len(h) // 3)]
    return ZeroCrossing(
        heights=h, periods=p, crossings=crossings,
        H_mean=float(np.mean(h)), H_rms=float(np.sqrt(np.mean(h * h))),
        H_1_3=float(np.mean(h[third])), T_1_3=float(np.mean(p[third])),
        H_max=float(np.max(h)), T_mean=float(np.mean(p)),
    )


# ------------------------------------------------------------------- spectra


def _segments(n: int, nseg: int) -> int:
    """Length of ``nseg`` segments overlapping by half that cover ``n`` samples."""
    if nseg < 1:
        raise ValueError("nseg must be at least 1")
    return n if nseg == 1 else int(2 * n // (nseg + 1))


#: the windows the spectral functions accept (scipy.signal.get_window names)
WINDOWS = ("hann", "boxcar")


def _welch_options(n: int, length: int, window: str) -> dict:
    """Options of scipy.signal.welch and csd for segments of ``length`` samples (at most
    ``n``) overlapping by half: each segment has its mean removed and is multiplied by the
    periodic window (scipy's default, whose overlapping halves add up to a constant); the
    densities are one-sided."""
    if window not in WINDOWS:
        raise ValueError(f"window {window!r}: use 'hann' or 'boxcar'")
    length = min(int(length), n)
    if length < 8:
        raise ValueError(f"segments of {length} samples are too short")
    # a step of floor(length/2) samples, for odd lengths too
    return dict(window=window, nperseg=length, noverlap=length - max(1, length // 2),
                detrend="constant", return_onesided=True, scaling="density", axis=-1)


def _rough_peak_frequency(y: np.ndarray, dt: float) -> float:
    """Peak frequency of the Hann periodogram of the whole record smoothed over five bins:
    good enough to choose the segment length of the Welch estimate."""
    f, P = signal.periodogram(y, fs=1.0 / dt, window="hann", detrend="constant")
    P = np.convolve(P, np.ones(5) / 5.0, mode="same")
    return float(f[1 + int(np.argmax(P[1:]))])


#: default length of the Welch segments, in peak periods
SEGMENT_PEAK_PERIODS = 20.0


@dataclass(frozen=True)
class Spectrum:
    """One-sided variance density ``S`` (m2/Hz) at frequencies ``f`` (Hz, bin width ``df``)
    and its parameters over the band ``[fmin, fmax]``: ``m0`` (m2), ``Hm0 = 4 sqrt(m0)``,
    peak period ``Tp = 1/f_peak``, ``Tm_10 = m-1/m0``, ``Tm02 = sqrt(m0/m2)``."""

    f: np.ndarray
    S: np.ndarray
    df: float
    m0: float
    Hm0: float
    Tp: float
    Tm_10: float
    Tm02: float
    fmin: float
    fmax: float


def spectrum(t: np.ndarray, eta: np.ndarray, segment: float | None = None, nseg: int | None = None,
             window: str = "hann", fmin: float | None = None, fmax: float | None = None) -> Spectrum:
    """Variance density spectrum of ``eta(t)`` by Welch's method (``scipy.signal.welch``).

    The record is cut into segments that overlap by half; each has its mean removed, is
    multiplied by a (periodic) Hann window and Fourier transformed; the densities
    ``2 |X|^2 / (fs sum w^2)`` (not doubled at 0 and at the Nyquist frequency) are averaged
    over the segments. The segments last ``segment`` seconds, or there are ``nseg`` of
    them; by default each lasts ``SEGMENT_PEAK_PERIODS = 20`` peak periods (the peak taken
    from the smoothed periodogram of the whole record), so that ``df`` is about ``fp/20``,
    or the whole record when it is shorter. ``nseg = 1`` is the plain Hann periodogram of
    the whole record. The frequency resolution is ``df = 1 / segment duration``.

    The moments ``m_n = sum f^n S df`` run over ``fmin <= f <= fmax`` (default: every
    frequency above zero); ``Tp`` is the inverse of the frequency of the highest bin there.
    """
    t, y, dt = _uniform(t, eta)
    if nseg is not None:
        length = _segments(len(y), nseg)
    elif segment is not None:
        length = int(round(segment / dt))
    else:
        length = int(round(SEGMENT_PEAK_PERIODS / (_rough_peak_frequency(y, dt) * dt)))
    f, S = signal.welch(y, fs=1.0 / dt, **_welch_options(len(y), length, window))
    df = float(f[1])
    lo = df if fmin is None else max(float(fmin), df * 0.5)
    hi = float(f[-1]) if fmax is None else float(fmax)
    band = (f >= lo - 1e-12 * df) & (f <= hi + 1e-12 * df)
    if not np.any(band):
        raise ValueError(f"no frequency bin in [{lo}, {hi}] Hz")
    fb, Sb = f[band], S[band]
    m0 = float(np.sum(Sb) * df)
    m_1 = float(np.sum(Sb / fb) * df)
    m2 = float(np.sum(Sb * fb * fb) * df)
    fp = float(fb[int(np.argmax(Sb))])
    return Spectrum(f=f, S=S, df=df, m0=m0, Hm0=4.0 * math.sqrt(m0), Tp=1.0 / fp,
                    Tm_10=m_1 / m0 if m0 > 0 else float("nan"),
                    Tm02=math.sqrt(m0 / m2) if m2 > 0 else float("nan"), fmin=lo, fmax=hi)


def is_regular(t: np.ndarray, eta: np.ndarray, fraction: float = 0.7) -> bool:
    """True when at least ``fraction`` of the variance lies within 10 % of the peak frequency
    (Hann periodogram of the whole record). A regular wave, even with its bound harmonics,
    has about all of it there; a JONSWAP sea (gamma = 3.3) about a third."""
    sp = spectrum(t, eta, nseg=1)
    fp = 1.0 / sp.Tp
    near = (sp.f >= 0.9 * fp) & (sp.f <= 1.1 * fp)
    return bool(np.sum(sp.S[near]) * sp.df >= fraction * sp.m0)


# ------------------------------------------------------------------ regular waves


@dataclass(frozen=True)
class RegularWave:
    """Height and period of a regular wave over ``n_periods`` whole periods from ``t_start``.

    ``H`` is twice the first-harmonic amplitude fitted by least squares at the given
    period; ``amplitudes[j-1]`` is the amplitude of harmonic ``j`` of that fit and
    ``H_crest_trough`` the crest-to-trough height of the fitted periodic wave (all its
    harmonics), the height of a nonlinear wave as wave theory defines it. For
    comparison ``H_zero_crossing`` and ``T_zero_crossing`` are the zero-crossing means over
    the same window, and ``T_fit`` the period whose fit (same harmonics, same window)
    leaves the least squared residual, searched within 20 % of the given period.
    """

    H: float
    amplitudes: np.ndarray
    H_crest_trough: float
    H_zero_crossing: float
    T_zero_crossing: float
    T_fit: float
    period: float
    n_periods: int
    t_start: float
    t_end: float


def _whole_periods(t: np.ndarray, period: float, t_start: float | None,
                   t_end: float | None) -> tuple[np.ndarray, float, float, int]:
    """The samples of the largest whole number ``n`` of periods from ``t_start`` (default:
    the first sample) that ends by ``t_end`` (default: the last sample), as a mask, with
    the window's start, end and ``n``. The window is half open, [start, start + n period):
    a sample at both ends would weigh that phase twice."""
    t0 = float(t[0]) if t_start is None else float(t_start)
    t1 = float(t[-1]) if t_end is None else float(t_end)
    n = int(math.floor((t1 - t0) / period + 1e-9))
    if n < 1:
        raise ValueError(f"the window [{t0}, {t1}] s holds no whole period of {period} s")
    t1 = t0 + n * period
    tol = 1e-6 * float(np.median(np.diff(t)))
    return (t >= t0 - tol) & (t < t1 - tol), t0, t1, n


def _harmonic_coefficients(t: np.ndarray, y: np.ndarray, omega: float, harmonics: int) -> tuple[np.ndarray, float]:
    """Least-squares coefficients (mean, then cos and sin of harmonics 1..harmonics) of
    ``y(t)``, and the sum of the squared residuals."""
    cols = [np.ones_like(t)]
    for j in range(1, harmonics + 1):
        cols += [np.cos(j * omega * t), np.sin(j * omega * t)]
    A = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(A, y, rcond=None)
    resid = y - A @ coef
    return coef, float(resid @ resid)


def _harmonic_fit(t: np.ndarray, y: np.ndarray, omega: float, harmonics: int) -> tuple[np.ndarray, float]:
    """Least-squares amplitudes of harmonics 1..harmonics (plus a mean) of ``y(t)``, and the
    sum of the squared residuals."""
    coef, res = _harmonic_coefficients(t, y, omega, harmonics)
    return np.hypot(coef[1::2], coef[2::2]), res


def _crest_trough(coef: np.ndarray) -> float:
    """Crest-to-trough height of ``sum_j a_j cos j p + b_j sin j p`` (coefficients after the
    mean), from 4096 phases over one period and parabolic refinement at both extremes."""
    p = np.linspace(0.0, 2.0 * np.pi, 4096, endpoint=False)
    y = np.zeros_like(p)
    for j in range(len(coef) // 2):
        y += coef[2 * j] * np.cos((j + 1) * p) + coef[2 * j + 1] * np.sin((j + 1) * p)

    def peak(v: np.ndarray) -> float:
        i = int(np.argmax(v))
        a, b, c = v[i - 1], v[i], v[(i + 1) % len(v)]
        den = a - 2.0 * b + c
        return float(b - 0.125 * (a - c) ** 2 / den) if den < 0.0 else float(b)

    return peak(y) + peak(-y)


def regular_wave_height(t: np.ndarray, eta: np.ndarray, period: float, t_start: float | None = None,
                        t_end: float | None = None, harmonics: int = 3) -> RegularWave:
    """Height and period of a regular wave of (nominal) ``period`` from ``eta(t)``.

    The window starts at ``t_start`` (default: the first sample) and holds the largest
    whole number of periods that ends before ``t_end`` (default: the last sample). The
    fit ``eta = c + sum_j (a_j cos j w t + b_j sin j w t)``, ``j = 1..harmonics``, is made over
    whole periods, so the harmonics are orthogonal and noise averages out; ``H = 2 sqrt(a1^2 +
    b1^2)`` is the first-harmonic height, which for a nonlinear (Stokes) wave is smaller than
    the crest-to-trough height by the bound harmonics' share.
    """
    t = np.asarray(t, dtype=float)
    eta = np.asarray(eta, dtype=float)
    sel, t0, t1, n = _whole_periods(t, period, t_start, t_end)
    ts, ys = t[sel], eta[sel]
    if len(ts) < 4 * harmonics + 2:
        raise ValueError(f"too few samples ({len(ts)}) in the window [{t0}, {t1}] s")
    omega = 2.0 * np.pi / period
    coef, _ = _harmonic_coefficients(ts - t0, ys, omega, harmonics)
    amps = np.hypot(coef[1::2], coef[2::2])
    zc = zero_crossing(ts, ys)

    # the fit leaves the least residual at the true frequency: scan, then golden section
    def amp(f: float) -> float:
        return -_harmonic_fit(ts - t0, ys, 2.0 * np.pi * f, harmonics)[1]

    f0 = 1.0 / period
    grid = np.linspace(0.8 * f0, 1.2 * f0, 161)
    vals = [amp(f) for f in grid]
    i = int(np.argmax(vals))
    a, b = grid[max(i - 1, 0)], grid[min(i + 1, len(grid) - 1)]
    ratio = (math.sqrt(5.0) - 1.0) / 2.0
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = amp(c), amp(d)
    while b - a > 1e-10 * f0:
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - ratio * (b - a)
            fc = amp(c)
        else:
            a, c, fc = c, d, fd
            d = a + ratio * (b - a)
            fd = amp(d)
    return RegularWave(H=2.0 * float(amps[0]), amplitudes=amps, H_crest_trough=_crest_trough(coef[1:]),
                       H_zero_crossing=zc.H_mean,
                       T_zero_crossing=zc.T_mean, T_fit=2.0 / (a + b), period=float(period),
                       n_periods=n, t_start=t0, t_end=t1)


# -------------------------------------------------------------------- reflection


@dataclass(frozen=True)
class Reflection:
    """Incident and reflected waves separated per frequency.

    ``f`` are the frequencies used (inside the band and not masked), ``S_i`` and ``S_r`` the
    incident and reflected variance densities there (m2/Hz), ``E_i`` and ``E_r`` their
    variances (m2), ``Kr = sqrt(E_r / E_i)``, ``Hm0_i = 4 sqrt(E_i)``, ``Hm0_r = 4 sqrt(E_r)``.
    ``f_masked`` are the frequencies of the band dropped by the conditioning criterion.
    """

    Kr: float
    E_i: float
    E_r: float
    Hm0_i: float
    Hm0_r: float
    f: np.ndarray
    S_i: np.ndarray
    S_r: np.ndarray
    f_masked: np.ndarray
    fmin: float
    fmax: float


def _complex_amplitudes(t: np.ndarray, y: np.ndarray, frequency: float, harmonics: int = 3) -> np.ndarray:
    """Complex amplitude ``Z`` (``y ~ Re[Z exp(i w t)]``) at ``frequency`` of each row of ``y``,
    fitted by least squares over the largest whole number of periods of the record, together
    with the mean and harmonics 2..``harmonics`` (orthogonal to it over whole periods)."""
    period = 1.0 / frequency
    n = int(math.floor((t[-1] - t[0]) / period + 1e-9))
    if n < 1:
        raise ValueError(f"the record ({t[-1] - t[0]} s) is shorter than one period ({period} s)")
    dt = float(t[1] - t[0])
    sel = t - t[0] < n * period - 0.5 * dt
    tau = t[sel] - t[0]
    w = 2.0 * np.pi * frequency
    cols = [np.ones_like(tau)]
    for j in range(1, harmonics + 1):
        cols += [np.cos(j * w * tau), np.sin(j * w * tau)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), y[:, sel].T, rcond=None)
    # the amplitudes refer to the time t[0] at every gauge alike
    return coef[1] - 1j * coef[2]


def _separate(t: np.ndarray, etas: Sequence[np.ndarray], xs: Sequence[float], depth: float,
              conditioned, fmin: float | None, fmax: float | None, band: tuple[float, float],
              nseg: int, window: str, frequency: float | None, g: float) -> Reflection:
    """Least-squares separation of ``Z_p = A_i exp(-i k x_p) + A_r exp(+i k x_p)``.

    With ``frequency`` the ``Z_p`` are the fitted complex amplitudes at that frequency (a
    regular wave); else the Fourier coefficients of every bin of every segment, whose
    energies averaged over the segments follow from the cross-spectral densities of the
    gauges (``scipy.signal.csd``). ``conditioned(k)`` is True where the gauge
    layout resolves the two waves.
    """
    t, y, dt = _uniform(t, np.vstack([np.asarray(e, dtype=float) for e in etas]))
    x = np.asarray(xs, dtype=float) - float(xs[0])
    if frequency is not None:
        Z = _complex_amplitudes(t, y, frequency)
        k = wavenumber(2.0 * np.pi * frequency, depth, g)
        f = np.array([float(frequency)])
        if not bool(np.all(conditioned(np.atleast_1d(k)))):
            nan = float("nan")
            return Reflection(nan, nan, nan, nan, nan, f[:0], f[:0], f[:0], f, f[0], f[0])
        M = np.column_stack([np.exp(-1j * k * x), np.exp(1j * k * x)])
        sol, *_ = np.linalg.lstsq(M, Z, rcond=None)
        E_i, E_r = 0.5 * abs(sol[0]) ** 2, 0.5 * abs(sol[1]) ** 2
        return Reflection(Kr=abs(sol[1]) / abs(sol[0]), E_i=E_i, E_r=E_r, Hm0_i=4.0 * math.sqrt(E_i),
                          Hm0_r=4.0 * math.sqrt(E_r), f=f, S_i=np.array([np.nan]), S_r=np.array([np.nan]),
                          f_masked=f[:0], fmin=f[0], fmax=f[0])
    length = _segments(y.shape[-1], nseg)
    # cross-spectral densities of every pair of gauges, C[p, q] = <conj(X_p) X_q>, one-sided
    f, C = signal.csd(y[:, None, :], y[None, :, :], fs=1.0 / dt,
                      **_welch_options(y.shape[-1], length, window))
    if fmin is None or fmax is None:
        # peak of the mean spectrum of the gauges
        S_mean = np.real(np.mean(np.diagonal(C), axis=-1))
        fp = float(f[1 + int(np.argmax(S_mean[1:]))])
        fmin = band[0] * fp if fmin is None else fmin
        fmax = band[1] * fp if fmax is None else fmax
    in_band = (f > 0) & (f >= fmin) & (f <= fmax)
    k = wavenumber(2.0 * np.pi * f, depth, g)
    ok = in_band & conditioned(k)
    S_i = np.zeros(len(f))
    S_r = np.zeros(len(f))
    for j in np.nonzero(ok)[0]:
        # A = P Z with P the least-squares inverse of the gauge layout, so that the mean
        # of |A_i|^2 over the segments is conj(P_0) C P_0 (and likewise for A_r)
        M = np.column_stack([np.exp(-1j * k[j] * x), np.exp(1j * k[j] * x)])
        P = np.linalg.pinv(M)
        S_i[j] = float(np.real(np.conj(P[0]) @ C[:, :, j] @ P[0]))
        S_r[j] = float(np.real(np.conj(P[1]) @ C[:, :, j] @ P[1]))
    df = float(f[1])
    E_i = float(np.sum(S_i[ok]) * df)
    E_r = float(np.sum(S_r[ok]) * df)
    return Reflection(Kr=math.sqrt(E_r / E_i) if E_i > 0 else float("nan"), E_i=E_i, E_r=E_r,
                      Hm0_i=4.0 * math.sqrt(E_i), Hm0_r=4.0 * math.sqrt(E_r), f=f[ok], S_i=S_i[ok],
                      S_r=S_r[ok], f_masked=f[in_band & ~ok], fmin=float(fmin), fmax=float(fmax))


def reflection_two_gauge(t: np.ndarray, eta1: np.ndarray, eta2: np.ndarray, dx: float, depth: float,
                         fmin: float | None = None, fmax: float | None = None,
                         band: tuple[float, float] = (0.5, 2.0), nseg: int = 1, window: str = "hann",
                         frequency: float | None = None, g: float = G) -> Reflection:
    """Incident and reflected waves from two gauges ``dx`` apart (Goda and Suzuki 1976).

    Gauge 2 lies ``dx > 0`` beyond gauge 1 in the direction of the incident waves. At each
    Fourier frequency, with ``k`` from linear dispersion in water ``depth`` deep, the complex
    amplitudes ``Z1 = A_i + A_r`` and ``Z2 = A_i e^{-ik dx} + A_r e^{ik dx}`` give
    ``A_i = (Z1 e^{ik dx} - Z2) / (2i sin k dx)`` and ``A_r = (Z2 - Z1 e^{-ik dx}) / (2i sin k dx)``.
    The division by ``sin k dx`` amplifies noise near ``dx/L = 0, 1/2, 1, ...``: only the
    frequencies with ``0.05 < dx/L < 0.45`` are used (the others are listed in
    ``f_masked``). ``Kr = sqrt(E_r / E_i)`` over those frequencies in ``[fmin, fmax]``; by
    default ``band`` times the peak frequency of the mean spectrum of the two gauges.

    Spectral path (``frequency`` None): the record is Hann-windowed and Fourier transformed
    whole (``nseg = 1``), or in half-overlapping segments whose energies are averaged
    (``nseg > 1``). The window keeps the energy of a component that falls between two bins
    in the next bins, where the wave number is nearly right; ``window = 'boxcar'`` is exact
    when every component is periodic in the record.

    Regular waves (``frequency`` given, Hz): the complex amplitudes at that frequency are
    fitted by least squares over whole periods (:func:`regular_wave_height`), which has no
    leakage; then ``Kr = |A_r| / |A_i|`` and the incident height is ``2 |A_i| = Hm0_i / sqrt 2``.
    """
    if dx <= 0:
        raise ValueError("dx must be positive: gauge 2 lies beyond gauge 1 in the direction of the incident waves")

    def conditioned(k: np.ndarray) -> np.ndarray:
        ratio = k * dx / (2.0 * np.pi)  # dx / L
        return (ratio > DX_OVER_L_BAND[0]) & (ratio < DX_OVER_L_BAND[1])

    return _separate(t, [eta1, eta2], [0.0, dx], depth, conditioned, fmin, fmax, band, nseg, window,
                     frequency, g)


def reflection_three_gauge(t: np.ndarray, eta1: np.ndarray, eta2: np.ndarray, eta3: np.ndarray,
                           x1: float, x2: float, x3: float, depth: float, fmin: float | None = None,
                           fmax: float | None = None, band: tuple[float, float] = (0.5, 2.0), nseg: int = 1,
                           window: str = "hann", frequency: float | None = None, g: float = G) -> Reflection:
    """Incident and reflected waves from three gauges at ``x1, x2, x3`` by least squares
    (Mansard and Funke 1980).

    At each Fourier frequency (or at ``frequency`` for a regular wave) the amplitudes
    ``A_i, A_r`` minimise ``sum_p |A_i e^{-ik x_p} + A_r e^{ik x_p} - Z_p|^2`` (incident waves
    travel towards +x). The normal equations are singular when all ``e^{2ik x_p}``
    coincide (every spacing a multiple of half a wavelength); a frequency is used when
    ``|mean_p e^{2ik x_p}| < cos(0.1 pi)``, which for two gauges is the criterion
    ``0.05 < dx/L < 0.45`` (modulo 1/2) of :func:`reflection_two_gauge`. Band, segments,
    window and ``frequency`` as there.
    """
    x = np.array([x1, x2, x3], dtype=float)
    limit = math.cos(0.1 * math.pi)

    def conditioned(k: np.ndarray) -> np.ndarray:
        mean_phase = np.abs(np.mean(np.exp(2j * np.outer(k, x - x[0])), axis=1))
        return mean_phase < limit

    return _separate(t, [eta1, eta2, eta3], list(x), depth, conditioned, fmin, fmax, band, nseg, window,
                     frequency, g)


@dataclass(frozen=True)
class DecayingWave:
    """A regular incident wave that decays along the flume and a reflected one, fitted to
    the complex first-harmonic amplitudes ``a(x)`` of gauges at ``x`` (from the paddle):
    ``a(x) = A exp(-(kappa + i k) x) + B exp(i k x)``. ``H0 = 2|A|`` is the incident height
    at ``x = 0``, ``kappa`` the decay rate of its amplitude [1/m], ``k`` the fitted wave
    number, ``Kr = |B|/|A|``; ``residual`` is the rms misfit over the gauges, as a
    fraction of ``|A|``."""

    H0: float
    kappa: float
    k: float
    Kr: float
    residual: float

    def height(self, x: float | np.ndarray) -> float | np.ndarray:
        """Height of the incident wave at ``x`` [m from the paddle]."""
        return self.H0 * np.exp(-self.kappa * np.asarray(x, dtype=float))


def _decaying_solve(x: np.ndarray, a: np.ndarray, k: float, kappa: float) -> tuple[np.ndarray, float]:
    M = np.column_stack([np.exp(-(kappa + 1j * k) * x), np.exp(1j * k * x)])
    c, *_ = np.linalg.lstsq(M, a, rcond=None)
    r = M @ c - a
    return c, float(np.real(np.vdot(r, r)))


def decaying_wave_fit(t: np.ndarray, etas: Sequence[np.ndarray], xs: Sequence[float], period: float,
                      k_guess: float, t_start: float | None = None, t_end: float | None = None) -> DecayingWave:
    """Fit :class:`DecayingWave` to records ``etas`` at ``xs`` (every record on the times
    ``t``). The first-harmonic amplitudes come from a least-squares fit (mean and three
    harmonics) over the largest whole number of periods from ``t_start`` (default: the
    first sample) that ends by ``t_end`` (default: the last sample). ``k`` is searched
    within 10 % of ``k_guess`` and ``kappa`` over -0.05 to +0.15 /m, A and B by least
    squares for each pair: a coarse grid, then two finer grids around its best point."""
    t = np.asarray(t, dtype=float)
    x = np.asarray(xs, dtype=float)
    if len(x) < 4 or len(etas) != len(x):
        raise ValueError(f"a decaying incident and a reflected wave need at least 4 gauges, not {len(x)}")
    sel, t0, _, _ = _whole_periods(t, period, t_start, t_end)
    w = 2.0 * np.pi / period
    tau = t[sel] - t0
    cols = [np.ones_like(tau)]
    for j in (1, 2, 3):
        cols += [np.cos(j * w * tau), np.sin(j * w * tau)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), np.vstack([np.asarray(e, dtype=float)[sel] for e in etas]).T,
                               rcond=None)
    a = coef[1] - 1j * coef[2]
    k_lo, k_hi, q_lo, q_hi = 0.9 * k_guess, 1.1 * k_guess, -0.05, 0.15
    best = (math.inf, k_guess, 0.0)
    for _ in range(3):
        for k in np.linspace(k_lo, k_hi, 41):
            for q in np.linspace(q_lo, q_hi, 41):
                res = _decaying_solve(x, a, float(k), float(q))[1]
                if res < best[0]:
                    best = (res, float(k), float(q))
        dk, dq = (k_hi - k_lo) / 20.0, (q_hi - q_lo) / 20.0
        k_lo, k_hi, q_lo, q_hi = best[1] - dk, best[1] + dk, best[2] - dq, best[2] + dq
    _, k, q = best
    c, res = _decaying_solve(x, a, k, q)
    return DecayingWave(H0=2.0 * abs(c[0]), kappa=q, k=k, Kr=abs(c[1]) / abs(c[0]),
                        residual=math.sqrt(res / len(x)) / abs(c[0]))


# --------------------------------------------------------------- case settings


def paddle_reflection_coefficient(t: np.ndarray, eta1: np.ndarray, eta2: np.ndarray, dx: float, depth: float,
                                  period: float) -> Reflection:
    """The reflection coefficient of a paddle at small x from two gauges dx apart in
    front of it (gauge 1 nearer the paddle): the wave going to the paddle (towards -x)
    is the incident one here, the wave leaving it the reflected one. Goda and Suzuki's
    separation at the wave's frequency (:func:`reflection_two_gauge`, whose incident
    wave runs towards +x), the roles swapped."""
    r = reflection_two_gauge(t, eta1, eta2, dx, depth, frequency=1.0 / period)
    kr = math.sqrt(r.E_i / r.E_r) if r.E_r > 0.0 else math.nan
    return Reflection(Kr=kr, E_i=r.E_r, E_r=r.E_i, Hm0_i=r.Hm0_r, Hm0_r=r.Hm0_i, f=r.f, S_i=r.S_r, S_r=r.S_i,
                      f_masked=r.f_masked, fmin=r.fmin, fmax=r.fmax)


def _group(nml, name: str):
    group = nml.get(name) if nml is not None else None
    if isinstance(group, list):
        group = group[0] if group else None
    return group


def wavemaker_settings(nml) -> dict:
    """Wave height, period and kind of the first ``&wavemaker`` group of a namelist (keys that
    are absent are left out): ``H`` (from ``h``, ``height`` or ``hs``), ``T`` (``period``, ``t``
    or ``tp``), ``regular`` (from ``kind``, ``type`` or ``wave_type``: 'regular' or not)."""
    group = _group(nml, "wavemaker")
    out: dict = {}
    if group is None:
        return out
    # the effective namelist lists every variable: height and hs are both there, one of them 0
    for key in ("h", "height", "hs", "wave_height"):
        if key in group and isinstance(group[key], (int, float)) and float(group[key]) > 0:
            out["H"] = float(group[key])
            break
    for key in ("period", "t", "tp", "wave_period"):
        if key in group and isinstance(group[key], (int, float)) and float(group[key]) > 0:
            out["T"] = float(group[key])
            break
    for key in ("kind", "type", "wave_type", "wave"):
        if key in group and isinstance(group[key], str):
            out["regular"] = group[key].strip().lower() == "regular"
            break
    return out


def measured_height(t: np.ndarray, eta: np.ndarray, regular: bool | None = None, period: float | None = None,
                    irregular_height: str = "hm0") -> tuple[float, str]:
    """The wave height of a record and how it was measured: for a regular wave the
    first-harmonic height of :func:`regular_wave_height` (period: ``period``, else the
    zero-crossing mean), else ``Hm0`` (``irregular_height = 'hm0'``) or ``H_1/3`` ('h13')."""
    if regular is None:
        regular = is_regular(t, eta)
    if regular:
        T = period if period is not None else zero_crossing(t, eta).T_mean
        return regular_wave_height(t, eta, T).H, "regular H"
    if irregular_height == "h13":
        return zero_crossing(t, eta).H_1_3, "H_1/3"
    return spectrum(t, eta).Hm0, "Hm0"


# ------------------------------------------------------------------------- CLI


def _clip(t: np.ndarray, y: np.ndarray, t0: float | None, t1: float | None) -> tuple[np.ndarray, np.ndarray]:
    sel = np.ones(len(t), dtype=bool)
    if t0 is not None:
        sel &= t >= t0
    if t1 is not None:
        sel &= t <= t1
    return t[sel], y[sel]


def _ids(text: str, count: int) -> list[int]:
    ids = [int(v) for v in text.split(",")]
    if len(ids) != count:
        raise argparse.ArgumentTypeError(f"expected {count} gauge ids separated by commas, got {text!r}")
    return ids


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", type=Path, help="output folder holding gauges.csv")
    ap.add_argument("--depth", type=float, default=None,
                    help="still water depth at the gauges (m); default: height of the first fluid &box")
    ap.add_argument("--pair", type=lambda s: _ids(s, 2), default=None,
                    help="ids i,j of two elevation gauges for Goda and Suzuki (i nearer the wavemaker)")
    ap.add_argument("--triple", type=lambda s: _ids(s, 3), default=None,
                    help="ids i,j,k of three elevation gauges for Mansard and Funke")
    ap.add_argument("--period", type=float, default=None,
                    help="period of a regular wave (s); default: &wavemaker, else the zero-crossing mean")
    ap.add_argument("--t-start", type=float, default=None, help="start of the analysed window (s)")
    ap.add_argument("--t-end", type=float, default=None, help="end of the analysed window (s)")
    ap.add_argument("--segment", type=float, default=None,
                    help="length of the Welch segments of the spectra (s); default 20 peak periods")
    ap.add_argument("--out", dest="figdir", type=Path, default=None, help="folder of the figures (default: OUT)")
    args = ap.parse_args(argv)

    gauges, time, columns = read_gauges(args.out)
    try:
        nml = read_case(args.out)
    except (FileNotFoundError, OSError):
        nml = None
    note_end(Path(args.out) / "gauges.csv", time, case_t_end(nml) if nml is not None else None)
    wm = wavemaker_settings(nml) if nml is not None else {}
    depth = args.depth
    if depth is None and nml is not None:
        box = fluid_box(nml)
        if box is not None and np.isfinite(box[3] - box[2]):
            depth = box[3] - box[2]
    period = args.period if args.period is not None else wm.get("T")
    elev = [g for g in gauges if g.kind == "elevation"]
    figdir = args.figdir if args.figdir is not None else args.out

    print(f"{'gauge':>5} {'x [m]':>8} {'H_1/3 [m]':>10} {'Hm0 [m]':>9} {'Tp [s]':>7} {'T_mean [s]':>10} "
          f"{'Hmax [m]':>9} {'waves':>5} {'regular H [m]':>13} {'T [s]':>7}")
    spectra = {}
    for g in elev:
        t, y = _clip(time, columns[g.column], args.t_start, args.t_end)
        zc = zero_crossing(t, y)
        sp = spectrum(t, y, segment=args.segment)
        spectra[g.id] = sp
        regular = wm.get("regular", is_regular(t, y)) if args.period is None else True
        reg = ""
        if regular and zc.count >= 1:
            T = period if period is not None else zc.T_mean
            try:
                rw = regular_wave_height(t, y, T)
                reg = f"{rw.H:13.5f} {rw.T_fit:7.4f}"
            except ValueError:
                reg = ""
        print(f"{g.id:5d} {g.x:8.3f} {zc.H_1_3:10.5f} {sp.Hm0:9.5f} {sp.Tp:7.4f} {zc.T_mean:10.4f} "
              f"{zc.H_max:9.5f} {zc.count:5d} {reg}")
    for g in gauges:
        if g.kind != "elevation":
            _, p = _clip(time, columns[g.column], args.t_start, args.t_end)
            print(f"pressure gauge {g.id} at ({g.x:.3f}, {g.y:.3f}) m: mean {np.mean(p):.2f} Pa, "
                  f"min {np.min(p):.2f} Pa, max {np.max(p):.2f} Pa")

    for ids in (args.pair, args.triple):
        if ids is None:
            continue
        if depth is None:
            print("reflection: give --depth (no fluid &box in case.nml)")
            return 2
        picked = [gauge_column(gauges, columns, i) for i in ids]
        t = _clip(time, picked[0][1], args.t_start, args.t_end)[0]
        ys = [_clip(time, col, args.t_start, args.t_end)[1] for _, col in picked]
        regular = args.period is not None or wm.get("regular", is_regular(t, ys[0]))
        frequency = None
        if regular:
            # the period measured at the first gauge: the fit at the true frequency has no leakage
            T = period if period is not None else zero_crossing(t, ys[0]).T_mean
            frequency = 1.0 / regular_wave_height(t, ys[0], T).T_fit
        if len(ids) == 2:
            dx = picked[1][0].x - picked[0][0].x
            r = reflection_two_gauge(t, ys[0], ys[1], dx, depth, frequency=frequency)
            method = "Goda and Suzuki (1976)"
        else:
            xs = [gc[0].x for gc in picked]
            r = reflection_three_gauge(t, *ys, *xs, depth, frequency=frequency)
            method = "Mansard and Funke (1980)"
        head = f"reflection, gauges {','.join(map(str, ids))}, {method}, depth {depth:g} m"
        if frequency is not None:
            print(f"{head}, regular wave T = {1.0 / frequency:.4f} s: Kr = {r.Kr:.4f}, H incident "
                  f"{r.Hm0_i / math.sqrt(2.0):.5f} m, reflected {r.Hm0_r / math.sqrt(2.0):.5f} m"
                  + ("" if len(r.f) else " (gauge spacing outside the conditioned band: no result)"))
        else:
            print(f"{head}, {r.fmin:.3f}-{r.fmax:.3f} Hz ({len(r.f)} bins used, {len(r.f_masked)} masked): "
                  f"Kr = {r.Kr:.4f}, Hm0 incident {r.Hm0_i:.5f} m, reflected {r.Hm0_r:.5f} m")

    if elev:
        fig, axes = plt.subplots(len(elev), 1, sharex=True, figsize=(8, 1.6 + 1.4 * len(elev)), squeeze=False)
        for ax, g in zip(axes[:, 0], elev):
            ax.plot(time, columns[g.column], lw=0.8)
            ax.axhline(0.0, color="0.6", lw=0.5)
            ax.set_ylabel("eta [m]")
            ax.set_title(f"gauge {g.id}, x = {g.x:.3f} m", fontsize=9)
        axes[-1, 0].set_xlabel("time [s]")
        fig.tight_layout()
        print(f"wrote {save_figure(fig, figdir / 'gauges.png')}")
        fig, ax = plt.subplots(figsize=(7, 4))
        for g in elev:
            sp = spectra[g.id]
            ax.plot(sp.f[1:], sp.S[1:], lw=1.0, label=f"gauge {g.id}: Hm0 {sp.Hm0:.4f} m, Tp {sp.Tp:.3f} s")
        fmax = max(4.0 / spectra[g.id].Tp for g in elev)
        ax.set_xlim(0.0, min(fmax, float(spectra[elev[0].id].f[-1])))
        ax.set_xlabel("f [Hz]")
        ax.set_ylabel("S [m$^2$/Hz]")
        ax.set_title("variance density (Welch, Hann windows)", fontsize=9)
        ax.legend(fontsize=8)
        fig.tight_layout()
        print(f"wrote {save_figure(fig, figdir / 'spectrum.png')}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.waves"))
