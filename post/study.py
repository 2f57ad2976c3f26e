"""Accuracy against cost: run a validation case over a set of parameter values.

    python -m post.study STUDY.toml [STUDY2.toml ...] [--workers N] [--nice N]
                                    [--doc doc/accuracy-cost.md] [--img doc/img] [--dry-run]

A study file (TOML) names a validation case of post/validation_cases.py (its base case
file, its error measure against the reference, its geometry that follows dp) and the
values to try::

    [study]
    case = "dambreak"            # a key of post.validation_cases.CASES
    base = "input/dambreak.nml"  # optional: another base case file
    combine = "factorial"        # every combination, or "zip" (the i-th value of each)
    workers = 0                  # runs at a time; 0: cores / ranks
    ranks = 1                    # MPI ranks per run (mpirun -np), 1: no mpirun
    out = "OUT/study/NAME"       # default OUT/study/<file stem>

    [set]                        # values for every run
    "run.t_end" = 0.3

    [parameters]                 # lists of values
    dp = [0.0073, 0.00365]
    kernel = ["wendland", "cubic"]

A parameter is a short name (dp, h_over_dp, kernel, integrator, cfl, viscosity, alpha,
nu, diffusion, delta, kernel_correction, shepard_every, verlet_every, boundary: &numerics;
contact: &contact model; t_end: &run), ``resolution`` (dp = L/N with the case's length
L), or any namelist variable as ``group.variable`` (every instance of a repeated
group) or ``group[i].variable`` (its i-th instance, from 1).

Each run gets its own folder ``<out>/<name from its values>/`` holding ``case.nml``,
the solver's output ``out/``, ``stdout.txt`` and ``result.json``. A run whose
``result.json`` exists, whose case file is unchanged and which the same build of the
solver made (SHA-256 of the binary) is not run again, so an interrupted study resumes
where it stopped; ``--retry-failed`` reruns the runs that failed, ``--any-binary`` keeps
runs of another build. Per run the CSV ``<out>/results.csv`` records the parameters, the error and its
extras, particles, steps, the solver's wall time and phase times (run.log), the
microseconds per particle-step, the process's elapsed and CPU time and the solver's peak
resident memory (ru_maxrss, through /usr/bin/time). Figures: ``<out>/error_cost.png``
(error against the cost, log-log, the Pareto front marked; the cost is the wall time, or
the CPU time with ``--cost cpu_s``) and, when dp varies, ``<out>/error_dp.png`` (error
against dp, with the observed order of convergence fitted per line).

``--doc FILE`` replaces, in FILE, the text between ``<!-- study:NAME -->`` and
``<!-- /study:NAME -->`` with the table of study NAME (the TOML stem), and between
``<!-- study:recommend -->`` and ``<!-- /study:recommend -->`` with the cheapest run of
every case for each of its target errors over all the studies given and the finished
studies beside them, and between ``<!-- study:side:PARAM -->`` and
``<!-- /study:side:PARAM -->`` with the studies whose only parameter is PARAM side by
side, and between ``<!-- study:total -->`` and ``<!-- /study:total -->`` with the count
of runs and their CPU time; ``--img DIR``
copies the figures to ``DIR/study_NAME_*.png``.
"""
from __future__ import annotations

import argparse
import csv
import hashlib
import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import threading
import time
import tomllib
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Sequence

import f90nml
import numpy as np

from .validation_cases import CASES, ValidationCase

__all__ = ["Study", "load_study", "expand", "case_text", "parse_log", "pareto_front", "observed_order",
           "run_study", "main", "ALIASES", "CSV_COLUMNS"]

ROOT = Path(__file__).resolve().parent.parent

#: short parameter names and the namelist variable they set
ALIASES = {name: ("numerics", name) for name in (
    "dp", "h_over_dp", "kernel", "integrator", "cfl", "viscosity", "alpha", "nu", "cs_sps", "ci_sps",
    "diffusion", "delta", "kernel_correction", "shepard_every", "verlet_every", "boundary")}
ALIASES.update({"contact": ("contact", "model"), "t_end": ("run", "t_end")})

