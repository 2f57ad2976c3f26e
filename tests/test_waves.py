"""Waves and the breakwater: the wavemaker against linear theory (Biesel), the damping
zone's reflection, the armour layer at rest, and the inputs that must be refused.

The flumes are laid out by post/wave_cases.py in wavelengths of the target wave.
Heights are measured by post/waves.py (least-squares first harmonic over whole
periods in a window after the wave front has passed the gauge and before the
reflection from the damping zone can return).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from conftest import EXIT_INPUT, assert_ok, describe, run_case
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
    "armour_too_many_units": (edit("density = 2200.0 /", "density = 2200.0, n_units = 40 /", BW_BASE), "armour",
                              "n_units", ("at most", "fit")),
    "armour_unit_too_big": (edit("dn = 0.04", "dn = 0.5", BW_BASE), "armour", "dn", ("fits",)),
    "armour_without_breakwater": (BW_BASE.replace(BW_BASE[BW_BASE.index("&breakwater"):
                                                          BW_BASE.index("&armour")], ""),
                                  "armour", "", ("&breakwater",)),
    "breakwater_beyond_domain": (edit("xmax = 2.2", "xmax = 1.6", BW_BASE), "breakwater", "crest_width",
                                 ("xmax",)),
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
