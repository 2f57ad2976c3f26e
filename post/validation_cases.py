"""The validation cases of the accuracy-cost studies, each defined once: its base case
file, how its geometry follows the resolution, and its error measure against its
reference (analytic or experimental).

Every error measure returns a dimensionless relative error (0.05 = 5 %) under the key
``error``, plus a few named extras that the study CSV records beside it. The measures
call the existing post-processing modules (post.hydrostatic, post.dambreak,
post.paper_cases, post.waves), so that a study and the single-run tools agree.

    from post.validation_cases import CASES
    CASES["dambreak"].measure(Path("OUT/dambreak"))   # {"error": 0.19, ...}

``python -m post.validation_cases`` lists the cases.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

import f90nml
import numpy as np

from . import dambreak, hydrostatic, waves
from . import paper_cases as pc
from .io import fluid_box, list_snapshots, read_case, read_csv, read_snapshot

__all__ = ["ValidationCase", "CASES", "groups", "wall_layers", "tank_walls"]

ROOT = Path(__file__).resolve().parent.parent


@dataclass(frozen=True)
class ValidationCase:
    """One validation case of the studies."""

    name: str
    base: str
    """base case file, relative to the repository root"""
    reference: str
    """what the run is compared with"""
    error: str
    """what the relative error measures"""
    measure: Callable[[Path], dict[str, float]]
    """output folder -> {"error": relative error, extras...}"""
    adapt: Callable[[f90nml.Namelist], None] | None = None
    """makes the geometry follow dp and h (wall thickness, spacing-defined gaps), in place"""
    length: float | None = None
    """characteristic length L: the study parameter ``resolution`` N sets dp = L / N"""
    length_name: str = ""
    targets: tuple[float, ...] = (0.2, 0.1, 0.05, 0.02, 0.01)
    """target errors of the recommendation table"""
    notes: str = field(default="", compare=False)


# ------------------------------------------------------------------ namelist helpers


def groups(nml: f90nml.Namelist, name: str) -> list[f90nml.Namelist]:
    """Every instance of a (possibly repeated) group, as a list (empty when absent)."""
    found = nml.get(name)
    if found is None:
        return []
    if isinstance(found, f90nml.Namelist):
        return [found]
    return list(found)


def wall_layers(nml: f90nml.Namelist) -> int:
    """Rows of boundary particles that cover the kernel support 2h: ceil(2 h/dp)."""
    return max(1, math.ceil(2.0 * h_over_dp_of(nml) - 1e-9))


def h_over_dp_of(nml: f90nml.Namelist) -> float:
    """The case's h/dp: its own, else the solver's default, which is 1.6 in a case with a
    wavemaker and neither bodies nor porous regions (doc/input.md, "Wave defaults") and
    sqrt 2 otherwise."""
    from post.wave_cases import WAVE_H_OVER_DP
    if "h_over_dp" in nml["numerics"]:
        return float(nml["numerics"]["h_over_dp"])
    porous = "porous" in nml or str(nml.get("breakwater", {}).get("core", "")).lower() == "porous"
    flume = "wavemaker" in nml and "body" not in nml and "armour" not in nml and not porous
    return WAVE_H_OVER_DP if flume else math.sqrt(2.0)


def _r(x: float) -> float:
    """Geometry values rounded to 12 significant digits, so the file shows 0.0219, not 0.021900000000000002."""
    return float(f"{x:.12g}")


def _widen_domain(nml: f90nml.Namelist, xmin: float, xmax: float, ymin: float, ymax: float) -> None:
    """Grow &domain so that it holds the rectangle plus one spacing."""
    dom, dp = nml["domain"], float(nml["numerics"]["dp"])
    dom["xmin"] = _r(min(float(dom["xmin"]), xmin - dp))
    dom["xmax"] = _r(max(float(dom["xmax"]), xmax + dp))
    dom["ymin"] = _r(min(float(dom["ymin"]), ymin - dp))
    dom["ymax"] = _r(max(float(dom["ymax"]), ymax + dp))


def tank_walls(nml: f90nml.Namelist) -> None:
    """A tank of three solid &box groups (floor, left and right wall): make floor and walls
    ceil(2h/dp) rows thick outwards from their inner faces, which stay where they are."""
    solids = [b for b in groups(nml, "box") if str(b.get("role", "solid")).lower() == "solid"]
    if len(solids) != 3:
        raise ValueError(f"a tank needs three solid &box groups, found {len(solids)}")
    floor = min(solids, key=lambda b: float(b["ymax"]))
    side = sorted((b for b in solids if b is not floor), key=lambda b: float(b["xmin"]))
    left, right = side
    t = wall_layers(nml) * float(nml["numerics"]["dp"])
    x_in, x_out, y_bed = float(left["xmax"]), float(right["xmin"]), float(floor["ymax"])
    left["xmin"] = floor["xmin"] = _r(x_in - t)
    right["xmax"] = floor["xmax"] = _r(x_out + t)
    floor["ymin"] = _r(y_bed - t)
    _widen_domain(nml, x_in - t, x_out + t, y_bed - t, max(float(left["ymax"]), float(right["ymax"])))


# ------------------------------------------------------------------ error measures


def tank_measure(out: Path) -> dict[str, float]:
    """Bed pressure of the still tank against rho0 g H: the linear fit of the interpolated
    mid-tank profile (post.hydrostatic), extrapolated to the bed, averaged over the
    snapshots of the last fifth of the run. Extras: the signed mean error and the mean
    fluid speed over sqrt(g H) in the last snapshot."""
    xmin, xmax, ymin, ymax = fluid_box(read_case(out))
    depth = ymax - ymin
    paths = list_snapshots(out)
    t_last = read_snapshot(paths[-1]).time
    errors = []
    snap = None
    for path in paths:
        snap = read_snapshot(path)
        if snap.time < 0.8 * t_last - 1e-9:
            continue
        ys = hydrostatic.sample_heights(snap, ymin, depth, n=10)
        fit = hydrostatic.bed_pressure(ys, hydrostatic.profile(snap, 0.5 * (xmin + xmax), ys), ymin)
        p_ref = snap.rho0 * snap.g * depth
        errors.append((fit.p_bed - p_ref) / p_ref)
    signed = float(np.mean(errors))
    speed = float(np.hypot(*snap.velocity[snap.fluid].T).mean()) / math.sqrt(snap.g * depth)
    return {"error": abs(signed), "bed_error_signed": signed, "speed_over_sqrt_gH": speed}


def dambreak_measure(out: Path) -> dict[str, float]:
    """Surge front against Martin and Moyce (1952): post.dambreak's largest relative error
    over 1 <= T <= 3. Extras: the front speed dZ/dT over the same window against the
    experiment's (relative) and the mean lead of the front in units of a."""
    box = fluid_box(read_case(out))
    a, x_wall = box[1] - box[0], box[0]
    res = dambreak.compare(out, a, x_wall)
    lo, hi = dambreak.ERROR_WINDOW
    w = (res.T >= lo - 1e-9) & (res.T <= hi + 1e-9) & np.isfinite(res.Z_exp) & np.isfinite(res.Z_sim)
    speed = lead = float("nan")
    if np.count_nonzero(w) >= 2:
        s_sim = np.polyfit(res.T[w], res.Z_sim[w], 1)[0]
        s_exp = np.polyfit(res.T[w], res.Z_exp[w], 1)[0]
        speed = float((s_sim - s_exp) / s_exp)
        lead = float(np.mean(res.Z_sim[w] - res.Z_exp[w]))
    return {"error": res.max_rel_error, "front_speed_error": speed, "lead_over_a": lead}


