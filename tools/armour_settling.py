"""Settling of an armour layer in still water, as numbers: for each run folder the largest
move of any unit between two times (default 0.5 s and the end of the settling, 1 s), the
largest move from the start, and the layer's porosity (reported by the generator, and
recomputed from the poses in armour.csv by the independent check of tests/test_waves.py;
in 3D that is tests/test_3d.py's), the largest turn between the two times (3D: from the
quaternions), how many units move by more than 0.05 dn from the start, and how the moves
follow the units' tilts (their correlation with |tilt| from the slope).

    python tools/armour_settling.py OUT/breakwater_regular OUT/breakwater_irregular
    python tools/armour_settling.py --test-case    # the case of test_armour_settles (2 s), both placements

``--test-case`` runs build/mbsph (nice 10) on the still-water case of
``tests/test_waves.py::test_armour_settles`` in a temporary folder and reports it the same way
over 0.5 s to 2 s: the numbers behind that test's bars (0.1 dn, porosity within 0.02).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT))
from post.armour import read_armour  # noqa: E402
from post.io import read_csv  # noqa: E402
from test_waves import SETTLE, layer_porosity  # noqa: E402


def report(out: Path, t0: float, t1: float, label: str | None = None, bar: float = 0.05) -> None:
    layer = read_armour(out)
    dn = layer.dn
    b = read_csv(out / "bodies.csv")
    three = layer.z0 is not None
    if three:
        # the 2D recomputation does not hold for rows side by side; tests/test_3d.py's layer_check does it in 3D
        recomputed = "recomputed in 3D by tests/test_3d.py"
        reported, target = float(layer.meta["porosity"]), float(layer.meta["porosity_target"])
    else:
        measured, reported, target = layer_porosity(out / "armour.csv")
        recomputed = f"recomputed {measured:.4f}"
    late, early, turn = [], [], []
    for body in layer.body:
        m = (b["body"] == body) & (b["time"] <= t1 + 0.01)
        t = b["time"][m]
        pos = np.column_stack([b[c][m] for c in (("x", "y", "z") if three else ("x", "y"))])
        i = int(np.argmin(abs(t - t0)))
        late.append(np.linalg.norm(pos[i:] - pos[i], axis=1).max())
        early.append(np.linalg.norm(pos - pos[0], axis=1).max())
        if three:
            q = np.column_stack([b[c][m] for c in ("qw", "qx", "qy", "qz")])
            turn.append(float(np.max(2.0 * np.arccos(np.clip(np.abs(q[i:] @ q[i]), 0.0, 1.0)))))
        else:
            turn.append(float(np.max(np.abs(b["rotation"][m][i:] - b["rotation"][m][i]))))
    early = np.array(early)
    tilt = np.abs(layer.angle0 - float(layer.meta["slope_angle_deg"]))
    corr = np.corrcoef(early, tilt)[0, 1] if np.ptp(tilt) > 0 and np.ptp(early) > 0 else float("nan")
    print(f"{label or out}: {len(layer.body)} units of dn = {dn:g} m; porosity target {target:g}, reported {reported:.4f}, "
          f"{recomputed}; largest move {t0:g} s to {t1:g} s: {max(late) / dn:.4f} dn, largest turn {max(turn):.3g} rad; "
          f"largest move from the start: {early.max() / dn:.3f} dn, {int(np.sum(early > bar * dn))} units beyond "
          f"{bar:g} dn, their correlation with |tilt| {corr:.2f}")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("runs", type=Path, nargs="*", help="run folders holding armour.csv and bodies.csv")
    ap.add_argument("--from", dest="t0", type=float, default=0.5, help="start of the late window (s)")
    ap.add_argument("--to", dest="t1", type=float, default=None, help="end of the settling (s): 1, or 2 with --test-case")
    ap.add_argument("--test-case", action="store_true", help="run and report the case of test_armour_settles")
    a = ap.parse_args(argv)
    for run in a.runs:
        report(run, a.t0, 1.0 if a.t1 is None else a.t1)
    if a.test_case:
        for placement in ("regular", "irregular"):
            with tempfile.TemporaryDirectory() as tmp:
                (Path(tmp) / "case.nml").write_text(SETTLE.format(placement=placement))
                p = subprocess.run(["nice", "-n", "10", str(ROOT / "build" / "mbsph"), "case.nml"], cwd=tmp,
                                   capture_output=True, text=True)
                if p.returncode != 0:
                    print(p.stdout[-2000:], p.stderr[-2000:])
                    return 1
                report(Path(tmp) / "OUT", a.t0, 2.0 if a.t1 is None else a.t1, f"test_armour_settles, {placement}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
