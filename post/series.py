"""Test series like a laboratory's: on one armour layer, steps of irregular (JONSWAP)
waves of rising Hs, each a restart of the last, so that the layer keeps its damage.

    python -m post.series study/series/trial.toml [--dry-run] [--ranks N] [--launcher srun]
    python -m post.series A.toml B.toml ... --overlay doc/img/damage_overlay.png

A series file (TOML)::

    [series]
    case = "input/breakwater/irregular_porous.nml"  # the base case: flume, core, armour
    out = "OUT/series/trial"          # the run's folder (default OUT/series/<file stem>)
    ranks = 1                         # MPI ranks (mpirun -np), 1: no mpirun
    settle = 1.0                      # still water before the first step [s]
    tp = 1.4                          # peak period of every step [s]
    gamma = 3.3
    waves = 100                       # waves per step (zero up-crossings expected, Tm02)
    rest = 3.0                        # still water after each step's wave [s]
    ramp_periods = 2.0                # the wave's ramps up and down, in Tp
    absorb = true                     # the paddle absorbs the waves coming back
    toe_gauges = [2.2, 2.4, 2.65]     # three elevation gauges in front of the toe [m]
    rocking_deg = 5.0                 # a unit rocks when it turns more than this and returns
    count_from = "start"              # displacement from the layer as placed, or "settle": as settled
    checkpoint_every = 0              # steps of the solver between checkpoints (0: at each end)

    [patch]                           # optional: namelist values for every step
    armour = { seed = 8 }             # e.g. another irregular placement

    [[step]]                          # one table per step, in order
    hs = 0.06                         # target Hm0 at the paddle [m]
    seed = 1                          # default: the step's number

The settling run and every step run in one output folder: step k is a restart of step
k - 1 with a new ``&wavemaker`` (``t_start`` the end of the last step, ``duration`` the
step's waves, ramped down at the end, then ``rest`` seconds of still water). The paddle
rests between steps, so the solver accepts the new wave (doc/input.md). A step whose
run ended (``step_NN.done``) is not run again, and a step that was stopped (a batch
job's time limit) continues from its last checkpoint: an interrupted series resumes.

After every step, ``<out>/series.csv`` gets one row: the step, its time window, the
incident Hm0 and H2% in front of the toe over the step's whole wave as it passes there (three gauges, Mansard and Funke's separation
with the mean still-water depth at the gauges, over 0.5 to 3 times 1/Tp; H2% by zero up-crossing of the incident
series rebuilt from the separated spectrum), the reflection coefficient, the stability
number Ns = Hm0 / (Delta dn), the units displaced by more than ``threshold`` dn since the
start of the series (cumulative: Nod of the 2D strip; with ``count_from = "settle"``
since the end of the settling run, so that a layer closing its placement gaps in still
water is not counted as damage), the units that rocked in the step
(turned by more than ``rocking_deg`` and came back within it) and the largest
displacement. ``<out>/series.png`` shows Nod against Ns; ``--overlay`` draws the curves
of several series (both placements, several seeds) on one figure from their CSVs.
"""

from __future__ import annotations

import argparse
import csv
import itertools
import math
import os
import subprocess
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import f90nml
import numpy as np

from . import armour, waves
from .io import read_csv
from .plotting import plt, save_figure

ROOT = Path(__file__).resolve().parent.parent
G = 9.81


class SeriesError(ValueError):
    pass


@dataclass
class Step:
    hs: float
    seed: int


@dataclass
class Series:
    name: str
    case: Path
    out: Path
    ranks: int = 1
    settle: float = 1.0
    tp: float = 1.4
    gamma: float = 3.3
    waves: float = 100.0
    rest: float = 3.0
    ramp_periods: float = 2.0
    absorb: bool = True
    toe_gauges: list[float] = field(default_factory=list)
    rocking_deg: float = 5.0
    count_from: str = "start"
    checkpoint_every: int = 0
    steps: list[Step] = field(default_factory=list)
    patch: dict[str, dict[str, Any]] = field(default_factory=dict)


_KEYS = {"case", "out", "ranks", "settle", "tp", "gamma", "waves", "rest", "ramp_periods", "absorb", "toe_gauges",
         "rocking_deg", "count_from", "checkpoint_every"}


