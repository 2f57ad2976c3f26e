"""The study tool post/study.py: a tiny study of two coarse dam-break runs (CSV columns,
resume), the Pareto front and the order-of-convergence fit on synthetic data, the
case-file edits and the study-file checks."""
from __future__ import annotations

import csv
import math
from pathlib import Path

import f90nml
import numpy as np
import pytest

from conftest import ROOT
from post import study as st
from post.validation_cases import CASES, wall_layers

TINY = """[study]
case = "dambreak"
workers = 1
out = "{out}"

[set]
"run.t_end" = 0.28
"run.dt_out" = 0.04

[parameters]
resolution = [8, 10]
"""


def write_study(tmp_path: Path, text: str, name: str = "tiny") -> Path:
    path = tmp_path / f"{name}.toml"
    path.write_text(text.format(out=tmp_path / "out"))
    return path


def test_tiny_study_csv_and_resume(tmp_path: Path, mbsph: Path, capsys: pytest.CaptureFixture) -> None:
    study = st.load_study(write_study(tmp_path, TINY))
    rows = st.run_study(study, binary=mbsph)
    assert [r["status"] for r in rows] == ["ok", "ok"]
    with open(tmp_path / "out" / "results.csv", newline="") as f:
        table = list(csv.DictReader(f))
    cols = list(table[0])
    # the parameters first, then every measured column, then the case's extras
    assert cols[0] == "resolution"
    for c in ["run", "status", "error", "particles", "steps", "wall_s", "us_per_particle_step", "elapsed_s",
              "cpu_s", "peak_rss_mb", "pair_loop_s", "front_speed_error", "lead_over_a"]:
        assert c in cols, f"results.csv lacks column {c}"
    for r in table:
        assert int(r["particles"]) > 0 and int(r["steps"]) > 0
        assert float(r["t_reached"]) >= 0.28 - 1e-9
        assert 0.0 < float(r["error"]) < 1.0
        assert float(r["wall_s"]) > 0.0 and float(r["us_per_particle_step"]) > 0.0
        # the solver's own memory: a few MB to a few hundred, not the Python parent's
        if st.GNU_TIME.is_file():
            assert 1.0 < float(r["peak_rss_mb"]) < 1000.0
    # finer dp, more particles: dp = a/N and the walls follow it
    assert int(table[1]["particles"]) > int(table[0]["particles"])
    assert (tmp_path / "out" / "error_cost.png").is_file()
    assert (tmp_path / "out" / "error_dp.png").is_file()
    stamps = {p: p.stat().st_mtime_ns for p in (tmp_path / "out").glob("*/out/run.log")}
    capsys.readouterr()
    # resume: a second invocation runs nothing and gives the same rows
    again = st.run_study(st.load_study(write_study(tmp_path, TINY)), binary=mbsph)
    assert "0 run(s) made, 2 already done" in capsys.readouterr().out
    assert {p: p.stat().st_mtime_ns for p in (tmp_path / "out").glob("*/out/run.log")} == stamps
    assert [r["error"] for r in again] == [r["error"] for r in rows]
    # another build of the solver (here: the same with one byte appended) runs them again
    other = tmp_path / "mbsph_other"
    other.write_bytes(mbsph.read_bytes() + b"\0")
    other.chmod(0o755)
    st.run_study(st.load_study(write_study(tmp_path, TINY)), binary=other)
    assert "2 run(s) made, 0 already done" in capsys.readouterr().out


def test_pareto_front() -> None:
    cost = [1.0, 2.0, 3.0, 4.0, 2.5, 5.0, float("nan")]
    error = [0.5, 0.3, 0.35, 0.1, 0.2, 0.1, 0.01]
    # 3.0/0.35 is beaten by 2.0/0.3; 5.0/0.1 by 4.0/0.1; NaN cost never counts
    assert st.pareto_front(cost, error) == [0, 1, 4, 3]
    rng = np.random.default_rng(1)
    c, e = rng.random(200), rng.random(200)
    front = st.pareto_front(c, e)
    for i in range(200):
        dominated = any(c[j] <= c[i] and e[j] <= e[i] and (c[j] < c[i] or e[j] < e[i]) for j in range(200))
        assert (i in front) == (not dominated)


