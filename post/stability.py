"""Verdicts of the stability cases (input/stability/*.nml, run by `make stability`).

For each run folder: the largest interpenetration of two surfaces (energy.csv,
max_penetration, in dp), the largest rise of the bodies' energy over the start
(kinetic + potential), the creep of every body after `--settle` seconds, and a
one-line verdict against the bars: interpenetration <= 0.5 dp, no energy gain
(above 1e-3 of the start: rounding of the explicit contact steps), creep <= 0.1 dp
over the last fifth of the run. A Markdown table goes to --table.

    .venv/bin/python -m post.stability OUT/stability/* [--table doc/stability.md]
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from post.io import read_case, read_csv


def verdict(out: Path) -> dict:
    dp = float(read_case(out)["numerics"]["dp"])
    e = read_csv(out / "energy.csv")
    b = read_csv(out / "bodies.csv")
    total = e["body_kinetic"] + e["body_potential"]
    gain = float(np.max(total - total[0]))
    pen = float(np.max(e["max_penetration"])) / dp
    creep = 0.0
    settle = 0.8 * float(b["time"][-1])
    for k in np.unique(b["body"]):
        m = (b["body"] == k) & (b["time"] >= settle)
        if np.count_nonzero(m) > 1:
            creep = max(creep, float(np.ptp(b["x"][m]) + np.ptp(b["y"][m])) / dp)
    ok = pen <= 0.5 and gain <= 1e-3 * abs(total[0]) and creep <= 0.1
    return {"case": out.name, "t_end": float(e["time"][-1]), "penetration_dp": pen, "energy_gain": gain,
            "energy_start": float(total[0]), "creep_dp": creep, "pass": ok}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", type=Path, nargs="+")
    ap.add_argument("--table", type=Path, default=None)
    args = ap.parse_args(argv)
    rows = [verdict(r) for r in args.runs if (r / "energy.csv").exists()]
    lines = ["| case | simulated [s] | largest interpenetration [dp] | body energy gain [J/m] | creep, last fifth [dp] | verdict |",
             "|---|---|---|---|---|---|"]
    for r in rows:
        word = "pass" if r["pass"] else "FAIL"
        print(f"{r['case']}: {word}: interpenetration {r['penetration_dp']:.3f} dp (bar 0.5), energy gain "
              f"{r['energy_gain']:.3g} J/m of {r['energy_start']:.4g}, creep {r['creep_dp']:.3f} dp")
        lines.append(f"| {r['case']} | {r['t_end']:.2f} | {r['penetration_dp']:.3f} | {r['energy_gain']:.3g} | "
                     f"{r['creep_dp']:.3f} | {word} |")
    if args.table:
        args.table.write_text("# Stability of hard contact cases\n\nMade by `make stability` "
                              "(`.venv/bin/python -m post.stability OUT/stability/* --table doc/stability.md`);\n"
                              "bars: interpenetration <= 0.5 dp, no body energy gain (above 1e-3 of the start), "
                              "creep <= 0.1 dp over the last fifth of the run. The cases are input/stability/*.nml; "
                              "a coarse subset of them (shorter runs) is in `make test`, tests/test_stability.py.\n\n"
                              + "\n".join(lines) + "\n")
    return 0 if all(r["pass"] for r in rows) else 1


if __name__ == "__main__":
    raise SystemExit(main())