def load_series(path: str | Path) -> Series:
    """Read and check a series file; errors name the file, the table and the key."""
    path = Path(path)
    with open(path, "rb") as fh:
        data = tomllib.load(fh)
    s = data.get("series")
    if not isinstance(s, dict):
        raise SeriesError(f"{path}: a [series] table is required")
    unknown = set(s) - _KEYS
    if unknown:
        raise SeriesError(f"{path}: [series]: unknown key(s) {sorted(unknown)}; allowed: {sorted(_KEYS)}")
    if "case" not in s:
        raise SeriesError(f"{path}: [series]: case (the base case file) is required")
    case = Path(s["case"])
    if not case.is_absolute():
        case = ROOT / case
    if not case.is_file():
        raise SeriesError(f"{path}: [series]: case: no file {case}")
    out = Path(s.get("out", f"OUT/series/{path.stem}"))
    ser = Series(name=path.stem, case=case, out=out if out.is_absolute() else ROOT / out)
    for key, lo, hi in (("ranks", 1, 4096), ("settle", 0.0, 1e4), ("tp", 1e-3, 1e3), ("gamma", 1.0, 20.0),
                        ("waves", 1.0, 1e6), ("rest", 0.0, 1e4), ("ramp_periods", 0.0, 100.0),
                        ("rocking_deg", 0.1, 90.0), ("checkpoint_every", 0, 10 ** 9)):
        if key in s:
            v = s[key]
            if not isinstance(v, (int, float)) or isinstance(v, bool) or not lo <= v <= hi:
                raise SeriesError(f"{path}: [series]: {key} = {v!r} is not in [{lo}, {hi}]")
            setattr(ser, key, type(getattr(ser, key))(v))
    if "absorb" in s:
        if not isinstance(s["absorb"], bool):
            raise SeriesError(f"{path}: [series]: absorb must be true or false")
        ser.absorb = s["absorb"]
    if "count_from" in s:
        if s["count_from"] not in ("start", "settle"):
            raise SeriesError(f"{path}: [series]: count_from = {s['count_from']!r}: \"start\" (the layer as "
                              f"placed) or \"settle\" (the layer at the end of the settling run)")
        ser.count_from = s["count_from"]
    ser.toe_gauges = [float(x) for x in s.get("toe_gauges", [])]
    if len(ser.toe_gauges) != 3 or sorted(ser.toe_gauges) != ser.toe_gauges:
        raise SeriesError(f"{path}: [series]: toe_gauges must be three increasing positions [m] in front of the toe")
    patch = data.get("patch", {})
    if not isinstance(patch, dict) or not all(isinstance(v, dict) for v in patch.values()):
        raise SeriesError(f"{path}: [patch]: one table per namelist group, e.g. armour = {{ seed = 8 }}")
    for group in ("run", "wavemaker"):
        if group in patch:
            raise SeriesError(f"{path}: [patch]: &{group} is the series' own; set its keys in [series]")
    ser.patch = patch
    steps = data.get("step", [])
    if not isinstance(steps, list) or not steps:
        raise SeriesError(f"{path}: at least one [[step]] table (hs, seed) is required")
    for i, st in enumerate(steps, start=1):
        hs = st.get("hs")
        if not isinstance(hs, (int, float)) or not hs > 0.0:
            raise SeriesError(f"{path}: [[step]] {i}: hs = {hs!r} must be a positive height [m]")
        seed = st.get("seed", i)
        if not isinstance(seed, int) or seed < 0:
            raise SeriesError(f"{path}: [[step]] {i}: seed = {seed!r} must be an integer >= 0")
        ser.steps.append(Step(float(hs), seed))
    return ser


def tm02_over_tp(gamma: float, f_lo: float = 0.5, f_hi: float = 3.0) -> float:
    """Tm02 / Tp of the JONSWAP spectrum (Goda's form) in the solver's band of components."""
    f = np.linspace(f_lo, f_hi, 4001)       # in units of fp
    sigma = np.where(f <= 1.0, 0.07, 0.09)
    s = f ** -5 * np.exp(-1.25 * f ** -4) * gamma ** np.exp(-((f - 1.0) ** 2) / (2.0 * sigma ** 2))
    m0 = np.trapezoid(s, f)
    m2 = np.trapezoid(s * f * f, f)
    return math.sqrt(m0 / m2)


