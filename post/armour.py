"""Damage of a breakwater armour layer: displaced units, Nod and the stability number Ns.

A breakwater run writes ``OUT/armour.csv`` once at its start: a header comment with the
layer's parameters (``dn``, ``density``, ``rho_water``, ``placement``, ``porosity_target``,
``porosity``, ``threshold``, ``slope_angle_deg``, ``seed``) and one row per unit
(``unit,body,x0,y0,angle0``; ``angle0`` in degrees; 3D adds ``z0`` and ``turn0``, the turn
about the slope's normal in degrees). Each unit is a rigid body whose
motion is in ``OUT/bodies.csv`` (``displacement`` in m and ``rotation`` in rad from the
start of the run).

- A unit is displaced when its final displacement exceeds ``threshold * dn``.
- ``Nod`` is the number of displaced units per strip one ``dn`` wide across the flume; a
  2D run is one such strip, so ``Nod`` is the number of displaced units; a 3D strip of
  width B (``width=`` in the header, ``z0`` a column) holds B/dn of them.
- ``Ns = H / (Delta dn)``, ``Delta = density / rho_water - 1``. ``H`` is given (``--H``),
  measured at a gauge of ``gauges.csv`` (``--gauge k``: the first-harmonic height of a
  regular wave, else ``Hm0``, or ``H_1/3`` with ``--hs h13``), or taken from the ``&wavemaker``
  group of ``case.nml``.

Usage::

    python -m post.armour OUT1 [OUT2 ...] [--H H | --gauge K] [--hs hm0|h13]
                          [--t-start T0] [--t-end T1] [--table FILE.md] [--out DIR]

For each run it prints the damage and draws ``armour_layer.png`` (units at the start and
the end, coloured by displacement/dn), ``armour_displacement.png`` (displacement/dn
against time) and, for a 3D layer, ``armour_plan.png`` (the layer seen along the slope's
normal, turned units as they lie); with ``--table`` it writes a Markdown table of the runs beside the
laboratory ranges, and ``armour_ns.png`` (Ns against Nod, with those ranges). Figures go
to ``--out`` (several runs: ``--out/<run>/``), by default each run's folder; ``armour_ns.png``
goes to ``--out``, else beside the table.
"""

from __future__ import annotations

import argparse
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Sequence

import numpy as np

from . import waves
from .io import case_t_end, note_end, read_case, read_csv
from .plotting import plt, save_figure

__all__ = [
    "LAB_RANGES",
    "ArmourLayer",
    "read_armour",
    "stability_number",
    "van_der_meer_cubes_nod",
    "UnitMotion",
    "unit_motion",
    "ArmourDamage",
    "analyse",
    "laboratory_verdict",
    "markdown_table",
    "plot_layer",
    "plot_displacement",
    "plot_plan",
    "footprint",
    "unit_rotations",
    "plot_ns",
    "main",
]

#: Laboratory stability of single-layer cube armour (listed in doc/post.md):
#: Van Gent (2003, Rock Manual 2007): start of damage at Ns 2.9-3.0 (Nod = 0), failure at
#: Ns 3.5-3.75 (Nod = 0.2); Van Buchem (2009) as the seed paper reports it: one unit
#: displaced at Ns = 5.
LAB_RANGES = {
    "start_of_damage": {"Ns": (2.9, 3.0), "Nod": 0.0, "source": "Van Gent (2003)"},
    "failure": {"Ns": (3.5, 3.75), "Nod": 0.2, "source": "Van Gent (2003)"},
    "one_unit": {"Ns": (5.0, 5.0), "units": 1, "source": "Van Buchem (2009)"},
}


# ------------------------------------------------------------------------ reading


def _value(text: str):
    text = text.strip()
    try:
        return int(text)
    except ValueError:
        pass
    try:
        return float(text)
    except ValueError:
        return text