def _body(out: Path, number: int) -> dict[str, np.ndarray]:
    d = read_csv(out / "bodies.csv")
    m = d["body"] == number
    return {k: v[m] for k, v in d.items()}


def tc1a_measure(out: Path) -> dict[str, float]:
    """TC1a rolling cylinder: largest deviation of the centre height from rolling without
    slip, (1/3) g sin^2(alpha) t^2, over the run, relative to the analytic drop at the end.
    Extra: the error of the height at the end (m)."""
    s = _body(out, 1)
    t, y = s["time"], s["y"]
    exact = pc.tc1a_height(t)
    drop = pc.TC1A_Z0 - float(pc.tc1a_height(t[-1]))
    return {"error": float(np.max(np.abs(y - exact))) / drop, "end_error_m": float(y[-1] - exact[-1])}


def tc3_measure(out: Path) -> dict[str, float]:
    """TC3 receding discs: the left disc must stay put, the right one slides and then rolls
    (post.paper_cases.disc_slip_roll). Error: the largest over the run of the right disc's
    deviation from its analytic travel plus the left disc's displacement, relative to the
    right disc's analytic travel at the end. Extras: both parts at their largest (m)."""
    left, right = _body(out, 1), _body(out, 2)
    t = right["time"]
    travel = pc.disc_slip_roll(t, pc.TC3_U, pc.TC3_MU)[0]
    dev_r = np.abs(right["x"] - right["x"][0] - travel)
    dev_l = np.abs(left["x"] - left["x"][0])
    return {"error": float(np.max(dev_r + dev_l)) / float(travel[-1]),
            "right_deviation_m": float(dev_r.max()), "left_drift_m": float(dev_l.max())}


