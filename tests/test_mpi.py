"""Runs on several MPI ranks (mpirun, 2 ranks, oversubscribed): the answer must not
depend on the number of ranks (doc/parallel.md).

- The dam break and three boxes stacked in water (in contact, straddling the slab edge)
  agree on 1 and 2 ranks after 200 steps: positions, velocities and densities to 1e-10
  of each field's largest magnitude (particles matched by id), body positions to 1e-9 m.
  They are not bit-identical: a pair's contributions reach a particle in another order
  on two ranks (the halo's share is added on its owner afterwards), so sums differ in
  the last bits and grow slowly over the steps.
- The same agreement for every optional model whose pair loops need halo values other
  than position, velocity and density (gradient correction, SPS stress, Shepard filter)
  and for the other integrators.
- A checkpoint written on 2 ranks continues on 1 rank, and one written on 1 rank on 2,
  as the uninterrupted run does (same tolerance); on 2 ranks again, bit for bit.
- Load balance: water in the left half of a tank; the two ranks' particle counts end
  within 10 % of each other, while slabs of equal width (balance_every = 0) differ
  far more.
- A bad input stops both ranks within 10 s with one message and exit code 2.
- The modified dynamic boundary (mDBC) agrees between 1 and 2 ranks like the other
  models: its ghost points whose water lies on both slabs are summed on both ranks.
"""

from __future__ import annotations

import os
import shutil
import signal
import subprocess
import time
from pathlib import Path

import h5py
import numpy as np
import pytest

from conftest import (EXIT_INPUT, ROOT, assert_same_datasets, case_text, dambreak_text, describe, out_dir_of,
                      snapshots, wait_for_checkpoint, walls)
from post.io import read_csv, read_snapshot

pytestmark = pytest.mark.usefixtures("mbsph")

MPIRUN = shutil.which("mpirun")
RANKS = 2
STEPS = 200
REL = 1e-10        # relative agreement of particle fields (issue 5)
BODY_TOL = 1e-9    # m, body trajectories (issue 5)


def mpirun_cmd(ranks: int) -> list[str]:
    cmd = [MPIRUN, "-q", "--oversubscribe", "-np", str(ranks)]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.insert(1, "--allow-run-as-root")
    return cmd


