"""Verdicts of the stability cases (input/stability/*.nml, run by `make stability`).

Each case file states its pass criteria twice: in words in its comment block, and on a
line ``! pass: name op value, ...`` that this module reads (op one of <=, >=, ==). An
optional ``! report: name, ...`` line names figures shown without a bar. The names are
the figures measured on a run folder:

- ``penetration_dp``: largest interpenetration of two solid surfaces (energy.csv
  ``max_penetration``) in dp;
- ``energy_gain_rel``: largest rise of the bodies' kinetic plus potential energy over
  the start, over the start (energy.csv);
- ``creep_dp``: largest travel (x range plus y range) of a body over the last fifth of
  the run, in dp (bodies.csv);
- ``lost``: fluid particles removed by the end (energy.csv);
- ``pressure_noise``: standard deviation over time of the first pressure gauge
  (gauges.csv) after t = 10 sqrt(H/g), over rho0 g H (H = ``&fluid h_swl``);
- ``ke_growth``: mean kinetic energy of the fluid over the last quarter of the run over
  its mean over the second quarter;
- ``crossed``: body particles whose centre lies inside the rectangle spanned by the
  particle centres of a fixed ``&box`` solid, summed over the snapshots: a body that
  passed into or through a wall;
- ``armour_move_dn``: largest distance of an armour unit's centre from where it was at
  t = 0.5 s, later in the run, in dn (armour.csv, bodies.csv);
- ``body_move_dn``, ``body_turn_deg``: largest distance of the first body's centre
  from where it was at t = 0.5 s, later in the run, over its width, and the largest
  angle it turned from then (bodies.csv);
- ``draft_error_dp``: |draft - Archimedes' draft| / dp of the first floating box in
  the first fluid ``&box``, the draft being the water level (fluid volume sum m/rho
  plus the submerged part of the body, over the tank width) minus the body's bottom,
  averaged over the snapshots of the second half of the run;
- ``dt_ratio``: largest ratio of the time step taken to the CFL limit of a state it
  reached (its middle and its end: the fluid's acoustic-viscous and force limits, the
  bodies' acceleration and motion limits), from the solver's summary in run.log;
- ``dt_ratio_contact``: the same against every limit of the step, the contacts'
  stiffness and approach limits too (run.log, cases with bodies);
- ``exit_status``: the solver's exit status, from ``exit_status`` in the run folder
  (written by `make stability` and by the tests);
- ``refused_fixed_step``: 1 when run.log holds the solver's refusal of a fixed step
  above the stable one, else 0;
- ``bad_values_in_output``: particles with a NaN or infinite position, velocity,
  density or pressure, or a fluid density outside the removal limits, summed over the
  snapshots.

A figure that cannot be measured (no such output) is NaN and fails its bar. Each run
gets a one-line verdict, printed and written to ``verdict.txt`` in its folder; a
Markdown table goes to --table (replacing the file up to its notes marker; the
hand-written notes after the marker are kept).

    .venv/bin/python -m post.stability OUT/stability/* [--table doc/stability.md]
"""
from __future__ import annotations

import argparse
import math
import re
from pathlib import Path

import f90nml
import numpy as np

from post.io import list_snapshots, read_case, read_csv, read_snapshot

_CRITERION = re.compile(r"^\s*([a-z_]+)\s*(<=|>=|==)\s*([-+0-9.eE]+)\s*$")
_RATIO = re.compile(r"largest dt / CFL limit of a state it reached\s+([0-9.eE+-]+)")
_WALL = re.compile(r"particle-steps in\s+([0-9.eE+-]+) s")
_RATIO_CONTACT = re.compile(r"largest dt / every limit, contacts too, of a state it reached\s+([0-9.eE+-]+)")
_REFUSED = "is above the stable step"
#: units of the figures in the table
UNITS = {"penetration_dp": "dp", "creep_dp": "dp", "draft_error_dp": "dp", "armour_move_dn": "dn",
         "pressure_noise": "of rho g H", "energy_gain_rel": "of the start"}


def _groups(nml: f90nml.Namelist, name: str) -> list:
    g = nml.get(name)
    if g is None:
        return []
    return [g] if isinstance(g, f90nml.Namelist) else list(g)


def source_of(out: Path) -> Path | None:
    """The case file a run came from: the first line of its case.nml names it
    (relative to the folder the solver ran in: tried as given, then beside the run)."""
    try:
        first = (out / "case.nml").read_text().splitlines()[0]
    except (OSError, IndexError):
        return None
    m = re.search(r"read from (\S+)\s*$", first)
    if not m:
        return None
    for cand in (Path(m.group(1)), out.parent / Path(m.group(1)).name):
        if cand.is_file():
            return cand
    return None