@dataclass
class StepTimes:
    start: float      # the wave starts (paddle leaves rest) [s]
    wave_end: float   # the paddle is at rest again [s]
    end: float        # the step's run ends [s]


def schedule(ser: Series) -> list[StepTimes]:
    """The time window of every step: the wave (waves Tm02 long, ramps included), then rest."""
    duration = ser.waves * tm02_over_tp(ser.gamma) * ser.tp
    duration = max(duration, 2.0 * ser.ramp_periods * ser.tp + ser.tp)
    out, t = [], ser.settle
    for _ in ser.steps:
        out.append(StepTimes(t, t + duration, t + duration + ser.rest))
        t = t + duration + ser.rest
    return out


def step_text(ser: Series, k: int) -> str:
    """The case file of step k (0: the settling run; 1..: the steps): the base case
    patched (&run, &wavemaker) and the toe gauges it lacks added."""
    import tempfile
    times = schedule(ser)
    run = {"out_dir": str(ser.out / "run"), "progress_interval": 60.0, "checkpoint_every": ser.checkpoint_every}
    if k == 0:
        run.update(t_end=ser.settle, overwrite=True, restart=False)
        st, tt = ser.steps[0], times[0]
    else:
        st, tt = ser.steps[k - 1], times[k - 1]
        run.update(t_end=tt.end, overwrite=False, restart=True)
    wm = {"wave": "irregular", "hs": st.hs, "tp": ser.tp, "gamma": ser.gamma, "seed": st.seed,
          "t_start": tt.start, "duration": tt.wave_end - tt.start, "ramp_periods": ser.ramp_periods,
          "absorb": ser.absorb}
    base = f90nml.read(str(ser.case))
    if "wavemaker" not in base:
        raise SeriesError(f"{ser.case}: the base case has no &wavemaker group")
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "case.nml"
        f90nml.patch(str(ser.case), {**ser.patch, "run": run, "wavemaker": wm}, str(out))
        text = out.read_text()
    gauges = base.get("gauge", [])
    gauges = [gauges] if isinstance(gauges, f90nml.Namelist) else list(gauges)
    have = [float(g["x"]) for g in gauges if str(g.get("kind", "elevation")).lower() == "elevation"]
    extra = "".join(f"&gauge kind = 'elevation', x = {x} /\n" for x in ser.toe_gauges
                    if not any(abs(x - h) < 1e-9 for h in have))
    head = (f"! series '{ser.name}', step {k} of {len(ser.steps)} (0: settling), base "
            f"{ser.case.relative_to(ROOT) if ser.case.is_relative_to(ROOT) else ser.case}\n")
    return head + text + ("" if text.endswith("\n") else "\n") + extra


# ------------------------------------------------------------------ analysis


def foreshore_depth(nml, x: float) -> float:
    """Still-water depth at x in a &breakwater flume (flat, then the foreshore up to the toe depth)."""
    bw = nml["breakwater"]
    depth, toe = float(bw["depth"]), float(bw["toe_depth"])
    x_fore = float(bw["x_start"]) + float(bw.get("flat_length", 0.0))
    slope = math.tan(math.radians(float(bw["foreshore_angle"])))
    return float(min(depth, max(toe, depth - (x - x_fore) * slope)))


def travel_time(nml, x0: float, x1: float, period: float, n: int = 200) -> float:
    """Time a wave group of the given period takes from x0 to x1 over the flume's
    still-water depths (linear theory, group speed at each depth)."""
    xs = np.linspace(x0, x1, n + 1)
    omega = 2.0 * math.pi / period
    cg = []
    for x in 0.5 * (xs[1:] + xs[:-1]):
        d = foreshore_depth(nml, float(x))
        k = float(waves.wavenumber(omega, d))
        cg.append(0.5 * omega / k * (1.0 + 2.0 * k * d / math.sinh(2.0 * k * d)))
    return float(np.sum(np.diff(xs) / np.asarray(cg)))