def run(text: str, folder: Path, ranks: int, binary: Path, timeout: float = 120.0):
    """Write the case into folder and run it there on `ranks` ranks (1: without mpirun)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "case.nml").write_text(text)
    cmd = [str(binary), "case.nml"]
    if ranks > 1:
        if MPIRUN is None:
            pytest.skip("mpirun is not installed")
        cmd = mpirun_cmd(ranks) + cmd
    proc = subprocess.run(cmd, cwd=folder, capture_output=True, text=True, timeout=timeout,
                          stdin=subprocess.DEVNULL)
    return proc, folder / out_dir_of(text)


def ok(proc) -> None:
    assert proc.returncode == 0, f"the solver failed\n{describe(proc)}"


def final_snapshot(out: Path):
    snaps = sorted(out.glob("snap_*.h5"))
    return read_snapshot(snaps[-1])


def assert_same_state(a: Path, b: Path, what: str) -> None:
    """Final snapshots of two runs: the same particles, fields within REL of their scale."""
    sa, sb = final_snapshot(a), final_snapshot(b)
    assert sa.step == sb.step == STEPS, (sa.step, sb.step)
    np.testing.assert_array_equal(sa.id, sb.id, err_msg=f"{what}: different particles")
    for name in ("position", "velocity", "density"):
        x, y = getattr(sa, name), getattr(sb, name)
        scale = float(np.max(np.abs(x)))
        err = float(np.max(np.abs(x - y)))
        assert err <= REL * scale, f"{what}: {name} differs by {err:.3e}, {err / scale:.2e} of its scale {scale:.3e}"


def assert_same_bodies(a: Path, b: Path, what: str) -> None:
    ba, bb = read_csv(a / "bodies.csv"), read_csv(b / "bodies.csv")
    assert len(ba["time"]) == len(bb["time"]) > 1, what
    for col in ("x", "y"):
        err = float(np.max(np.abs(ba[col] - bb[col])))
        assert err <= BODY_TOL, f"{what}: body {col} differs by {err:.3e} m"


def dambreak(out_dir: str, numerics: dict | None = None, run_extra: dict | None = None) -> str:
    run_vars = {"max_steps": STEPS, "overwrite": True}
    run_vars.update(run_extra or {})
    return dambreak_text(t_end=1.0, dt_out=1.0, out_dir=out_dir, run=run_vars, numerics=numerics)


def stack(out_dir: str, steps: int = STEPS, restart: bool = False) -> str:
    """TC4 of the seed paper: three boxes stacked under water, in contact; the slab edge
    of two ranks runs through them."""
    text = (ROOT / "input" / "paper" / "tc4_stack_noncohesive_spring.nml").read_text()
    text = text.replace("out_dir = 'OUT/paper/tc4_stack_noncohesive_spring'", f"out_dir = '{out_dir}'")
    text = text.replace("energy_interval = 0.01", f"energy_interval = 0.001, max_steps = {steps}")
    if restart:
        text = text.replace("overwrite = .true.", "restart = .true.")
    return text


@pytest.fixture(scope="module")
def serial_dambreak(tmp_path_factory: pytest.TempPathFactory, mbsph: Path) -> Path:
    folder = tmp_path_factory.mktemp("dambreak_1")
    proc, out = run(dambreak("OUT"), folder, 1, mbsph)
    ok(proc)
    return out


def test_dambreak_same_on_two_ranks(serial_dambreak: Path, tmp_path: Path, mbsph: Path) -> None:
    proc, out = run(dambreak("OUT"), tmp_path, RANKS, mbsph)
    ok(proc)
    assert "ranks 2" in proc.stdout
    assert_same_state(serial_dambreak, out, "dam break, 1 and 2 ranks")
    with h5py.File(out / "checkpoint.h5") as f:
        counts = f["rank_counts"][()]
    assert len(counts) == RANKS and min(counts) > 0, f"a rank owns nothing: {counts}"


MODELS = {
    "gradient_correction": {"kernel_correction": "gradient"},
    "laminar_sps": {"viscosity": "laminar_sps", "nu": 1e-6},
    # both: the correction matrices and the SPS velocity gradients from one shared sweep
    "gradient_laminar_sps": {"kernel_correction": "gradient", "viscosity": "laminar_sps", "nu": 1e-6},
    "shepard": {"kernel_correction": "shepard", "shepard_every": 20},
    "verlet": {"integrator": "verlet"},
    "predictor_corrector": {"integrator": "predictor_corrector", "diffusion": "molteni"},
    "repulsive_boundary": {"boundary": "repulsive", "diffusion": "none"},
    # particle shifting: the halo's share of its sums goes to the owners
    "shifting": {"shifting": "fickian"},
    "shifting_verlet": {"shifting": "fickian", "integrator": "verlet"},
    # mDBC: the ghost points whose water lies on both slabs are summed on both
    # ranks and the sums added; the halo's wall particles take their owners' density
    "mdbc": {"boundary": "mdbc"},
    "mdbc_noslip_shifting": {"boundary": "mdbc", "mdbc_slip": "noslip", "shifting": "fickian"},
}


@pytest.mark.parametrize("model", sorted(MODELS))
def test_models_same_on_two_ranks(model: str, tmp_path: Path, mbsph: Path) -> None:
    text = dambreak("OUT", numerics=MODELS[model])
    ok(run(text, tmp_path / "one", 1, mbsph)[0])
    ok(run(text, tmp_path / "two", RANKS, mbsph)[0])
    assert_same_state(tmp_path / "one" / "OUT", tmp_path / "two" / "OUT", f"{model}, 1 and 2 ranks")


def test_bodies_in_contact_same_on_two_ranks(tmp_path: Path, mbsph: Path) -> None:
    ok(run(stack("OUT"), tmp_path / "one", 1, mbsph)[0])
    proc, out = run(stack("OUT"), tmp_path / "two", RANKS, mbsph)
    ok(proc)
    with h5py.File(out / "checkpoint.h5") as f:
        edge = int(f["slab_edges"][1])
    x_edge = -0.05 + edge * 2.0 * 1.3 * 0.01       # domain xmin + columns of 2h
    assert 0.25 < x_edge < 0.35, f"the slab edge x = {x_edge:.3f} m does not cut the boxes (0.25 to 0.35 m)"
    assert_same_state(tmp_path / "one" / "OUT", out, "stacked boxes, 1 and 2 ranks")
    assert_same_bodies(tmp_path / "one" / "OUT", out, "stacked boxes, 1 and 2 ranks")


def wave_case(name: str) -> str:
    """The wave flume (piston, gauges, damping zone) and the armoured breakwater of
    tests/test_waves.py, 200 steps, gauges every step; the gauges at x = 1.5 m sit on
    the slab edge of two ranks."""
    from test_waves import BW_BASE, WAVE_BASE
    run_line = ("t_end = 1.0, dt_out = 1.0, out_dir = 'OUT', max_steps = 200, gauge_interval = 1e-6, "
                "overwrite = .true.")
    if name == "flume":
        text = WAVE_BASE.replace("t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1", run_line)
        return text + ("&gauge kind = 'elevation', x = 1.5 /\n"
                       "&gauge kind = 'pressure', x = 1.5, y = 0.05 /\n")
    text = BW_BASE.replace("t_end = 0.01, dt_out = 0.01, out_dir = 'OUT', max_steps = 1", run_line)
    return text + "&gauge kind = 'elevation', x = 0.6 /\n"


@pytest.mark.parametrize("name", ["flume", "breakwater"])
def test_waves_and_armour_same_on_two_ranks(name: str, tmp_path: Path, mbsph: Path) -> None:
    text = wave_case(name)
    ok(run(text, tmp_path / "one", 1, mbsph)[0])
    ok(run(text, tmp_path / "two", RANKS, mbsph)[0])
    a, b = tmp_path / "one" / "OUT", tmp_path / "two" / "OUT"
    assert_same_state(a, b, f"{name}, 1 and 2 ranks")
    from post.waves import read_gauges
    _, ta, ga = read_gauges(a)
    _, tb, gb = read_gauges(b)
    assert len(ta) == len(tb) > 100
    for col in ga:
        x, y = ga[col], gb[col]
        np.testing.assert_array_equal(np.isnan(x), np.isnan(y), err_msg=f"{name}: {col} dry at other times")
        scale = float(np.nanmax(np.abs(x))) or 1.0
        err = float(np.nanmax(np.abs(x - y)))
        assert err <= REL * scale, f"{name}: gauge {col} differs by {err:.3e} (scale {scale:.3e})"
    if (a / "bodies.csv").exists():
        assert_same_bodies(a, b, f"{name}, 1 and 2 ranks")


@pytest.mark.parametrize("first, second", [(2, 1), (1, 2), (2, 2)])
def test_restart_on_another_rank_count(first: int, second: int, serial_dambreak: Path, tmp_path: Path,
                                       mbsph: Path) -> None:
    half = dambreak("OUT", run_extra={"max_steps": STEPS // 2})
    ok(run(half, tmp_path, first, mbsph)[0])
    rest = dambreak("OUT").replace("overwrite = .true.", "restart = .true.")
    proc, out = run(rest, tmp_path, second, mbsph)
    ok(proc)
    assert_same_state(serial_dambreak, out, f"restart {first} -> {second} ranks against 1 rank uninterrupted")
    if first == second == 2:
        ok(run(dambreak("OUT"), tmp_path / "whole", 2, mbsph)[0])
        a, b = final_snapshot(tmp_path / "whole" / "OUT"), final_snapshot(out)
        for name in ("position", "velocity", "density", "id"):
            np.testing.assert_array_equal(getattr(a, name), getattr(b, name),
                                          err_msg=f"restart on 2 ranks: {name} not bit-identical")


def half_tank(out_dir: str, balance_every: int) -> str:
    """Water 0.2 m deep filling the left half of a tank 1 m wide (dp = 0.01 m)."""
    dp = 0.01
    text = case_text("tank", run={"max_steps": 100, "balance_every": balance_every, "overwrite": True},
                     out_dir=out_dir, t_end=10.0, dt_out=10.0, dp=dp, depth=0.2, width=1.0, wall_top=0.3,
                     dom_xmin=-0.05, dom_xmax=1.05, dom_ymin=-0.05, dom_ymax=0.4, **walls(dp, 0.0, 1.0))
    return text.replace("xmax = 1.0, ymin = 0.0, ymax = 0.2", "xmax = 0.5, ymin = 0.0, ymax = 0.2")


def test_load_balance(tmp_path: Path, mbsph: Path) -> None:
    """Slabs of equal width over water in the left half of a tank are uneven; balanced,
    the ranks' work (a fluid particle counted twice, a wall one once: doc/parallel.md)
    is even within 10 %. The checkpoint holds each rank's particles in rank order."""
    counts, work = {}, {}
    for every in (0, 20):
        proc, out = run(half_tank("OUT", every), tmp_path / str(every), RANKS, mbsph)
        ok(proc)
        with h5py.File(out / "checkpoint.h5") as f:
            counts[every] = f["rank_counts"][()]
            kind = f["kind"][()]
        starts = np.concatenate([[0], np.cumsum(counts[every])[:-1]])
        work[every] = [int(2 * (kind[s:s + n] == 1).sum() + (kind[s:s + n] != 1).sum())
                       for s, n in zip(starts, counts[every])]
        assert read_snapshot(sorted(out.glob("snap_*.h5"))[0]).fluid.sum() == 1000
    equal, balanced = work[0], work[20]
    assert abs(balanced[0] - balanced[1]) <= 0.1 * max(balanced), f"balanced work {balanced} (counts {counts[20]})"
    assert abs(equal[0] - equal[1]) > 0.5 * max(equal), f"slabs of equal width should be uneven: {equal}"


