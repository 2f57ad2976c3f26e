"""Waves and the breakwater: the wavemaker against linear theory (Biesel), the damping
zone's reflection, the armour layer at rest, and the inputs that must be refused.

The flumes are laid out by post/wave_cases.py in wavelengths of the target wave.
Heights are measured by post/waves.py (least-squares harmonics over whole periods in a
window after the wave front has passed the gauges; the incident wave separated from the
reflected one by a fit over all gauges). The wave-height flumes take minutes each and
are marked `long`: they run first, one per pytest-xdist worker (tests/conftest.py).
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest

from conftest import EXIT_INPUT, ROOT, assert_ok, describe, run_case
from test_bad_input import assert_no_output, error_line

pytestmark = pytest.mark.usefixtures("mbsph")

CASE = "case.nml"

# A short flume of constant depth 0.2 m with a piston, one gauge and a damping zone.
WAVE_BASE = """\
&run
  case_name = 'wave_input', t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1
/
&domain xmin = 0.0, xmax = 3.0, ymin = -0.1, ymax = 0.5 /
&fluid rho0 = 1000.0, gamma = 7.0 /
&numerics dp = 0.02 /
&box role = 'solid', xmin = 0.0, xmax = 3.0, ymin = -0.06, ymax = 0.0 /
&box role = 'solid', xmin = 2.94, xmax = 3.0, ymin = 0.0, ymax = 0.4 /
&box role = 'fluid', xmin = 0.2, xmax = 2.94, ymin = 0.0, ymax = 0.2 /
&wavemaker paddle = 'piston', wave = 'regular', x0 = 0.2, depth = 0.2, height = 0.02, period = 1.0 /
&gauge kind = 'elevation', x = 1.0 /
&damping x0 = 2.0, x1 = 2.94 /
"""

# A breakwater flume of the paper's profile at a coarse scale, with its armour.
BW_BASE = """\
&run
  case_name = 'bw_input', t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1
/
&domain xmin = 0.0, xmax = 2.2, ymin = -0.05, ymax = 0.5 /
&fluid rho0 = 1000.0, gamma = 7.0 /
&numerics dp = 0.01 /
&breakwater x_start = 0.05, depth = 0.3, toe_depth = 0.1, flat_length = 0.2, foreshore_angle = 10.0,
  slope_cot = 1.5, rc = 0.065, crest_width = 0.15 /
&armour placement = 'regular', dn = 0.04, density = 2200.0 /
"""


def edit(old: str, new: str, text: str) -> str:
    assert text.count(old) == 1, f"the test's own edit {old!r} does not match once"
    return text.replace(old, new)


BAD = {
    # T = 1 s in 0.2 m: L = 1.27 m, Miche's limit 0.142 L tanh(kd) = 0.137 m
    "wave_breaks_at_paddle": (edit("height = 0.02", "height = 0.18", WAVE_BASE), "wavemaker", "height",
                              ("breaks", "0.142")),
    # T = 4 s in 0.2 m: kd = 0.22, the piston must move H / 0.22 = 0.45 m, more than 0.8 depth
    "stroke_too_long": (edit("height = 0.02, period = 1.0", "height = 0.1, period = 4.0", WAVE_BASE),
                        "wavemaker", "height", ("stroke", "max_stroke")),
    "gauge_outside_domain": (edit("x = 1.0 /", "x = 3.5 /", WAVE_BASE), "gauge #1", "x", ("outside",)),
    "paddle_outside_domain": (edit("x0 = 0.2,", "x0 = 0.05,", WAVE_BASE), "wavemaker", "x0", ("&domain",)),
    "wavemaker_no_depth": (edit("depth = 0.2,", "", WAVE_BASE), "wavemaker", "depth", ("(0",)),
    "wave_kind_unknown": (edit("wave = 'regular'", "wave = 'solitary'", WAVE_BASE), "wavemaker", "wave",
                          ("'irregular'",)),
    "signal_file_missing": (edit("wave = 'regular'", "wave = 'file', signal_file = 'no_such_signal.txt'",
                                 WAVE_BASE), "wavemaker", "signal_file", ("no_such_signal.txt",)),
    "damping_outside_domain": (edit("x1 = 2.94", "x1 = 3.5", WAVE_BASE), "damping", "x0, x1", ("inside",)),
    # the absorber needs the wave the paddle makes; a wave with an end needs room for its ramps
    "absorb_with_signal_file": (edit("wave = 'regular'", "wave = 'file', signal_file = 's.txt', absorb = .true.",
                                     WAVE_BASE), "wavemaker", "absorb", ("'regular'", "'irregular'")),
    "wave_shorter_than_its_ramps": (edit("period = 1.0 /", "period = 1.0, duration = 3.0 /", WAVE_BASE),
                                    "wavemaker", "duration", ("ramps", "4.00000")),
    "wave_with_an_end_but_no_ramp": (edit("period = 1.0 /", "period = 1.0, duration = 3.0, ramp_periods = 0.0 /",
                                          WAVE_BASE), "wavemaker", "duration", ("ramp",)),
    "absorb_with_second_order": (edit("period = 1.0 /", "period = 1.0, second_order = .true., absorb = .true. /",
                                      WAVE_BASE), "wavemaker", "absorb", ("second_order",)),
    "armour_too_many_units": (edit("density = 2200.0 /", "density = 2200.0, n_units = 40 /", BW_BASE), "armour",
                              "n_units", ("at most", "fit")),
    "armour_unit_too_big": (edit("dn = 0.04", "dn = 0.5", BW_BASE), "armour", "dn", ("fits",)),
    "armour_without_breakwater": (BW_BASE.replace(BW_BASE[BW_BASE.index("&breakwater"):
                                                          BW_BASE.index("&armour")], ""),
                                  "armour", "", ("&breakwater",)),
    "breakwater_beyond_domain": (edit("xmax = 2.2", "xmax = 1.6", BW_BASE), "breakwater", "crest_width",
                                 ("xmax",)),
    # a porous core: its choice, porosities in (0, 1), an underlayer that fits under the
    # crest, a stone size without &armour, numerics the pores work with
    "core_unknown": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'rubble' /", BW_BASE), "breakwater",
                     "core", ("'impermeable'", "'porous'")),
    "core_porosity_one": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'porous', core_porosity = 1.0 /",
                               BW_BASE), "breakwater", "core_porosity", ("(0.00000, 1.00000)",)),
    "underlayer_porosity_zero": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'porous', "
                                      "underlayer_porosity = 0.0 /", BW_BASE), "breakwater", "underlayer_porosity",
                                 ("(0.00000, 1.00000)",)),
    "underlayer_past_the_crest": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'porous', "
                                       "underlayer_thickness = 0.2 /", BW_BASE).replace(
                                           "&numerics dp = 0.01 /", "&numerics dp = 0.01, h_over_dp = 2.0 /"),
                                  "breakwater", "underlayer_thickness", ("crest",)),
    "porous_core_without_stone_size": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'porous' /",
                                            BW_BASE[:BW_BASE.index("&armour")]), "breakwater", "underlayer_d50",
                                       ("&armour", "(0, 10]")),
    "porous_core_with_gradient_correction": (edit("crest_width = 0.15 /", "crest_width = 0.15, core = 'porous' /",
                                                  BW_BASE).replace("&numerics dp = 0.01 /", "&numerics dp = 0.01, "
                                                                   "kernel_correction = 'gradient' /"),
                                             "numerics", "kernel_correction", ("core = 'porous'", "'none'")),
}


@pytest.mark.parametrize("name", list(BAD))
def test_bad_wave_input(name: str, tmp_path: Path, mbsph: Path) -> None:
    text, group, var, words = BAD[name]
    proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, f"expected exit code {EXIT_INPUT}\n{describe(proc)}"
    msg = error_line(proc)
    where = f"&{group}: " + (f"{var}: " if var else "")
    assert where in msg, f"the message should name {where!r}:\n{msg}"
    for w in words:
        assert w in msg, f"the message should mention {w!r}:\n{msg}"
    assert_no_output(tmp_path)


@pytest.mark.parametrize("text", [WAVE_BASE, BW_BASE], ids=["flume", "breakwater"])
def test_base_cases_run(text: str, tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    assert (out / "snap_00000.h5").is_file()


# ----------------------------------------------------------------- gauges at rest

def read_gauges_csv(out: Path) -> dict:
    """The columns of ``gauges.csv``, by the post package's reader of that file."""
    from post.waves import read_gauges
    return read_gauges(out / "gauges.csv")[2]