@dataclass(frozen=True)
class ArmourLayer:
    """Contents of ``armour.csv``: ``meta`` holds the header's ``key=value`` pairs (numbers
    as int or float), the arrays one entry per unit; ``angle0`` is in degrees as written."""

    meta: dict
    unit: np.ndarray
    body: np.ndarray
    x0: np.ndarray
    y0: np.ndarray
    angle0: np.ndarray
    z0: np.ndarray | None = None
    """3D: the units' places across the width (``z0``), else None"""
    turn0: np.ndarray | None = None
    """3D: the units' turns about the slope's normal in degrees (``turn0``; the body's
    ``angle_y``, applied before ``angle0``), else None"""

    @property
    def dn(self) -> float:
        return float(self.meta["dn"])

    @property
    def strips(self) -> float:
        """Strips one dn wide across the layer: ``width / dn`` in 3D (``width=`` in the header), 1 in 2D."""
        return float(self.meta["width"]) / self.dn if "width" in self.meta else 1.0

    @property
    def threshold(self) -> float:
        """Displacement, in units of dn, beyond which a unit counts as displaced."""
        return float(self.meta.get("threshold", 1.0))


def read_armour(path: str | Path) -> ArmourLayer:
    """Read ``armour.csv`` (or the ``armour.csv`` of an output folder)."""
    path = Path(path)
    if path.is_dir():
        path = path / "armour.csv"
    lines = [ln.strip() for ln in path.read_text().splitlines() if ln.strip()]
    meta: dict = {}
    body_lines = []
    for line in lines:
        if line.startswith("#"):
            for item in line[1:].split(","):
                if "=" in item:
                    key, val = item.split("=", 1)
                    meta[key.strip().lower()] = _value(val)
        else:
            body_lines.append(line)
    if "dn" not in meta:
        raise ValueError(f"{path}: no dn=... in the header comment")
    names = [n.strip() for n in body_lines[0].split(",")] if body_lines else []
    for need in ("unit", "body", "x0", "y0", "angle0"):
        if need not in names:
            raise ValueError(f"{path}: header {body_lines[:1]} has no column {need!r}")
    rows = [[float(v) for v in ln.split(",")] for ln in body_lines[1:]]
    data = np.array(rows, dtype=float).reshape(len(rows), len(names))
    col = {n: data[:, j] for j, n in enumerate(names)}
    return ArmourLayer(meta=meta, unit=col["unit"].astype(int), body=col["body"].astype(int),
                       x0=col["x0"], y0=col["y0"], angle0=col["angle0"], z0=col.get("z0"),
                       turn0=col.get("turn0"))


def van_der_meer_cubes_nod(ns: float | np.ndarray, n_waves: float, s_om: float | np.ndarray) -> np.ndarray:
    """Damage Nod of a double layer of cubes by Van der Meer (1988):
    ``Ns = (6.7 Nod^0.4 / N^0.3 + 1.0) s_om^-0.1``, solved for Nod; ``s_om`` is the
    wave steepness 2 pi Hs / (g Tm^2) with the mean period Tm, ``N`` the number of waves.
    Zero where Ns is below the formula's no-damage value ``s_om^-0.1``."""
    x = np.asarray(ns, float) * np.asarray(s_om, float) ** 0.1 - 1.0
    return np.where(x > 0.0, (np.maximum(x, 0.0) * n_waves ** 0.3 / 6.7) ** 2.5, 0.0)


def stability_number(H: float, dn: float, density: float, rho_water: float) -> float:
    """``Ns = H / (Delta dn)`` with the relative buoyant density ``Delta = density/rho_water - 1``."""
    return H / ((density / rho_water - 1.0) * dn)


@dataclass(frozen=True)
class UnitMotion:
    """Motion of one unit from ``bodies.csv``: times (s), position of its centre (m),
    displacement (m) and rotation (rad) from the start of the run."""

    body: int
    time: np.ndarray
    x: np.ndarray
    y: np.ndarray
    displacement: np.ndarray
    rotation: np.ndarray
    z: np.ndarray | None = None
    """3D: the centre across the width (m), else None"""
    quaternion: np.ndarray | None = None
    """3D: the orientation (qw, qx, qy, qz) at each time, (n, 4), else None"""