def test_bad_input_stops_every_rank(tmp_path: Path, mbsph: Path) -> None:
    text = dambreak("OUT").replace("t_end = 1.0", "t_end = -1.0")
    start = time.monotonic()
    proc, _ = run(text, tmp_path, RANKS, mbsph, timeout=60.0)
    elapsed = time.monotonic() - start
    assert proc.returncode == EXIT_INPUT, describe(proc)
    assert elapsed < 10.0, f"took {elapsed:.1f} s to stop"
    lines = [ln for ln in proc.stderr.splitlines() if "mbsph: error" in ln]
    assert len(lines) == 1, f"expected one message, got {lines}"
    assert "(rank 0)" in lines[0] and "&run: t_end" in lines[0], lines[0]


def mpmd(tmp_path: Path, mbsph: Path, parts: list[tuple[Path, str]]):
    """One rank per (working directory, case file) pair, started together (mpirun's colon form)."""
    if MPIRUN is None:
        pytest.skip("mpirun is not installed")
    cmd = mpirun_cmd(1)
    for k, (wdir, case) in enumerate(parts):
        if k > 0:
            cmd += [":", "-np", "1"]
        cmd += ["-wdir", str(wdir), str(mbsph), case]
    start = time.monotonic()
    proc = subprocess.run(cmd, cwd=tmp_path, capture_output=True, text=True, timeout=60.0, stdin=subprocess.DEVNULL)
    return proc, time.monotonic() - start


