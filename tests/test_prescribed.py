"""A prescribed body follows its function of time,

    pose(t) = pose0 + (u, v, omega) t + (amplitude_x, amplitude_y, amplitude_angle) sin(2 pi t / period + phase),

with the velocities its exact derivative, at every written time of bodies.csv, in
every integrator, and across a restart (the pose is a function of absolute time).
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_ok, run_case
from post.io import read_csv

pytestmark = pytest.mark.usefixtures("mbsph")

# pose0 (the box's centre and angle), rates and oscillation of the body
X0, Y0, ANGLE0_DEG = 0.30, 0.20, 10.0
U, V, OMEGA = 0.05, 0.0, 0.3
AX, AY, AA = 0.02, 0.01, 0.2
PERIOD, PHASE = 0.25, 0.4


def case(integrator: str, max_steps: int = 100000, restart: bool = False) -> str:
    """A small water column in a tank and a prescribed box clear of it, 0.3 s with a
    bodies.csv row every 0.01 s (the oscillation's period is 0.25 s)."""
    return f"""\
&run
  case_name = 'prescribed', t_end = 0.3, dt_out = 0.1, energy_interval = 0.01, out_dir = 'OUT'
  max_steps = {max_steps}, restart = {'.true.' if restart else '.false.'}
/
&domain xmin = -0.1, xmax = 0.7, ymin = -0.1, ymax = 0.5 /
&fluid rho0 = 1000.0, gamma = 7.0 /
&numerics dp = 0.02, kernel = 'wendland', integrator = '{integrator}', cfl = 0.2 /
&box role = 'fluid', xmin = 0.0, xmax = 0.1, ymin = 0.0, ymax = 0.1 /
&box role = 'solid', xmin = -0.06, xmax = 0.66, ymin = -0.06, ymax = 0.0 /
&box role = 'solid', xmin = -0.06, xmax = 0.0, ymin = 0.0, ymax = 0.4 /
&box role = 'solid', xmin = 0.6, xmax = 0.66, ymin = 0.0, ymax = 0.4 /
&body shape = 'box', x = {X0}, y = {Y0}, width = 0.08, height = 0.06, angle = {ANGLE0_DEG},
  motion = 'prescribed', u = {U}, v = {V}, omega = {OMEGA},
  amplitude_x = {AX}, amplitude_y = {AY}, amplitude_angle = {AA}, period = {PERIOD}, phase = {PHASE} /
"""


def exact(t: np.ndarray) -> dict[str, np.ndarray]:
    w = 2.0 * math.pi / PERIOD
    s, c = np.sin(w * t + PHASE), np.cos(w * t + PHASE)
    return {"x": X0 + U * t + AX * s, "y": Y0 + V * t + AY * s, "angle": math.radians(ANGLE0_DEG) + OMEGA * t + AA * s,
            "u": U + AX * w * c, "v": V + AY * w * c, "omega": OMEGA + AA * w * c}


def assert_follows(d: dict, n_min: int) -> None:
    t = d["time"]
    assert len(t) >= n_min, f"bodies.csv has {len(t)} rows, expected at least {n_min}"
    want = exact(t)
    for key in ("x", "y", "angle"):
        err = np.max(np.abs(d[key] - want[key]))
        # 1e-10 m / rad: the function evaluated at the stage time in double precision
        # (bodies.csv carries 16 significant digits), no integration error
        assert err <= 1e-10, f"{key}: largest error {err:.3e} against pose(t)"
    for key in ("u", "v", "omega"):
        err = np.max(np.abs(d[key] - want[key]))
        # the exact derivative, same precision (|velocities| < 2)
        assert err <= 1e-10, f"{key}: largest error {err:.3e} against d pose / dt"


@pytest.mark.parametrize("integrator", ["symplectic", "predictor_corrector", "verlet"])
def test_prescribed_pose_follows_function(integrator: str, tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(case(integrator), tmp_path, binary=mbsph)
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    assert d["time"][0] == 0.0 and d["time"][-1] >= 0.3 * (1.0 - 1e-12)
    assert_follows(d, 31)


def test_prescribed_pose_continues_after_restart(tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(case("symplectic", max_steps=150), tmp_path, binary=mbsph)
    assert_ok(proc)
    t_stop = read_csv(out / "bodies.csv")["time"][-1]
    assert 0.0 < t_stop < 0.29, f"the first run should stop early, it reached t = {t_stop}"
    proc, out = run_case(case("symplectic", restart=True), tmp_path, binary=mbsph)
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    assert d["time"][-1] >= 0.3 * (1.0 - 1e-12)
    assert_follows(d, 31)


def test_fast_prescribed_body_limits_the_step(tmp_path: Path, mbsph: Path) -> None:
    """A prescribed box driven at 20 m/s, clear of the water: no point of it may move
    more than cfl h in a step, as the fluid's CFL keeps its own particles (here the
    fluid alone would allow a step twice as long: 0.2 h / c0 with c0 = 9.9 m/s)."""
    u, cfl, dp = 20.0, 0.2, 0.02
    h = math.sqrt(2.0) * dp
    text = case("symplectic").replace("t_end = 0.3, dt_out = 0.1, energy_interval = 0.01",
                                      "t_end = 0.012, dt_out = 0.006, energy_interval = 0.001")
    text = text.replace(f"u = {U}, v = {V}, omega = {OMEGA},", f"u = {u}, v = 0.0, omega = 0.0,")
    text = text.replace(f"amplitude_x = {AX}, amplitude_y = {AY}, amplitude_angle = {AA}, period = {PERIOD}, "
                        f"phase = {PHASE}", "")
    proc, out = run_case(text, tmp_path, binary=mbsph)
    assert_ok(proc)
    e = read_csv(out / "energy.csv")
    dt = np.diff(e["time"]) / np.diff(e["step"])
    limit = cfl * h / u
    # 1e-9: rounding of the times written; the mean step between two rows is below the
    # largest step taken, so the bar is on every step
    assert len(dt) >= 5 and np.max(dt) <= limit * (1.0 + 1e-9), \
        f"mean step {np.max(dt):.3e} s between energy rows, motion limit cfl h / u = {limit:.3e} s"
    # and not far below it: the fluid does not limit this step
    assert np.min(dt) >= 0.5 * limit, f"step {np.min(dt):.3e} s, far below the motion limit {limit:.3e} s"
