"""A coarse subset of the hard cases of `make stability` (input/stability/), each held to
the bars its own case file states on its `! pass:` line (post/stability.py reads them):
interpenetration, energy gain and creep of bodies, lost particles, pressure noise and
kinetic-energy growth of still water, particles through a wall, armour movement, the
draft of a floating box against Archimedes, the time step against its stable limit, and
the refusal of a fixed step far above it. Shorter runs than `make stability` where the
full one would not fit the test budget; doc/stability.md has the long runs.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest

from conftest import ROOT, assert_ok, describe, run_case
from post import stability
from post.io import read_snapshot

pytestmark = pytest.mark.usefixtures("mbsph")


def case(name: str, t_end: float | None = None) -> str:
    """input/stability/<name>.nml (comments and `! pass:` line kept), run for t_end
    seconds (default: as in the file) into the test's folder."""
    text = (ROOT / "input" / "stability" / f"{name}.nml").read_text()
    if t_end is not None:
        text = re.sub(r"t_end = [0-9.]+", f"t_end = {t_end}", text)
    return re.sub(r"out_dir = '[^']*'", "out_dir = 'out'", text)


def judge(name: str, tmp_path: Path, mbsph: Path, t_end: float | None = None) -> dict:
    """Run the case, keep its exit status beside its output as `make stability` does,
    and assert every bar of its `! pass:` line."""
    proc, out = run_case(case(name, t_end), tmp_path, binary=mbsph)
    out.mkdir(exist_ok=True)
    (out / "exit_status").write_text(f"{proc.returncode}\n")
    (out / "stderr").write_text(proc.stderr)
    v = stability.verdict(out, tmp_path / "case.nml")
    assert v["pass"], f"{stability.line(v)}\n{describe(proc)}"
    return v


def test_heavy_box_dropped_on_a_light_one(tmp_path: Path, mbsph: Path) -> None:
    """Density 5000 dropped from 1 m (4.4 m/s at impact) on density 500 resting on the
    floor; 0.8 s covers the fall, the impact at 0.45 s and the settling."""
    judge("drop_heavy", tmp_path, mbsph, 0.8)


def test_wedge_on_its_tip_and_box_sliding_into_a_corner(tmp_path: Path, mbsph: Path) -> None:
    """A 37 degree wedge standing on its tip, and a box sliding at 1 m/s into the corner
    of the floor and a wall."""
    judge("wedge_tip", tmp_path, mbsph, 1.0)


def test_five_box_stack_in_still_water(tmp_path: Path, mbsph: Path) -> None:
    """The five-box stack under water for 2 s instead of 20 s: the creep is taken
    over the last 0.4 s, after the start has settled."""
    judge("stack5", tmp_path, mbsph, 2.0)


def test_still_water_stays_still(tmp_path: Path, mbsph: Path) -> None:
    """The still-water tank for 25 sqrt(H/g) = 3.6 s instead of 100: nothing lost, the
    bottom pressure's noise after 10 sqrt(H/g) within 2 % of rho g H, the kinetic energy
    of the last quarter not above that of the second."""
    judge("still_tank", tmp_path, mbsph, 3.6)


def test_impact_at_10_m_s_stays_out_of_the_wall(tmp_path: Path, mbsph: Path) -> None:
    """Two boxes at 10 m/s into a wall (the full case, 0.06 s): no body particle inside
    the wall in any snapshot, no energy gain, a normal end, the step within its CFL
    limit."""
    judge("impact10", tmp_path, mbsph)


def test_armour_layer_at_rest_in_still_water(tmp_path: Path, mbsph: Path) -> None:
    """The light irregular armour (Delta = 0.3, the demo scene's) of the coarse
    breakwater in still water for 4 s instead of 10: no unit moves more than 0.1 dn
    after 0.5 s. (Before the friction spring the upper units crept down the slope at
    a steady 0.03 dn/s and passed the bar after about 4 s.)"""
    judge("armour_still", tmp_path, mbsph, 4.0)


def test_cube_on_a_slope_sixteen_particles_across(tmp_path: Path, mbsph: Path) -> None:
    """A cube (density 1300, mu 0.8) on a 20 degree slope, 16 particles across: from
    0.5 s to 2 s it moves at most 0.1 of its side and turns by at most 1 degree."""
    judge("cube_slope_fine", tmp_path, mbsph)


def test_cube_on_a_slope_four_particles_across(tmp_path: Path, mbsph: Path) -> None:
    """The same cube at 4 particles across: it must neither slide nor tip (a cube tips
    only above 45 degrees; its particles' outline only above atan(3/4) = 37 degrees),
    so from 0.5 s to 2 s it moves at most 0.1 of its side and turns at most 1 degree.
    (Under a static term of 2 g the corner sank so far into the slope that the cube
    rolled down it like a wheel, doc/contact.md.)"""
    judge("cube_slope_coarse", tmp_path, mbsph)


def test_floating_box_four_particles_across(tmp_path: Path, mbsph: Path) -> None:
    """The coarse end of the resolution pair (the fine one, 40 across, is in
    `make stability` only): the run completes and the draft is Archimedes' within
    0.5 dp."""
    judge("float_coarse", tmp_path, mbsph)


def test_fixed_step_far_above_the_limit_is_refused(tmp_path: Path, mbsph: Path) -> None:
    """dt_fixed ten times the stable step: exit status 1 before the first step, a
    message naming dt_fixed and the stable step, and no NaN or wild density in what
    was written (the last snapshot is the untouched start)."""
    judge("dt_forced", tmp_path, mbsph)
    out = tmp_path / "out"
    assert read_snapshot(out / "snap_00001.h5").step == 0


def test_fixed_step_below_the_limit_is_taken(tmp_path: Path, mbsph: Path) -> None:
    """dt_fixed at half the stable step of the still tank: every step is that long
    (the step count is t_end / dt_fixed) and the water stays still as with the
    variable step (lost, pressure noise and kinetic energy within the case's bars)."""
    text = case("dt_forced").replace("dt_fixed = 2.0e-3", "dt_fixed = 1.0e-4").replace("t_end = 1.0", "t_end = 2.0")
    text = re.sub(r"! pass: .*", "! pass: exit_status == 0, lost <= 0, pressure_noise <= 0.02, "
                  "dt_ratio <= 1.0", text)
    text = text.replace("&box role = 'fluid'", "&gauge kind = 'pressure', x = 0.2, y = 0.015 /\n&box role = 'fluid'")
    proc, out = run_case(text, tmp_path, binary=mbsph)
    assert_ok(proc)
    (out / "exit_status").write_text("0\n")
    v = stability.verdict(out, tmp_path / "case.nml")
    assert v["pass"], stability.line(v)
    steps = [int(m) for m in re.findall(r"after (\d+) steps", (out / "run.log").read_text())]
    assert steps and steps[-1] == pytest.approx(2.0 / 1.0e-4, abs=1)
