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
