"""Porous regions (doc/porous.md) against the laws they solve; the cases are those of
post/porous_cases.py, which prints the table of doc/porous.md.

- Drainage: a block of water inside stones, free on every side, falls under gravity
  against the stones' resistance. Its pressure stays near zero, so the pore velocity V
  obeys (1 + c_A) dV/dt = g - kl V - kq V^2 (Van Gent's Forchheimer law with the added
  mass): the block's mean velocity must follow that equation's solution and reach its
  terminal velocity, the flow rate at which the head loss per unit length is 1. Three
  stone sizes put the flow in the Darcy, the transitional and the turbulent regime.
- Still water in a tank filled with stones: the pore water's pressure is hydrostatic and
  it stays at rest, to the bars of the open-water tank (tests/test_cases.py), walls and
  floor among the pores.
- Still water in a tank half filled with stones: the water stands at one level inside
  and outside the stones (communicating vessels) and has one pressure at one depth.
- Regular long waves on a rectangular porous breakwater: its reflection and transmission
  coefficients against Madsen's (1974) theory (post/porous_waves.py), with the flume's
  own decay, measured in the same flume without the structure, taken out.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from conftest import assert_ok, assert_same_datasets, read_attrs, run_case, snapshots
from post import hydrostatic
from post.io import FLUID, list_snapshots, read_snapshot
from post.porous_cases import (STEADY, STEADY_DP, G, H, N, REGIMES, T_SETTLE, TANK_DP, WIDTH, coefficients,
                               drain_case, steady_case, steady_law, steady_loss, steady_t_end,
                               drain_velocity, stones_tank_case, surface, terminal_velocity)
from post.porous_waves import case as porous_waves_case
from post.porous_waves import corrected, measure


@pytest.fixture(scope="module", params=sorted(REGIMES))
def drain(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    d50 = REGIMES[request.param]
    proc, out = run_case(drain_case(d50), tmp_path_factory.mktemp(f"drain_{request.param}"))
    assert_ok(proc)
    rows = []
    for path in list_snapshots(out):
        snap = read_snapshot(path)
        fluid = snap.kind == FLUID
        rows.append((snap.time, -snap.velocity[fluid, 1].mean(), int(fluid.sum()),
                     float(np.abs(snap.pressure[fluid]).max())))
    return request.param, d50, np.array(rows)


def test_drainage_regime_is_the_one_named(drain) -> None:
    """The stone sizes span the regimes: the linear share of the terminal resistance."""
    name, d50, _ = drain
    kl, _, _ = coefficients(N, d50)
    share = kl * terminal_velocity(N, d50) / G
    assert {"darcy": share > 0.9, "transitional": 0.2 < share < 0.8, "turbulent": share < 0.1}[name], share


def test_drainage_reaches_the_forchheimer_flow_rate(drain) -> None:
    """Terminal pore velocity within 0.5 % of the root of kl V + kq V^2 = g (I = 1)."""
    _, d50, rows = drain
    vt = terminal_velocity(N, d50)
    late = rows[rows[:, 0] >= 0.4, 1]
    assert late.size >= 4
    assert np.all(np.abs(late / vt - 1) < 0.005), (late, vt)


def test_drainage_follows_the_momentum_equation(drain) -> None:
    """V(t) from rest within 1 % of (1 + c_A) dV/dt = g - kl V - kq V^2 at every snapshot."""
    _, d50, rows = drain
    exact = drain_velocity(N, d50, rows[1:, 0])
    assert np.all(np.abs(rows[1:, 1] / exact - 1) < 0.01), list(zip(rows[1:, 0], rows[1:, 1], exact))


def test_drainage_keeps_the_water_and_its_pressure_near_zero(drain) -> None:
    """No particle lost; the pressure of the free-falling block stays below 5 % of
    rho g (block height) at every particle."""
    _, _, rows = drain
    assert np.all(rows[:, 2] == rows[0, 2])
    assert np.all(rows[1:, 3] < 0.05 * 1000.0 * G * 0.2), rows[:, 3]


def stones_tank(stones: str, tmp: Path):
    """The last snapshot of the still tank with stones, after T_SETTLE."""
    proc, out = run_case(stones_tank_case(stones), tmp)
    assert_ok(proc)
    snap = read_snapshot(list_snapshots(out)[-1])
    assert snap.time >= T_SETTLE
    return snap


@pytest.fixture(scope="module")
def full_tank(tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    return stones_tank("full", tmp_path_factory.mktemp("stones_full"))


@pytest.fixture(scope="module")
def half_tank(tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    return stones_tank("half", tmp_path_factory.mktemp("stones_half"))


def test_stones_tank_is_hydrostatic(full_tank) -> None:
    """Filled with stones: the bed pressure by a linear fit within 2 % of rho g H and the
    profile within 3 % of rho g H (the open-water tank's bars), in the middle of the tank."""
    ys = hydrostatic.sample_heights(full_tank, 0.0, H, n=10)
    p = hydrostatic.profile(full_tank, 0.5 * WIDTH, ys)
    fit = hydrostatic.bed_pressure(ys, p, 0.0)
    p_ref = 1000.0 * G * H
    assert abs(fit.p_bed / p_ref - 1) <= 0.02, (fit.p_bed, p_ref)
    assert np.nanmax(np.abs(p - 1000.0 * G * (H - ys))) <= 0.03 * p_ref


def test_stones_tank_is_at_rest(full_tank) -> None:
    """Filled with stones: the mean Darcy speed n |V| below 1e-3 sqrt(gH), the open-water
    tank's bar. The Darcy velocity, the discharge per unit of total area, is what compares
    with open water's velocity (it is the one continuous across the stones' edge); the
    pore water's own speed is 1/n of it (doc/porous.md gives both)."""
    fluid = full_tank.kind == FLUID
    darcy = full_tank.datasets["porosity"][fluid] * np.hypot(*full_tank.velocity[fluid].T)
    assert darcy.mean() <= 1e-3 * math.sqrt(G * H), darcy.mean()


def test_half_stones_tank_has_one_level(half_tank) -> None:
    """Half filled with stones: one water level inside and outside the stones within half
    a particle spacing. (The water by the stones' edge still moves at a few 1e-3 sqrt(gH)
    after T_SETTLE: doc/porous.md.)"""
    outside = surface(half_tank, 0.1, 0.3)
    inside = surface(half_tank, 0.7, 0.9)
    assert abs(inside - outside) <= 0.5 * TANK_DP, (inside, outside)


def test_half_stones_tank_has_one_pressure_at_one_depth(half_tank) -> None:
    """Half filled with stones: at three depths the pressure inside and outside the
    stones agree within 2 % of rho g H (0.69 % measured, doc/porous.md; 2.06 % before
    each particle's mass was that of the space it fills on its start lattice)."""
    ys = np.array([0.2, 0.4, 0.6]) * H
    p_out = hydrostatic.profile(half_tank, 0.2, ys)
    p_in = hydrostatic.profile(half_tank, 0.8, ys)
    assert np.all(np.abs(p_in - p_out) <= 0.02 * 1000.0 * G * H), (p_in, p_out)


def test_debug_build_half_stones_tank(tmp_path: Path, mbsph_debug: Path) -> None:
    """The debug build (bounds checks, traps on invalid, zero-division and overflow) runs
    50 steps of the tank half filled with stones (pores, their edge, walls among them),
    and the water is still near rest: the mean speed below 1e-2 sqrt(gH)."""
    text = stones_tank_case("half").replace("dt_out = 0.5,", "dt_out = 0.5, max_steps = 50,")
    proc, out = run_case(text, tmp_path, binary=mbsph_debug)
    assert_ok(proc)
    snap = read_snapshot(list_snapshots(out)[-1])
    assert snap.attrs["step"] == 50
    speed = np.hypot(*snap.velocity[snap.kind == FLUID].T)
    assert speed.mean() < 1e-2 * math.sqrt(G * H), speed.mean()


def test_snapshots_hold_the_porosity(half_tank) -> None:
    """The snapshots hold each particle's porosity (listed in the XDMF index for ParaView):
    n deep in the stones, 1 in the open water, between the two only within half the
    transition's width (2h = 4 dp here) of the stones' edge."""
    n = half_tank.datasets["porosity"]
    x = half_tank.position[:, 0]
    fluid = half_tank.kind == FLUID
    assert np.allclose(n[fluid & (x > 0.5 * WIDTH + 2 * TANK_DP)], N)
    assert np.all(n[fluid & (x < 0.5 * WIDTH - 2 * TANK_DP)] == 1.0)
    assert np.all((n >= N - 1e-12) & (n <= 1.0))
    assert 'Name="porosity"' in (half_tank.path.parent / "particles.xmf").read_text()


def test_restart_with_stones_is_bit_identical(tmp_path: Path, mbsph: Path) -> None:
    """A run with stones stopped at step 100 and restarted to step 200 gives the same
    snapshots, bit for bit, as one run of 200 steps (the porosity is a function of the
    positions, nothing of it is kept but the superficial density)."""
    def text(max_steps: int, restart: bool = False) -> str:
        return stones_tank_case("half").replace(
            "dt_out = 0.5,", f"dt_out = 0.02, max_steps = {max_steps}, restart = {'.true.' if restart else '.false.'},")

    (tmp_path / "a").mkdir()
    (tmp_path / "b").mkdir()
    proc, out_a = run_case(text(200), tmp_path / "a")
    assert_ok(proc)
    proc, out_b = run_case(text(100), tmp_path / "b")
    assert_ok(proc)
    proc, _ = run_case(text(200, restart=True), tmp_path / "b")
    assert_ok(proc)
    by_step = {int(read_attrs(p)["step"]): p for p in snapshots(out_b)}
    for snap_a in snapshots(out_a):
        step = int(read_attrs(snap_a)["step"])
        assert step in by_step, f"the restarted run has no snapshot of step {step}"
        assert_same_datasets(snap_a, by_step[step])
    assert int(read_attrs(snapshots(out_a)[-1])["step"]) == 200


WAVES_DP = 0.03               # 10 particles over the depth: K_R and K_T as at 20 mm (doc/porous.md)


@pytest.fixture(scope="module")
def porous_waves(tmp_path_factory: pytest.TempPathFactory, mbsph: Path):
    """The porous breakwater in regular waves and the same flume without it (about two
    minutes each on one core)."""
    runs = {}
    for name, structure in (("block", True), ("empty", False)):
        tmp = tmp_path_factory.mktemp(f"porous_waves_{name}")
        _, text = porous_waves_case(out_dir="OUT/porous_waves", dp=WAVES_DP, structure=structure)
        proc, out = run_case(text, tmp)
        assert_ok(proc)
        runs[name] = measure(out)
    return runs


@pytest.mark.long
def test_porous_breakwater_reflects_and_transmits_as_madsen(porous_waves) -> None:
    """The issue's bar: K_R and K_T of the structure (n = 0.45, D50 = 0.03 m, 0.5 m wide,
    kh = 0.5) within 10 % of Madsen's long-wave theory with the solver's resistance, at the
    measured incident height, once the flume's own decay (the empty flume's height behind
    over its incident height, over the same paths) is taken out. The empty flume itself:
    reflection below 3 % (the damping zone takes the wave) and a decay below 15 % over the
    wavelength from the gauges to the one behind, so that what is taken out is small."""
    m, th = porous_waves["block"]
    empty, _ = porous_waves["empty"]
    assert empty.KR < 0.03, empty
    assert 0.85 < empty.KT <= 1.0, empty
    kr, kt = corrected(m, empty)
    assert abs(kt / th.KT - 1) <= 0.10, (kt, th.KT, m, empty)
    assert abs(kr / th.KR - 1) <= 0.10, (kr, th.KR, m, empty)


BOUNDARIES = ("dynamic", "mdbc")


@pytest.fixture(scope="module", params=BOUNDARIES)
def steady_still(request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory,
                 mbsph: Path) -> tuple[str, Path]:
    """The still channel, the reference of the head loss, with either wall treatment."""
    boundary = request.param
    proc, out = run_case(steady_case(0.01, 0.0, boundary=boundary), tmp_path_factory.mktemp(f"steady_still_{boundary}"))
    assert_ok(proc)
    return boundary, out


def steady_error(regime: str, still: tuple[str, Path], tmp: Path) -> tuple[float, float, float]:
    d50, u = STEADY[regime]
    boundary, reference = still
    t_end = steady_t_end(u)
    proc, out = run_case(steady_case(d50, u, t_end=t_end, boundary=boundary), tmp)
    assert_ok(proc)
    loss = steady_loss(out, reference, t_end - 0.25, t_end)
    law, lin = steady_law(u, d50, 4.0 * STEADY_DP)
    return loss, law, lin


def test_steady_darcy_flow_loses_the_forchheimer_head(steady_still, tmp_path: Path) -> None:
    """Water pushed at 10.3 mm/s up a channel through a layer of fine stones (D = 2 mm,
    n = 0.4, linear share of the resistance 0.96), open water at the same speed below and
    above it: the head loss across the layer (the two gauges' pressure difference less the
    still water's) within 2 % of the Forchheimer law integrated over the porosity profile
    (issue 17's bar; -1.5 % measured with the dynamic boundary, -1.6 % with mDBC,
    doc/porous.md)."""
    loss, law, lin = steady_error("darcy", steady_still, tmp_path)
    assert lin > 0.9
    assert abs(loss / law - 1) <= 0.02, (loss, law)


def test_steady_transitional_flow_loses_the_forchheimer_head(steady_still, tmp_path: Path) -> None:
    """The same channel with D = 10 mm stones at 70 mm/s (linear share 0.44): within 2 %
    (+1.3 % measured with the dynamic boundary, -0.1 % with mDBC; +12.7 % while the pores'
    start lattice held 5.6 % more water than their porosity, doc/porous.md)."""
    loss, law, lin = steady_error("transitional", steady_still, tmp_path)
    assert 0.3 < lin < 0.6
    assert abs(loss / law - 1) <= 0.02, (loss, law)


@pytest.mark.xfail(strict=True, reason="known: the turbulent flow loses 8 % more head than the law with mDBC "
                   "(14 % with the dynamic boundary), about the head of the pore water's jets leaving the "
                   "layer, which the smooth volume-averaged equations do not have: doc/porous.md, what "
                   "does not work yet")
def test_steady_turbulent_flow_loses_the_forchheimer_head(steady_still, tmp_path: Path) -> None:
    """The same channel with D = 50 mm stones at 0.24 m/s (linear share 0.04): within 2 %."""
    if steady_still[0] != "mdbc":
        pytest.skip("measured with mDBC, the porous cases' boundary (the dynamic boundary's +14 % in doc/porous.md)")
    loss, law, lin = steady_error("turbulent", steady_still, tmp_path)
    assert lin < 0.1
    assert abs(loss / law - 1) <= 0.02, (loss, law)