@pytest.mark.parametrize("order", [0.5, 1.0, 2.0, 3.3])
def test_observed_order_on_synthetic_data(order: float) -> None:
    dp = np.array([0.04, 0.02, 0.01, 0.005])
    p, c = st.observed_order(dp, 0.7 * dp**order)
    assert math.isclose(p, order, rel_tol=1e-12) and math.isclose(c, 0.7, rel_tol=1e-10)
    # a 10 % scatter moves the fitted order by much less than 0.2
    noisy = 0.7 * dp**order * np.array([1.1, 0.9, 1.1, 0.9])
    assert abs(st.observed_order(dp, noisy)[0] - order) < 0.2
    assert math.isnan(st.observed_order([0.01, 0.01], [0.1, 0.2])[0])


def test_case_text_edits(tmp_path: Path) -> None:
    text = """[study]
case = "tc3"
combine = "zip"
out = "{out}"
[set]
contact = "hertz"
"body[2].u" = 1.5
[parameters]
dp = [0.005, 0.0025]
h_over_dp = [1.3, 2.0]
"""
    study = st.load_study(write_study(tmp_path, text, "edits"))
    assert study.runs == [{"dp": 0.005, "h_over_dp": 1.3}, {"dp": 0.0025, "h_over_dp": 2.0}]
    nml = f90nml.reads(st.case_text(study, study.runs[1]))
    assert nml["numerics"]["dp"] == 0.0025 and nml["numerics"]["h_over_dp"] == 2.0
    assert nml["contact"]["model"] == "hertz"
    assert nml["body"][1]["u"] == 1.5 and nml["body"][0].get("u", 0.0) == 0.0
    assert nml["run"]["out_dir"] == "out"
    # floor ceil(2h/dp) = 4 rows thick for h/dp = 2; the particle rows of the discs stay 1 cm apart
    assert wall_layers(nml) == 4
    assert math.isclose(nml["box"]["ymax"] - nml["box"]["ymin"], 4 * 0.0025)
    assert math.isclose(nml["body"][1]["x"] - nml["body"][0]["x"], 0.03 + 0.01 - 0.0025)


def test_tank_walls_follow_dp(tmp_path: Path) -> None:
    study = st.load_study(write_study(tmp_path, '[study]\ncase = "tank"\nout = "{out}"\n'
                                      '[parameters]\nresolution = [10]\n', "walls"))
    nml = f90nml.reads(st.case_text(study, study.runs[0]))
    dp = nml["numerics"]["dp"]
    assert math.isclose(dp, 0.01)
    floor, left, right = nml["box"][1:]
    # three rows for h/dp = sqrt(2), outward from the inner faces x = 0, x = 0.2, y = 0
    assert math.isclose(floor["ymin"], -3 * dp) and floor["ymax"] == 0.0
    assert math.isclose(left["xmin"], -3 * dp) and left["xmax"] == 0.0
    assert right["xmin"] == 0.2 and math.isclose(right["xmax"], 0.2 + 3 * dp)
    assert nml["domain"]["xmin"] <= left["xmin"] and nml["domain"]["ymin"] <= floor["ymin"]


@pytest.mark.parametrize("text, words", [
    ('[study]\ncase = "nope"\n[parameters]\ndp = [0.01]\n', ["case = 'nope'", "tank", "dambreak"]),
    ('[study]\ncase = "tank"\n[parameters]\nfoo = [1]\n', ["parameter 'foo'", "group.variable"]),
    ('[study]\ncase = "tank"\ncombine = "zip"\n[parameters]\ndp = [0.01, 0.02]\ncfl = [0.1]\n', ["zip"]),
    ('[study]\ncase = "tank"\n[parameters]\ndp = 0.01\n', ["dp", "non-empty list"]),
    ('[study]\ncase = "tank"\nworkers = -1\n[parameters]\ndp = [0.01]\n', ["workers"]),
])
def test_bad_study_file(tmp_path: Path, text: str, words: list[str], capsys: pytest.CaptureFixture) -> None:
    path = tmp_path / "bad.toml"
    path.write_text(text)
    assert st.main([str(path)]) == 2
    err = capsys.readouterr().err
    assert str(path) in err
    for w in words:
        assert w in err, f"{w!r} not in the message: {err}"