def test_ranks_on_different_case_files_stop_together(tmp_path: Path, mbsph: Path) -> None:
    # two valid cases that differ: the ranks used to wait for each other for ever
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    (a / "case.nml").write_text(dambreak("OUT"))
    (b / "case.nml").write_text(dambreak("OUT").replace("t_end = 1.0", "t_end = 0.9"))
    assert (a / "case.nml").read_text() != (b / "case.nml").read_text()
    proc, elapsed = mpmd(tmp_path, mbsph, [(a, "case.nml"), (a, str(b / "case.nml"))])
    assert proc.returncode == EXIT_INPUT, describe(proc)
    assert elapsed < 20.0, f"took {elapsed:.1f} s to stop"
    lines = [ln for ln in proc.stderr.splitlines() if "mbsph: error" in ln]
    assert len(lines) == 1 and "did not all read the same case file" in lines[0], lines
    assert not (a / "OUT").exists(), "the refused run prepared its output folder"


def test_rank_that_cannot_see_the_folder_stops_every_rank(tmp_path: Path, mbsph: Path) -> None:
    # rank 1 runs in another working directory, so the relative out_dir rank 0 made is not
    # there for it: the ranks used to hang in the collective open of the first snapshot
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    text = dambreak("OUT")
    (a / "case.nml").write_text(text)
    (b / "case.nml").write_text(text)
    proc, elapsed = mpmd(tmp_path, mbsph, [(a, "case.nml"), (b, "case.nml")])
    assert proc.returncode == EXIT_INPUT, describe(proc)
    assert elapsed < 20.0, f"took {elapsed:.1f} s to stop"
    lines = [ln for ln in proc.stderr.splitlines() if "mbsph: error" in ln]
    assert len(lines) == 1 and "&run: out_dir: rank 1 cannot write the folder 'OUT'" in lines[0], lines