def incident_series(t: np.ndarray, etas: Sequence[np.ndarray], xs: Sequence[float], depth: float,
                    band: tuple[float, float] = (0.5, 3.0),
                    fp: float | None = None) -> tuple[np.ndarray, np.ndarray, float, float]:
    """The incident and reflected elevations at the first gauge from three gauges (least
    squares per Fourier bin of the whole record, boxcar; bins of the band ``band`` times
    the peak frequency ``fp`` only, elsewhere 0), and their Hm0. ``fp`` defaults to the
    peak of the record, which a slow change of the level can take: give the sea's."""
    tu, y, dt = waves._uniform(t, np.vstack([np.asarray(e, float) for e in etas]))
    y = y - y.mean(axis=1, keepdims=True)
    n = y.shape[1]
    Z = np.fft.rfft(y, axis=1)
    f = np.fft.rfftfreq(n, dt)
    power = np.mean(np.abs(Z) ** 2, axis=0)
    if fp is None:
        fp = f[1 + int(np.argmax(power[1:]))]
    x = np.asarray(xs, float) - float(xs[0])
    Ai = np.zeros(len(f), complex)
    Ar = np.zeros(len(f), complex)
    for j in np.nonzero((f >= band[0] * fp) & (f <= band[1] * fp))[0]:
        k = float(waves.wavenumber(2.0 * np.pi * f[j], depth))
        M = np.column_stack([np.exp(-1j * k * x), np.exp(1j * k * x)])
        if np.linalg.cond(M) > 10.0:
            continue
        sol, *_ = np.linalg.lstsq(M, Z[:, j], rcond=None)
        Ai[j], Ar[j] = sol
    eta_i = np.fft.irfft(Ai, n)
    eta_r = np.fft.irfft(Ar, n)
    return tu, eta_i, 4.0 * float(np.std(eta_i)), 4.0 * float(np.std(eta_r))


def h2_percent(t: np.ndarray, eta: np.ndarray) -> float:
    """The height exceeded by 2 % of the zero up-crossing waves (interpolated rank)."""
    zc = waves.zero_crossing(t, eta)
    h = np.sort(np.asarray(zc.heights, float))[::-1]
    if len(h) == 0:
        return float("nan")
    return float(np.interp(0.02 * len(h), np.arange(1, len(h) + 1) - 0.5, h))


@dataclass
class StepResult:
    step: int
    hs_target: float
    seed: int
    t_start: float
    t_end: float
    Hm0_i: float
    H2_i: float
    Kr: float
    Ns: float
    displaced: int
    rocking: int
    max_disp_dn: float
    displaced_closed: int = -1
    """2D: the units farther than the threshold from the stretch of slope they could slide
    down by closing the gaps below them (closing_segments); -1 in 3D"""


def displacement_from(mo: armour.UnitMotion, t_ref: float | None) -> np.ndarray:
    """The unit's displacement at each of its rows: from where it was placed (t_ref None,
    the output's own column), or from where it stood at t_ref (its last row at or before
    it; the centre's distance, in 3D across the width too)."""
    if t_ref is None:
        return mo.displacement
    before = np.nonzero(mo.time <= t_ref + 1e-9)[0]
    if before.size == 0:
        raise SeriesError(f"body {mo.body}: no row at or before t = {t_ref} s to count its displacement from")
    k = before[-1]
    d2 = (mo.x - mo.x[k]) ** 2 + (mo.y - mo.y[k]) ** 2
    if mo.z is not None:
        d2 = d2 + (mo.z - mo.z[k]) ** 2
    return np.sqrt(d2)


def closing_segments(lay: armour.ArmourLayer) -> tuple[np.ndarray, np.ndarray] | None:
    """2D: for each unit, its centre as placed and its centre with every gap below it
    closed: the units in their order up the slope, each dn above the one below it from the
    lowest unit (which the toe holds) up, at their own distance from the slope. A 2D layer
    has its porosity as gaps along the slope, which a layer of cubes in a flume does not
    have: a unit sliding down onto its lower neighbour closes its gap without leaving the
    layer. None for a 3D layer (its units stand in slots across the width)."""
    if lay.z0 is not None:
        return None
    a = math.radians(float(lay.meta["slope_angle_deg"]))
    up = np.array([math.cos(a), math.sin(a)])
    c0 = np.column_stack([lay.x0, lay.y0])
    s = c0 @ up
    order = np.argsort(s, kind="stable")
    closed = c0.copy()
    for rank, k in enumerate(order):
        target = s[order[0]] + rank * lay.dn
        if s[k] > target:
            closed[k] = c0[k] - (s[k] - target) * up
    return c0, closed