def tc4_measure(out: Path) -> dict[str, float]:
    """TC4 stack under still water: the vertical force on each box (fluid + contact +
    friction) over its weight, averaged over the last 0.2 s; error: the largest
    |ratio - 1| of the three boxes (the paper's figure 13). Extra: the largest vertical
    drift of a box after 0.3 s, in dp."""
    dp = float(read_case(out)["numerics"]["dp"])
    d = read_csv(out / "bodies.csv")
    worst, drift = 0.0, 0.0
    for b in np.unique(d["body"]):
        m = d["body"] == b
        s = {k: v[m] for k, v in d.items()}
        late = s["time"] >= s["time"][-1] - 0.2 - 1e-9
        vertical = s["fy_fluid"] + s["fy_contact"] + s["fy_friction"]
        ratio = float(np.mean(vertical[late] / -s["fy_gravity"][late]))
        worst = max(worst, abs(ratio - 1.0))
        settled = s["time"] >= 0.3
        if np.count_nonzero(settled) > 1:
            drift = max(drift, float(np.ptp(s["y"][settled])) / dp)
    return {"error": worst, "drift_dp": drift}


def waves_measure(out: Path) -> dict[str, float]:
    """Regular waves in a flume (post/wave_cases.py layout): the first-harmonic height at
    every elevation gauge over the last three periods of the run (post.waves), against the
    &wavemaker target height; error: the largest |H / H_target - 1|. Extras: the signed
    ratio at the first and the last gauge, and the largest relative period error."""
    target = waves.wavemaker_settings(read_case(out))
    gauges, t, cols = waves.read_gauges(out)
    ratios, period_err = [], 0.0
    for g in gauges:
        if g.kind != "elevation":
            continue
        w = waves.regular_wave_height(t, cols[g.column], target["T"], t_start=t[-1] - 3.0 * target["T"], t_end=t[-1])
        ratios.append(w.H / target["H"] - 1.0)
        period_err = max(period_err, abs(w.T_fit / target["T"] - 1.0))
    return {"error": float(np.max(np.abs(ratios))), "height_first_gauge": ratios[0],
            "height_last_gauge": ratios[-1], "period_error": period_err}


# ------------------------------------------------------------------ geometry that follows dp


def tc1a_adapt(nml: f90nml.Namelist) -> None:
    """The slope is ceil(2h/dp) rows thick."""
    for s in groups(nml, "slope"):
        s["layers"] = wall_layers(nml)


def tc3_adapt(nml: f90nml.Namelist) -> None:
    """Floor ceil(2h/dp) rows thick; the discs' boundary particles stay TC3_PARTICLE_GAP
    apart (the paper's definition), so their surfaces are that minus dp apart."""
    dp = float(nml["numerics"]["dp"])
    t = wall_layers(nml) * dp
    for b in groups(nml, "box"):
        b["ymin"] = _r(float(b["ymax"]) - t)
        _widen_domain(nml, float(b["xmin"]), float(b["xmax"]), float(b["ymin"]), float(b["ymax"]))
    bodies = groups(nml, "body")
    bodies[1]["x"] = _r(float(bodies[0]["x"]) + 2.0 * pc.TC3_R + pc.TC3_PARTICLE_GAP - dp)