def unit_motion(bodies: dict[str, np.ndarray], body: int) -> UnitMotion:
    """The rows of ``body`` in the columns of ``bodies.csv`` (as read by post.io.read_csv)."""
    m = bodies["body"] == body
    if not np.any(m):
        raise KeyError(f"body {body} has no row in bodies.csv")
    order = np.argsort(bodies["time"][m], kind="stable")
    pick = {k: np.asarray(bodies[k][m], dtype=float)[order] for k in ("time", "x", "y", "displacement", "rotation")}
    if "qw" in bodies:
        pick["z"] = np.asarray(bodies["z"][m], dtype=float)[order]
        pick["quaternion"] = np.column_stack([np.asarray(bodies[k][m], dtype=float)[order]
                                              for k in ("qw", "qx", "qy", "qz")])
    return UnitMotion(body=body, **pick)


# --------------------------------------------------------------------- analysis


@dataclass(frozen=True)
class ArmourDamage:
    """Damage of one run (see the module docstring for the definitions).

    Per-unit arrays follow the unit order of ``armour.csv``: ``final_displacement`` (m),
    ``max_displacement`` (largest during the run, m), ``final_rotation`` (rad), ``displaced``
    (bool). ``H`` (m) may be NaN when no height was given or found; then ``Ns`` is NaN.
    """

    run: str
    layer: ArmourLayer
    motions: list[UnitMotion] = field(repr=False)
    final_displacement: np.ndarray
    max_displacement: np.ndarray
    final_rotation: np.ndarray
    displaced: np.ndarray
    rho_water: float
    H: float
    H_source: str
    Ns: float

    @property
    def units(self) -> int:
        return len(self.layer.unit)

    @property
    def n_displaced(self) -> int:
        return int(np.count_nonzero(self.displaced))

    @property
    def Nod(self) -> float:
        """Displaced units per dn-wide strip: in 2D the number displaced, in 3D that over width/dn."""
        return float(self.n_displaced) / self.layer.strips

    @property
    def delta(self) -> float:
        return float(self.layer.meta["density"]) / self.rho_water - 1.0


def _wave_height(out: Path, nml, H: float | None, gauge: int | None, irregular_height: str,
                 t_start: float | None, t_end: float | None) -> tuple[float, str]:
    if H is not None:
        return float(H), "given"
    wm = waves.wavemaker_settings(nml) if nml is not None else {}
    if gauge is not None:
        gauges, time, columns = waves.read_gauges(out)
        g, eta = waves.gauge_column(gauges, columns, gauge)
        if g.kind != "elevation":
            raise ValueError(f"gauge {gauge} is a {g.kind} gauge, not an elevation gauge")
        sel = np.ones(len(time), dtype=bool)
        if t_start is not None:
            sel &= time >= t_start
        if t_end is not None:
            sel &= time <= t_end
        if not sel.any():
            raise ValueError(f"{Path(out) / 'gauges.csv'}: gauge {gauge} has no sample in the window "
                             f"[{t_start}, {t_end}] s; the record covers {time[0]:g} to {time[-1]:g} s: "
                             f"choose --t-start and --t-end inside it")
        value, how = waves.measured_height(time[sel], eta[sel], regular=wm.get("regular"), period=wm.get("T"),
                                           irregular_height=irregular_height)
        return value, f"{how} at gauge {gauge}"
    if "H" in wm:
        return float(wm["H"]), "&wavemaker"
    return float("nan"), "none"