#: the cost axis of the figures, the Pareto front and the recommendation: the solver's
#: wall time of its time loop ("wall_s") or the process's CPU time ("cpu_s", which other
#: processes on a shared machine do not inflate)
COST = {"wall_s": "wall time of the run (s)", "cpu_s": "CPU time of the run (s)"}

#: columns of results.csv after the parameters and before the error extras
CSV_COLUMNS = ["run", "status", "error", "particles", "steps", "t_reached", "lost", "wall_s",
               "us_per_particle_step", "elapsed_s", "cpu_s", "peak_rss_mb", "setup_s", "grid_s", "pair_loop_s",
               "bodies_s", "integrate_s", "output_s", "comm_s", "solver"]


@dataclass
class Study:
    """A study file, read and checked."""

    name: str
    case: ValidationCase
    base: Path
    parameters: dict[str, list[Any]]
    fixed: dict[str, Any]
    combine: str = "factorial"
    workers: int = 0
    ranks: int = 1
    out: Path = Path("OUT/study")
    source: Path | None = None
    runs: list[dict[str, Any]] = field(default_factory=list)


class StudyError(ValueError):
    """A study file that cannot be used (the message names the file and the key)."""


def _target(name: str) -> tuple[str, int | None, str]:
    """(group, instance from 1 or None for all, variable) of a parameter name."""
    if name in ALIASES:
        group, var = ALIASES[name]
        return group, None, var
    m = re.fullmatch(r"([A-Za-z_]\w*)(?:\[(\d+)\])?\.([A-Za-z_]\w*)", name)
    if not m:
        raise StudyError(f"parameter '{name}': not a known short name ({', '.join(sorted(ALIASES))}, "
                         "resolution) nor group.variable or group[i].variable")
    return m.group(1).lower(), (int(m.group(2)) if m.group(2) else None), m.group(3).lower()


def load_study(path: str | Path) -> Study:
    """Read a study file; relative paths in it are relative to the working directory."""
    path = Path(path)
    try:
        data = tomllib.loads(path.read_text())
    except (OSError, tomllib.TOMLDecodeError) as err:
        raise StudyError(f"{path}: {err}") from err
    head = data.get("study", {})
    unknown = set(data) - {"study", "set", "parameters"}
    if unknown:
        raise StudyError(f"{path}: unknown table(s) {sorted(unknown)}; allowed: study, set, parameters")
    unknown = set(head) - {"case", "base", "combine", "workers", "ranks", "out"}
    if unknown:
        raise StudyError(f"{path}: [study] unknown key(s) {sorted(unknown)}")
    if head.get("case") not in CASES:
        raise StudyError(f"{path}: [study] case = {head.get('case')!r}; allowed: {', '.join(CASES)}")
    case = CASES[head["case"]]
    base = Path(head.get("base", ROOT / case.base))
    if not base.is_file():
        raise StudyError(f"{path}: [study] base = '{base}': no such file")
    combine = head.get("combine", "factorial")
    if combine not in ("factorial", "zip"):
        raise StudyError(f"{path}: [study] combine = {combine!r}; allowed: factorial, zip")
    workers, ranks = head.get("workers", 0), head.get("ranks", 1)
    if not (isinstance(workers, int) and workers >= 0):
        raise StudyError(f"{path}: [study] workers = {workers!r}; allowed: an integer >= 0")
    if not (isinstance(ranks, int) and ranks >= 1):
        raise StudyError(f"{path}: [study] ranks = {ranks!r}; allowed: an integer >= 1")
    params = data.get("parameters", {})
    if not params:
        raise StudyError(f"{path}: [parameters] is empty: give at least one list of values")
    for name, values in list(params.items()):
        if not isinstance(values, list) or not values:
            raise StudyError(f"{path}: [parameters] {name}: give a non-empty list of values")
        if name == "resolution" and case.length is None:
            raise StudyError(f"{path}: [parameters] resolution: case '{case.name}' has no length; use dp")
    fixed = data.get("set", {})
    if "resolution" in fixed and case.length is None:
        raise StudyError(f"{path}: [set] resolution: case '{case.name}' has no length; use dp")
    for name in [n for n in list(params) + list(fixed) if n != "resolution"]:
        try:
            _target(name)
        except StudyError as err:
            raise StudyError(f"{path}: {err}") from err
    if combine == "zip" and len({len(v) for v in params.values()}) > 1:
        raise StudyError(f"{path}: combine = 'zip' needs lists of one length, "
                         f"got {({k: len(v) for k, v in params.items()})}")
    study = Study(name=path.stem, case=case, base=base, parameters=params, fixed=fixed, combine=combine,
                  workers=workers, ranks=ranks, out=Path(head.get("out", Path("OUT") / "study" / path.stem)),
                  source=path)
    study.runs = expand(params, combine)
    return study