def criteria(case_file: Path) -> tuple[list[tuple[str, str, float]], list[str]]:
    """The ``! pass:`` criteria (name, op, value) and the ``! report:`` names of a case file."""
    bars: list[tuple[str, str, float]] = []
    report: list[str] = []
    for line in case_file.read_text().splitlines():
        s = line.strip()
        if s.startswith("! pass:"):
            for item in s[len("! pass:"):].split(","):
                m = _CRITERION.match(item)
                if not m:
                    raise ValueError(f"{case_file}: cannot read the criterion {item.strip()!r}")
                bars.append((m.group(1), m.group(2), float(m.group(3))))
        elif s.startswith("! report:"):
            report += [n.strip() for n in s[len("! report:"):].split(",") if n.strip()]
    if not bars:
        raise ValueError(f"{case_file}: no '! pass:' line")
    return bars, report


def _energy(out: Path) -> dict | None:
    return read_csv(out / "energy.csv") if (out / "energy.csv").is_file() else None


def _bodies(out: Path) -> dict | None:
    return read_csv(out / "bodies.csv") if (out / "bodies.csv").is_file() else None


def penetration_dp(out: Path, nml) -> float:
    e = _energy(out)
    return float(np.max(e["max_penetration"])) / float(nml["numerics"]["dp"]) if e else math.nan


def energy_gain_rel(out: Path, nml) -> float:
    e = _energy(out)
    if not e:
        return math.nan
    total = e["body_kinetic"] + e["body_potential"]
    return float(np.max(total - total[0])) / max(abs(float(total[0])), 1e-300)


def creep_dp(out: Path, nml) -> float:
    b = _bodies(out)
    if not b:
        return math.nan
    creep = 0.0
    settle = 0.8 * float(b["time"][-1])
    for k in np.unique(b["body"]):
        m = (b["body"] == k) & (b["time"] >= settle)
        if np.count_nonzero(m) > 1:
            creep = max(creep, float(np.ptp(b["x"][m]) + np.ptp(b["y"][m])))
    return creep / float(nml["numerics"]["dp"])


def lost(out: Path, nml) -> float:
    e = _energy(out)
    return float(e["lost"][-1]) if e else math.nan


def _fluid(nml) -> tuple[float, float, float]:
    f = nml.get("fluid", {})
    return float(f.get("rho0", 1000.0)), float(f.get("gravity", 9.81)), float(f.get("h_swl", 0.0))


def pressure_noise(out: Path, nml) -> float:
    from post.waves import read_gauges
    if not (out / "gauges.csv").is_file():
        return math.nan
    _, t, columns = read_gauges(out)
    cols = [n for n in columns if n.startswith("p_")]
    rho0, g, depth = _fluid(nml)
    if not cols or depth <= 0.0 or len(t) < 2:
        return math.nan
    keep = t > 10.0 * math.sqrt(depth / g)
    return float(np.std(columns[cols[0]][keep])) / (rho0 * g * depth) if np.count_nonzero(keep) > 1 else math.nan


def ke_growth(out: Path, nml) -> float:
    e = _energy(out)
    if not e:
        return math.nan
    t, k = e["time"], e["kinetic"]
    end = float(t[-1])
    second = k[(t >= 0.25 * end) & (t < 0.5 * end)]
    last = k[t >= 0.75 * end]
    if len(second) == 0 or len(last) == 0:
        return math.nan
    return float(np.mean(last)) / max(float(np.mean(second)), 1e-300)


def crossed(out: Path, nml) -> float:
    n_box = sum(1 for g in _groups(nml, "box"))
    boxes = [k + 1 for k, g in enumerate(_groups(nml, "box"))
             if str(g.get("role", "solid")).strip().lower() == "solid"]
    snaps = list_snapshots(out)
    if not snaps or n_box == 0:
        return math.nan
    count = 0
    for path in snaps:
        s = read_snapshot(path)
        body = s.position[s.kind == 4]
        for k in boxes:
            wall = s.position[(s.body == k) & (s.kind == 2)]
            if len(wall) == 0:
                continue
            lo, hi = wall.min(axis=0), wall.max(axis=0)
            inside = np.all((body > lo + 1e-9) & (body < hi - 1e-9), axis=1)
            count += int(np.count_nonzero(inside))
    return float(count)


