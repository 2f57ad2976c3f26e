"""Bodies at rest on other bodies: a box on a fixed or prescribed body that has no mass
(the contact takes it as infinitely heavy), and the tilting table: a cube on a table
turned slowly about its centre, which must slide where tan(angle) = mu and tip where
a cube tips, at 45 degrees (doc/contact.md#tilting-table)."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_ok, run_case
from post.io import read_csv

pytestmark = pytest.mark.usefixtures("mbsph")

SIDE, DENSITY = 0.04, 1300.0


@pytest.mark.parametrize("motion", ["fixed", "prescribed"])
def test_box_rests_on_a_body_without_mass(tmp_path: Path, motion: str) -> None:
    """A body that is not floating may have no mass (doc/contact.md#the-pair-mass). A
    cube dropped from a hair above a massless fixed (or prescribed, at rest) plate:
    the run completes, and over the last 0.1 s of 0.5 s the plate's contact and
    friction forces carry the cube's weight within 1 % and the cube moves less than
    0.01 of its side. (The implicit step once divided the massless plate's rows by
    its zero mass, and the first step ended in NaN.)"""
    text = f"""\
&run case_name = 'massless', t_end = 0.5, dt_out = 0.5, energy_interval = 0.01, out_dir = 'OUT' /
&domain xmin = -0.2, xmax = 0.2, ymin = -0.1, ymax = 0.2 /
&numerics dp = 0.01 /
&body shape = 'box', x = 0.0, y = 0.0, width = 0.2, height = 0.04, motion = '{motion}' /
&body shape = 'box', x = 0.0, y = 0.0401, width = {SIDE}, height = {SIDE}, density = {DENSITY}, mu = 0.5 /
"""
    proc, out = run_case(text, tmp_path)
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    cube = d["body"] == 2
    t = d["time"][cube]
    late = t >= t[-1] - 0.1 - 1e-9
    weight = DENSITY * SIDE**2 * 9.81
    carried = d["fy_contact"][cube][late] + d["fy_friction"][cube][late]
    assert np.all(abs(carried / weight - 1.0) < 0.01), f"contact carries {carried / weight} of the weight"
    x, y = d["x"][cube][late], d["y"][cube][late]
    assert np.hypot(x - x[0], y - y[0]).max() < 0.01 * SIDE


def tilt_table(tmp_path: Path, n_across: int, mu: float, start_deg: float, end_deg: float,
               rate_deg_s: float = 1.0, contact: str = "",
               binary: Path | str | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A cube of side SIDE (n_across particles across) at rest on a massless table 0.24 m
    long, turned counter-clockwise about its centre from start_deg at rate_deg_s until
    end_deg. Returns the table's angle, the cube's turn against the table [deg], and
    its travel along the table [sides], at every row of bodies.csv. contact: variables
    of a &contact group (none: the defaults)."""
    dp = SIDE / n_across
    thick = max(0.04, 3 * dp)
    a0 = math.radians(start_deg)
    r = thick / 2 + SIDE / 2 + 0.01 * dp          # the cube's centre above the table's
    text = f"""\
&run case_name = 'tilt', t_end = {(end_deg - start_deg) / rate_deg_s}, dt_out = 100.0, energy_interval = 0.01,
     out_dir = 'OUT' /
&domain xmin = -0.3, xmax = 0.3, ymin = -0.3, ymax = 0.3 /
&numerics dp = {dp} /
{f"&contact {contact} /" if contact else ""}
&body shape = 'box', x = 0.0, y = 0.0, width = 0.24, height = {thick}, angle = {start_deg},
      motion = 'prescribed', omega = {math.radians(rate_deg_s)} /
&body shape = 'box', x = {-r * math.sin(a0)}, y = {r * math.cos(a0)}, width = {SIDE}, height = {SIDE},
      angle = {start_deg}, density = {DENSITY}, mu = {mu} /
"""
    proc, out = run_case(text, tmp_path, **({"binary": binary} if binary else {}))
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    table, cube = d["body"] == 1, d["body"] == 2
    ta = d["angle"][table]
    turn = np.degrees(d["angle"][cube] - ta)
    along = (d["x"][cube] * np.cos(ta) + d["y"][cube] * np.sin(ta)) / SIDE
    return np.degrees(ta), turn - turn[0], along - along[0]


def onset(angle: np.ndarray, measure: np.ndarray, bar: float) -> float:
    """The table angle at which |measure| first exceeds bar (inf: never)."""
    k = np.flatnonzero(np.abs(measure) > bar)
    return float(angle[k[0]]) if len(k) else math.inf


@pytest.mark.parametrize("n_across", [4, 8])
def test_cube_tips_at_45_degrees(tmp_path: Path, n_across: int) -> None:
    """A cube that cannot slide (mu = 1.5) tips over its lower edge when the table
    passes 45 degrees, the square's analytic limit: the cube turns by more than 2
    degrees against the table between 44 and 46 degrees, at 4 and at 8 particles
    across, with the table turning at 1 degree per second. (Before the contact's stiff
    core, the soft contact let the cube lean on its lower edge and fall at 23 degrees
    at 4 across and 30 at 8; doc/contact.md#tilting-table.)"""
    angle, turn, _ = tilt_table(tmp_path, n_across, 1.5, 40.0, 47.0)
    tip = onset(angle, turn, 2.0)
    assert 44.0 <= tip <= 46.0, f"tips at {tip:.2f} deg, not within 1 degree of 45"


@pytest.mark.parametrize("n_across", [4, 8])
def test_cube_slides_where_tan_is_mu(tmp_path: Path, n_across: int) -> None:
    """With mu = 0.5 the cube slides before it can tip, at atan(0.5) = 26.57 degrees:
    it moves 0.02 of its side along the table within 1 degree of that angle, and does
    not turn on the table (less than 2 degrees) until it has slid."""
    angle, turn, along = tilt_table(tmp_path, n_across, 0.5, 22.0, 30.0)
    slide = onset(angle, along, 0.02)
    limit = math.degrees(math.atan(0.5))
    assert abs(slide - limit) <= 1.0, f"slides at {slide:.2f} deg, atan(mu) = {limit:.2f}"
    assert onset(angle, turn, 2.0) >= slide, "the cube tipped before it slid"