def expand(parameters: dict[str, list[Any]], combine: str = "factorial") -> list[dict[str, Any]]:
    """The runs of a study: every combination (factorial) or the i-th value of each list (zip)."""
    names = list(parameters)
    if combine == "zip":
        rows = zip(*(parameters[n] for n in names))
    else:
        rows = itertools.product(*(parameters[n] for n in names))
    return [dict(zip(names, row)) for row in rows]


def _fmt(value: Any) -> str:
    if isinstance(value, bool):
        return "T" if value else "F"
    if isinstance(value, float):
        return f"{value:.6g}"
    return str(value)


def run_name(values: dict[str, Any]) -> str:
    """Folder name of a run, from its parameter values (so it does not depend on the order of runs)."""
    parts = [f"{k}-{_fmt(v)}" for k, v in values.items()]
    return re.sub(r"[^\w.+-]", "_", "__".join(parts))


def _set(nml: f90nml.Namelist, name: str, value: Any) -> None:
    group, index, var = _target(name)
    if group not in nml:
        nml[group] = f90nml.Namelist()
    found = nml[group]
    instances = [found] if isinstance(found, f90nml.Namelist) else list(found)
    if index is not None:
        if not 1 <= index <= len(instances):
            raise StudyError(f"parameter '{name}': the base case has {len(instances)} &{group} group(s)")
        instances = [instances[index - 1]]
    for g in instances:
        g[var] = value


def case_text(study: Study, values: dict[str, Any]) -> str:
    """The case file of one run: the base file with the fixed and the run's values, the
    case's geometry made to follow dp, the output into ``out`` (relative: the solver runs
    in the run's folder)."""
    nml = f90nml.read(str(study.base))
    for name, value in {**study.fixed, **values}.items():
        if name == "resolution":
            _set(nml, "dp", float(f"{study.case.length / value:.12g}"))
        else:
            _set(nml, name, value)
    if study.case.adapt is not None:
        study.case.adapt(nml)
    nml["run"]["out_dir"] = "out"
    nml["run"]["overwrite"] = True
    nml["run"]["restart"] = False
    nml["run"]["progress_interval"] = 1.0e9
    base = os.path.relpath(study.base.resolve(), ROOT) if study.base.resolve().is_relative_to(ROOT) else study.base
    head = (f"! study '{study.name}', case '{study.case.name}', base {base}\n"
            f"! values: {', '.join(f'{k} = {_fmt(v)}' for k, v in values.items())}\n")
    return head + str(nml) + "\n"


_PHASES = {"setup": "setup_s", "grid": "grid_s", "pair loop": "pair_loop_s", "bodies": "bodies_s",
           "integrate": "integrate_s", "output": "output_s", "comm": "comm_s"}


def parse_log(text: str) -> dict[str, float]:
    """Particles, steps, final time, losses, phase times and cost from the solver's run.log
    (the banner and the end-of-run summary of src/solver.f90); missing items are absent."""
    out: dict[str, float] = {}
    if m := re.search(r"particles: (\d+)", text):
        out["particles"] = int(m.group(1))
    if m := re.search(r"done: t = ([-+.\dEe]+) s after (\d+) steps; fluid particles lost: (\d+)", text):
        out["t_reached"], out["steps"], out["lost"] = float(m.group(1)), int(m.group(2)), int(m.group(3))
    for label, key in _PHASES.items():
        if m := re.search(rf"^\s+{label}\s+([\d.]+)\s+[\d.]+ %", text, re.MULTILINE):
            out[key] = float(m.group(1))
    if m := re.search(r"cost: ([\d.]+) microseconds per particle-step \((\d+) particle-steps in ([\d.]+) s\)", text):
        out["us_per_particle_step"] = float(m.group(1))
        out["wall_s"] = float(m.group(3))
    return out