def processes_in(folder: Path) -> list[int]:
    """The live (not zombie) processes of build/mbsph whose working directory is folder."""
    found = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            if Path(os.readlink(entry / "cwd")) != folder.resolve():
                continue
            if b"mbsph" not in (entry / "cmdline").read_bytes():
                continue
            state = (entry / "stat").read_text().rsplit(")", 1)[1].split()[0]
        except (OSError, IndexError):
            continue
        if state != "Z":
            found.append(int(entry.name))
    return found


def test_kill_and_restart_on_two_ranks_is_bit_identical(tmp_path: Path, mbsph: Path) -> None:
    # as tests/test_cases.py::test_kill_and_restart_is_bit_identical, on two ranks: every
    # process of the run killed with SIGKILL after some checkpoints, a checkpoint.h5.tmp
    # cut short left behind, and the restart on two ranks ends as the run never interrupted
    if MPIRUN is None:
        pytest.skip("mpirun is not installed")
    text = dambreak("OUT", run_extra={"max_steps": 1200, "checkpoint_every": 100, "progress_interval": 1.0e9})
    proc, out_a = run(text, tmp_path / "a", RANKS, mbsph, timeout=300.0)
    ok(proc)
    folder = tmp_path / "b"
    folder.mkdir()
    (folder / "case.nml").write_text(text)
    run_b = subprocess.Popen(mpirun_cmd(RANKS) + [str(mbsph), "case.nml"], cwd=folder, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL, start_new_session=True)
    ckpt = folder / "OUT" / "checkpoint.h5"
    try:
        wait_for_checkpoint(ckpt, 300)
    finally:
        # mpirun's process group, and the ranks themselves (Open MPI may start them in
        # groups of their own): every process of the run, as a batch system kills a job
        os.killpg(run_b.pid, signal.SIGKILL)
        run_b.wait()
        for _ in range(100):
            ranks = processes_in(folder)
            if not ranks:
                break
            for pid in ranks:
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
            time.sleep(0.05)
    with h5py.File(ckpt, "r") as f:
        killed_at = int(f.attrs["istep"])
    assert 300 <= killed_at < 1200, f"the run was not killed mid-way (checkpoint of step {killed_at})"
    data = ckpt.read_bytes()
    (folder / "OUT" / "checkpoint.h5.tmp").write_bytes(data[: len(data) // 2])
    assert "max_steps = 1200" in text
    proc, out_b = run(text.replace("max_steps = 1200", "max_steps = 1200, restart = .true."), folder, RANKS, mbsph,
                      timeout=300.0)
    ok(proc)
    final_a, final_b = snapshots(out_a)[-1], snapshots(out_b)[-1]
    assert read_snapshot(final_a).step == read_snapshot(final_b).step == 1200
    # bit for bit: the same ranks, the same slabs, the same memory order from the checkpoint
    assert_same_datasets(final_a, final_b)
    assert (out_a / "energy.csv").read_text() == (out_b / "energy.csv").read_text(), "energy.csv differs"
