"""A permeable filter (``&slope role = 'filter'``, doc/porous.md): a row of particles
that stops bodies as a wall does and that the water does not see.

- Dry: the paper's sliding block (TC1b) on a filter slides exactly as on a solid slope
  (the contact acts on the outer row of either).
- Water passes: a block of water draining through stones crosses a filter laid across
  them at the same pore velocity, snapshot by snapshot, as without it.
- Under water: a block on a filter over stones comes to rest on it, no deeper than it
  rests dry; the water reaches under it and buoys it by Archimedes, the contact carries
  the rest of its weight, and the water under it keeps the hydrostatic pressure of the
  water beside it (the stones, not the water, carry the block).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, assert_ok, run_case
from post.io import FLOATING_BODY, FLUID, list_snapshots, read_csv, read_snapshot
from post.porous_cases import FILTER_BOX, FILTER_Y, drain_case, filter_case

pytestmark = pytest.mark.usefixtures("mbsph")

DP = 0.01


def test_dry_block_slides_on_a_filter_as_on_a_wall(tmp_path: Path) -> None:
    """TC1b (30 degrees, mu = 0.3): bodies.csv of the block on a one-row filter equals,
    value for value, that on the three-row solid slope of input/paper."""
    text = (ROOT / "input" / "paper" / "tc1b_sliding_noncohesive_spring.nml").read_text()
    rows = {}
    for role, layers in (("solid", 3), ("filter", 1)):
        t = text.replace("&slope x0", f"&slope role = '{role}', x0").replace("layers = 3", f"layers = {layers}")
        t = t.replace("out_dir = 'OUT/paper/tc1b_sliding_noncohesive_spring'", f"out_dir = 'OUT/{role}'")
        assert t.count(f"role = '{role}'") == 1 and f"OUT/{role}" in t
        (tmp_path / role).mkdir()
        proc, out = run_case(t, tmp_path / role)
        assert_ok(proc)
        rows[role] = read_csv(out / "bodies.csv")
    assert len(rows["solid"]["time"]) > 5
    disp = np.asarray(rows["solid"]["displacement"])
    assert disp[-1] > 0.2, "the block must slide for the comparison to mean anything"
    for name in ("x", "y", "angle", "u", "v", "omega", "fx_contact", "fy_contact", "fx_friction"):
        assert np.array_equal(rows["solid"][name], rows["filter"][name]), name


def test_water_drains_through_a_filter_unhindered(tmp_path: Path) -> None:
    """The draining block (D = 0.01 m) crosses a filter at y = 0.55 m between t = 0.25 and
    0.6 s: at every snapshot its mean pore velocity within 1e-6 relative, and its mean height
    within 0.001 dp, of the run without the filter."""
    runs = {}
    for name, extra in (("plain", ""), ("filter", "&slope role = 'filter', x0 = 0.0, y0 = 0.55, x1 = 0.4, "
                                                  "y1 = 0.55 /\n")):
        (tmp_path / name).mkdir()
        proc, out = run_case(drain_case(0.01) + extra, tmp_path / name)
        assert_ok(proc)
        rows = []
        for path in list_snapshots(out):
            s = read_snapshot(path)
            f = s.kind == FLUID
            rows.append((s.time, -s.velocity[f, 1].mean(), s.position[f, 1].mean(), s.position[f, 1].min(),
                         s.position[f, 1].max()))
        runs[name] = np.array(rows)
    a, b = runs["plain"], runs["filter"]
    assert a.shape == b.shape
    assert a[-1, 3] < 0.55 - 4 * DP and a[0, 4] > 0.55, "the water must reach 4 dp past the filter line"
    # the filter's pairs enter the viscous step limit: the snapshots fall up to a step
    # apart, so the plain run is read at the filter run's times
    b = b[1:][b[1:, 0] <= a[-1, 0]]
    assert len(b) >= 10
    plain = np.interp(b[:, 0], a[:, 0], a[:, 1])
    assert np.allclose(plain, b[:, 1], rtol=1e-6, atol=0.0), (plain, b[:, 1])
    plain = np.interp(b[:, 0], a[:, 0], a[:, 2])
    assert np.allclose(plain, b[:, 2], rtol=0.0, atol=1e-3 * DP), (plain - b[:, 2])


@pytest.fixture(scope="module")
def rest(tmp_path_factory: pytest.TempPathFactory):
    out = {}
    for wet in (True, False):
        proc, folder = run_case(filter_case(wet), tmp_path_factory.mktemp("wet" if wet else "dry"))
        assert_ok(proc)
        out[wet] = folder
    return out


@pytest.fixture(scope="module")
def rest_mdbc(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The wet case with the modified dynamic boundary, the porous cases' boundary."""
    text = filter_case(True).replace("&numerics ", "&numerics boundary = 'mdbc', ")
    assert "boundary = 'mdbc'" in text
    proc, folder = run_case(text, tmp_path_factory.mktemp("wet_mdbc"))
    assert_ok(proc)
    return folder