def analyse(out: str | Path, H: float | None = None, gauge: int | None = None, irregular_height: str = "hm0",
            t_start: float | None = None, t_end: float | None = None) -> ArmourDamage:
    """Damage of the armour of the run in ``out`` (armour.csv, bodies.csv, case.nml if
    present, gauges.csv when ``gauge`` is given). ``H`` wins over ``gauge``, which wins over
    the ``&wavemaker`` height; the gauge record is clipped to ``[t_start, t_end]``.
    """
    out = Path(out)
    layer = read_armour(out)
    bodies = read_csv(out / "bodies.csv")
    try:
        nml = read_case(out)
    except (FileNotFoundError, OSError):
        nml = None
    # a run that stopped after a few steps moves no unit: say what time the damage is of
    note_end(out / "bodies.csv", np.unique(bodies["time"]), case_t_end(nml) if nml is not None else None)
    rho_water = float(layer.meta.get("rho_water", float("nan")))
    if not math.isfinite(rho_water) and nml is not None and "fluid" in nml and "rho0" in nml["fluid"]:
        rho_water = float(nml["fluid"]["rho0"])
    if not math.isfinite(rho_water):
        rho_water = 1000.0
    motions = [unit_motion(bodies, int(b)) for b in layer.body]
    final = np.array([m.displacement[-1] for m in motions])
    largest = np.array([np.max(m.displacement) for m in motions])
    rot = np.array([m.rotation[-1] for m in motions])
    displaced = final > layer.threshold * layer.dn
    height, source = _wave_height(out, nml, H, gauge, irregular_height, t_start, t_end)
    ns = stability_number(height, layer.dn, float(layer.meta["density"]), rho_water)
    return ArmourDamage(run=out.name or str(out), layer=layer, motions=motions, final_displacement=final,
                        max_displacement=largest, final_rotation=rot, displaced=displaced,
                        rho_water=rho_water, H=height, H_source=source, Ns=ns)


def laboratory_verdict(Ns: float) -> str:
    """Where ``Ns`` lies against the laboratory ranges of single-layer cubes."""
    if not math.isfinite(Ns):
        return "no H"
    sd, fl = LAB_RANGES["start_of_damage"]["Ns"], LAB_RANGES["failure"]["Ns"]
    if Ns < sd[0]:
        return f"below start of damage (Ns < {sd[0]}): lab Nod = 0"
    if Ns <= sd[1]:
        return "start of damage (lab Nod = 0)"
    if Ns < fl[0]:
        return "between start of damage and failure"
    if Ns <= fl[1]:
        return "failure range (lab Nod = 0.2)"
    return f"beyond failure (Ns > {fl[1]}); Van Buchem: 1 unit at Ns = 5"


