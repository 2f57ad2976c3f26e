"""The output folder of a run against doc/output.md: snapshot datasets and attributes,
case.nml (and that it repeats the run), energy.csv, run.log and the screen, and the
XDMF index as ParaView reads it.
"""

from __future__ import annotations

import json
import math
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from conftest import (
    COLUMN_ON_FLOOR,
    ROOT,
    SNAPSHOT_DATASETS,
    assert_ok,
    assert_same_datasets,
    dambreak_text,
    describe,
    paddle_text,
    read_attrs,
    read_datasets,
    run_case,
    snapshots,
)
from post.io import read_csv, read_snapshot

pytestmark = pytest.mark.usefixtures("mbsph")

DP = 0.025           # m: divides every length of tests/cases/paddle.nml
DT_OUT = 0.01        # s
T_END = 0.05         # s
RHO0, G, GAMMA, COEF = 1000.0, 9.81, 7.0, 10.0   # &fluid of the case templates
H_OVER_DP = 1.4142135623730951                   # the default of &numerics
DEPTH = 0.15         # water depth of tests/cases/paddle.nml (m): it sets h_swl and c0
ROOT_ATTRS = ("time", "dt", "step", "n_particles", "dp", "h", "rho0", "c0", "gravity", "case_name", "case_nml")
PROGRESS_RE = re.compile(r"^t = \d*\.\d+ s +\d+\.\d %  step \d+  dt ")


