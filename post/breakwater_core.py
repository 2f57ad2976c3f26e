"""The breakwater with and without a porous core, side by side (doc/porous.md): the water
level inside the core, the pressure in the underlayer under the armour, the fluid force
on each unit normal to the slope (the uplift that pulls a unit out of the layer on
run-down), and the units' displacement.

    .venv/bin/python -m post.breakwater_core POROUS_RUN IMPERMEABLE_RUN [--t-start 3.5]
        [--out doc/img/breakwater_core.png] [--table OUT/breakwater_core.md]

Both runs are `input/breakwater/regular_porous.nml`-like cases (its gauges: 3 at the toe,
5 and 6 in the core, 7 and 8 in the underlayer under the armour); the impermeable one is
the same file with `core = 'impermeable'` (`make breakwater_core`), so that the two differ
in the core alone. The force normal to the slope is taken outward (away from the slope),
per unit of the unit's submerged weight (rho_c - rho_w) g dn^2: above 1 the water alone
would lift a unit that nothing else held.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from post.armour import analyse
from post.io import read_csv
from post.waves import read_gauges

G = 9.81


@dataclass(frozen=True)
class CoreRun:
    """What one run says about its core and its armour over the analysis window."""

    name: str
    Ns: float                       # from the first-harmonic height at the toe gauge
    H: float
    level: dict[str, tuple[float, float, float]]   # core gauge -> (mean, min, max) [m above still water]
    pressure: dict[str, tuple[float, float]]       # underlayer gauge -> (min, max) [Pa]
    uplift: np.ndarray              # per unit: largest outward normal fluid force / submerged weight
    uplift_t: np.ndarray            # per unit: time of it [s]
    max_disp: float                 # largest displacement of any unit [dn]
    displaced: int


def normal_force(bodies: dict[str, np.ndarray], body: int, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """Time and the fluid force on ``body`` along the slope's outward normal (N/m)."""
    m = bodies["body"] == body
    t = np.asarray(bodies["time"][m], float)
    n = np.array([-math.sin(alpha), math.cos(alpha)])
    f = n[0] * np.asarray(bodies["fx_fluid"][m], float) + n[1] * np.asarray(bodies["fy_fluid"][m], float)
    o = np.argsort(t, kind="stable")
    return t[o], f[o]


def core_run(out: Path, t_start: float, toe_gauge: int = 3) -> CoreRun:
    dmg = analyse(out, gauge=toe_gauge, t_start=t_start)
    lay = dmg.layer
    alpha = math.radians(float(lay.meta["slope_angle_deg"]))
    dn = lay.dn
    weight = (float(lay.meta["density"]) - dmg.rho_water) * G * dn * dn
    bodies = read_csv(out / "bodies.csv")
    up, up_t = [], []
    for b in lay.body:
        t, f = normal_force(bodies, int(b), alpha)
        w = t >= t_start
        k = int(np.argmax(f[w]))
        up.append(f[w][k] / weight)
        up_t.append(t[w][k])
    gauges, time, cols = read_gauges(out)
    win = time >= t_start
    level, pressure = {}, {}
    for g in gauges:
        col = f"eta_{g.id}" if g.kind == "elevation" else f"p_{g.id}"
        if g.id in (5, 6) and g.kind == "elevation":
            v = cols[col][win]
            v = v[np.isfinite(v)]
            level[f"{g.id} (x = {g.x:.2f} m)"] = ((float(v.mean()), float(v.min()), float(v.max())) if v.size
                                                  else (math.nan,) * 3)
        if g.id in (7, 8) and g.kind == "pressure":
            v = cols[col][win]
            pressure[f"{g.id} (y = {g.y:.3f} m)"] = (float(v.min()), float(v.max()))
    return CoreRun(name=out.name, Ns=dmg.Ns, H=dmg.H, level=level, pressure=pressure, uplift=np.array(up),
                   uplift_t=np.array(up_t), max_disp=float(dmg.max_displacement.max() / dn),
                   displaced=dmg.n_displaced)