def test_gauges_in_still_water(tmp_path: Path, mbsph: Path) -> None:
    """Before the paddle has moved the water (the ramp keeps it still for the first
    tenths of a second), an elevation gauge reads the still-water level and a pressure
    gauge the hydrostatic pressure."""
    text = edit("t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1",
                "t_end = 0.1, dt_out = 0.1, out_dir = 'OUT', gauge_interval = 0.02", WAVE_BASE)
    text += "&gauge kind = 'pressure', x = 1.5, y = 0.05 /\n"
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    d = read_gauges_csv(out)
    dp, depth, rho, g = 0.02, 0.2, 1000.0, 9.81
    assert len(d["time"]) >= 5
    # the still-water line within 0.05 dp (1 mm)
    assert abs(d["eta_1"]).max() <= 0.05 * dp, d["eta_1"]
    # rho g (d - y): exact in the hydrostatic start (0.5 %); then the weakly compressible
    # pressure carries acoustic noise of a few per cent, and its mean sits within 3 %
    # (the hydrostatic tank's bed pressure at this resolution: doc/validation.md)
    p_exact = rho * g * (depth - 0.05)
    assert abs(d["p_2"][0] / p_exact - 1.0) <= 0.005, d["p_2"]
    assert abs(d["p_2"].mean() / p_exact - 1.0) <= 0.03, d["p_2"]


# ------------------------------------------------------------- armour at rest

SETTLE = """\
&run case_name = 'settle', t_end = 2.0, dt_out = 0.5, energy_interval = 0.05, out_dir = 'OUT' /
&domain xmin = 0.0, xmax = 1.3, ymin = -0.05, ymax = 0.4 /
&fluid rho0 = 1000.0, gamma = 7.0 /
&numerics dp = 0.01 /
&breakwater x_start = 0.05, depth = 0.2, toe_depth = 0.2, flat_length = 0.25, slope_cot = 1.5, rc = 0.065,
  crest_width = 0.1 /
&armour placement = '{placement}', dn = 0.04, density = 2200.0, seed = 3 /
"""


def layer_porosity(armour_csv: Path) -> tuple[float, float, float]:
    """Porosity of the layer recomputed from the units' starting poses (squares of side dn
    on a slope of the angle in the file), independently of the generator: the void
    fraction of the band of thickness dn above the slope from the toe unit's upper face
    to the end of the last unit, sampled on a fine grid. Returns (measured, reported, target)."""
    import numpy as np
    from post.armour import read_armour
    layer = read_armour(armour_csv)
    meta = layer.meta
    dn = layer.dn
    alpha = np.radians(float(meta["slope_angle_deg"]))
    t = np.array([np.cos(alpha), np.sin(alpha)])
    n = np.array([-t[1], t[0]])
    c = np.stack([layer.x0, layer.y0], axis=1)
    phi = np.radians(layer.angle0) - alpha
    # slope coordinates of the centres; the slope line passes under the lowest corner
    s_c = c @ t
    nu_c = c @ n
    half = 0.5 * dn * (np.abs(np.cos(phi)) + np.abs(np.sin(phi)))
    nu0 = np.min(nu_c - half)                       # the slope line
    s_lo = s_c[0] - half[0]                         # the toe unit's upper face
    s_hi = s_c[-1] + half[-1]
    ds = dn / 80.0
    ss = np.arange(s_lo + ds / 2, s_hi, ds)
    nn = nu0 + np.arange(ds / 2, dn, ds)
    S, N = np.meshgrid(ss, nn, indexing="ij")
    inside = np.zeros(S.shape, bool)
    for k in range(len(s_c)):
        du, dv = S - s_c[k], N - nu_c[k]
        a = np.cos(phi[k]) * du + np.sin(phi[k]) * dv
        b = -np.sin(phi[k]) * du + np.cos(phi[k]) * dv
        inside |= (np.abs(a) <= dn / 2) & (np.abs(b) <= dn / 2)
    return 1.0 - inside.mean(), float(meta["porosity"]), float(meta["porosity_target"])