def pareto_front(cost: Sequence[float], error: Sequence[float]) -> list[int]:
    """Indices of the runs that no other run beats in both cost and error (both lower is
    better; ties in both keep the first), ordered by cost. NaN entries are never on it."""
    c, e = np.asarray(cost, float), np.asarray(error, float)
    ok = [i for i in range(len(c)) if np.isfinite(c[i]) and np.isfinite(e[i])]
    ok.sort(key=lambda i: (c[i], e[i], i))
    front, best = [], math.inf
    for i in ok:
        if e[i] < best:
            front.append(i)
            best = e[i]
    return front


def observed_order(dp: Sequence[float], error: Sequence[float]) -> tuple[float, float]:
    """Order p and constant C of error = C dp^p, least squares in log-log over the points
    with a finite positive error; NaN when fewer than two distinct dp remain."""
    d, e = np.asarray(dp, float), np.asarray(error, float)
    ok = np.isfinite(d) & np.isfinite(e) & (d > 0) & (e > 0)
    if len(np.unique(d[ok])) < 2:
        return float("nan"), float("nan")
    p, logc = np.polyfit(np.log(d[ok]), np.log(e[ok]), 1)
    return float(p), float(math.exp(logc))


# ------------------------------------------------------------------ running


#: GNU time: reports the peak resident memory of the solver alone. The rusage of a child
#: of this Python process would not do: Linux counts the memory the child had before its
#: exec, i.e. this interpreter's, in ru_maxrss.
GNU_TIME = Path("/usr/bin/time")


def _command(study: Study, binary: Path, nice: int) -> list[str]:
    cmd = [str(binary)]
    if study.ranks > 1:
        cmd = ["mpirun", "-np", str(study.ranks)] + cmd
    if GNU_TIME.is_file():
        cmd = [str(GNU_TIME), "-f", "%M", "-o", "rss_kb.txt"] + cmd
    if nice > 0:
        cmd = ["nice", "-n", str(nice)] + cmd
    return cmd


def solver_id(binary: Path) -> str:
    """Fingerprint of the solver build (SHA-256 of the binary, 16 hex digits)."""
    return hashlib.sha256(Path(binary).read_bytes()).hexdigest()[:16]


def _run_one(study: Study, values: dict[str, Any], binary: Path, nice: int, retry_failed: bool,
             lock: threading.Lock, solver: str | None) -> dict[str, Any]:
    """Run one combination unless its result is already there (same case file and, unless
    ``solver`` is None, the same solver build); return its CSV row."""
    name = run_name(values)
    folder = study.out / name
    folder.mkdir(parents=True, exist_ok=True)
    text = case_text(study, values)
    case, result = folder / "case.nml", folder / "result.json"
    if result.is_file() and case.is_file() and case.read_text() == text:
        row = json.loads(result.read_text())
        same = solver is None or row.get("solver") == solver
        if same and (row.get("status") == "ok" or not retry_failed):
            row["skipped"] = True
            return row
    result.unlink(missing_ok=True)
    case.write_text(text)
    t0 = time.perf_counter()
    with open(folder / "stdout.txt", "w") as log:
        proc = subprocess.Popen(_command(study, binary, nice) + ["case.nml"], cwd=folder, stdout=log,
                                stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)
        _, status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(status)
    elapsed = time.perf_counter() - t0
    rss_kb = float("nan")
    try:
        rss_kb = float((folder / "rss_kb.txt").read_text().split()[-1])
    except (OSError, ValueError, IndexError):
        pass  # no GNU time: the peak memory is not known
    row: dict[str, Any] = {"run": name, **values, "solver": solver_id(binary), "elapsed_s": round(elapsed, 3),
                           "cpu_s": round(usage.ru_utime + usage.ru_stime, 3),
                           "peak_rss_mb": round(rss_kb / 1024.0, 1)}
    runlog = folder / "out" / "run.log"
    if runlog.is_file():
        row.update(parse_log(runlog.read_text()))
    row["status"] = "ok" if proc.returncode == 0 else f"exit {proc.returncode}"
    if proc.returncode == 0:
        try:
            measured = study.case.measure(folder / "out")
            row.update({k: float(v) for k, v in measured.items()})
        except Exception as err:  # a measure that cannot read the run: record why, keep the study going
            row["status"] = f"measure failed: {type(err).__name__}: {err}"
    row.setdefault("error", float("nan"))
    result.write_text(json.dumps(row, indent=1) + "\n")
    with lock:
        err = row["error"]
        print(f"  {name}: {row['status']}, error {err:.4g}, wall {row.get('wall_s', float('nan')):.2f} s, "
              f"{row.get('particles', 0)} particles, {row.get('steps', 0)} steps", flush=True)
    return row