def table(runs: Sequence[CoreRun], t_start: float) -> str:
    head = "| | " + " | ".join(r.name for r in runs) + " |\n|---|" + "---|" * len(runs) + "\n"
    rows = [("H at the toe gauge, first harmonic; Ns", [f"{r.H:.3f} m; {r.Ns:.2f}" for r in runs])]
    keys = sorted({k for r in runs for k in r.level})
    for k in keys:
        rows.append((f"water level in the core, gauge {k}: mean, min, max above still water",
                     [("dry (solid core)" if k not in r.level or not math.isfinite(r.level[k][0]) else
                       f"{1000 * r.level[k][0]:.1f}, {1000 * r.level[k][1]:.1f}, {1000 * r.level[k][2]:.1f} mm")
                      for r in runs]))
    keys = sorted({k for r in runs for k in r.pressure})
    for k in keys:
        rows.append((f"pressure in the underlayer under the armour, gauge {k}: min, max",
                     [("solid (no water)" if k not in r.pressure or r.pressure[k][1] == 0.0 else
                       f"{r.pressure[k][0]:.0f}, {r.pressure[k][1]:.0f} Pa") for r in runs]))
    rows.append(("largest outward fluid force normal to the slope, over the units, / submerged weight",
                 [f"{r.uplift.max():.2f} (unit {int(np.argmax(r.uplift)) + 1}, t = "
                  f"{r.uplift_t[int(np.argmax(r.uplift))]:.2f} s)" for r in runs]))
    rows.append(("mean over the units of their largest outward normal force / submerged weight",
                 [f"{r.uplift.mean():.2f}" for r in runs]))
    rows.append(("largest displacement of a unit; units displaced (> 1 dn)",
                 [f"{r.max_disp:.2f} dn; {r.displaced}" for r in runs]))
    body = "".join(f"| {name} | " + " | ".join(vals) + " |\n" for name, vals in rows)
    return f"From t = {t_start} s to the end of each run.\n\n" + head + body


def plot(runs: Sequence[Path], t_start: float, path: Path) -> Path:
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(3, 1, figsize=(9, 8.5), sharex=True)
    colours = ["tab:blue", "tab:red"]
    for out, c in zip(runs, colours):
        gauges, time, cols = read_gauges(out)
        ax[0].plot(time, 1000 * cols["eta_3"], color=c, lw=0.8, label=f"{out.name}: toe (gauge 3)")
        if np.isfinite(cols.get("eta_5", np.array([np.nan]))).any():
            ax[0].plot(time, 1000 * cols["eta_5"], color=c, ls="--", lw=1.2, label=f"{out.name}: in the core (gauge 5)")
        if "p_8" in cols and np.any(cols["p_8"] != 0):
            ax[1].plot(time, cols["p_7"], color="tab:green", lw=0.9, label=f"{out.name}: under the armour, y = 0.49 m")
            ax[1].plot(time, cols["p_8"], color="tab:olive", lw=0.9, label=f"{out.name}: under the armour, y = 0.59 m")
        dmg = analyse(out, gauge=3, t_start=t_start)
        lay = dmg.layer
        alpha = math.radians(float(lay.meta["slope_angle_deg"]))
        weight = (float(lay.meta["density"]) - dmg.rho_water) * G * lay.dn ** 2
        bodies = read_csv(out / "bodies.csv")
        # the unit whose centre is nearest the still-water level takes the run-down
        depth = 0.6
        k = int(np.argmin(np.abs(lay.y0 - depth)))
        t, f = normal_force(bodies, int(lay.body[k]), alpha)
        ax[2].plot(t, f / weight, color=c, lw=0.8, label=f"{out.name}: unit {k + 1} (at the still-water level)")
    ax[0].set_ylabel("water level [mm]")
    ax[1].set_ylabel("pore pressure [Pa]")
    ax[2].set_ylabel("outward normal fluid force\n/ submerged weight")
    ax[2].axhline(1.0, color="k", lw=0.5, ls=":")
    ax[2].set_xlabel("t [s]")
    for a in ax:
        a.axvline(t_start, color="0.6", lw=0.5)
        a.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def main(argv: Sequence[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("porous", type=Path)
    ap.add_argument("impermeable", type=Path)
    ap.add_argument("--t-start", type=float, default=3.5, help="start of the analysis window [s]")
    ap.add_argument("--out", type=Path, help="figure (png)")
    ap.add_argument("--table", type=Path, help="markdown table")
    a = ap.parse_args(argv)
    runs = [core_run(a.porous, a.t_start), core_run(a.impermeable, a.t_start)]
    text = table(runs, a.t_start)
    print(text)
    if a.table:
        a.table.parent.mkdir(parents=True, exist_ok=True)
        a.table.write_text(text)
    if a.out:
        print(plot([a.porous, a.impermeable], a.t_start, a.out))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