def markdown_table(results: Sequence[ArmourDamage]) -> str:
    """One row per run with its damage and the laboratory verdict at its Ns, then the ranges."""
    lines = ["| run | placement | porosity (target) | H [m] | H from | Ns | units | displaced | Nod | "
             "largest final displacement [dn] | largest during run [dn] | laboratory at this Ns |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        m = r.layer.meta
        por = f"{float(m['porosity']):.3f}" if "porosity" in m else "-"
        tgt = f" ({float(m['porosity_target']):.3f})" if "porosity_target" in m else ""
        lines.append(f"| {r.run} | {m.get('placement', '-')} | {por}{tgt} | {r.H:.4f} | {r.H_source} | "
                     f"{r.Ns:.2f} | {r.units} | {r.n_displaced} | {r.Nod:g} | "
                     f"{np.max(r.final_displacement) / r.layer.dn:.3f} | "
                     f"{np.max(r.max_displacement) / r.layer.dn:.3f} | {laboratory_verdict(r.Ns)} |")
    thresholds = sorted({r.layer.threshold for r in results})
    lines += ["",
              "A unit is displaced when its final displacement exceeds "
              + " / ".join(f"{t:g}" for t in thresholds)
              + " dn; Nod is the number of displaced units per dn-wide strip (a 2D run is one strip).",
              "",
              "| laboratory (single-layer cubes) | Ns | damage |",
              "|---|---|---|",
              "| Van Gent (2003): start of damage | 2.9-3.0 | Nod = 0 |",
              "| Van Gent (2003): failure | 3.5-3.75 | Nod = 0.2 |",
              "| Van Buchem (2009), as the seed paper reports it | 5 | one unit displaced in the flume |"]
    return "\n".join(lines) + "\n"


# --------------------------------------------------------------------- figures


def _square(x: float, y: float, angle: float, side: float) -> np.ndarray:
    """Closed outline (5 x 2) of a square of ``side`` centred at (x, y), turned by ``angle`` rad."""
    c, s = math.cos(angle), math.sin(angle)
    half = 0.5 * side
    corners = np.array([[-half, -half], [half, -half], [half, half], [-half, half], [-half, -half]])
    return corners @ np.array([[c, s], [-s, c]]) + np.array([x, y])


def _final_poses(r: ArmourDamage) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Final centre and angle (rad) of each unit: the initial pose of armour.csv moved by the
    change of position and the rotation of bodies.csv (so whether bodies.csv angles are
    absolute does not matter)."""
    lay = r.layer
    x = lay.x0 + np.array([m.x[-1] - m.x[0] for m in r.motions])
    y = lay.y0 + np.array([m.y[-1] - m.y[0] for m in r.motions])
    return x, y, np.radians(lay.angle0) + r.final_rotation


def _slope_line(lay: ArmourLayer) -> tuple[np.ndarray, np.ndarray] | None:
    """The slope under the layer: the line through the initial centres (angle from the
    header's slope_angle_deg when given, its sign from a fit), dn/2 below them."""
    if len(lay.x0) < 2 or np.ptp(lay.x0) <= 0:
        return None
    fit = np.polyfit(lay.x0, lay.y0, 1)[0]
    theta = math.atan(fit)
    if "slope_angle_deg" in lay.meta:
        theta = math.copysign(math.radians(float(lay.meta["slope_angle_deg"])), fit if fit != 0 else 1.0)
    d = np.array([math.cos(theta), math.sin(theta)])
    n = np.array([-d[1], d[0]])
    pts = np.column_stack([lay.x0, lay.y0])
    centre = pts.mean(axis=0) - 0.5 * lay.dn * n
    s = (pts - pts.mean(axis=0)) @ d
    ends = np.array([s.min() - lay.dn, s.max() + lay.dn])
    return centre[0] + ends * d[0], centre[1] + ends * d[1]


def plot_layer(r: ArmourDamage, path: str | Path) -> Path:
    """``armour_layer.png``: each unit at its initial pose (dashed outline) and its final
    pose (filled by final displacement/dn), the slope line, a colour bar."""
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize

    lay = r.layer
    xf, yf, af = _final_poses(r)
    ratio = r.final_displacement / lay.dn
    norm = Normalize(0.0, max(1.5 * lay.threshold, float(np.max(ratio))))
    fig, ax = plt.subplots(figsize=(8, 5))
    initial = [_square(x, y, math.radians(a), lay.dn) for x, y, a in zip(lay.x0, lay.y0, lay.angle0)]
    final = [_square(x, y, a, lay.dn) for x, y, a in zip(xf, yf, af)]
    filled = PolyCollection(final, array=ratio, cmap="viridis", norm=norm, edgecolors="k", linewidths=0.6)
    ax.add_collection(filled)
    ax.add_collection(PolyCollection(initial, facecolors="none", edgecolors="0.3", linestyles="--",
                                     linewidths=0.8, label="start"))
    line = _slope_line(lay)
    if line is not None:
        ax.plot(*line, color="saddlebrown", lw=1.5, label="slope (dn/2 below the initial centres)")
    for k in np.nonzero(r.displaced)[0]:
        ax.annotate(str(lay.unit[k]), (xf[k], yf[k]), ha="center", va="center", fontsize=7, color="w")
    allx = np.r_[np.concatenate(initial)[:, 0], np.concatenate(final)[:, 0]]
    ally = np.r_[np.concatenate(initial)[:, 1], np.concatenate(final)[:, 1]]
    ax.set_xlim(allx.min() - lay.dn, allx.max() + lay.dn)
    ax.set_ylim(ally.min() - lay.dn, ally.max() + lay.dn)
    ax.set_aspect("equal")
    fig.colorbar(filled, ax=ax, label="final displacement / dn")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title(f"{r.run}: {r.n_displaced} of {r.units} units displaced (> {lay.threshold:g} dn), "
                 f"Ns = {r.Ns:.2f}", fontsize=9)
    ax.legend(fontsize=8, loc="best")
    fig.tight_layout()
    return save_figure(fig, path)


def _quaternion_matrix(q: np.ndarray) -> np.ndarray:
    """Rotation matrix of the unit quaternion (w, x, y, z)."""
    w, x, y, z = q / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def unit_rotations(lay: ArmourLayer) -> np.ndarray:
    """3D: each unit's start orientation from its own frame, Rz(angle0) Ry(turn0), (n, 3, 3)."""
    out = []
    turns = lay.turn0 if lay.turn0 is not None else np.zeros_like(lay.angle0)
    for a, b in zip(np.radians(lay.angle0), np.radians(turns)):
        rz = np.array([[math.cos(a), -math.sin(a), 0.0], [math.sin(a), math.cos(a), 0.0], [0.0, 0.0, 1.0]])
        ry = np.array([[math.cos(b), 0.0, math.sin(b)], [0.0, 1.0, 0.0], [-math.sin(b), 0.0, math.cos(b)]])
        out.append(rz @ ry)
    return np.array(out)


def _hull(points: np.ndarray) -> np.ndarray:
    """Convex hull of 2D points, counter-clockwise and closed (Andrew's monotone chain)."""
    pts = sorted(map(tuple, np.round(points, 15)))

    def half(seq):
        out: list[tuple[float, float]] = []
        for p in seq:
            while len(out) >= 2 and ((out[-1][0] - out[-2][0]) * (p[1] - out[-2][1])
                                     - (out[-1][1] - out[-2][1]) * (p[0] - out[-2][0])) <= 0.0:
                out.pop()
            out.append(p)
        return out

    lower, upper = half(pts), half(reversed(pts))
    ring = lower[:-1] + upper[:-1]
    return np.array(ring + ring[:1])


def footprint(centre: np.ndarray, rot: np.ndarray, dn: float, alpha: float) -> np.ndarray:
    """Outline of a cube (side dn, centre, rotation rot from its own frame) projected on the
    slope plane of angle alpha: (s along the slope, z across), closed polygon."""
    corners = 0.5 * dn * np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], dtype=float)
    v = centre + corners @ rot.T
    t = np.array([math.cos(alpha), math.sin(alpha), 0.0])
    return _hull(np.column_stack([v @ t, v[:, 2]]))