def test_block_rests_on_the_filter_under_water(rest) -> None:
    """At t = 2 s the block is at rest (speed below 1e-3 m/s) on the filter, no lower
    than it rests dry (it does not sink into the stones), and the water's force and the
    contact's together carry its weight within 1e-4 (their means from 1.5 to 2 s; 8e-7
    measured). The water's share is the next test's (a known failure with this, the
    dynamic boundary)."""
    wet = read_csv(rest[True] / "bodies.csv")
    dry = read_csv(rest[False] / "bodies.csv")
    assert abs(wet["time"][-1] - 2.0) < 0.01 and abs(dry["time"][-1] - 2.0) < 0.01
    speed = np.hypot(wet["u"][-1], wet["v"][-1])
    assert speed < 1e-3, speed
    y_wet, y_dry = wet["y"][-1], dry["y"][-1]
    assert y_dry > FILTER_Y, "the dry block must rest on the filter"
    assert y_wet >= y_dry, (y_wet, y_dry)
    w, hgt, rho = FILTER_BOX
    fluid, contact = late_forces(wet)
    weight = rho * 9.81 * w * hgt
    assert abs((fluid + contact) / weight - 1) < 1e-4, (fluid, contact, weight)


def late_forces(bodies) -> tuple[float, float]:
    """The block's mean vertical fluid and contact forces from 1.5 to 2 s [N/m]."""
    late = bodies["time"] >= 1.5 - 1e-9
    assert late.sum() >= 10
    return float(bodies["fy_fluid"][late].mean()), float(bodies["fy_contact"][late].mean())


@pytest.mark.xfail(strict=True, reason="with the dynamic boundary the water buoys the block dropped onto the "
                   "filter by 98.5 % of Archimedes (100.4 % over open water instead of stones), though the "
                   "water under it stands 4 to 5 % above hydrostatic: doc/porous.md, what does not work yet")
def test_water_buoys_the_block_on_the_filter_by_archimedes(rest) -> None:
    """The water, which reaches under the block through the filter, buoys it by
    Archimedes' rho g V within 1 % (the mean from 1.5 to 2 s)."""
    w, hgt, _ = FILTER_BOX
    fluid, _ = late_forces(read_csv(rest[True] / "bodies.csv"))
    archimedes = 1000.0 * 9.81 * w * hgt
    assert abs(fluid / archimedes - 1) < 0.01, (fluid, archimedes)


def test_water_buoys_the_block_on_the_filter_by_archimedes_with_mdbc(rest_mdbc: Path) -> None:
    """With the modified dynamic boundary: no water enters the block (it is solid
    particles through, its mid-line included), the block rests on the filter, and the
    water buoys it by Archimedes within 1 % (99.5 % measured; 88 % while the block's
    mid-line was a hollow that six water particles filled)."""
    s = read_snapshot(list_snapshots(rest_mdbc)[-1])
    body = s.position[s.kind == FLOATING_BODY]
    water = s.position[s.kind == FLUID]
    c = body.mean(axis=0)
    w, hgt, rho = FILTER_BOX
    inside = (np.abs(water[:, 0] - c[0]) < 0.5 * w) & (np.abs(water[:, 1] - c[1]) < 0.5 * hgt)
    assert not inside.any(), water[inside]
    bodies = read_csv(rest_mdbc / "bodies.csv")
    assert np.hypot(bodies["u"][-1], bodies["v"][-1]) < 1e-3
    fluid, contact = late_forces(bodies)
    archimedes = 1000.0 * 9.81 * w * hgt
    assert abs(fluid / archimedes - 1) < 0.01, (fluid, archimedes)
    assert abs((fluid + contact) / (rho * 9.81 * w * hgt) - 1) < 1e-4, (fluid, contact)


def test_water_under_the_block_keeps_its_pressure(rest) -> None:
    """At t = 2 s the mean pressure of the water within 3 cm of the floor under the block
    is within 1 % of that beside it, 0.15 m to either side."""
    s = read_snapshot(list_snapshots(rest[True])[-1])
    assert abs(s.time - 2.0) < 0.01
    f = s.kind == FLUID
    x, p = s.position[f], s.pressure[f]
    assert np.any(s.kind == FLOATING_BODY)

    def bed(xc: float) -> float:
        m = (np.abs(x[:, 0] - xc) < 0.03) & (x[:, 1] < 0.03)
        assert m.sum() >= 4
        return float(p[m].mean())
    under = bed(0.2)
    beside = 0.5 * (bed(0.05) + bed(0.35))
    assert abs(under / beside - 1) < 0.01, (under, beside)