def armour_move_dn(out: Path, nml) -> float:
    from post.armour import read_armour
    b = _bodies(out)
    if not b or not (out / "armour.csv").is_file():
        return math.nan
    lay = read_armour(out)
    move = 0.0
    for k in lay.body:
        m = b["body"] == k
        t, x, y = b["time"][m], b["x"][m], b["y"][m]
        i = int(np.argmin(np.abs(t - 0.5)))
        move = max(move, float(np.hypot(x[i:] - x[i], y[i:] - y[i]).max()))
    return move / lay.dn


def _body_after(out: Path, t0: float = 0.5):
    """Time, x, y and angle of body 1 from the sample nearest t0 on (bodies.csv)."""
    b = _bodies(out)
    if not b:
        return None
    m = b["body"] == 1
    t = b["time"][m]
    i = int(np.argmin(np.abs(t - t0)))
    return t[i:], b["x"][m][i:], b["y"][m][i:], b["angle"][m][i:]


def body_move_dn(out: Path, nml) -> float:
    s = _body_after(out)
    bodies = _groups(nml, "body")
    if s is None or not bodies:
        return math.nan
    _, x, y, _ = s
    return float(np.hypot(x - x[0], y - y[0]).max()) / float(bodies[0]["width"])


def body_turn_deg(out: Path, nml) -> float:
    s = _body_after(out)
    return float(np.degrees(np.abs(s[3] - s[3][0]).max())) if s is not None else math.nan


def draft_error_dp(out: Path, nml) -> float:
    b = _bodies(out)
    boxes = [g for g in _groups(nml, "box") if str(g.get("role", "")).strip().lower() == "fluid"]
    bodies = _groups(nml, "body")
    snaps = list_snapshots(out)
    if not b or not boxes or not bodies or not snaps:
        return math.nan
    tank, body = boxes[0], bodies[0]
    width = float(tank["xmax"]) - float(tank["xmin"])
    bed = float(tank["ymin"])
    bw, bh, rho_b = float(body["width"]), float(body["height"]), float(body["density"])
    rho0, _, _ = _fluid(nml)
    dp = float(nml["numerics"]["dp"])
    t_end = float(b["time"][-1])
    drafts = []
    for path in snaps:
        s = read_snapshot(path)
        if s.time < 0.5 * t_end - 1e-9:
            continue
        m = b["body"] == 1
        j = int(np.argmin(np.abs(b["time"][m] - s.time)))
        bottom = float(b["y"][m][j]) - 0.5 * bh
        volume = float(np.sum(s.volume[s.fluid]))
        # level L = bed + (V + d bw) / width with d = L - bottom
        drafts.append((bed + volume / width - bottom) / (1.0 - bw / width))
    if not drafts:
        return math.nan
    return abs(float(np.mean(drafts)) - rho_b / rho0 * bh) / dp


def _log_figure(out: Path, pattern: re.Pattern) -> float:
    path = out / "run.log"
    m = pattern.search(path.read_text()) if path.is_file() else None
    return float(m.group(1)) if m else math.nan


def dt_ratio(out: Path, nml) -> float:
    return _log_figure(out, _RATIO)


def dt_ratio_contact(out: Path, nml) -> float:
    return _log_figure(out, _RATIO_CONTACT)


def exit_status(out: Path, nml) -> float:
    path = out / "exit_status"
    return float(path.read_text().strip()) if path.is_file() else math.nan


def refused_fixed_step(out: Path, nml) -> float:
    text = "".join(p.read_text() for p in (out / "run.log", out / "stderr") if p.is_file())
    return 1.0 if _REFUSED in text else 0.0


def bad_values_in_output(out: Path, nml) -> float:
    snaps = list_snapshots(out)
    if not snaps:
        return math.nan
    f = nml.get("fluid", {})
    rho0 = float(f.get("rho0", 1000.0))
    lo, hi = float(f.get("rho_min", 0.7)) * rho0, float(f.get("rho_max", 1.3)) * rho0
    bad = 0
    for path in snaps:
        s = read_snapshot(path)
        finite = (np.all(np.isfinite(s.position), axis=1) & np.all(np.isfinite(s.velocity), axis=1)
                  & np.isfinite(s.density) & np.isfinite(s.pressure))
        wild = s.fluid & ((s.density < lo) | (s.density > hi))
        bad += int(np.count_nonzero(~finite | wild))
    return float(bad)