def plot_plan(r: ArmourDamage, path: str | Path) -> Path:
    """3D: ``armour_plan.png``, the layer seen along the slope's normal: each unit's outline
    on the slope plane (s along the slope, z across) at the start (dashed) and at the end
    (filled by final displacement/dn), the turned units as they lie."""
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize

    lay = r.layer
    if lay.z0 is None or any(m.quaternion is None for m in r.motions):
        raise ValueError(f"{r.run}: the plan view is for a 3D layer (armour.csv z0, bodies.csv quaternions)")
    alpha = math.radians(float(lay.meta["slope_angle_deg"]))
    rot0 = unit_rotations(lay)
    start, end = [], []
    for k, m in enumerate(r.motions):
        c0 = np.array([lay.x0[k], lay.y0[k], lay.z0[k]])
        start.append(footprint(c0, rot0[k], lay.dn, alpha))
        # the final pose: the start moved and turned as bodies.csv says, relative to its first row
        turn = _quaternion_matrix(m.quaternion[-1]) @ _quaternion_matrix(m.quaternion[0]).T
        c1 = c0 + np.array([m.x[-1] - m.x[0], m.y[-1] - m.y[0], m.z[-1] - m.z[0]])
        end.append(footprint(c1, turn @ rot0[k], lay.dn, alpha))
    ratio = r.final_displacement / lay.dn
    norm = Normalize(0.0, max(1.5 * lay.threshold, float(np.max(ratio))))
    allp = np.concatenate(start + end)
    fig, ax = plt.subplots(figsize=(9, 3.5))
    filled = PolyCollection([p[:-1] for p in end], array=ratio, cmap="viridis", norm=norm, edgecolors="k",
                            linewidths=0.6)
    ax.add_collection(filled)
    ax.add_collection(PolyCollection([p[:-1] for p in start], facecolors="none", edgecolors="0.3",
                                     linestyles="--", linewidths=0.8))
    width = float(lay.meta.get("width", np.ptp(allp[:, 1])))
    for zz in (0.0, width):
        ax.axhline(zz, color="0.6", lw=0.8)
    ax.set_xlim(allp[:, 0].min() - lay.dn, allp[:, 0].max() + lay.dn)
    ax.set_ylim(min(0.0, allp[:, 1].min()) - 0.5 * lay.dn, max(width, allp[:, 1].max()) + 0.5 * lay.dn)
    ax.set_aspect("equal")
    fig.colorbar(filled, ax=ax, label="final displacement / dn")
    ax.set_xlabel("along the slope, s = x cos(alpha) + y sin(alpha) [m]")
    ax.set_ylabel("across, z [m]")
    ax.set_title(f"{r.run}: the layer along the slope's normal, start dashed ({lay.meta.get('placement', '')}); "
                 f"{r.n_displaced} of {r.units} displaced", fontsize=9)
    fig.tight_layout()
    return save_figure(fig, path)


