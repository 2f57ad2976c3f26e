"""Rigid bodies and contact: the seed paper's test cases against their analytic
answers (post/paper_cases.py), rest on a face, and free motion in every integrator.

Each tolerance comes from the issue; the case files are input/paper/*.nml.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import ROOT, assert_ok, run_case
from post import paper_cases as pc
from post.io import read_csv

pytestmark = pytest.mark.usefixtures("mbsph")


def run_paper(name: str, model: str, tmp_path: Path, mbsph: Path) -> dict:
    text = (ROOT / "input" / "paper" / f"{name}_{model}.nml").read_text()
    proc, out = run_case(text, tmp_path, binary=mbsph)
    assert_ok(proc)
    return read_csv(out / "bodies.csv")


def body(d: dict, b: int) -> dict:
    m = d["body"] == b
    return {k: v[m] for k, v in d.items()}


@pytest.mark.parametrize("model", ["noncohesive_spring", "repulsive"])
def test_tc1a_rolling(model: str, tmp_path: Path, mbsph: Path) -> None:
    s = body(run_paper("tc1a_rolling", model, tmp_path, mbsph), 1)
    t = s["time"][-1]
    z_exact = float(pc.tc1a_height(t))
    # 1 cm: the bar for the centre height at 0.5 s (paper: 0.55 -> 0.22 m)
    assert abs(t - 0.5) < 1e-3
    assert abs(s["y"][-1] - z_exact) <= 0.01, f"z(0.5 s) = {s['y'][-1]:.4f} m, rolling without slip {z_exact:.4f} m"
    speed = math.hypot(s["u"][-1], s["v"][-1])
    # 5 %: angular velocity consistent with rolling, omega R = v
    assert abs(abs(s["omega"][-1]) * pc.TC1A_R / speed - 1.0) <= 0.05, \
        f"omega R = {abs(s['omega'][-1]) * pc.TC1A_R:.4f} m/s, v = {speed:.4f} m/s"


def test_tc1b_sliding(tmp_path: Path, mbsph: Path) -> None:
    s = body(run_paper("tc1b_sliding", "noncohesive_spring", tmp_path, mbsph), 1)
    dist = math.hypot(s["x"][-1] - s["x"][0], s["y"][-1] - s["y"][0])
    exact = float(pc.tc1b_distance(s["time"][-1]))
    # 2 cm: the bar for the sliding block at 0.5 s
    assert abs(dist - exact) <= 0.02, f"slid {dist:.4f} m, g (sin a - mu cos a) t^2/2 = {exact:.4f} m"


def test_tc1b_static_friction_holds(tmp_path: Path, mbsph: Path) -> None:
    s = body(run_paper("tc1b_static", "noncohesive_spring", tmp_path, mbsph), 1)
    a = pc.TC1B_STATIC_ALPHA
    tdir = np.array([math.cos(a), -math.sin(a)])
    # slip of the contact face: the centre of the bottom face, whose position does not
    # change when the block only leans on its compliant contact
    off = np.array([0.0, -0.5 * pc.TC1B_H])

    def face(k):
        c, sn = math.cos(s["angle"][k]), math.sin(s["angle"][k])
        return np.array([s["x"][k], s["y"][k]]) + np.array([c * off[0] - sn * off[1], sn * off[0] + c * off[1]])
    slip = abs(float(np.dot(face(-1) - face(0), tdir)))
    # 1 mm: the bar; mu = 0.5 > tan 20 deg, so the block must not slide
    assert slip <= 1e-3, f"the contact face slipped {1e3 * slip:.2f} mm along the slope"


def test_static_friction_does_not_creep(tmp_path: Path, mbsph: Path) -> None:
    """The TC1b block held by friction (mu = 0.5 > tan 20 deg) for 2 s: once the contact
    has taken the load, the block must stand still (Coulomb: no slip below mu N). The
    friction spring on the contact's slip memory allows an elastic slip of at most
    `stick_length` dp (0.01 dp = 0.05 mm) in all; without it the regularised friction
    lets the block creep at stick_velocity tan(a)/mu = 0.7 mm/s."""
    text = (ROOT / "input" / "paper" / "tc1b_static_noncohesive_spring.nml").read_text()
    text = text.replace("t_end = 0.5, dt_out = 0.05", "t_end = 2.0, dt_out = 0.1")
    proc, out = run_case(text, tmp_path, binary=mbsph)
    assert_ok(proc)
    s = body(read_csv(out / "bodies.csv"), 1)
    a = pc.TC1B_STATIC_ALPHA
    tdir = np.array([math.cos(a), -math.sin(a)])
    off = np.array([0.0, -0.5 * pc.TC1B_H])

    def face(k: int) -> np.ndarray:
        c, sn = math.cos(s["angle"][k]), math.sin(s["angle"][k])
        return np.array([s["x"][k], s["y"][k]]) + np.array([c * off[0] - sn * off[1], sn * off[0] + c * off[1]])
    k0 = int(np.argmin(abs(s["time"] - 0.5)))
    assert abs(s["time"][-1] - 2.0) < 1e-3
    slip = abs(float(np.dot(face(len(s["time"]) - 1) - face(k0), tdir)))
    # 0.01 dp: the elastic slip the spring allows in all (stick_length); a creep at the
    # regularised rate would be 1.1 mm = 0.2 dp over these 1.5 s
    assert slip <= 0.01 * pc.DP, f"the contact face slipped {1e3 * slip:.4f} mm from 0.5 s to 2 s"


def test_tc2_jump(tmp_path: Path, mbsph: Path) -> None:
    s = body(run_paper("tc2_jump", "noncohesive_spring", tmp_path, mbsph), 1)
    # landing: the first output time at which the disc touches the ground (centre at R)
    land = np.nonzero(s["y"] <= pc.TC2_R + 0.5 * pc.DP)[0]
    assert land.size > 0, "the disc never landed"
    k = land[0]
    t_exact, x_exact = pc.tc2_landing()
    # 0.02 s and 3 cm: the bars (outputs every 0.01 s)
    assert abs(s["time"][k] - t_exact) <= 0.02, f"landed at t = {s['time'][k]:.3f} s, analytic {t_exact:.3f} s"
    assert abs(s["x"][k] - x_exact) <= 0.03, f"landed at x = {s['x'][k]:.4f} m, analytic {x_exact:.4f} m"


@pytest.mark.parametrize("model", ["noncohesive", "noncohesive_spring", "repulsive"])
def test_tc3_receding(model: str, tmp_path: Path, mbsph: Path) -> None:
    d = run_paper("tc3_receding", model, tmp_path, mbsph)
    left, right = body(d, 1), body(d, 2)
    moved = abs(left["x"][-1] - left["x"][0])
    if model == "repulsive":
        # the cohesion artefact of Eq. 4 the paper shows: the left disc is dragged
        assert moved > 1e-3, f"left disc moved only {1e3 * moved:.2f} mm with the repulsive model"
        return
    # 1 mm: a receding neighbour must not pull the resting disc (non-cohesive)
    assert moved < 1e-3, f"left disc moved {1e3 * moved:.2f} mm"
    travel = right["x"][-1] - right["x"][0]
    exact = float(pc.disc_slip_roll(right["time"][-1], pc.TC3_U, pc.TC3_MU)[0])
    # 3 cm: the bar for the right disc's travel in 0.5 s
    assert abs(travel - exact) <= 0.03, f"right disc travelled {travel:.4f} m, slide-then-roll {exact:.4f} m"


FREE = """&run case_name='free', t_end=0.2, dt_out=0.05, out_dir='out' /
&domain xmin=0, xmax=2, ymin=0, ymax=2 /
&numerics dp=0.01, integrator='{integrator}' /
&fluid gravity = {g} /
&body shape='box', x=0.5, y=1.5, width=0.1, height=0.1, density=2000 /
&body shape='circle', x=0.3, y=1.0, radius=0.05, density=500, u=1.5, v=0.5, omega=3.0 /
"""


@pytest.mark.parametrize("integrator", ["symplectic", "predictor_corrector", "verlet"])
def test_free_fall_every_integrator(integrator: str, tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(FREE.format(integrator=integrator, g=9.81), tmp_path, binary=mbsph)
    assert_ok(proc)
    s = body(read_csv(out / "bodies.csv"), 1)
    t = s["time"]
    # 1e-6 m over 0.2 s: the bar for z = z0 - g t^2 / 2 in air
    err = np.max(np.abs(s["y"] - (1.5 - 0.5 * 9.81 * t**2)))
    assert t[-1] >= 0.2 - 1e-12 and err <= 1e-6, f"{integrator}: largest deviation {err:.2e} m"


@pytest.mark.parametrize("integrator", ["symplectic", "predictor_corrector", "verlet"])
def test_free_flight_and_spin_every_integrator(integrator: str, tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(FREE.format(integrator=integrator, g=0.0), tmp_path, binary=mbsph)
    assert_ok(proc)
    s = body(read_csv(out / "bodies.csv"), 2)
    t = s["time"]
    # 1e-9: a free body travels u t and turns omega t (no gravity, no fluid, no contact)
    assert np.max(np.abs(s["x"] - (0.3 + 1.5 * t))) <= 1e-9
    assert np.max(np.abs(s["y"] - (1.0 + 0.5 * t))) <= 1e-9
    assert np.max(np.abs(s["angle"] - 3.0 * t)) <= 1e-9


REST = """&run case_name='rest', t_end=1.0, dt_out=0.1, out_dir='out' /
&domain xmin=0, xmax=1, ymin=0, ymax=1 /
&numerics dp=0.01, integrator='symplectic' /
&box role='solid', xmin=0.0, xmax=1.0, ymin=0.0, ymax=0.05 /
&body shape='box', x=0.3, y=0.1, width=0.1, height=0.1, density=2000, mu=0.5 /
&body shape='circle', x=0.7, y=0.1, radius=0.05, density=2000, mu=0.5 /
&body shape='box', x=0.3, y=0.2, width=0.1, height=0.1, density=2000, mu=0.5 /
"""


def test_bodies_rest_at_touching_distance(tmp_path: Path, mbsph: Path) -> None:
    """A box and a disc on the floor and a box on the box, in air: they sit within
    0.5 dp of touching (the floor top is at y = 0.05) and do not creep."""
    proc, out = run_case(REST, tmp_path, binary=mbsph)
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    b1, b2, b3 = body(d, 1), body(d, 2), body(d, 3)
    dp = 0.01
    gaps = {"box on floor": b1["y"][-1] - 0.1, "disc on floor": b2["y"][-1] - 0.1,
            "box on box": b3["y"][-1] - b1["y"][-1] - 0.1}
    for what, gap in gaps.items():
        # 0.5 dp: the bar for bodies at rest on each other or on a wall
        assert abs(gap) <= 0.5 * dp, f"{what}: gap {gap / dp:+.3f} dp"
    for b in (b1, b2, b3):
        late = b["time"] >= 0.5
        creep = np.max(np.abs(b["y"][late] - b["y"][late][-1]))
        # 0.1 dp: no creep once settled (last half second)
        assert creep <= 0.1 * dp, f"creep {creep / dp:.3f} dp"


def test_tc4_stack_in_still_water(tmp_path: Path, mbsph: Path) -> None:
    """Three boxes resting on each other and on the floor under still water."""
    d = run_paper("tc4_stack", "noncohesive_spring", tmp_path, mbsph)
    dp, h_box = 0.01, 0.06
    ys = []
    for b in (1, 2, 3):
        s = body(d, b)
        late = s["time"] >= s["time"][-1] - 0.2 - 1e-9
        vertical = s["fy_fluid"] + s["fy_contact"] + s["fy_friction"]
        ratio = float(np.mean(vertical[late] / -s["fy_gravity"][late]))
        # 0.0015: the paper's figure 13 bar, vertical force over weight averaged over the last 0.2 s
        assert abs(ratio - 1.0) <= 0.0015, f"body {b}: vertical force / weight = {ratio:.5f}"
        settled = s["time"] >= 0.3
        drift = float(np.max(s["y"][settled]) - np.min(s["y"][settled]))
        # 0.1 dp: no drift once the start has settled (after 0.3 s)
        assert drift <= 0.1 * dp, f"body {b} drifted {drift / dp:.3f} dp"
        ys.append(s["y"][-1])
    gaps = [ys[0] - 0.5 * h_box, ys[1] - ys[0] - h_box, ys[2] - ys[1] - h_box]
    for k, gap in enumerate(gaps):
        # 0.5 dp: bodies at rest sit within half a spacing of touching
        assert abs(gap) <= 0.5 * dp, f"contact {k + 1} (from the floor up): gap {gap / dp:+.3f} dp"


HERTZ = """&run case_name='hertz', t_end=0.3, dt_out=0.1, energy_interval=0.0005, out_dir='out' /
&domain xmin=0, xmax=0.4, ymin=-0.03, ymax=0.4 /
&numerics dp=0.005, h_over_dp=1.3, integrator='symplectic' /
&contact model='hertz' /
&box role='solid', xmin=0.0, xmax=0.4, ymin=-0.015, ymax=0.0 /
&body shape='circle', x=0.2, y=0.2, radius=0.05, density=2000, restitution={e}, young=2.0e10 /
"""


@pytest.mark.parametrize("e", [0.5, 0.9])
def test_hertz_restitution(e: float, tmp_path: Path, mbsph: Path) -> None:
    """A disc dropped on a wall rebounds with the set restitution: the largest upward
    speed after the impact over the largest downward speed before it."""
    proc, out = run_case(HERTZ.format(e=e), tmp_path, binary=mbsph)
    assert_ok(proc)
    s = body(read_csv(out / "bodies.csv"), 1)
    k = int(np.argmin(s["v"]))
    ratio = -float(np.max(s["v"][k:k + 200])) / float(s["v"][k])
    # 5 %: the bar for the rebound velocity ratio
    assert abs(ratio - e) <= 0.05 * e, f"rebound ratio {ratio:.4f}, restitution {e}"


DROP = """&run case_name='drop', t_end=0.8, dt_out=0.4, energy_interval=0.001, out_dir='out' /
&domain xmin=0, xmax=1, ymin=0, ymax=1.4 /
&numerics dp=0.01, integrator='symplectic' /
&box role='solid', xmin=0.0, xmax=1.0, ymin=0.0, ymax=0.05 /
&body shape='box', x=0.5, y=0.1, width=0.2, height=0.1, density=500, mu=0.5 /
&body shape='box', x=0.85, y=0.1, width=0.1, height=0.1, density=2000, mu=0.1, u=1.0 /
&box role='solid', xmin=0.95, xmax=1.0, ymin=0.05, ymax=0.3 /
"""


def test_hard_contacts_stay_stable(tmp_path: Path, mbsph: Path) -> None:
    """A box resting on the floor and a box sliding at 1 m/s into a corner: no
    interpenetration beyond 0.5 dp, no energy gain, no NaN. (The heavy drop from 1 m and
    the wedge on its tip are in tests/test_stability.py.)"""
    proc, out = run_case(DROP, tmp_path, binary=mbsph)
    assert_ok(proc)
    e = read_csv(out / "energy.csv")
    dp = 0.01
    pen = float(np.max(e["max_penetration"]))
    # the overlap of two surfaces is dp minus the normal distance of their particles;
    # 0.5 dp: the bar
    assert pen <= 0.5 * dp, f"largest penetration {pen / dp:.3f} dp"
    total = e["body_kinetic"] + e["body_potential"]
    # no energy gain: the contact and friction only dissipate (1e-3 of the start's energy)
    assert np.max(total - total[0]) <= 1e-3 * abs(total[0]), \
        f"body energy rose by {np.max(total - total[0]):.4g} J/m over {total[0]:.4g} J/m"


@pytest.mark.parametrize("integrator", ["symplectic", "verlet", "symplectic+mdbc"])
def test_restart_with_bodies_is_bit_identical(integrator: str, tmp_path: Path, mbsph: Path) -> None:
    """Bodies in contact under water: 200 steps in one go, and 100 steps plus a restart
    for 100 more, give the same final snapshot and body state bit for bit (also with the
    modified dynamic boundary, whose ghost offsets turn with the bodies)."""
    base = (ROOT / "input" / "paper" / "tc4_stack_noncohesive_spring.nml").read_text()
    integrator, _, boundary = integrator.partition("+")
    base = base.replace("integrator = 'symplectic'", f"integrator = '{integrator}'")
    if boundary:
        assert base.count("integrator = 'symplectic'") == 1
        base = base.replace("integrator = 'symplectic'", f"integrator = 'symplectic', boundary = '{boundary}'")

    def text(steps: int, restart: bool = False) -> str:
        extra = f"\n  max_steps = {steps}" + ("\n  restart = .true." if restart else "")
        return base.replace("  overwrite = .true.", "  overwrite = .true." + extra)

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    proc, out_a = run_case(text(200), tmp_path / "a", binary=mbsph)
    assert_ok(proc)
    proc, out_b = run_case(text(100), tmp_path / "b", binary=mbsph)
    assert_ok(proc)
    proc, _ = run_case(text(200, restart=True), tmp_path / "b", binary=mbsph)
    assert_ok(proc)
    import h5py
    snaps_a = sorted(out_a.glob("snap_*.h5"))
    snaps_b = sorted(out_b.glob("snap_*.h5"))
    with h5py.File(snaps_a[-1]) as fa, h5py.File(snaps_b[-1]) as fb:
        assert fa.attrs["step"] == fb.attrs["step"] == 200
        for name in fa:
            assert np.array_equal(fa[name][()], fb[name][()]), f"dataset {name} differs after the restart"
    rows_a = (out_a / "bodies.csv").read_text().splitlines()[-3:]
    rows_b = (out_b / "bodies.csv").read_text().splitlines()[-3:]
    assert rows_a == rows_b, "the final body rows differ after the restart"


def test_debug_build_runs_bodies_in_water(tmp_path: Path, mbsph_debug: Path) -> None:
    """The debug build (bounds checks, traps on invalid, zero, overflow) runs bodies in
    contact under water without a trap."""
    text = (ROOT / "input" / "paper" / "tc4_stack_noncohesive_spring.nml").read_text()
    text = text.replace("  overwrite = .true.", "  overwrite = .true.\n  max_steps = 60")
    proc, _ = run_case(text, tmp_path, binary=mbsph_debug)
    assert_ok(proc)


def test_body_input_errors_name_group_and_variable(tmp_path: Path, mbsph: Path) -> None:
    """Bad &body input stops with the file, the group and the variable; a body placed
    exactly on a floor (touching, not overlapping) is accepted."""
    base = """&run out_dir='out' /