@pytest.fixture(scope="module")
def run(tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    """The paddle case (fluid, fixed and moving boundary particles), 0.05 s, a snapshot every
    0.01 s and a progress line at every step; returns (process, output folder)."""
    text = paddle_text(amplitude_x=0.01, period=0.2, t_end=T_END, dt_out=DT_OUT, dp=DP,
                       run={"progress_interval": 0.0})
    proc, out = run_case(text, tmp_path_factory.mktemp("output"), binary=mbsph)
    assert_ok(proc)
    return proc, out


def test_snapshot_files(run) -> None:
    _, out = run
    names = [p.name for p in snapshots(out)]
    # t = 0, 0.01, ..., 0.05: one snapshot per output time, numbered from 00000
    expected = [f"snap_{k:05d}.h5" for k in range(round(T_END / DT_OUT) + 1)]
    assert names == expected, f"snapshots {names}"
    for name in ("case.nml", "particles.xmf", "energy.csv", "checkpoint.h5", "run.log"):
        assert (out / name).is_file(), f"{name} is missing from the output folder"


def test_snapshot_datasets(run) -> None:
    _, out = run
    for path in snapshots(out):
        data = read_datasets(path)
        assert sorted(data) == sorted(SNAPSHOT_DATASETS), f"{path.name}: datasets {sorted(data)}"
        n = data["id"].shape[0]
        for name in ("position", "velocity"):
            assert data[name].shape == (n, 2) and data[name].dtype == np.float64, (name, data[name].shape)
        for name in ("density", "pressure", "mass"):
            assert data[name].shape == (n,) and data[name].dtype == np.float64, (name, data[name].shape)
        for name in ("kind", "body", "id", "connectivity"):
            assert data[name].shape == (n,) and data[name].dtype == np.int32, (name, data[name].dtype)
        ids = data["id"]
        assert ids[0] >= 1 and np.all(np.diff(ids) > 0), f"{path.name}: ids not unique and increasing"
        np.testing.assert_array_equal(data["connectivity"], np.arange(n))
        kinds = set(np.unique(data["kind"]).tolist())
        # this case has fluid (1), fixed walls (2) and the moving paddle (3), no floating body
        assert kinds == {1, 2, 3}, f"{path.name}: kinds {kinds}"
        fluid = data["kind"] == 1
        assert np.all(data["body"][fluid] == 0) and np.all(data["body"][~fluid] >= 1)
        # 2D lattice particles: m = rho0 dp^2 per metre of width
        np.testing.assert_allclose(data["mass"], RHO0 * DP * DP, rtol=1e-12)
        # Tait equation of state, B = c0^2 rho0 / gamma: the pressure belongs to the stored density
        c0 = float(read_attrs(path)["c0"])
        b = c0 * c0 * RHO0 / GAMMA
        np.testing.assert_allclose(data["pressure"], b * ((data["density"] / RHO0) ** GAMMA - 1.0),
                                   rtol=0, atol=1e-9 * b)
        assert np.all(np.isfinite(data["position"])) and np.all(np.isfinite(data["velocity"]))


def test_snapshot_attributes(run) -> None:
    _, out = run
    paths = snapshots(out)
    text = (out / "case.nml").read_text()
    times, steps = [], []
    for k, path in enumerate(paths):
        attrs = read_attrs(path)
        missing = [a for a in ROOT_ATTRS if a not in attrs]
        assert not missing, f"{path.name}: root attributes missing: {missing}"
        snap = read_snapshot(path)
        assert snap.n_particles == snap.id.shape[0]
        assert snap.dp == DP and snap.rho0 == RHO0 and snap.g == G
        assert snap.h == pytest.approx(H_OVER_DP * DP, rel=1e-14)
        # c0 = coef sqrt(g h_swl), h_swl the depth of the water (src/input_fluid.f90)
        assert snap.c0 == pytest.approx(COEF * math.sqrt(G * DEPTH), rel=1e-12)
        assert snap.case_name == "paddle"
        assert snap.case_nml == text, f"{path.name}: case_nml is not the text of case.nml"
        # snapshot k comes at the first step at or after t = k dt_out (dt: the step just taken)
        assert k * DT_OUT * (1 - 1e-12) <= snap.time <= k * DT_OUT + snap.dt * (1 + 1e-9), (k, snap.time, snap.dt)
        times.append(snap.time)
        steps.append(snap.step)
    assert steps[0] == 0 and times[0] == 0.0
    assert np.all(np.diff(steps) > 0) and np.all(np.diff(times) > 0)


def test_energy_csv(run) -> None:
    _, out = run
    lines = (out / "energy.csv").read_text().splitlines()
    assert lines[0] == "time,step,kinetic,potential,total_mass,n_fluid,lost,body_kinetic,body_potential,max_penetration"
    data = read_csv(out / "energy.csv")
    paths = snapshots(out)
    # energy_interval = 0: a row at every output time, as many as snapshots
    assert len(data["time"]) == len(paths), f"energy.csv has {len(data['time'])} rows for {len(paths)} snapshots"
    assert np.all(np.diff(data["time"]) > 0) and np.all(np.diff(data["step"]) > 0)
    rows = {int(s): i for i, s in enumerate(data["step"])}
    for path in paths:
        snap = read_snapshot(path)
        assert snap.step in rows, f"no energy.csv row for step {snap.step} of {path.name}"
        i = rows[snap.step]
        f = snap.fluid
        m = snap.mass[f]
        assert data["time"][i] == pytest.approx(snap.time, rel=1e-14)
        # the sums of doc/output.md over the snapshot's fluid; 1e-12: summation order and the
        # 16 significant digits written
        assert data["kinetic"][i] == pytest.approx(0.5 * np.sum(m * np.sum(snap.velocity[f] ** 2, axis=1)),
                                                   rel=1e-12, abs=1e-300)
        assert data["potential"][i] == pytest.approx(np.sum(m * G * snap.position[f, 1]), rel=1e-12)
        assert data["total_mass"][i] == pytest.approx(np.sum(m), rel=1e-12)
        assert data["n_fluid"][i] == np.count_nonzero(f)
        assert data["lost"][i] == 0


def test_run_log_and_screen(run) -> None:
    proc, out = run
    # standard output is a pipe here: progress lines are plain lines, never redrawn in place
    assert "\r" not in proc.stdout, "carriage returns on stdout although it is not a terminal"
    assert "\x1b[" not in proc.stdout, "terminal escape sequences on stdout although it is not a terminal"
    screen = proc.stdout.splitlines()
    progress = [ln for ln in screen if PROGRESS_RE.match(ln)]
    # progress_interval = 0: a progress line at every step
    last_step = read_attrs(snapshots(out)[-1])["step"]
    assert len(progress) == last_step, f"{len(progress)} progress lines for {last_step} steps"
    assert progress[-1].split("%")[0].endswith("100.0 "), progress[-1]
    assert any("microseconds per particle-step" in ln for ln in screen)
    # the paddle case has no body: its effects line names neither bodies nor contact
    effects = [ln for ln in screen if "effects on:" in ln]
    assert len(effects) == 1 and "rigid bodies" not in effects[0] and "contact" not in effects[0], effects
    log = (out / "run.log").read_text().splitlines()
    assert log, "run.log is empty"
    assert [ln for ln in log if PROGRESS_RE.match(ln)] == progress, "run.log lacks the progress lines"
    assert any("microseconds per particle-step" in ln for ln in log), "run.log lacks the cost summary"
    # run.log is what the screen showed, as plain lines (doc/output.md)
    assert log == screen


def test_case_nml_repeats_the_run(tmp_path: Path, mbsph: Path) -> None:
    text = dambreak_text(t_end=1.0, dt_out=0.005, run={"max_steps": 60})
    proc, out = run_case(text, tmp_path, binary=mbsph)
    assert_ok(proc)
    effective = (out / "case.nml").read_text()
    pattern = re.compile(r"""(?im)^(\s*out_dir\s*=\s*)(["']).*?\2""")
    assert len(pattern.findall(effective)) == 1, "case.nml should set out_dir once"
    again = pattern.sub(lambda m: f"{m.group(1)}{m.group(2)}OUT2{m.group(2)}", effective)
    proc, out2 = run_case(again, tmp_path, binary=mbsph, name="repeat.nml")
    assert_ok(proc)
    assert out2 == tmp_path / "OUT2"
    first, second = snapshots(out), snapshots(out2)
    assert [p.name for p in first] == [p.name for p in second]
    for a, b in zip(first, second):
        assert_same_datasets(a, b)


# ---------------------------------------------------------------- ParaView


def test_paraview_reads_the_series(run) -> None:
    missing = [tool for tool in ("pvpython", "xvfb-run", "xauth") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"ParaView check needs {', '.join(missing)} (tools/deps.sh installs them)")
    _, out = run
    proc = subprocess.run([str(ROOT / "tools" / "pv_probe.sh"), str(out / "particles.xmf"), "pressure"],
                          capture_output=True, text=True, timeout=300, stdin=subprocess.DEVNULL)
    assert proc.returncode == 0, f"tools/pv_probe.sh failed\n{describe(proc)}"
    seen = json.loads(proc.stdout.strip().splitlines()[-1])
    paths = snapshots(out)
    last = read_snapshot(paths[-1])
    assert seen["n_timesteps"] == len(paths), seen["times"]
    np.testing.assert_allclose(seen["times"], [read_snapshot(p).time for p in paths], rtol=1e-12, atol=1e-15)
    assert seen["time"] == pytest.approx(last.time, rel=1e-12)
    assert seen["n_points"] == last.n_particles
    assert seen["n_cells"] == last.n_particles
    # every point array of the index, with its number of components
    assert seen["point_arrays"] == {"velocity": 2, "density": 1, "pressure": 1, "kind": 1, "body": 1, "id": 1}
    # the points span the particles of the last snapshot (x, y; z = 0)
    lo, hi = last.position.min(axis=0), last.position.max(axis=0)
    assert seen["bounds"] == pytest.approx([lo[0], hi[0], lo[1], hi[1], 0.0, 0.0], rel=1e-12, abs=1e-15)
    # 1e-6: ParaView reports the range of the array it read from the same doubles
    assert seen["range"] == pytest.approx([last.pressure.min(), last.pressure.max()], rel=1e-6)


# ------------------------------------------------------------ particles that leave the domain

# the column of conftest spills off its floor, which ends 0.04 m inside the domain
SPILL = (COLUMN_ON_FLOOR.replace("case_name = 'bad_input'", "case_name = 'spill'")
         .replace("t_end = 0.01\n  dt_out = 0.01", "t_end = 0.3\n  dt_out = 0.3")
         .replace("max_steps = 1\n", "max_lost_fraction = 1.0\n"))


def test_particles_that_leave_the_domain_are_removed_and_counted(tmp_path: Path, mbsph: Path) -> None:
    """Water spilling off a floor narrower than the domain falls out of it. Every fluid
    particle that leaves is taken out and counted: the fluid at the end plus the removals
    that run.log reports one by one is the fluid at the start, the summary's total is
    their sum, and what remains is inside the domain."""
    proc, out = run_case(SPILL, tmp_path, binary=mbsph)
    assert_ok(proc)
    snaps = snapshots(out)
    first, last = read_datasets(snaps[0]), read_datasets(snaps[-1])
    assert read_attrs(snaps[-1])["time"] == pytest.approx(0.3, abs=2e-3)
    fluid0, fluid1 = first["kind"] == 1, last["kind"] == 1
    log = (out / "run.log").read_text()
    removals = [(int(a), int(b), int(c)) for a, b, c in re.findall(
        r"removed (\d+) fluid particles \(left the domain: (\d+), density outside \[[^]]*\] kg/m3: (\d+)\)", log)]
    removed = sum(a for a, _, _ in removals)
    assert removed >= 10, f"the case should spill water out of the domain ({removed} removed)"
    assert all(a == b + c for a, b, c in removals)
    assert int(re.search(r"fluid particles lost: (\d+)", log).group(1)) == removed
    assert fluid0.sum() - fluid1.sum() == removed
    x = last["position"][fluid1]
    assert np.all((x[:, 0] >= -0.1) & (x[:, 0] <= 0.5) & (x[:, 1] >= -0.1) & (x[:, 1] <= 0.5))