def default_workers(ranks: int = 1) -> int:
    """Cores available to this process divided by the ranks of one run, at least 1."""
    try:
        cores = len(os.sched_getaffinity(0))
    except AttributeError:
        cores = os.cpu_count() or 1
    return max(1, cores // ranks)


def run_study(study: Study, binary: Path = ROOT / "build" / "mbsph", workers: int | None = None,
              nice: int = 0, retry_failed: bool = False, cost: str = "wall_s",
              any_binary: bool = False) -> list[dict[str, Any]]:
    """Run (or resume) every run of the study; write results.csv and the figures; return the rows.
    A finished run made by another build of the solver is run again unless ``any_binary``."""
    solver = None if any_binary else solver_id(binary)
    study.out.mkdir(parents=True, exist_ok=True)
    n = workers if workers else (study.workers or default_workers(study.ranks))
    lock = threading.Lock()
    print(f"study '{study.name}': case '{study.case.name}', {len(study.runs)} runs, {n} at a time, "
          f"output {study.out}", flush=True)
    with ThreadPoolExecutor(max_workers=n) as pool:
        rows = list(pool.map(lambda v: _run_one(study, v, binary, nice, retry_failed, lock, solver), study.runs))
    done = sum(1 for r in rows if not r.get("skipped"))
    print(f"study '{study.name}': {done} run(s) made, {len(rows) - done} already done", flush=True)
    for r in rows:
        r.pop("skipped", None)
    write_csv(study, rows)
    figures(study, rows, cost)
    return rows


def columns(study: Study, rows: list[dict[str, Any]]) -> list[str]:
    """CSV columns: parameters, the fixed columns, then the error extras of the case."""
    params = list(study.parameters)
    extras = sorted({k for r in rows for k in r} - set(params) - set(CSV_COLUMNS))
    return params + CSV_COLUMNS + extras


def write_csv(study: Study, rows: list[dict[str, Any]]) -> Path:
    path = study.out / "results.csv"
    cols = columns(study, rows)
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols, extrasaction="ignore")
        w.writeheader()
        for r in rows:
            w.writerow({k: r.get(k, "") for k in cols})
    return path


def read_results(path: str | Path) -> list[dict[str, Any]]:
    """results.csv back as a list of rows (numbers as floats where they parse)."""
    rows = []
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            row = {}
            for k, v in r.items():
                try:
                    row[k] = float(v) if v != "" else float("nan")
                except ValueError:
                    row[k] = v
            rows.append(row)
    return rows


# ------------------------------------------------------------------ figures and tables


def _dp_of(study: Study, row: dict[str, Any]) -> float:
    if "dp" in row:
        return float(row["dp"])
    if "resolution" in row:
        return study.case.length / float(row["resolution"])
    if "dp" in study.fixed:
        return float(study.fixed["dp"])
    if "resolution" in study.fixed:
        return study.case.length / float(study.fixed["resolution"])
    return float(f90nml.read(str(study.base))["numerics"]["dp"])


def _label(values: dict[str, Any]) -> str:
    return ", ".join(f"{k}={_fmt(v)}" for k, v in values.items())


