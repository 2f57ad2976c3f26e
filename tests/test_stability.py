"""A coarse subset of the hard contact cases of `make stability` (input/stability/),
each held to the bars of post/stability.py: largest interpenetration of two surfaces
at most 0.5 dp, no gain of the bodies' kinetic plus potential energy (above 1e-3 of
the start, the rounding of the explicit contact steps), no creep beyond 0.1 dp over the
last fifth of the run, no NaN (the solver stops on one, so the run must end normally).
doc/stability.md has the long runs.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from conftest import ROOT, assert_ok, run_case
from post import stability

pytestmark = pytest.mark.usefixtures("mbsph")


def case(name: str, t_end: float) -> str:
    """input/stability/<name>.nml, run for t_end seconds into the test's folder."""
    text = (ROOT / "input" / "stability" / f"{name}.nml").read_text()
    text = re.sub(r"t_end = [0-9.]+", f"t_end = {t_end}", text)
    return re.sub(r"out_dir = '[^']*'", "out_dir = 'out'", text)


def assert_bars(out: Path) -> None:
    v = stability.verdict(out)
    assert v["penetration_dp"] <= 0.5, f"{v['case']}: interpenetration {v['penetration_dp']:.3f} dp (bar 0.5)"
    assert v["energy_gain"] <= 1e-3 * abs(v["energy_start"]), \
        f"{v['case']}: bodies gained {v['energy_gain']:.3g} J/m of {v['energy_start']:.4g}"
    assert v["creep_dp"] <= 0.1, f"{v['case']}: creep {v['creep_dp']:.3f} dp over the last fifth (bar 0.1)"


def test_heavy_box_dropped_on_a_light_one(tmp_path: Path, mbsph: Path) -> None:
    """Density 5000 dropped from 1 m (4.4 m/s at impact) on density 500 resting on the
    floor; 0.8 s covers the fall, the impact at 0.45 s and the settling."""
    proc, out = run_case(case("drop_heavy", 0.8), tmp_path, binary=mbsph)
    assert_ok(proc)
    assert_bars(out)


def test_wedge_on_its_tip_and_box_sliding_into_a_corner(tmp_path: Path, mbsph: Path) -> None:
    """A 37 degree wedge standing on its tip, and a box sliding at 1 m/s into the corner
    of the floor and a wall."""
    proc, out = run_case(case("wedge_tip", 1.0), tmp_path, binary=mbsph)
    assert_ok(proc)
    assert_bars(out)


def test_five_box_stack_in_still_water(tmp_path: Path, mbsph: Path) -> None:
    """The five-box stack under water for 2 s instead of 10 s: the creep is taken
    over the last 0.4 s, after the start has settled."""
    proc, out = run_case(case("stack5", 2.0), tmp_path, binary=mbsph)
    assert_ok(proc)
    assert_bars(out)