def waves_adapt(nml: f90nml.Namelist) -> None:
    """Flume of post/wave_cases.py: floor and end wall ceil(2h/dp) rows thick; the paddle
    stays where the base file has it unless its rows (as thick as the walls) and the 0.1 m
    that wave_cases leaves for its stroke need more room, then it moves right by that
    (plus 1 mm); the gauges and the damping zone keep their distances from the paddle; the
    flume's end a whole number of spacings from the paddle."""
    dp = float(nml["numerics"]["dp"])
    t = wall_layers(nml) * dp
    fluid = next(b for b in groups(nml, "box") if str(b.get("role")).lower() == "fluid")
    solids = [b for b in groups(nml, "box") if str(b.get("role", "solid")).lower() == "solid"]
    floor = min(solids, key=lambda b: float(b["ymax"]))
    wall = next(b for b in solids if b is not floor)
    x0_old = float(fluid["xmin"])
    x0 = _r(max(x0_old, t + 0.1 + 1e-3))
    shift = x0 - x0_old
    x_end = _r(x0 + math.ceil((float(fluid["xmax"]) - x0_old) / dp - 1e-9) * dp)
    fluid["xmin"] = x0
    for w in groups(nml, "wavemaker"):
        w["x0"] = x0
    for g in groups(nml, "gauge"):
        g["x"] = _r(float(g["x"]) + shift)
    for d in groups(nml, "damping"):
        d["x0"] = _r(float(d["x0"]) + shift)
        d["x1"] = x_end
    fluid["xmax"] = wall["xmin"] = x_end
    wall["xmax"] = floor["xmax"] = _r(x_end + t)
    floor["ymin"] = _r(float(floor["ymax"]) - t)
    nml["domain"]["xmax"] = _r(x_end + t + 0.01)
    nml["domain"]["ymin"] = _r(float(floor["ymin"]) - 0.01)


# ------------------------------------------------------------------ the registry


CASES: dict[str, ValidationCase] = {c.name: c for c in [
    ValidationCase(
        "tank", "input/tank.nml",
        "hydrostatic bed pressure rho0 g H",
        "|p_bed - rho0 g H| / (rho0 g H), last fifth of the run",
        tank_measure, tank_walls, length=0.1, length_name="H",
        targets=(0.05, 0.02, 0.01, 0.005)),
    ValidationCase(
        "dambreak", "input/dambreak.nml",
        "surge front of Martin and Moyce (1952), n^2 = 2",
        "max |Z - Z_exp| / Z_exp over 1 <= T <= 3",
        dambreak_measure, tank_walls, length=0.146, length_name="a",
        targets=(0.2, 0.175, 0.15)),
    ValidationCase(
        "tc1a", "input/paper/tc1a_rolling_noncohesive_spring.nml",
        "rolling without slip, z = z0 - (1/3) g sin^2(alpha) t^2",
        "max |z - z_exact| over the run / analytic drop",
        tc1a_measure, tc1a_adapt, length=pc.TC1A_R, length_name="R",
        targets=(0.05, 0.02, 0.01, 0.005)),
    ValidationCase(
        "tc3", "input/paper/tc3_receding_noncohesive_spring.nml",
        "left disc at rest; right disc slides, then rolls (u0 = 2 m/s, mu = 0.2)",
        "max (|x_R - x_R,exact| + |x_L - x_L0|) over the run / analytic travel",
        tc3_measure, tc3_adapt, length=2 * pc.TC3_R, length_name="D",
        targets=(0.05, 0.01, 0.005, 0.001)),
    ValidationCase(
        "tc4", "input/paper/tc4_stack_noncohesive_spring.nml",
        "vertical force balance: fluid + contact + friction = weight",
        "max over boxes |F_y / W - 1|, last 0.2 s",
        tc4_measure, tank_walls, length=0.06, length_name="box height",
        targets=(0.01, 0.0015, 0.0001)),
    ValidationCase(
        "waves", "input/waves_regular.nml",
        "target height of the piston (Biesel), kh = 1.2, H/L = 0.03",
        "max over the gauges (2 and 2.5 L from the paddle) |H / H_target - 1|, last 3 periods",
        waves_measure, waves_adapt, length=0.25, length_name="depth",
        targets=(0.3, 0.2, 0.15, 0.1)),
]}


def main() -> int:
    for c in CASES.values():
        res = f", resolution N: dp = {c.length_name}/N ({c.length} m)" if c.length else ""
        print(f"{c.name:10s} {c.base}\n{'':10s} reference: {c.reference}\n{'':10s} error: {c.error}{res}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.validation_cases"))