def order_lines(study: Study, rows: list[dict[str, Any]]) -> list[tuple[dict[str, Any], list[int], float, float]]:
    """The runs grouped by every parameter but dp/resolution: (other values, row indices,
    order p, constant C) for every group with at least two resolutions."""
    res = [k for k in ("dp", "resolution") if k in study.parameters]
    if not res:
        return []
    others = [k for k in study.parameters if k not in res]
    found: dict[tuple, list[int]] = {}
    for i, r in enumerate(rows):
        found.setdefault(tuple(_fmt(r.get(k)) for k in others), []).append(i)
    out = []
    for key, idx in found.items():
        dps = [_dp_of(study, rows[i]) for i in idx]
        if len(set(dps)) < 2:
            continue
        p, c = observed_order(dps, [rows[i].get("error", float("nan")) for i in idx])
        out.append((dict(zip(others, key)), sorted(idx, key=lambda i: -dps[idx.index(i)]), p, c))
    return out


def figures(study: Study, rows: list[dict[str, Any]], cost: str = "wall_s") -> list[Path]:
    """error_cost.png (and error_dp.png when dp varies) in the study folder."""
    from .plotting import plt, save_figure
    written = []
    err = np.array([float(r.get("error", np.nan)) for r in rows])
    wall = np.array([float(r.get(cost, np.nan)) for r in rows])
    if not np.any(np.isfinite(err) & np.isfinite(wall) & (err > 0)):
        return written
    front = pareto_front(wall, err)
    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    ax.loglog(wall, err, "o", color="C0", ms=5, label="runs")
    ax.loglog(wall[front], err[front], "-s", color="C3", mfc="none", ms=9, label="Pareto front")
    for i in front:
        ax.annotate(_label({k: rows[i][k] for k in study.parameters}), (wall[i], err[i]), fontsize=7,
                    xytext=(4, 4), textcoords="offset points")
    ax.set_xlabel(COST[cost])
    ax.set_ylabel(f"relative error: {study.case.error}", fontsize=8)
    ax.set_title(f"study {study.name}: {study.case.reference}", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    written.append(save_figure(fig, study.out / "error_cost.png"))
    lines = order_lines(study, rows)
    if lines:
        fig, ax = plt.subplots(figsize=(7.5, 5.0))
        for k, (others, idx, p, c) in enumerate(lines):
            dps = np.array([_dp_of(study, rows[i]) for i in idx])
            e = err[idx]
            lab = (_label(others) + ": " if others else "") + f"order {p:.2f}"
            ax.loglog(dps, e, "o-", color=f"C{k % 10}", label=lab)
            if np.isfinite(p):
                ax.loglog(dps, c * dps**p, ":", color=f"C{k % 10}", lw=1)
        ax.set_xlabel("dp (m)")
        ax.set_ylabel("relative error")
        ax.set_title(f"study {study.name}: error against dp, fitted error = C dp^p", fontsize=9)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        written.append(save_figure(fig, study.out / "error_dp.png"))
    return written


def table(study: Study, rows: list[dict[str, Any]], cost: str = "wall_s") -> str:
    """Markdown table of a study: parameters, error and the case's extras, cost; Pareto runs
    (error against ``cost``) marked."""
    err = [float(r.get("error", np.nan)) for r in rows]
    wall = [float(r.get(cost, np.nan)) for r in rows]
    front = set(pareto_front(wall, err))
    params = list(study.parameters)
    extras = [k for k in columns(study, rows) if k not in params and k not in CSV_COLUMNS]
    head = params + ["error"] + extras + ["particles", "steps", "wall [s]", "CPU [s]", "us/particle-step",
                                          "peak RSS [MB]", "Pareto"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]

    def num(v: Any, fmt: str) -> str:
        return format(float(v), fmt) if _finite(v) else "-"
    for i, r in enumerate(rows):
        e = err[i]
        cells = [_fmt(r.get(k)) for k in params]
        cells.append(f"{100 * e:.3g} %" if np.isfinite(e) else str(r.get("status")))
        cells += [num(r.get(k), ".3g") for k in extras]
        cells += [num(r.get("particles"), ".0f"), num(r.get("steps"), ".0f"), num(r.get("wall_s"), ".3g"),
                  num(r.get("cpu_s"), ".3g"), num(r.get("us_per_particle_step"), ".3f"),
                  num(r.get("peak_rss_mb"), ".0f"), "*" if i in front else ""]
        out.append("| " + " | ".join(cells) + " |")
    for others, idx, p, _ in order_lines(study, rows):
        what = f" ({_label(others)})" if others else ""
        out.append(f"\nObserved order of convergence{what}: {p:.2f} "
                   f"(least-squares slope of log error against log dp over {len(idx)} resolutions).")
    return "\n".join(out)


def _finite(v: Any) -> bool:
    try:
        return math.isfinite(float(v))
    except (TypeError, ValueError):
        return False


def recommend(studies: list[tuple[Study, list[dict[str, Any]]]], cost: str = "wall_s") -> str:
    """For each case and each of its target errors, the cheapest run (by ``cost``) of all
    the given studies that meets it."""
    unit = {"wall_s": "wall [s]", "cpu_s": "CPU [s]"}[cost]
    out = [f"| case | target error | cheapest settings | error | {unit} | study |", "|---|---|---|---|---|---|"]
    by_case: dict[str, list[tuple[Study, dict[str, Any]]]] = {}
    for st, rows in studies:
        by_case.setdefault(st.case.name, []).extend((st, r) for r in rows)
    for name, items in by_case.items():
        case = CASES[name]
        for target in case.targets:
            ok = [(st, r) for st, r in items if _finite(r.get("error")) and float(r["error"]) <= target
                  and _finite(r.get(cost))]
            if not ok:
                out.append(f"| {name} | {100 * target:.3g} % | none of the runs | - | - | - |")
                continue
            st, r = min(ok, key=lambda sr: float(sr[1][cost]))
            settings = {k: v for k, v in {**st.fixed, **{k: r[k] for k in st.parameters}}.items()
                        if not (k.startswith("run.") or k in ("t_end", "dp", "resolution"))}
            dp = _dp_of(st, r)
            res = f"{case.length_name}/{_fmt(case.length / dp)} = " if case.length else ""
            settings = {"dp": f"{res}{_fmt(dp)} m", **settings}
            out.append(f"| {name} | {100 * target:.3g} % | {_label(settings)} | {100 * float(r['error']):.3g} % | "
                       f"{float(r[cost]):.3g} | {st.name} |")
    return "\n".join(out)


def side_by_side(studies: list[tuple[Study, list[dict[str, Any]]]], param: str, cost: str = "wall_s") -> str:
    """One row per value of ``param``, and the error and cost of every study whose only
    parameter is ``param`` side by side (e.g. the contact models on several cases)."""
    chosen = [(st, rows) for st, rows in studies if list(st.parameters) == [param]]
    unit = {"wall_s": "wall [s]", "cpu_s": "CPU [s]"}[cost]
    head = [param] + [f"{st.case.name} {w}" for st, _ in chosen for w in ("error", unit)]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    values: list[Any] = []
    for st, _ in chosen:
        values += [v for v in st.parameters[param] if v not in values]
    for v in values:
        cells = [_fmt(v)]
        for st, rows in chosen:
            r = next((r for r in rows if _fmt(r.get(param)) == _fmt(v)), None)
            e = float(r["error"]) if r is not None and _finite(r.get("error")) else float("nan")
            cells.append(f"{100 * e:.3g} %" if math.isfinite(e) else "-")
            cells.append(f"{float(r[cost]):.3g}" if r is not None and _finite(r.get(cost)) else "-")
        out.append("| " + " | ".join(cells) + " |")
    return "\n".join(out)


def totals(studies: list[tuple[Study, list[dict[str, Any]]]]) -> str:
    """One line: studies, runs, and their summed CPU and elapsed time."""
    rows = [r for _, rs in studies for r in rs]
    cpu = sum(float(r["cpu_s"]) for r in rows if _finite(r.get("cpu_s")))
    elapsed = sum(float(r["elapsed_s"]) for r in rows if _finite(r.get("elapsed_s")))
    return (f"{len(studies)} studies, {len(rows)} runs, {cpu / 60:.1f} minutes of CPU time "
            f"({elapsed / 60:.1f} minutes elapsed, one run at a time).")


def _other_results(studies: list[Study]) -> list[tuple[Study, list[dict[str, Any]]]]:
    """The finished results of the other study files in the folders of ``studies``, so that
    the recommendation covers every study even when only some were run now."""
    given = {p.source.resolve() for p in studies if p.source}
    out = []
    for folder in sorted({p.source.resolve().parent for p in studies if p.source}):
        for path in sorted(folder.glob("*.toml")):
            if path.resolve() in given:
                continue
            try:
                other = load_study(path)
            except StudyError:
                continue
            if (other.out / "results.csv").is_file():
                out.append((other, read_results(other.out / "results.csv")))
    return out


def replace_block(text: str, key: str, body: str) -> str:
    """Replace the text between ``<!-- study:KEY -->`` and ``<!-- /study:KEY -->``."""
    start, end = f"<!-- study:{key} -->", f"<!-- /study:{key} -->"
    pattern = re.compile(re.escape(start) + r".*?" + re.escape(end), re.DOTALL)
    if not pattern.search(text):
        return text
    return pattern.sub(lambda _: f"{start}\n{body}\n{end}", text)


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="python -m post.study", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("studies", type=Path, nargs="+", help="study files (TOML)")
    ap.add_argument("--workers", type=int, default=None, help="runs at a time (default: the study's, else cores/ranks)")
    ap.add_argument("--nice", type=int, default=0, help="run the solver under nice -n N")
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "mbsph", help="solver (default build/mbsph)")
    ap.add_argument("--retry-failed", action="store_true", help="run again the runs that failed")
    ap.add_argument("--any-binary", action="store_true",
                    help="keep finished runs made by another build of the solver (default: run them again)")
    ap.add_argument("--doc", type=Path, default=None, help="Markdown file whose study blocks are replaced")
    ap.add_argument("--img", type=Path, default=None, help="copy the figures here as study_NAME_*.png")
    ap.add_argument("--cost", choices=list(COST), default="wall_s",
                    help="cost axis of the figures, Pareto front and recommendation (default wall_s)")
    ap.add_argument("--dry-run", action="store_true", help="list the runs and write their case files only")
    args = ap.parse_args(argv)
    try:
        studies = [load_study(p) for p in args.studies]
    except StudyError as err:
        print(f"error: {err}", file=sys.stderr)
        return 2
    if not args.binary.is_file():
        print(f"error: {args.binary} is missing: build it with `make`", file=sys.stderr)
        return 2
    done = []
    for st in studies:
        if args.dry_run:
            for v in st.runs:
                folder = st.out / run_name(v)
                folder.mkdir(parents=True, exist_ok=True)
                (folder / "case.nml").write_text(case_text(st, v))
                print(folder / "case.nml")
            continue
        rows = run_study(st, args.binary, args.workers, args.nice, args.retry_failed, args.cost, args.any_binary)
        done.append((st, rows))
        if args.img:
            for fig in ("error_cost", "error_dp"):
                src = st.out / f"{fig}.png"
                if src.is_file():
                    args.img.mkdir(parents=True, exist_ok=True)
                    shutil.copyfile(src, args.img / f"study_{st.name}_{fig}.png")
    if args.doc and done:
        text = args.doc.read_text()
        for st, rows in done:
            text = replace_block(text, st.name, table(st, rows, args.cost))
        everything = done + _other_results(studies)
        text = replace_block(text, "recommend", recommend(everything, args.cost))
        text = replace_block(text, "total", totals(everything))
        for param in re.findall(r"<!-- study:side:([\w.\[\]]+) -->", text):
            text = replace_block(text, f"side:{param}", side_by_side(everything, param, args.cost))
        args.doc.write_text(text)
        print(f"wrote the tables into {args.doc}")
    failed = [(st.name, r["run"]) for st, rows in done for r in rows if r.get("status") != "ok"]
    for name, run in failed:
        print(f"failed: study {name}, run {run}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.study"))