def moves_after(out: Path, t0: float, t_end: float) -> dict[int, float]:
    """Per armour unit (body number), the largest distance its centre moved from where it
    was at t0 to the end of the run, which must reach t_end."""
    import numpy as np
    from post.armour import read_armour
    from post.io import read_csv
    d = read_csv(out / "bodies.csv")
    moves = {}
    for b in read_armour(out / "armour.csv").body:
        m = d["body"] == b
        t, x, y = d["time"][m], d["x"][m], d["y"][m]
        assert t[-1] == pytest.approx(t_end, abs=1e-3)
        i = int(np.argmin(abs(t - t0)))
        moves[int(b)] = float(np.hypot(x[i:] - x[i], y[i:] - y[i]).max())
    return moves


@pytest.mark.parametrize("placement,target", [("regular", 0.21), ("irregular", 0.25)])
def test_armour_settles(placement: str, target: float, tmp_path: Path, mbsph: Path) -> None:
    """The armour layer in still water (the paper's first run): after the first 0.5 s
    no unit moves more than 0.1 dn to the end of a 2 s run; the layer's porosity,
    recomputed from the poses, within 0.02 of the target."""
    proc, out = run_case(SETTLE.format(placement=placement), tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    measured, reported, tgt = layer_porosity(out / "armour.csv")
    assert tgt == pytest.approx(target)
    assert abs(measured - target) <= 0.02, f"porosity {measured:.4f} (reported {reported:.4f}), target {target}"
    assert abs(reported - measured) <= 0.01
    dn = 0.04
    moves = moves_after(out, 0.5, 2.0)
    assert len(moves) >= 6
    for b, move in moves.items():
        assert move <= 0.1 * dn, f"unit (body {b}) moved {move * 1e3:.2f} mm after 0.5 s (bar {0.1 * dn * 1e3} mm)"


def submerged_normal_forces(out: Path, t0: float, dn: float = 0.04, depth: float = 0.2) -> dict[int, float]:
    """Per fully submerged armour unit of the settling flume (1:1.5 slope), the mean fluid
    force normal to the slope from t0 to the end [N/m], positive away from the slope."""
    import math

    import numpy as np
    from post.armour import read_armour
    from post.io import read_csv
    alpha = math.atan(1 / 1.5)
    normal = np.array([-math.sin(alpha), math.cos(alpha)])
    d = read_csv(out / "bodies.csv")
    layer = read_armour(out / "armour.csv")
    forces = {}
    for b, y in zip(layer.body, layer.y0):
        if y + dn / math.sqrt(2) >= depth:
            continue
        m = (d["body"] == b) & (d["time"] >= t0)
        forces[int(b)] = float((normal[0] * d["fx_fluid"][m] + normal[1] * d["fy_fluid"][m]).mean())
    return forces


# The settling flume with a porous core and underlayer (doc/porous.md): the pores need
# h = 2 dp and no gradient correction. Gauge 1 in the core under the crest, 2 at its bed.
POROUS_SETTLE = SETTLE.replace("&numerics dp = 0.01 /", "&numerics dp = 0.01, h_over_dp = 2.0 /").replace(
    "crest_width = 0.1 /", "crest_width = 0.1, core = 'porous' /") + """\
&gauge kind = 'elevation', x = 0.776 /
&gauge kind = 'pressure', x = 0.9, y = 0.02 /
"""


@pytest.fixture(scope="module")
def porous_settle(tmp_path_factory: pytest.TempPathFactory, mbsph: Path) -> Path:
    assert POROUS_SETTLE.count("core = 'porous'") == 1 and "h_over_dp = 2.0" in POROUS_SETTLE
    folder = tmp_path_factory.mktemp("porous_settle")
    proc, out = run_case(POROUS_SETTLE.format(placement="regular"), folder, binary=mbsph, name=CASE)
    assert_ok(proc)
    return out


def test_armour_rests_on_a_porous_core(porous_settle: Path) -> None:
    """The regular layer on the filter of a porous underlayer, in still water that fills
    the core, for 2 s: the pores hold water of the stones' porosity (n = 0.4); the filter
    stops the units (no particle of a unit comes within 0.25 dp of the slope line: they
    rest 0.5 dp above it); and the water under the fully submerged units presses on them:
    the mean fluid force normal to the slope, from 1 to 2 s, points away from the slope on
    each (on an impermeable core, with no water under them, it presses them onto the
    slope with one to three times their submerged weight; doc/porous.md)."""
    import math

    import numpy as np
    from post.io import FILTER, FLOATING_BODY, list_snapshots, read_snapshot
    out = porous_settle
    dn, dp, depth = 0.04, 0.01, 0.2       # the flume's unit size, spacing and water depth
    first = read_snapshot(list_snapshots(out)[0])
    assert np.count_nonzero(first.kind == FILTER) > 0
    core = (first.position[:, 0] > 0.78) & (first.position[:, 0] < 0.95) & (first.position[:, 1] < 0.1) & \
        (first.kind == 1)
    assert core.sum() > 50
    assert np.allclose(first.datasets["porosity"][core], 0.4, atol=1e-9)
    # the slope line runs from the toe (x_start + flat_length, 0) at 1:1.5
    alpha = math.atan(1 / 1.5)
    normal = np.array([-math.sin(alpha), math.cos(alpha)])
    last = read_snapshot(list_snapshots(out)[-1])
    assert last.time == pytest.approx(2.0, abs=1e-3)
    units = last.kind == FLOATING_BODY
    height = (last.position[units] - np.array([0.3, 0.0])) @ normal
    assert height.min() >= 0.25 * dp, height.min()
    forces = submerged_normal_forces(out, 1.0, dn, depth)
    assert len(forces) >= 3
    for b, fn in forces.items():
        assert fn > 0.0, (b, fn)


def test_units_that_friction_holds_stay_on_a_porous_core(tmp_path: Path, mbsph: Path) -> None:
    """Units whose friction holds them on the slope with a wide margin (density 5000
    kg/m3, mu = 2: mu cos(alpha) - sin(alpha) = 1.11 of the submerged weight) rest on the
    porous core's filter in still water: from 1 s to the end of the 2 s run no unit
    moves more than 0.02 dn (the light units of the flume, whose margin is a tenth of
    their submerged weight, slide: doc/porous.md). The first second is the layer's
    settling: one unit (body 3) closes its placement gap, 0.22 dn, by 0.7 s (by 0.5 s
    while the pore water started with 5.6 % too much mass; the same final place)."""
    text = POROUS_SETTLE.format(placement="regular").replace("density = 2200.0", "density = 5000.0, mu = 2.0")
    assert "mu = 2.0" in text
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    dn = 0.04
    for b, move in moves_after(out, 1.0, 2.0).items():
        assert move <= 0.02 * dn, f"unit (body {b}) moved {move / dn:.3f} dn after 1 s"


@pytest.fixture(scope="module")
def porous_settle_mdbc(tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    """The settling flume on the porous core with the modified dynamic boundary."""
    text = POROUS_SETTLE.format(placement="regular").replace("h_over_dp = 2.0 /",
                                                             "h_over_dp = 2.0, boundary = 'mdbc' /")
    assert "boundary = 'mdbc'" in text
    proc, out = run_case(text, tmp_path_factory.mktemp("porous_settle_mdbc"), binary=mbsph, name=CASE)
    assert_ok(proc)
    return proc, out


def unit_buoyancy(out: Path, near_bed: bool) -> dict[int, float]:
    """The fully submerged units' mean fluid force normal to the slope from 1 to 2 s over
    Archimedes' share rho g dn^2 cos(alpha); near_bed: only the units whose kernel support
    (2h = 0.04 m below their lowest corner) reaches the impermeable bed, else only the others."""
    import math

    from post.armour import read_armour
    dn, depth, rho, g, support = 0.04, 0.2, 1000.0, 9.81, 0.04
    alpha = math.atan(1 / 1.5)
    archimedes = rho * g * dn * dn * math.cos(alpha)
    layer = read_armour(out / "armour.csv")
    low = {int(b): y - 0.5 * dn * (math.cos(alpha) + math.sin(alpha)) for b, y in zip(layer.body, layer.y0)}
    return {b: fn / archimedes for b, fn in submerged_normal_forces(out, 1.0, dn, depth).items()
            if (low[b] < support) == near_bed}


def test_armour_rests_on_a_porous_core_with_mdbc(porous_settle_mdbc) -> None:
    """The flume's light units (friction holds them with a tenth of their submerged weight)
    on the porous core's filter in still water, with the modified dynamic boundary (the
    solids among the stones take the pore water's density, rho_s / n; doc/porous.md): no
    water leaks through the solids; from 1 s to the end of the 2 s run no unit moves
    more than 0.02 dn (0.0003 dn measured; with the dynamic boundary 0.09 dn). The first second is the layer's settling: three units close
    their placement gaps, 0.31 to 0.63 dn, by 0.7 s. And the water under each fully
    submerged unit clear of the bed carries it as Archimedes says: the mean fluid force
    normal to the slope from 1 to 2 s within 10 % of rho g dn^2 cos(alpha), the
    buoyancy's share along the normal (1 to 4 % below it measured); one unit, the
    toe's, is near the bed (the known failure below)."""
    proc, out = porous_settle_mdbc
    assert "removed" not in proc.stdout, describe(proc)
    dn = 0.04
    for b, move in moves_after(out, 1.0, 2.0).items():
        assert move <= 0.02 * dn, f"unit (body {b}) moved {move / dn:.3f} dn after 1 s"
    assert len(unit_buoyancy(out, near_bed=True)) == 1
    ratios = unit_buoyancy(out, near_bed=False)
    assert len(ratios) >= 3
    for b, r in ratios.items():
        assert abs(r - 1.0) <= 0.10, (b, r)


@pytest.mark.xfail(strict=True, reason="known: a body within the kernel's support of a fixed wall gets no "
                   "pressure from the wall's share of its support (8 % for the toe unit, buoyed by 89 %; "
                   "doc/porous.md, What does not work yet)")
def test_toe_unit_is_buoyed_as_archimedes_says(porous_settle_mdbc) -> None:
    """The toe unit, whose kernel support reaches the impermeable bed, buoyed within 10 %
    of Archimedes' share as the units above it."""
    _, out = porous_settle_mdbc
    for b, r in unit_buoyancy(out, near_bed=True).items():
        assert abs(r - 1.0) <= 0.10, (b, r)


@pytest.mark.xfail(strict=True, reason="known: the pore water of the core sinks steadily below the open water, "
                   "0.11 dp by 0.5 s and 0.44 dp as the mean of 1 to 2 s, its cause not yet found (the bed "
                   "pressure holds: +0.3 %; doc/porous.md, What does not work yet)")
def test_porous_core_stands_level_with_the_sea(porous_settle: Path) -> None:
    """Communicating vessels: the water in the core (gauge under the crest, mean of 1 to
    2 s) at the still-water level within 0.25 dp, and the pressure at the core's bed
    hydrostatic (mean of 1 to 2 s within 2 % of rho g (d - y))."""
    import numpy as np
    dp, depth = 0.01, 0.2
    g = read_gauges_csv(porous_settle)
    late = g["time"] >= 1.0
    assert late.sum() >= 40
    p_exact = 1000.0 * 9.81 * (depth - 0.02)
    assert abs(g["p_2"][late].mean() / p_exact - 1.0) <= 0.02, (g["p_2"][late].mean(), p_exact)
    assert abs(np.nanmean(g["eta_1"][late])) <= 0.25 * dp, g["eta_1"][late]


@pytest.mark.parametrize("paddle", ["piston", "flap"])
def test_paddle_follows_signal_file(paddle: str, tmp_path: Path, mbsph: Path) -> None:
    """A paddle driven by a signal file (time, displacement at the still-water level) is
    where the signal puts it: a piston's particles all moved by X(t); a flap's turned
    about the hinge at the bed by atan(X/d), so a particle at height y above the hinge
    moved by y sin(theta) and dropped by y (1 - cos(theta))."""
    import math

    import numpy as np
    amp, per, t_end, depth = 0.01, 1.0, 0.3, 0.2
    ts = np.arange(0.0, 2.0, 0.005)
    np.savetxt(tmp_path / "paddle.txt", np.c_[ts, amp * np.sin(2 * np.pi * ts / per)],
               header="time [s], displacement [m]")
    text = edit("t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1",
                f"t_end = {t_end}, dt_out = {t_end}, out_dir = 'OUT'", WAVE_BASE)
    text = edit("paddle = 'piston', wave = 'regular', x0 = 0.2, depth = 0.2, height = 0.02, period = 1.0",
                f"paddle = '{paddle}', wave = 'file', signal_file = 'paddle.txt', x0 = 0.2, depth = {depth}",
                text)
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    snaps = sorted(out.glob("snap_*.h5"))

    def moving(path):
        from post.io import read_snapshot
        snap = read_snapshot(path)  # particles in id order
        return snap.time, snap.position[snap.kind == 3]
    t0, x0 = moving(snaps[0])
    t1, x1 = moving(snaps[-1])
    assert t1 == pytest.approx(t_end, abs=1e-3)
    X = amp * np.sin(2 * np.pi * t1 / per)
    if paddle == "piston":
        assert np.abs(x1[:, 0] - x0[:, 0] - X).max() <= 1e-6
        assert np.abs(x1[:, 1] - x0[:, 1]).max() <= 1e-12
    else:
        hinge = np.array([0.2, 0.0])
        th = math.atan2(X, depth)
        r = x0 - hinge
        expect = hinge + np.c_[r[:, 0] * math.cos(th) + r[:, 1] * math.sin(th),
                               -r[:, 0] * math.sin(th) + r[:, 1] * math.cos(th)]
        assert np.abs(x1 - expect).max() <= 1e-6


# ------------------------------------------------------- waves against linear theory

# Numerics of the wave tests: Wendland kernel, kernel gradient correction (it halves the
# decay of the wave along the flume at this resolution), artificial viscosity 0.005, Fourtakas
# density diffusion; 20 particles over the depth. doc/waves.md gives the measured heights
# at other settings.
WAVE_NUMERICS = "  kernel_correction = 'gradient'"


def flume(kh: float, tmp_path: Path, **kw):
    from post.wave_cases import flume_case
    f = flume_case(kh, out_dir="OUT", extra_numerics=WAVE_NUMERICS, **kw)
    return f, f.text.replace("alpha = 0.01", "alpha = 0.005")


def measured(out: Path, f, gauge: int, periods: float = 3.0):
    """First-harmonic height and period at a gauge over the last `periods` periods of the
    run (the wave front, travelling at the group speed, passed the gauge at least one
    period before the window starts: flume_case sets t_end so)."""
    from post.waves import regular_wave_height
    d = read_gauges_csv(out)
    t, eta = d["time"], d[f"eta_{gauge}"]
    return regular_wave_height(t, eta, f.period, t_start=f.t_end - periods * f.period, t_end=f.t_end)


def test_damping_zone_reflection(tmp_path: Path, mbsph: Path) -> None:
    """The damping zone (1.5 wavelengths, strength 10/s) reflects less than 10 % of a
    regular wave (kh = 1.7): two gauges a quarter wavelength apart in front of the zone,
    Goda and Suzuki's separation over the last three periods, after the wave reflected
    at the far end of the zone has come back past the gauges."""
    from post.wave_cases import flume_case
    from post.waves import reflection_two_gauge
    kh, depth = 1.7, 0.25
    probe = flume_case(kh, depth=depth, dp=depth / 15, gauges_at=(1.0, 1.25), damping_len=1.5)
    x_end = probe.damping[1]
    x1 = probe.gauges[0]
    t_end = 2.0 * probe.period + (2.0 * (x_end - probe.x0) - (x1 - probe.x0)) / probe.group_speed \
        + 3.0 * probe.period
    # 15 particles over the depth: the zone's reflection, not the wave's height, is measured
    f, text = flume(kh, tmp_path, depth=depth, dp=depth / 15, steepness=0.03, gauges_at=(1.0, 1.25),
                    damping_len=1.5, t_end=t_end)
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    d = read_gauges_csv(out)
    m = d["time"] >= t_end - 3.0 * f.period
    r = reflection_two_gauge(d["time"][m], d["eta_1"][m], d["eta_2"][m], f.gauges[1] - f.gauges[0], depth,
                             frequency=1.0 / f.period)
    # the incident wave is there (the measurement means something) ...
    assert r.Hm0_i > 0.5 * f.height
    # ... and the zone returns less than a tenth of it
    assert r.Kr < 0.10, f"Kr = {r.Kr:.3f}"




# ------------------------------------------------------------ the absorbing paddle

@pytest.mark.parametrize("absorb", [True, False], ids=["absorbing", "rigid"])
def test_absorbing_paddle_reflection(absorb: bool, tmp_path: Path, mbsph: Path) -> None:
    """A regular wave (kh = 1.2, H/L = 0.02) made by a piston wall 3.5 wavelengths away
    runs to the paddle, which rests. Two gauges a quarter wavelength in front of it
    separate the wave that comes in from the one it returns (Goda and Suzuki) over four
    periods, before the far end's own reflection comes back: the absorbing paddle returns
    less than 5 % of the wave; the same paddle not absorbing returns more than 85 % (the
    measurement sees a reflection; the rest is the wave's loss on its way, 12.5
    particles over the depth)."""
    from post.wave_cases import absorption_case
    from post.waves import paddle_reflection_coefficient
    f = absorption_case(1.2, dp=0.25 / 12.5, absorb=absorb, out_dir="OUT")
    proc, out = run_case(f.text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    d = read_gauges_csv(out)
    m = (d["time"] >= f.window[0]) & (d["time"] <= f.window[1])
    r = paddle_reflection_coefficient(d["time"][m], d["eta_1"][m], d["eta_2"][m], f.gauges[1] - f.gauges[0],
                                      f.depth, f.period)
    # the wave came in at about its height
    assert r.Hm0_i > 0.8 * f.height, f"incoming {r.Hm0_i:.4f} m, the wave {f.height:.4f} m"
    if absorb:
        assert r.Kr < 0.05, f"Kr = {r.Kr:.3f}"
    else:
        assert r.Kr > 0.85, f"Kr = {r.Kr:.3f}"


def test_absorbing_paddle_stops_at_its_stroke(tmp_path: Path, mbsph: Path) -> None:
    """An absorbing paddle that the waves coming back would push beyond max_stroke/2
    (here 5 mm, against the about 11 mm its absorption asks for) stops the run with
    exit status 1, naming max_stroke, and leaves a last snapshot; before it stops, it
    has moved by more than a millimetre (it was absorbing)."""
    from post.wave_cases import absorption_case
    f = absorption_case(1.2, dp=0.25 / 10, absorb=True, out_dir="OUT")
    head, sep, tail = f.text.partition("&wavemaker")
    tail = re.sub(r"height = [0-9.]+", "height = 0.002", tail, count=1)
    tail = tail.replace("  absorb = .true.", "  absorb = .true., max_stroke = 0.01")
    proc, out = run_case(head + sep + tail, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == 1, describe(proc)
    msg = error_line(proc)
    assert "max_stroke/2 = " in msg and "absorbing paddle" in msg, msg
    import h5py
    from conftest import snapshots
    snaps = snapshots(out)
    assert len(snaps) >= 2, "a last snapshot is written before the stop"
    pad_x = []
    for s in (snaps[0], snaps[-1]):
        with h5py.File(s) as f:
            pad_x.append(f["position"][:, 0][f["kind"][:] == 3].mean())
    assert abs(pad_x[1] - pad_x[0]) > 1e-3, f"the paddle moved {abs(pad_x[1] - pad_x[0]):.2e} m before the stop"


def test_absorbing_paddle_makes_the_same_wave(tmp_path: Path, mbsph: Path) -> None:
    """The absorber must not take from the wave the paddle makes: in a flume with a
    damping zone, the first-harmonic height 1 and 1.5 wavelengths from an absorbing
    paddle is at least that of the same paddle not absorbing less 2 % (kh = 1.2, 12.5
    particles over the depth; both runs the same numerics, so the wave's decay cancels:
    the dynamic boundary, which an absorbing paddle keeps among the wave defaults). Its
    gauge reads the paddle's wave against the target's (Biesel at the gauge, the
    evanescent modes included): where the water makes less than Biesel (6 to 9 % here,
    the wave's loss at 12.5 particles), the absorber takes the shortfall for a wave
    coming in and makes up part of it, never beyond the target (within 2 %)."""
    heights = {}
    for absorb in (False, True):
        f, text = flume(1.2, tmp_path, depth=0.25, dp=0.02, gauges_at=(1.0, 1.5), damping_len=1.0,
                        extra_wavemaker="  absorb = .true." if absorb else "")
        text = edit("  kernel_correction = 'gradient'", "  kernel_correction = 'gradient', boundary = 'dynamic'", text)
        run_dir = tmp_path / str(absorb)
        run_dir.mkdir()
        proc, out = run_case(text, run_dir, binary=mbsph, name=CASE)
        assert_ok(proc)
        heights[absorb] = [measured(out, f, k).H for k in (1, 2)]
    for k in range(2):
        got = f"gauge {k + 1}: {heights[True][k]:.5f} m absorbing, {heights[False][k]:.5f} m not, " \
              f"target {f.height:.5f} m"
        assert heights[True][k] > 0.98 * heights[False][k], got
        assert heights[True][k] < 1.02 * max(f.height, heights[False][k]), got


def absorbing_flume_text(max_steps: int, restart: bool = False) -> str:
    """A coarse flume (kh = 1.2, 10 particles over the depth) whose absorbing paddle
    makes a wave group of 3 periods; snapshots every 0.05 s."""
    from post.wave_cases import flume_case
    f = flume_case(1.2, depth=0.25, dp=0.025, out_dir="OUT", gauges_at=(0.5, 1.0), damping_len=1.0,
                   ramp_periods=1.0, extra_wavemaker="  duration = 3.0\n  absorb = .true.")
    text = f.text.replace("overwrite = .true.", f"overwrite = .true., max_steps = {max_steps}, "
                          f"restart = {'.true.' if restart else '.false.'}")
    return re.sub(r"dt_out = [0-9.]+", "dt_out = 0.05", text)


def test_absorbing_paddle_restart_is_bit_identical(tmp_path: Path, mbsph: Path) -> None:
    """The absorber's state (its correction, mean level and recent elevations) is in the
    checkpoint: a run restarted half-way ends bit for bit as the run not interrupted."""
    from test_cases import assert_same_datasets, read_attrs, snapshots
    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    proc, out_a = run_case(absorbing_flume_text(1600), tmp_path / "a", binary=mbsph, name=CASE)
    assert_ok(proc)
    proc, out_b = run_case(absorbing_flume_text(800), tmp_path / "b", binary=mbsph, name=CASE)
    assert_ok(proc)
    proc, _ = run_case(absorbing_flume_text(1600, restart=True), tmp_path / "b", binary=mbsph, name=CASE)
    assert_ok(proc)
    final_a, final_b = snapshots(out_a)[-1], snapshots(out_b)[-1]
    assert read_attrs(final_a)["step"] == read_attrs(final_b)["step"] == 1600
    assert_same_datasets(final_a, final_b)


def test_restart_changes_the_wave_only_while_the_paddle_rests(tmp_path: Path, mbsph: Path) -> None:
    """A test series continues a run under a new wave. Restarted while the paddle
    moves, with another wave, the run is refused (the paddle would jump), naming
    &wavemaker; restarted after the wave's end (the paddle at rest again) with a
    new wave that starts later, it runs."""
    text = absorbing_flume_text(1600)
    t_end_first = 4.0
    first = re.sub(r"t_end = [0-9.]+", f"t_end = {t_end_first}", text).replace("max_steps = 1600", "max_steps = 0")
    proc, out = run_case(first, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    # mid-wave: the same run stopped at 1.5 s, continued with a higher wave
    mid = tmp_path / "mid"
    mid.mkdir()
    proc, _ = run_case(re.sub(r"t_end = [0-9.]+", "t_end = 1.5", first), mid, binary=mbsph, name=CASE)
    assert_ok(proc)
    again = re.sub(r"height = ([0-9.]+)", lambda m_: f"height = {1.5 * float(m_.group(1)):.6f}",
                   re.sub(r"t_end = [0-9.]+", "t_end = 2.0", first)).replace("restart = .false.", "restart = .true.")
    proc, _ = run_case(again, mid, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert "&wavemaker: " in msg and "rests" in msg, msg
    # after the wave's end (3 s): the next step of the series, a higher wave from 4.5 s
    series = re.sub(r"t_end = [0-9.]+", "t_end = 5.0", again).replace(
        "duration = 3.0", "duration = 3.0, t_start = 4.5")
    proc, _ = run_case(series, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)


# The wave-height tests: (kh, paddle, Madsen's second-order stroke, particles over the depth,
# bar on the height). Every case: depth 0.25 m, H/L = 0.03, h/dp = 1.6, laminar viscosity +
# SPS, gradient correction with the plain continuity equation (kgc_continuity = .false.),
# 15 gauges from 0.5 to 4 L a quarter wavelength apart, a damping zone 1 L long after
# 4.25 L. At the solver's default h/dp = sqrt 2 the wave decays about ten times faster
# (doc/waves.md, "The smoothing length"). The particles over the depth are the fewest at
# which the case meets its bar by a margin of at least 3 %; the longest runs come first,
# so that the pytest workers end together (tests/conftest.py).
WAVE_H_OVER_DP = 1.6
HEIGHT_CASES = {
    "piston_kh0.7": (0.7, "piston", True, 15, 0.05),
    "piston_kh1.7": (1.7, "piston", False, 20, 0.05),
    "flap_kh1.2": (1.2, "flap", False, 15, 0.07),
    "piston_kh1.2": (1.2, "piston", False, 15, 0.05),
}


@pytest.mark.long
@pytest.mark.parametrize("case", list(HEIGHT_CASES))
def test_regular_wave_height_2_to_4_wavelengths(case: str, tmp_path: Path, mbsph: Path) -> None:
    """The height the paddle makes, 2 to 4 wavelengths from it, against the target H of
    linear wavemaker theory (Biesel), and the period against the paddle's.

    H is the crest-to-trough height of the incident wave, which is what the target
    means: the gauges' first-harmonic amplitudes over the last three periods (the wave
    front, at the group speed, passed 4 L at least one period before) are fitted by an
    incident wave that decays and a reflected one (post.waves.decaying_wave_fit); its
    first-harmonic height at 2, 3 and 4 L times the gauges' mean ratio of the
    crest-to-trough height (all harmonics of the fit) to the first-harmonic one. At
    kh = 0.7 (Ursell number 22) the third harmonic alone makes the first-harmonic height
    6 % lower than the crest-to-trough one, which is the wave of Stokes theory, not a
    loss. Bars: 5 % (piston), 7 % (flap); the period within 2 % at every gauge from 2 L;
    the fit within 5 % rms of the gauges."""
    import math

    import numpy as np
    from post.wave_cases import flume_case
    from post.waves import decaying_wave_fit, regular_wave_height
    kh, paddle, second_order, n, bar = HEIGHT_CASES[case]
    depth = 0.25
    gauges_at = tuple(0.5 + 0.25 * i for i in range(15))
    f = flume_case(kh, depth=depth, dp=depth / n, steepness=0.03, paddle=paddle, out_dir="OUT",
                   gauges_at=gauges_at, damping_len=1.0, second_order=second_order, h_over_dp=WAVE_H_OVER_DP,
                   extra_numerics="  kernel_correction = 'gradient'\n  kgc_continuity = .false.")
    text = f.text.replace("viscosity = 'artificial', alpha = 0.01", "viscosity = 'laminar_sps'")
    assert "viscosity = 'laminar_sps'" in text
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE, timeout=3600.0)
    assert_ok(proc)
    d = read_gauges_csv(out)
    t, T, H = d["time"], f.period, f.height
    t0, t1 = f.t_end - 3.0 * T, f.t_end
    etas = [d[f"eta_{j + 1}"] for j in range(len(gauges_at))]
    waves = [regular_wave_height(t, eta, T, t_start=t0, t_end=t1) for eta in etas]
    far = [w for a, w in zip(gauges_at, waves) if a >= 2.0]
    for a, w in zip(gauges_at, waves):
        if a >= 2.0:
            assert abs(w.T_fit / T - 1.0) < 0.02, f"{case}: period {w.T_fit:.4f} s at {a} L, target {T:.4f} s"
    fit = decaying_wave_fit(t, etas, [x - f.x0 for x in f.gauges], T, 2.0 * math.pi / f.length,
                            t_start=t0, t_end=t1)
    assert fit.residual < 0.05, f"{case}: the incident + reflected wave leaves {fit.residual:.1%} rms"
    ratio = float(np.mean([w.H_crest_trough / w.H for w in far]))
    errors = {a: fit.height(a * f.length) * ratio / H - 1.0 for a in (2.0, 3.0, 4.0)}
    report = ", ".join(f"{a:.0f} L {e:+.2%}" for a, e in errors.items())
    print(f"{case}: incident crest-to-trough height against the target: {report}; decay "
          f"{fit.kappa:.4f} /m, Kr {fit.Kr:.3f}, crest-to-trough / first harmonic {ratio:.3f}")
    for a, e in errors.items():
        assert abs(e) < bar, f"{case}: height {e:+.2%} at {a} L (bar {bar:.0%}); {report}"


@pytest.mark.long
def test_irregular_sea_keeps_its_height_and_its_volume(tmp_path: Path, mbsph: Path) -> None:
    """The JONSWAP sea of input/waves_irregular.nml (Hs 0.04 m, Tp 1 s, 12.5 particles
    over the depth, the solver's wave defaults, 36 s) against the wave it was asked for:
    at each gauge, Hm0 over 8 to 36 s (0.5 to 3 fp) against that of the solver's own
    target elevation at the paddle (build/jonswap_signal) carried to the gauge by linear
    dispersion over the same window, so that like is compared with like (a 28 s window of
    a perfect flume holds 0.79 to 1.26 Hs; doc/waves.md, "Measured: irregular waves").
    Issue 18's bar: within 5 % at both gauges; measured -2.2 and -3.2 %.

    And the water keeps its volume (the plain kernel gradient in the continuity
    equation, one of the wave defaults): the mean level at each gauge moves by less than
    1 mm between the two halves of the window (measured +0.39 and +0.35 mm; 14 peak
    periods each), and the kernel sum at mid-depth at 36 s is within 1 % of the carried
    density (measured -0.79 %; -0.52 % at 18 s). With the corrected gradient in the
    continuity equation the kernel sum rose 5.7 % by 36 s at h = 1.6 dp and the level
    sank 4.5 to 4.9 mm over 8 to 36 s (doc/waves.md, "The corrected continuity equation")."""
    import subprocess

    import numpy as np
    from post.interp import mass_sum
    from post.io import list_snapshots, read_case, read_csv, read_snapshot
    from post.waves import read_gauges, spectrum, target_elevation_at
    signal_tool = ROOT / "build" / "jonswap_signal"
    assert signal_tool.exists(), "build/jonswap_signal is missing (make unit builds it)"
    text = (ROOT / "input" / "waves_irregular.nml").read_text()
    text = re.sub(r"out_dir\s*=\s*'[^']*'", "out_dir = 'OUT'", text)
    for name in ("boundary", "h_over_dp", "kernel_correction", "kgc_continuity", "viscosity"):
        assert re.search(rf"^\s*{name}\s*=", text, re.M) is None, f"the case sets {name}: it is to test the defaults"
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE, timeout=1800.0)
    assert_ok(proc)
    assert "wave numerics (a wave flume that leaves them out): boundary = 'mdbc'" in proc.stdout
    # the solver's own synthesis of the case's signal (the run's effective &wavemaker)
    nml = read_case(out)
    wm = nml["wavemaker"]
    args = [wm["hs"], wm["tp"], wm["gamma"], wm["depth"], wm["seed"], nml["run"]["t_end"]]
    (tmp_path / "signal.csv").write_text(subprocess.run([str(signal_tool)] + [str(a) for a in args],
                                                        capture_output=True, text=True, check=True).stdout)
    sig = read_csv(tmp_path / "signal.csv")
    gauges, t, cols = read_gauges(out / "gauges.csv")
    sel = t >= 8.0
    tt = t[sel]
    half = tt < 22.0
    errors = {}
    for g in gauges:
        y = cols[g.column][sel]
        ref = target_elevation_at(tt, g.x, sig["time"], sig["eta"], wm["x0"], wm["depth"])
        errors[g.id] = spectrum(tt, y, fmin=0.5, fmax=3.0).Hm0 / spectrum(tt, ref, fmin=0.5, fmax=3.0).Hm0 - 1.0
        shift = float(np.mean(y[~half]) - np.mean(y[half]))
        assert abs(shift) < 1.0e-3, f"gauge {g.id}: mean level moved {shift * 1e3:+.2f} mm from 8-22 s to 22-36 s"
    assert len(errors) == 2
    report = ", ".join(f"gauge {k} {e:+.1%}" for k, e in errors.items())
    print(f"irregular sea: Hm0 against the target over 8 to 36 s: {report}")
    for k, e in errors.items():
        assert abs(e) < 0.05, f"Hm0 {e:+.1%} of the target at gauge {k} (bar 5 %); {report}"
    snap = read_snapshot(list_snapshots(out)[-1])
    x = snap.position
    mid = snap.fluid & (x[:, 0] > 0.6) & (x[:, 0] < 1.6) & (x[:, 1] > 0.05) & (x[:, 1] < 0.15)
    assert mid.sum() > 200
    ratio = mass_sum(snap, x[mid]).mean() / snap.density[mid].mean() - 1.0
    assert abs(ratio) < 0.01, f"kernel sum against carried density at {snap.time:.1f} s: {ratio:+.2%}"