def _segment_distance(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """The distance of point p from the segment a-b."""
    ab = b - a
    den = float(ab @ ab)
    w = 0.0 if den == 0.0 else min(max(float((p - a) @ ab) / den, 0.0), 1.0)
    return float(np.linalg.norm(p - a - w * ab))


def count_closed(motions: list[armour.UnitMotion], segments: tuple[np.ndarray, np.ndarray] | None,
                 limit: float, t_end: float) -> int:
    """The units whose centre at t_end (their last row at or before it) lies farther than
    limit [m] from the stretch between their placed and their closed-up centre
    (closing_segments); -1 without segments (3D)."""
    if segments is None:
        return -1
    c0, closed = segments
    n = 0
    for k, mo in enumerate(motions):
        upto = np.nonzero(mo.time <= t_end + 1e-9)[0]
        if upto.size == 0:
            continue
        p = np.array([mo.x[upto[-1]], mo.y[upto[-1]]])
        n += int(_segment_distance(p, c0[k], closed[k]) > limit)
    return n


def count_damage(motions: list[armour.UnitMotion], limit: float, rocking_deg: float, tt: StepTimes,
                 t_ref: float | None) -> tuple[int, int, float]:
    """Up to the end of step tt: the units whose last displacement (displacement_from
    t_ref) exceeds limit [m], the units that turned by more than rocking_deg within the
    step and came back within it, and the largest displacement [m]."""
    displaced = rocking = 0
    worst = 0.0
    for mo in motions:
        upto = mo.time <= tt.end + 1e-9
        if not np.any(upto):
            continue
        d = displacement_from(mo, t_ref)[upto]
        displaced += int(d[-1] > limit)
        worst = max(worst, float(np.max(d)))
        inside = upto & (mo.time >= tt.start - 1e-9)
        if np.any(inside):
            rot = np.degrees(mo.rotation[inside] - mo.rotation[inside][0])
            if np.max(np.abs(rot)) > rocking_deg and abs(rot[-1]) <= rocking_deg:
                rocking += 1
    return displaced, rocking, worst


def analyse_step(ser: Series, k: int) -> StepResult:
    """Waves and damage of step k (1..) from the series' output folder."""
    out = ser.out / "run"
    nml = f90nml.read(str(out / "case.nml"))
    tt = schedule(ser)[k - 1]
    gauges, time, cols = waves.read_gauges(out)
    etas = []
    for x in ser.toe_gauges:
        g = next(g for g in gauges if g.kind == "elevation" and abs(g.x - x) < 1e-6)
        etas.append(cols[g.column])
    # the step's whole wave as it passes the toe gauges: the paddle's record shifted by
    # the travel time at the group speed of Tp over the flume's depths
    travel = travel_time(nml, float(nml["wavemaker"]["x0"]) if "x0" in nml["wavemaker"] else
                         float(nml["breakwater"]["x_start"]), ser.toe_gauges[0], ser.tp)
    m = (time >= tt.start + travel) & (time <= tt.wave_end + travel)
    depth = float(np.mean([foreshore_depth(nml, x) for x in ser.toe_gauges]))
    ok = m & np.all(np.isfinite(np.vstack(etas)), axis=0)
    if ok.sum() < 64:
        raise SeriesError(f"{out}/gauges.csv: too few samples of step {k} at the toe gauges")
    tu, eta_i, hm0_i, hm0_r = incident_series(time[ok], [e[ok] for e in etas], ser.toe_gauges, depth,
                                              fp=1.0 / ser.tp)
    lay = armour.read_armour(out)
    bodies = read_csv(out / "bodies.csv")
    rho_w = float(lay.meta.get("rho_water", 1000.0))
    ns = armour.stability_number(hm0_i, lay.dn, float(lay.meta["density"]), rho_w)
    t_ref = ser.settle if ser.count_from == "settle" else None
    motions = [armour.unit_motion(bodies, int(b)) for b in lay.body]
    displaced, rocking, worst = count_damage(motions, lay.threshold * lay.dn, ser.rocking_deg, tt, t_ref)
    closed = count_closed(motions, closing_segments(lay), lay.threshold * lay.dn, tt.end)
    return StepResult(k, ser.steps[k - 1].hs, ser.steps[k - 1].seed, tt.start, tt.end, hm0_i, h2_percent(tu, eta_i),
                      hm0_r / hm0_i if hm0_i > 0 else float("nan"), ns, displaced, rocking, worst / lay.dn, closed)


_COLS = ["step", "hs_target", "seed", "t_start", "t_end", "Hm0_i", "H2_i", "Kr", "Ns", "displaced", "rocking",
         "max_disp_dn", "displaced_closed"]


def write_csv(ser: Series, rows: list[StepResult]) -> Path:
    path = ser.out / "series.csv"
    with open(path, "w", newline="") as fh:
        w = csv.writer(fh)
        w.writerow(_COLS)
        for r in rows:
            w.writerow([getattr(r, c) if not isinstance(getattr(r, c), float) else f"{getattr(r, c):.6g}"
                        for c in _COLS])
    return path


def _laboratory(ax) -> None:
    """The axes of a damage curve and the laboratory's marks: Van Gent's (2003) ranges of
    start of damage and failure, Van Buchem's (2009) one unit at Ns = 5."""
    lab = armour.LAB_RANGES
    ax.axvspan(*lab["start_of_damage"]["Ns"], color="tab:green", alpha=0.2, label="start of damage (Van Gent 2003)")
    ax.axvspan(*lab["failure"]["Ns"], color="tab:red", alpha=0.2, label="failure (Van Gent 2003)")
    ax.plot([5.0], [1.0], "k*", ms=10, label="Van Buchem (2009): one unit")
    ax.set_xlabel("Ns = Hm0 / (Delta dn), incident at the toe")
    ax.set_ylabel("Nod (units displaced > threshold dn)")


def plot(ser: Series, rows: list[StepResult]) -> Path:
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    ns = [r.Ns for r in rows]
    nod = [r.displaced for r in rows]
    ax.plot(ns, nod, "o-", label=f"{ser.name} (cumulative)")
    if all(r.displaced_closed >= 0 for r in rows):
        ax.plot(ns, [r.displaced_closed for r in rows], "s--", color="tab:gray",
                label="beyond the gaps below them (2D)")
    _laboratory(ax)
    # the double-layer cube formula for contrast, at the series' waves so far and mean period
    lay = armour.read_armour(ser.out / "run")
    delta = float(lay.meta["density"]) / float(lay.meta.get("rho_water", 1000.0)) - 1.0
    tm = tm02_over_tp(ser.gamma) * ser.tp
    grid = np.linspace(1.0, max(6.0, max(ns) + 0.5 if ns else 6.0), 200)
    s_om = 2.0 * math.pi * grid * delta * lay.dn / (G * tm * tm)
    n_total = ser.waves * len(rows)
    ax.plot(grid, armour.van_der_meer_cubes_nod(grid, n_total, s_om), "k--", lw=1,
            label=f"Van der Meer (1988), double layer, N = {n_total:g}")
    ax.set_ylim(bottom=-0.2, top=max(3.0, max(nod) + 1.0 if nod else 3.0))
    ax.legend(fontsize=8)
    return save_figure(fig, ser.out / "series.png")


def placement_label(ser: Series) -> str:
    """The layer a series tests: the base case's &armour placement and seed, with the
    series' [patch] over them."""
    arm = dict(f90nml.read(str(ser.case)).get("armour", {}))
    arm.update({k.lower(): v for k, v in ser.patch.get("armour", {}).items()})
    placement = str(arm.get("placement", "regular"))
    # the seed places the units of the irregular placement only
    return f"{placement} placement" + (f", seed {arm.get('seed', 1)}" if placement == "irregular" else "")


def overlay_data(sers: Sequence[Series]) -> list[tuple[str, np.ndarray, np.ndarray]]:
    """(label, Ns, Nod) of every series from its series.csv, in the order given."""
    data = []
    for ser in sers:
        path = ser.out / "series.csv"
        if not path.is_file():
            raise SeriesError(f"{path}: no such file: run the series {ser.name} first")
        rows = read_csv(path)
        data.append((f"{ser.name}: {placement_label(ser)}", np.asarray(rows["Ns"], float),
                     np.asarray(rows["displaced"], float)))
    return data


def plot_overlay(sers: Sequence[Series], path: Path) -> Path:
    """Nod against Ns of several series on one figure (placements, seeds), with the
    laboratory's ranges: the spread between seeds is the answer's uncertainty."""
    fig, ax = plt.subplots(figsize=(6.0, 4.2))
    _laboratory(ax)
    top = 3.0
    for (label, ns, nod), marker in zip(overlay_data(sers), itertools.cycle("osD^v<>ph")):
        ax.plot(ns, nod, marker + "-", label=label)
        top = max(top, float(np.max(nod)) + 1.0 if nod.size else top)
    ax.set_ylim(bottom=-0.2, top=top)
    ax.legend(fontsize=8)
    return save_figure(fig, path)


# ------------------------------------------------------------------ running


def _launch(ser: Series, binary: Path, case: Path, launcher: str) -> list[str]:
    """The command of one step: the binary alone (one rank), under mpirun (as the
    Makefile's MPIRUN: Open MPI refuses root without the flag), or under another
    launcher given whole (srun in a SLURM job takes the job's tasks)."""
    cmd = [str(binary), str(case)]
    if launcher != "mpirun":
        return launcher.split() + cmd
    if ser.ranks <= 1:
        return cmd
    root = ["--allow-run-as-root"] if os.geteuid() == 0 else []
    return ["mpirun", *root, "--oversubscribe", "-np", str(ser.ranks)] + cmd


def run_series(ser: Series, binary: Path, dry_run: bool = False, launcher: str = "mpirun") -> list[StepResult]:
    ser.out.mkdir(parents=True, exist_ok=True)
    rows: list[StepResult] = []
    for k in range(len(ser.steps) + 1):
        case = ser.out / f"step_{k:02d}.nml"
        text = step_text(ser, k)
        done = ser.out / f"step_{k:02d}.done"
        if done.is_file() and case.is_file() and case.read_text() == text:
            print(f"step {k}: done before, kept", flush=True)
        else:
            case.write_text(text)
            if dry_run:
                print(f"step {k}: {case} written (dry run)")
                continue
            cmd = _launch(ser, binary, case, launcher)
            print(f"step {k}: {' '.join(cmd)}", flush=True)
            with open(ser.out / f"step_{k:02d}.log", "w") as log:
                proc = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT)
            if proc.returncode != 0:
                raise SeriesError(f"step {k} stopped with exit status {proc.returncode}: see "
                                  f"{ser.out / f'step_{k:02d}.log'}")
            done.write_text("")
        if k > 0:
            r = analyse_step(ser, k)
            rows.append(r)
            print(f"step {k}: Hm0_i {r.Hm0_i:.4f} m, H2% {r.H2_i:.4f} m, Kr {r.Kr:.2f}, Ns {r.Ns:.2f}, "
                  f"displaced {r.displaced} ({r.displaced_closed} beyond the gaps below them), rocking {r.rocking}, "
                  f"largest {r.max_disp_dn:.2f} dn", flush=True)
            write_csv(ser, rows)
    if rows:
        plot(ser, rows)
    return rows


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("series", type=Path, nargs="+", help="series file(s); several with --overlay")
    ap.add_argument("--overlay", type=Path, default=None, metavar="PNG",
                    help="no runs: draw Nod against Ns of the series given (their series.csv) on one figure")
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "mbsph")
    ap.add_argument("--dry-run", action="store_true", help="write the step case files only")
    ap.add_argument("--ranks", type=int, default=None, help="MPI ranks (instead of the file's ranks)")
    ap.add_argument("--launcher", default="mpirun",
                    help="'mpirun' (default: mpirun -np ranks) or a launcher command given whole, e.g. 'srun'")
    a = ap.parse_args(argv)
    try:
        if a.overlay is not None:
            print(plot_overlay([load_series(p) for p in a.series], a.overlay))
            return 0
        if len(a.series) != 1:
            raise SeriesError("one series file at a time (several only with --overlay)")
        ser = load_series(a.series[0])
        if a.ranks is not None:
            ser.ranks = a.ranks
        run_series(ser, a.binary, a.dry_run, a.launcher)
    except SeriesError as e:
        print(f"post.series: error: {e}", file=sys.stderr)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())


__all__: list[Any] = ["Series", "Step", "load_series", "schedule", "step_text", "incident_series", "h2_percent",
                      "displacement_from", "count_damage", "closing_segments", "count_closed", "analyse_step", "run_series", "overlay_data", "plot_overlay", "main"]