&domain xmax=1, ymax=1 /
&numerics dp=0.01 /
&box role='solid', xmin=0, xmax=1, ymin=0, ymax=0.05 /
"""
    cases = {
        "&body shape='box', x=0.5, y=0.075, width=0.1, height=0.05, colour=2 /": ("&body", "colour"),
        "&body shape='star', x=0.5, y=0.5, radius=0.1, density=1000 /": ("&body #1", "shape"),
        "&body shape='circle', x=0.5, y=0.5, radius=0.1, density=-5 /": ("&body #1", "density"),
        "&body shape='circle', x=0.5, y=0.12, radius=0.1, density=1000 /": ("&body #1", "overlaps"),
        "&contact model='glue' /": ("&contact", "model"),
    }
    for k, (body_text, (group, word)) in enumerate(cases.items()):
        folder = tmp_path / f"c{k}"
        folder.mkdir()
        proc, out = run_case(base + body_text + "\n", folder, binary=mbsph)
        assert proc.returncode == 2, f"{body_text}: exit {proc.returncode}\n{proc.stderr}"
        assert "case.nml" in proc.stderr and group in proc.stderr and word in proc.stderr, proc.stderr
        assert not (out / "snap_00000.h5").exists()
    folder = tmp_path / "ok"
    folder.mkdir()
    text = base.replace("out_dir='out'", "out_dir='out', t_end=0.01") + \
        "&body shape='box', x=0.5, y=0.075, width=0.1, height=0.05, density=2000 /\n"
    proc, _ = run_case(text, folder, binary=mbsph)
    assert_ok(proc)


COLLIDE = """&run case_name='collide', t_end=0.3, dt_out=0.1, energy_interval=0.005, out_dir='out' /
&domain xmin=0, xmax=1, ymin=0, ymax=1 /
&numerics dp=0.005, h_over_dp=1.3, integrator='{integrator}' /
&fluid gravity = 0.0 /
&contact model = '{model}' /
&body shape='circle', x=0.3, y=0.5, radius=0.05, density=2000, mu=0.3, u=1.0, v=0.1, omega=5.0, young=1.0e8 /
&body shape='box', x=0.6, y=0.52, width=0.08, height=0.12, angle=20.0, density=800, mu=0.3, u=-0.5, young=1.0e8 /
"""


@pytest.mark.parametrize("model", ["noncohesive_spring", "repulsive", "hertz"])
def test_isolated_collision_conserves_momentum(model: str, tmp_path: Path, mbsph: Path) -> None:
    """Two bodies collide off-centre with friction, no gravity, no fluid: every pair
    force is applied equal and opposite, so the total momentum stays as it started."""
    proc, out = run_case(COLLIDE.format(model=model, integrator="symplectic"), tmp_path, binary=mbsph)
    assert_ok(proc)
    d = read_csv(out / "bodies.csv")
    m1 = 2000.0 * math.pi * 0.05**2
    m2 = 800.0 * 0.08 * 0.12
    a, b = body(d, 1), body(d, 2)
    px = m1 * a["u"] + m2 * b["u"]
    py = m1 * a["v"] + m2 * b["v"]
    p0 = math.hypot(px[0], py[0])
    # the bodies did meet: the disc's velocity changed
    assert abs(a["u"][-1] - a["u"][0]) > 0.1, "no collision happened"
    # 1e-10 relative: the bar for an isolated two-body collision
    assert np.max(np.hypot(px - px[0], py - py[0])) <= 1e-10 * p0


def test_bodies_stay_rigid_and_are_named_in_the_effects_line(tmp_path: Path, mbsph: Path) -> None:
    """Two bodies that collide and spin: every particle is placed from its body's pose
    after every stage, so in the body frame (pose removed) the particles sit exactly
    where they started. The effects line names the bodies and the contact model."""
    from post.io import list_snapshots, read_snapshot
    proc, out = run_case(COLLIDE.format(model="noncohesive_spring", integrator="symplectic"), tmp_path,
                         binary=mbsph)
    assert_ok(proc)
    effects = [ln for ln in proc.stdout.splitlines() if "effects on:" in ln]
    assert len(effects) == 1 and "2 rigid bodies, contact noncohesive_spring" in effects[0], effects
    snaps = list_snapshots(out)

    def body_frame(path: Path) -> dict[int, np.ndarray]:
        s = read_snapshot(path)
        pose = s.datasets["body_pose"]
        frames = {}
        for b in (1, 2):
            x, y, th = pose[b - 1]
            r = s.position[s.body == b] - [x, y]
            c, sn = math.cos(th), math.sin(th)
            # rotate back by the current angle: the pattern in a frame fixed to the body
            frames[b] = np.column_stack([c * r[:, 0] + sn * r[:, 1], -sn * r[:, 0] + c * r[:, 1]])
        return frames

    first, last = body_frame(snaps[0]), body_frame(snaps[-1])
    end = read_csv(out / "bodies.csv")
    assert abs(body(end, 1)["rotation"][-1]) > 0.1, "the disc hardly turned: the test would prove little"
    for b in (1, 2):
        # 1e-12 m: rounding of the placement from the pose; a drift of the pattern is far larger
        err = float(np.max(np.abs(last[b] - first[b])))
        assert err <= 1e-12, f"body {b}: particles moved {err:.2e} m in the body frame"