MEASURES = {f.__name__: f for f in (penetration_dp, energy_gain_rel, creep_dp, lost, pressure_noise, ke_growth,
                                    crossed, armour_move_dn, body_move_dn, body_turn_deg, draft_error_dp,
                                    dt_ratio, dt_ratio_contact, exit_status, refused_fixed_step,
                                    bad_values_in_output)}


def _holds(value: float, op: str, bar: float) -> bool:
    if not math.isfinite(value):
        return False
    return {"<=": value <= bar, ">=": value >= bar, "==": value == bar}[op]


def verdict(out: Path, case_file: Path | None = None) -> dict:
    """Measure the figures a case's criteria name on its run folder and judge them."""
    out = Path(out)
    case_file = case_file or source_of(out)
    if case_file is None:
        raise FileNotFoundError(f"{out}: cannot find the case file the run came from")
    bars, report = criteria(case_file)
    nml = read_case(out)
    names = [n for n, _, _ in bars] + [n for n in report if n not in [b[0] for b in bars]]
    values = {n: MEASURES[n](out, nml) for n in names}
    checks = [(n, op, bar, _holds(values[n], op, bar)) for n, op, bar in bars]
    e = _energy(out)
    wall = _log_figure(out, _WALL)
    return {"case": out.name, "t_end": float(e["time"][-1]) if e else math.nan, "wall_s": wall, "values": values,
            "checks": checks, "report": report, "pass": all(c[3] for c in checks)}


def _fmt(v: float) -> str:
    if not math.isfinite(v):
        return "n/a"
    if v == int(v) and abs(v) < 1e6:
        return str(int(v))
    return f"{v:.3g}"


def line(v: dict) -> str:
    """The one-line verdict of a run."""
    parts = [f"{n} {_fmt(v['values'][n])} ({op} {_fmt(bar)}{'' if ok else ': FAILS'})"
             for n, op, bar, ok in v["checks"]]
    parts += [f"{n} {_fmt(v['values'][n])} (reported)" for n in v["report"]
              if n not in [c[0] for c in v["checks"]]]
    return f"{v['case']}: {'pass' if v['pass'] else 'FAIL'}: " + ", ".join(parts)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", type=Path, nargs="+")
    ap.add_argument("--table", type=Path, default=None)
    args = ap.parse_args(argv)
    runs = [r for r in sorted(args.runs) if (r / "case.nml").is_file()]
    if not runs:
        raise FileNotFoundError(2, "no such file", str(args.runs[0] / "case.nml"))
    for r in [r for r in runs if source_of(r) is None]:
        print(f"{r.name}: skipped: the case file it came from is gone")
    runs = [r for r in runs if source_of(r) is not None]
    rows = [verdict(r) for r in runs]
    table = ["| case | simulated [s] | solver wall [s] | criteria: measured (bar) | verdict |",
             "|---|---|---|---|---|"]
    for r, v in zip(runs, rows):
        text = line(v)
        print(text)
        (r / "verdict.txt").write_text(text + "\n")
        cells = "; ".join(f"{n} {_fmt(v['values'][n])} ({op} {_fmt(bar)})" for n, op, bar, _ in v["checks"])
        extra = [n for n in v["report"] if n not in [c[0] for c in v["checks"]]]
        if extra:
            cells += "; reported: " + "; ".join(f"{n} {_fmt(v['values'][n])}" for n in extra)
        wall = f"{v['wall_s']:.1f}" if math.isfinite(v["wall_s"]) else "-"
        table.append(f"| {v['case']} | {_fmt(v['t_end'])} | {wall} | {cells} | {'pass' if v['pass'] else 'FAIL'} |")
    if args.table:
        # hand-written notes below the marker survive the regeneration
        notes = ""
        if args.table.is_file() and NOTES in args.table.read_text():
            notes = args.table.read_text().split(NOTES, 1)[1]
        args.table.write_text(TABLE_HEAD + "\n".join(table) + "\n\n" + NOTES + notes)
    return 0 if all(v["pass"] for v in rows) else 1


NOTES = "<!-- notes: kept when the table above is regenerated -->"
TABLE_HEAD = """# Stability of hard cases

Made by `make stability`: every case of input/stability/ run on one rank, then
`.venv/bin/python -m post.stability OUT/stability/* --table doc/stability.md`. Each case
file states in its comment block what it checks and why, and on its `! pass:` line the
bars this table applies; the figures are defined in post/stability.py. Solver wall:
the time loop's wall time (the `cost:` line of run.log), one rank of a shared 2-core
machine. A coarse subset (shorter or coarser runs, the same bars) runs in `make test`
(tests/test_stability.py).

"""


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.stability"))