def plot_displacement(r: ArmourDamage, path: str | Path) -> Path:
    """``armour_displacement.png``: displacement/dn of every unit against time, threshold line."""
    fig, ax = plt.subplots(figsize=(8, 4.5))
    dn = r.layer.dn
    for m, unit, moved in zip(r.motions, r.layer.unit, r.displaced):
        ax.plot(m.time, m.displacement / dn, lw=1.2 if moved else 0.6,
                label=f"unit {unit}" if moved else None)
    ax.axhline(r.layer.threshold, color="r", ls="--", lw=1.0, label=f"threshold {r.layer.threshold:g} dn")
    ax.set_xlabel("time [s]")
    ax.set_ylabel("displacement / dn")
    ax.set_title(f"{r.run}: {r.units} units", fontsize=9)
    ax.legend(fontsize=8, loc="upper left")
    fig.tight_layout()
    return save_figure(fig, path)


def plot_ns(results: Sequence[ArmourDamage], path: str | Path) -> Path:
    """``armour_ns.png``: Ns against Nod of the runs with the laboratory ranges."""
    fig, ax = plt.subplots(figsize=(7, 4.5))
    sd, fl = LAB_RANGES["start_of_damage"], LAB_RANGES["failure"]
    nod_max = max([0.5] + [1.2 * r.Nod for r in results])
    ax.axhspan(*sd["Ns"], color="tab:green", alpha=0.25, label="Van Gent (2003): start of damage, Nod = 0")
    ax.axhspan(*fl["Ns"], color="tab:red", alpha=0.25, label="Van Gent (2003): failure, Nod = 0.2")
    ax.errorbar([sd["Nod"], fl["Nod"]], [np.mean(sd["Ns"]), np.mean(fl["Ns"])],
                yerr=[[np.mean(sd["Ns"]) - sd["Ns"][0], np.mean(fl["Ns"]) - fl["Ns"][0]],
                      [sd["Ns"][1] - np.mean(sd["Ns"]), fl["Ns"][1] - np.mean(fl["Ns"])]],
                fmt="s", color="k", capsize=4, label="Van Gent (2003)")
    ax.axhline(LAB_RANGES["one_unit"]["Ns"][0], color="tab:purple", ls="--",
               label="Van Buchem (2009): one unit displaced in the flume")
    for r in results:
        if math.isfinite(r.Ns):
            ax.plot(r.Nod, r.Ns, "o", ms=7)
            ax.annotate(r.run, (r.Nod, r.Ns), textcoords="offset points", xytext=(6, 4), fontsize=8)
    ax.set_xlim(-0.1, nod_max)
    ns_top = max([6.0] + [1.1 * r.Ns for r in results if math.isfinite(r.Ns)])
    ax.set_ylim(0.0, ns_top)
    ax.set_xlabel("Nod (displaced units per dn-wide strip; 2D: units displaced)")
    ax.set_ylabel("Ns = H / (Delta dn)")
    ax.legend(fontsize=7, loc="lower right")
    fig.tight_layout()
    return save_figure(fig, path)