def test_parse_log() -> None:
    log = """MBSPH case 'x' from case.nml
  particles: 1466 (fluid 800, fixed boundary 666, moving boundary 0, floating body 0)
done: t = 0.280002 s after 2553 steps; fluid particles lost: 3
wall time by phase [s]:
    setup              0.011     0.9 %
    grid               0.034     3.2 %
    pair loop          0.961    89.6 %
    bodies             0.000     0.0 %
    integrate          0.039     3.7 %
    output             0.019     1.8 %
    comm               0.000     0.0 %
cost: .2839 microseconds per particle-step (3742698 particle-steps in 1.062 s)
"""
    got = st.parse_log(log)
    assert got == {"particles": 1466, "t_reached": 0.280002, "steps": 2553, "lost": 3, "setup_s": 0.011,
                   "grid_s": 0.034, "pair_loop_s": 0.961, "bodies_s": 0.0, "integrate_s": 0.039,
                   "output_s": 0.019, "comm_s": 0.0, "us_per_particle_step": 0.2839, "wall_s": 1.062}


def test_every_case_has_its_base_file() -> None:
    for case in CASES.values():
        assert (ROOT / case.base).is_file(), case.base


def test_replace_block() -> None:
    doc = "a\n<!-- study:x -->\nold\n<!-- /study:x -->\nb\n"
    assert st.replace_block(doc, "x", "new") == "a\n<!-- study:x -->\nnew\n<!-- /study:x -->\nb\n"
    assert st.replace_block(doc, "y", "new") == doc


def test_tc3_converges_at_first_order_or_better(tmp_path: Path, mbsph: Path) -> None:
    """TC3 receding discs (study/tc3_dp.toml) at D/6, D/12, D/24: the error of the discs'
    motion against slide-then-roll falls at every refinement, with an observed order of at
    least 1 (the particle outline of a disc, which carries the contact and the rolling
    radius, is first-order accurate in dp). About 10 s of CPU time."""
    text = (ROOT / "study" / "tc3_dp.toml").read_text().replace("[study]", f'[study]\nout = "{tmp_path / "out"}"')
    path = tmp_path / "tc3_dp.toml"
    path.write_text(text)
    study = st.load_study(path)
    assert study.parameters == {"resolution": [6, 12, 24]}
    rows = st.run_study(study, binary=mbsph, workers=1)
    err = [r["error"] for r in rows]
    assert all(r["status"] == "ok" for r in rows)
    assert err[0] > err[1] > err[2], f"errors {err} do not fall with dp"
    dp = [st._dp_of(study, r) for r in rows]
    order, _ = st.observed_order(dp, err)
    # 1.0: first order, the accuracy of the particle outline of the discs
    assert order >= 1.0, f"observed order {order:.2f} over dp = {dp}, errors {err}"


def test_wave_flume_follows_dp(tmp_path: Path) -> None:
    study = st.load_study(write_study(tmp_path, '[study]\ncase = "waves"\nout = "{out}"\n'
                                      '[parameters]\nresolution = [15]\n', "flume"))
    nml = f90nml.reads(st.case_text(study, study.runs[0]))
    dp = nml["numerics"]["dp"]
    floor, wall, fluid = nml["box"]
    assert math.isclose(dp, 0.25 / 15, rel_tol=1e-9) and fluid["role"] == "fluid"
    # 15 rows of water, the flume a whole number of spacings long from the paddle
    assert math.isclose((fluid["ymax"] - fluid["ymin"]) / dp, 15.0, rel_tol=1e-9)
    n = (fluid["xmax"] - fluid["xmin"]) / dp
    assert abs(n - round(n)) < 1e-6
    # floor and end wall four rows thick (2h at the wave flume's h = 1.6 dp), the damping
    # zone ends at the wall; the paddle moved to 0.1 m + 4 dp + 1 mm (room for its rows and
    # stroke), gauges and damping zone as far from it as in the base file
    assert math.isclose(floor["ymax"] - floor["ymin"], 4 * dp, rel_tol=1e-9)
    assert math.isclose(wall["xmax"] - wall["xmin"], 4 * dp, rel_tol=1e-9) and wall["xmin"] == fluid["xmax"]
    assert nml["damping"]["x1"] == fluid["xmax"]
    x0 = nml["wavemaker"]["x0"]
    assert x0 == fluid["xmin"] and math.isclose(x0, 0.1 + 4 * dp + 1e-3, rel_tol=1e-9)
    base = f90nml.read(str(ROOT / "input" / "waves_regular.nml"))
    for g, g0 in zip(nml["gauge"], base["gauge"]):
        assert math.isclose(g["x"] - x0, g0["x"] - base["wavemaker"]["x0"], abs_tol=1e-9)
    assert math.isclose(nml["damping"]["x0"] - x0, base["damping"]["x0"] - base["wavemaker"]["x0"], abs_tol=1e-9)