# ------------------------------------------------------------------------- CLI


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", type=Path, nargs="+", help="output folders holding armour.csv and bodies.csv")
    how = ap.add_mutually_exclusive_group()
    how.add_argument("--H", type=float, default=None, help="wave height for Ns (m), the same for every run")
    how.add_argument("--gauge", type=int, default=None, help="id of the elevation gauge where H is measured")
    ap.add_argument("--hs", choices=("hm0", "h13"), default="hm0",
                    help="height of an irregular sea at the gauge: Hm0 (default) or H_1/3")
    ap.add_argument("--t-start", type=float, default=None, help="start of the gauge window (s)")
    ap.add_argument("--t-end", type=float, default=None, help="end of the gauge window (s)")
    ap.add_argument("--table", type=Path, default=None, help="write a Markdown table of the runs here")
    ap.add_argument("--out", type=Path, default=None, help="folder of the figures (default: each run's folder)")
    args = ap.parse_args(argv)

    results = []
    for run in args.runs:
        try:
            r = analyse(run, H=args.H, gauge=args.gauge, irregular_height=args.hs, t_start=args.t_start,
                        t_end=args.t_end)
        except ValueError as err:
            print(f"post.armour: error: {err}", file=sys.stderr)
            return 2
        results.append(r)
        figdir = run if args.out is None else (args.out if len(args.runs) == 1 else args.out / r.run)
        print(f"{r.run}: {r.units} units, dn {r.layer.dn:g} m, Delta {r.delta:.3f}, H {r.H:.4f} m ({r.H_source}), "
              f"Ns {r.Ns:.3f}; displaced (> {r.layer.threshold:g} dn) {r.n_displaced}, Nod {r.Nod:g}, "
              f"largest final displacement {np.max(r.final_displacement) / r.layer.dn:.4f} dn, "
              f"largest during the run {np.max(r.max_displacement) / r.layer.dn:.4f} dn")
        print(f"wrote {plot_layer(r, figdir / 'armour_layer.png')}")
        print(f"wrote {plot_displacement(r, figdir / 'armour_displacement.png')}")
        if r.layer.z0 is not None:
            print(f"wrote {plot_plan(r, figdir / 'armour_plan.png')}")
    if args.table is not None:
        args.table.parent.mkdir(parents=True, exist_ok=True)
        command = " ".join(sys.argv[1:] if argv is None else argv)
        args.table.write_text(f"# Armour damage\n\nMade by `python -m post.armour {command}`.\n\n"
                              + markdown_table(results))
        print(f"wrote {args.table}")
    if args.table is not None or args.out is not None or len(results) > 1:
        ns_dir = args.out if args.out is not None else (args.table.parent if args.table is not None else args.runs[0])
        print(f"wrote {plot_ns(results, ns_dir / 'armour_ns.png')}")
    return 0


if __name__ == "__main__":
    from post.cli import run
    raise SystemExit(run(main, "python -m post.armour"))
