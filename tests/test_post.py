"""Tests of the post-processing package ``post`` on small synthetic output folders.

The snapshots are written with h5py in the layout of doc/output.md: a lattice of
fluid particles in a tank with a hydrostatic pressure field, boundary particles
below the bed and beside the walls.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import h5py
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the package post/ at the repository root

from post import dambreak, hydrostatic, plot_field, plot_series  # noqa: E402
from post.interp import free_surface_height, interpolate, kernel_sum, mass_sum, wendland_c2  # noqa: E402
from post.io import (  # noqa: E402
    closest_snapshots,
    fluid_box,
    list_snapshots,
    read_case,
    read_csv,
    read_snapshot,
)

DP = 0.01
RHO0 = 1000.0
C0 = 20.0
G = 9.81
TANK_L = 0.4
TANK_H = 0.2  # water depth of the still tank
CASE_NML = """&run
 case_name = 'tank'
 out_dir = 'OUT'
/
&box
 role = 'boundary'
 xmin = -0.03, xmax = 0.43, ymin = -0.03, ymax = 0.0
/
&box
 role = 'fluid'
 xmin = 0.0, xmax = 0.4, ymin = 0.0, ymax = 0.2
/
"""


def lattice(x0: float, x1: float, y0: float, y1: float, dp: float = DP) -> np.ndarray:
    """Particle centres filling the rectangle [x0, x1] x [y0, y1] at spacing dp."""
    xs = x0 + dp * (np.arange(round((x1 - x0) / dp)) + 0.5)
    ys = y0 + dp * (np.arange(round((y1 - y0) / dp)) + 0.5)
    X, Y = np.meshgrid(xs, ys, indexing="ij")
    return np.column_stack([X.ravel(), Y.ravel()])


def write_snapshot(path: Path, fluid: np.ndarray, solid: np.ndarray, *, time: float = 0.0,
                   h: float = 1.5 * DP, dp: float = DP, depth: float = TANK_H,
                   velocity: np.ndarray | None = None, case_name: str = "tank") -> None:
    """Write a snapshot in the format of doc/output.md, with hydrostatic pressure below ``depth``."""
    pos = np.vstack([fluid, solid])
    n, nf = len(pos), len(fluid)
    kind = np.r_[np.ones(nf, np.int32), np.full(len(solid), 2, np.int32)]
    pressure = RHO0 * G * np.clip(depth - pos[:, 1], 0.0, None)
    b = RHO0 * C0**2 / 7.0
    density = RHO0 * (1.0 + pressure / b) ** (1.0 / 7.0)
    if velocity is None:
        velocity = np.zeros((n, 2))
    with h5py.File(path, "w") as f:
        f["position"] = pos
        f["velocity"] = velocity
        f["density"] = density
        f["pressure"] = pressure
        f["mass"] = np.full(n, RHO0 * dp * dp)
        f["kind"] = kind
        f["body"] = np.where(kind == 1, 0, 1).astype(np.int32)
        f["id"] = np.arange(1, n + 1, dtype=np.int32)
        f["connectivity"] = np.arange(n, dtype=np.int32)
        f.attrs["time"] = time
        f.attrs["dt"] = 1.0e-4
        f.attrs["step"] = np.int32(round(time / 1.0e-4))
        f.attrs["n_particles"] = np.int32(n)
        f.attrs["dp"] = dp
        f.attrs["h"] = h
        f.attrs["rho0"] = RHO0
        f.attrs["c0"] = C0
        f.attrs["gravity"] = np.array([0.0, -G])
        f.attrs["case_name"] = np.bytes_(case_name.ljust(32))
        f.attrs["case_nml"] = np.bytes_(CASE_NML)


def tank_particles(dp: float = DP) -> tuple[np.ndarray, np.ndarray]:
    """Fluid lattice of the still tank and three layers of wall particles around it."""
    fluid = lattice(0.0, TANK_L, 0.0, TANK_H, dp)
    w = 3 * dp
    solid = np.vstack([lattice(-w, TANK_L + w, -w, 0.0, dp),
                       lattice(-w, 0.0, 0.0, 2 * TANK_H, dp),
                       lattice(TANK_L, TANK_L + w, 0.0, 2 * TANK_H, dp)])
    return fluid, solid


@pytest.fixture
def tank(tmp_path: Path) -> Path:
    """Output folder with five snapshots of a still tank at t = 0, 0.05, ..., 0.2 s and case.nml."""
    fluid, solid = tank_particles()
    pos = np.vstack([fluid, solid])
    vel = np.column_stack([0.1 + pos[:, 0], 0.5 - pos[:, 1]])
    for k in range(5):
        write_snapshot(tmp_path / f"snap_{k:05d}.h5", fluid, solid, time=0.05 * k, velocity=vel)
    (tmp_path / "case.nml").write_text(CASE_NML)
    return tmp_path


def interior_points(h: float, n: int = 60, seed: int = 1) -> np.ndarray:
    """Random points at least 2h + dp away from the walls, the bed and the surface of the tank."""
    rng = np.random.default_rng(seed)
    m = 2 * h + DP
    return np.column_stack([rng.uniform(m, TANK_L - m, n), rng.uniform(m, TANK_H - m, n)])


# ---------------------------------------------------------------------------- io


def test_read_snapshot_round_trip(tank: Path) -> None:
    snap = read_snapshot(tank / "snap_00001.h5")
    fluid, solid = tank_particles()
    assert snap.position.shape == (len(fluid) + len(solid), 2)
    np.testing.assert_array_equal(snap.position[: len(fluid)], fluid)
    assert snap.time == pytest.approx(0.05)
    assert snap.step == 500
    assert snap.n_particles == len(fluid) + len(solid)
    assert (snap.dp, snap.h, snap.rho0, snap.c0) == (DP, 1.5 * DP, RHO0, C0)
    assert snap.g == pytest.approx(G)
    assert snap.case_name == "tank"
    assert "role = 'fluid'" in snap.case_nml
    assert int(snap.fluid.sum()) == len(fluid)
    np.testing.assert_array_equal(snap.id, np.arange(1, snap.n_particles + 1))
    np.testing.assert_allclose(snap.volume[snap.fluid], RHO0 * DP**2 / snap.density[snap.fluid])


def test_list_and_closest_snapshots(tmp_path: Path) -> None:
    fluid, solid = tank_particles()
    for k, t in [(10, 1.0), (2, 0.2), (0, 0.0), (100000, 10.0)]:
        write_snapshot(tmp_path / f"snap_{k:05d}.h5", fluid, solid, time=t)
    (tmp_path / "snap_notes.txt").write_text("not a snapshot")
    names = [p.name for p in list_snapshots(tmp_path)]
    assert names == ["snap_00000.h5", "snap_00002.h5", "snap_00010.h5", "snap_100000.h5"]
    chosen = closest_snapshots(tmp_path, [0.15, 0.9, 0.95])
    assert [p.name for p in chosen] == ["snap_00002.h5", "snap_00010.h5"]


def test_closest_snapshots_default_spread(tank: Path) -> None:
    # 4 times evenly spread over 0..0.2 s: 0, 0.0667, 0.1333, 0.2 -> snapshots 0, 1, 3, 4
    chosen = closest_snapshots(tank)
    assert [p.name for p in chosen] == ["snap_00000.h5", "snap_00001.h5", "snap_00003.h5", "snap_00004.h5"]


def test_read_csv_round_trip(tmp_path: Path) -> None:
    time = np.array([0.0, 0.1, 0.2, 0.30000000000000004])
    kinetic = np.array([0.0, 1.25e-3, 3.5e-3, 2.0e-3])
    step = np.array([0, 1000, 2000, 3000])
    lines = ["time,step,kinetic,potential,total_mass,n_fluid,lost"]
    for t, s, k in zip(time, step, kinetic):
        lines.append(f"{float(t)!r},{s},{float(k)!r},{float(196.2 - k)!r},40.0,800,0")
    (tmp_path / "energy.csv").write_text("\n".join(lines) + "\n\n")
    data = read_csv(tmp_path / "energy.csv")
    assert list(data) == ["time", "step", "kinetic", "potential", "total_mass", "n_fluid", "lost"]
    np.testing.assert_array_equal(data["time"], time)
    np.testing.assert_array_equal(data["kinetic"], kinetic)
    np.testing.assert_array_equal(data["potential"], 196.2 - kinetic)
    np.testing.assert_array_equal(data["step"], step)
    assert data["step"].dtype == np.int64 and data["time"].dtype == np.float64
    assert data["n_fluid"].tolist() == [800] * 4


def test_read_csv_rejects_ragged_line(tmp_path: Path) -> None:
    (tmp_path / "bad.csv").write_text("time,kinetic\n0.0,1.0\n0.1\n")
    with pytest.raises(ValueError, match="line 3"):
        read_csv(tmp_path / "bad.csv")


def test_read_case_and_fluid_box(tank: Path) -> None:
    nml = read_case(tank)
    assert nml["run"]["case_name"] == "tank"
    assert fluid_box(nml) == (0.0, 0.4, 0.0, 0.2)
    (tank / "case.nml").unlink()  # falls back to the case_nml attribute of the first snapshot
    assert fluid_box(read_case(tank)) == (0.0, 0.4, 0.0, 0.2)


# ------------------------------------------------------------------------ interp


def test_wendland_kernel_values_and_normalisation() -> None:
    h = 0.02
    assert wendland_c2(0.0, h) == pytest.approx(7.0 / (4.0 * np.pi * h * h))
    assert wendland_c2(h, h) == pytest.approx(7.0 / (4.0 * np.pi * h * h) * 0.5**4 * 3.0)
    assert wendland_c2(2.0 * h, h) == 0.0
    assert wendland_c2(2.5 * h, h) == 0.0
    step = h / 40.0
    x = np.arange(-2.0 * h, 2.0 * h + step / 2, step)
    X, Y = np.meshgrid(x, x)
    assert (wendland_c2(np.hypot(X, Y), h) * step * step).sum() == pytest.approx(1.0, abs=1e-6)


@pytest.mark.parametrize("h_over_dp", [1.3, 1.5, 2.0])
def test_interpolation_reproduces_linear_fields(tmp_path: Path, h_over_dp: float) -> None:
    fluid, solid = tank_particles()
    h = h_over_dp * DP
    pos = np.vstack([fluid, solid])
    vel = np.column_stack([0.1 + pos[:, 0], 0.5 - pos[:, 1]])
    write_snapshot(tmp_path / "snap_00000.h5", fluid, solid, h=h, velocity=vel)
    snap = read_snapshot(tmp_path / "snap_00000.h5")
    pts = interior_points(h)
    linear = 5.0 + 2.0 * snap.position[:, 0] - 3.0 * snap.position[:, 1]
    exact = 5.0 + 2.0 * pts[:, 0] - 3.0 * pts[:, 1]
    got = interpolate(snap, linear, pts)
    assert np.max(np.abs(got - exact) / np.abs(exact)) < 1e-3
    # the hydrostatic pressure of the snapshot, a linear field in y vanishing at the
    # surface: its error is measured against the bed pressure
    p_exact = RHO0 * G * (TANK_H - pts[:, 1])
    p = interpolate(snap, "pressure", pts)
    assert np.max(np.abs(p - p_exact)) < 1e-3 * RHO0 * G * TANK_H
    # a vector field comes back with one column per component
    v = interpolate(snap, "velocity", pts)
    assert v.shape == (len(pts), 2)
    np.testing.assert_allclose(v, np.column_stack([0.1 + pts[:, 0], 0.5 - pts[:, 1]]), rtol=1e-3)


def test_kernel_sum_matches_direct_sum_on_disordered_particles(tmp_path: Path) -> None:
    rng = np.random.default_rng(7)
    fluid = lattice(0.0, 0.3, 0.0, 0.15) + rng.uniform(-0.3 * DP, 0.3 * DP, (450, 2))
    solid = lattice(-0.03, 0.33, -0.03, 0.0)
    write_snapshot(tmp_path / "snap_00000.h5", fluid, solid, h=1.7 * DP)
    snap = read_snapshot(tmp_path / "snap_00000.h5")
    pts = np.column_stack([rng.uniform(-0.1, 0.4, 500), rng.uniform(-0.1, 0.25, 500)])
    r = np.hypot(*(pts[:, None, :] - snap.position[None, snap.fluid, :]).transpose(2, 0, 1))
    direct = wendland_c2(r, snap.h) @ snap.volume[snap.fluid]
    np.testing.assert_allclose(kernel_sum(snap, pts), direct, rtol=1e-12, atol=1e-15)
    assert np.count_nonzero(direct == 0.0) > 50  # some points are out of reach of every particle
    # the same sum with masses instead of volumes (the density of the packing)
    direct_mass = wendland_c2(r, snap.h) @ snap.mass[snap.fluid]
    np.testing.assert_allclose(mass_sum(snap, pts), direct_mass, rtol=1e-12, atol=1e-12)


def test_kernel_sum_and_nan_outside_the_water(tank: Path) -> None:
    snap = read_snapshot(tank / "snap_00000.h5")
    inside = kernel_sum(snap, interior_points(snap.h))
    assert np.all(np.abs(inside - 1.0) < 0.02)
    # on the flat free surface the kernel is half in the water
    assert kernel_sum(snap, [0.2, TANK_H])[0] == pytest.approx(0.5, abs=0.02)
    # below the bed there are only boundary particles, which do not count
    below = -2.0 * snap.h - DP  # out of reach of the lowest fluid row at dp/2
    assert kernel_sum(snap, [0.2, below])[0] == 0.0
    p = interpolate(snap, "pressure", [[0.2, TANK_H + 3 * snap.h], [0.2, below], [0.2, 0.1]])
    assert np.isnan(p[0]) and np.isnan(p[1])
    assert p[2] == pytest.approx(RHO0 * G * 0.1, rel=1e-3)


def test_free_surface_height_of_a_still_tank(tank: Path) -> None:
    snap = read_snapshot(tank / "snap_00000.h5")
    xs = np.array([0.05, 0.123, 0.2, 0.35])
    eta = free_surface_height(snap, xs)
    assert eta.shape == xs.shape
    assert np.all(np.abs(eta - TANK_H) < DP)
    single = free_surface_height(snap, 0.2)
    assert isinstance(single, float) and abs(single - TANK_H) < DP
    assert np.isnan(free_surface_height(snap, TANK_L + 1.0))


def test_free_surface_height_of_a_sloping_surface(tmp_path: Path) -> None:
    # a column of fluid whose top rises by one particle every 5 columns
    fluid = lattice(0.0, 0.4, 0.0, 0.3)
    top = 0.1 + DP * np.floor(fluid[:, 0] / (5 * DP))
    fluid = fluid[fluid[:, 1] < top]
    write_snapshot(tmp_path / "snap_00000.h5", fluid, np.empty((0, 2)))
    snap = read_snapshot(tmp_path / "snap_00000.h5")
    xs = np.array([0.125, 0.225, 0.325])
    expected = 0.1 + DP * np.floor(xs / (5 * DP))
    assert np.all(np.abs(free_surface_height(snap, xs) - expected) < DP)


# ------------------------------------------------------------------------- plots


def _png_size(path: Path) -> tuple[int, int]:
    """(width, height) in pixels read from the PNG header."""
    head = path.read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(head[16:20], "big"), int.from_bytes(head[20:24], "big")


def test_plot_field_default_writes_png(tank: Path) -> None:
    path = plot_field.plot_field(tank, "pressure")
    assert path == tank / "field_pressure.png"
    width, height = _png_size(path)
    assert width > 2 * height  # a row of four panels of a tank twice as wide as deep


def test_field_figure_panels_titles_and_colour_scale(tank: Path) -> None:
    snaps = [read_snapshot(p) for p in closest_snapshots(tank, [0.04, 0.11])]
    fig = plot_field.field_figure(snaps, "pressure")
    panels, cbar = fig.axes[:2], fig.axes[2]
    assert len(fig.axes) == 3
    assert [ax.get_title() for ax in panels] == ["t = 0.050 s", "t = 0.100 s"]
    assert cbar.get_ylabel() == "pressure p (Pa)"
    p = snaps[0].pressure[snaps[0].fluid]
    clim = panels[0].collections[1].get_clim()
    np.testing.assert_allclose(clim, np.percentile(p, [0.5, 99.5]))
    # fluid particles coloured by pressure, boundary particles drawn separately
    assert len(panels[0].collections[1].get_offsets()) == int(snaps[0].fluid.sum())
    assert len(panels[0].collections[0].get_offsets()) == int((~snaps[0].fluid).sum())
    plot_field.plt.close(fig)


def test_plot_field_cli_velocity(tank: Path, capsys: pytest.CaptureFixture[str]) -> None:
    out = tank / "v.png"
    assert plot_field.main([str(tank), "--field", "velocity", "--times", "0.2", "--out", str(out)]) == 0
    assert "wrote" in capsys.readouterr().out
    width, height = _png_size(out)
    assert width > height > 100
    snap = read_snapshot(tank / "snap_00004.h5")
    speed = plot_field.field_values(snap, "velocity")
    np.testing.assert_allclose(speed, np.hypot(0.1 + snap.position[:, 0], 0.5 - snap.position[:, 1]))


def test_plot_series_groups_columns_by_unit(tmp_path: Path) -> None:
    t = np.linspace(0.0, 1.0, 11)
    rows = ["time,step,kinetic,potential,total_mass,n_fluid,lost"]
    rows += [f"{ti},{i},{ti**2},{10 - ti**2},4.0,800,{i // 5}" for i, ti in enumerate(t)]
    csv = tmp_path / "energy.csv"
    csv.write_text("\n".join(rows) + "\n")
    data = read_csv(csv)
    fig = plot_series.series_figure(data, ["kinetic", "potential", "lost"])
    assert len(fig.axes) == 2
    energy_ax, lost_ax = fig.axes
    assert [line.get_label() for line in energy_ax.lines] == ["kinetic", "potential"]
    np.testing.assert_allclose(energy_ax.lines[1].get_ydata(), 10 - t**2)
    np.testing.assert_allclose(lost_ax.lines[0].get_xdata(), t)
    assert energy_ax.get_ylabel() == "kinetic, potential (J/m)"
    plot_series.plt.close(fig)
    assert plot_series.main([str(csv), "kinetic", "potential"]) == 0
    width, height = _png_size(tmp_path / "energy_kinetic_potential.png")
    assert width > 500 and height > 300
    with pytest.raises(SystemExit):
        plot_series.main([str(csv), "enthalpy"])


# --------------------------------------------------------------------- dam break

A = 0.1
X_WALL = 0.05
DB_DP = 0.005


def test_experiment_table_and_ritter() -> None:
    T, Z = dambreak.experiment()
    assert len(T) == len(Z) == 15
    assert np.all(np.diff(T) > 0) and np.all(np.diff(Z) > 0)
    assert (T[0], Z[0], T[-1], Z[-1]) == (0.41, 1.11, 3.33, 4.11)
    # the experiment is slower than the ideal shallow-water front
    assert np.all(Z < dambreak.ritter_front(T))
    assert dambreak.ritter_front(1.5) == pytest.approx(4.0)
    assert dambreak.ritter_front(1.0, n2=1.0) == pytest.approx(1.0 + np.sqrt(2.0))


def dambreak_run(out: Path) -> np.ndarray:
    """Snapshots whose fluid is a block reaching the experimental front; returns their times T."""
    T_exp, Z_exp = dambreak.experiment()
    T = np.array([0.0, 0.6, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5])
    z = np.interp(T, np.r_[0.0, T_exp], np.r_[1.0, Z_exp])
    solid = lattice(X_WALL - 3 * DB_DP, X_WALL + 6 * A, -3 * DB_DP, 0.0, DB_DP)
    for k, (Tk, zk) in enumerate(zip(T, z)):
        width = DB_DP * round(A * zk / DB_DP)
        height = DB_DP * max(3, round(2 * A * A / width / DB_DP))
        fluid = lattice(X_WALL, X_WALL + width, 0.0, height, DB_DP)
        spray = np.array([[X_WALL + width + 0.5 * A, 0.5 * DB_DP],            # lone drop on the bed
                          [X_WALL + width + 0.3 * A, 1.5 * DB_DP],            # a pair of drops
                          [X_WALL + width + 0.3 * A + DB_DP, 1.5 * DB_DP]])
        write_snapshot(out / f"snap_{k:05d}.h5", np.vstack([fluid, spray]), solid,
                       time=Tk / np.sqrt(2 * G / A), dp=DB_DP, h=1.5 * DB_DP, depth=height,
                       case_name="dambreak")
    return T


def test_front_position_ignores_spray(tmp_path: Path) -> None:
    dambreak_run(tmp_path)
    snap = read_snapshot(tmp_path / "snap_00000.h5")
    assert dambreak.front_position(snap, X_WALL) == pytest.approx(A)
    snap = read_snapshot(tmp_path / "snap_00004.h5")  # T = 2
    Z_exp_2 = np.interp(2.0, *dambreak.experiment())
    assert dambreak.front_position(snap, X_WALL) / A == pytest.approx(Z_exp_2, abs=DB_DP / A)


def test_compare_with_experiment(tmp_path: Path) -> None:
    T = dambreak_run(tmp_path)
    result = dambreak.compare(tmp_path, A, X_WALL)
    np.testing.assert_allclose(result.T, T, rtol=1e-12)
    assert result.Z_sim[0] == pytest.approx(1.0)
    assert np.isnan(result.Z_exp[0]) and np.isnan(result.Z_exp[-1])  # outside the measured range
    inside = np.isfinite(result.Z_exp)
    assert np.all(np.abs(result.Z_sim[inside] - result.Z_exp[inside]) <= 0.5 * DB_DP / A + 1e-9)
    window = (T >= 1.0) & (T <= 3.0)
    expected = np.max(np.abs(result.Z_sim - result.Z_exp)[window] / result.Z_exp[window])
    assert result.max_rel_error == pytest.approx(expected)
    assert result.max_rel_error < 0.02


def test_dambreak_cli_reads_geometry_from_case(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    dambreak_run(tmp_path)
    (tmp_path / "case.nml").write_text(
        f"&box\n role = 'boundary'\n xmin = -1.0, xmax = 2.0, ymin = -0.1, ymax = 0.0\n/\n"
        f"&box\n role = 'fluid'\n xmin = {X_WALL}, xmax = {X_WALL + A}, ymin = 0.0, ymax = {2 * A}\n/\n")
    assert dambreak.main([str(tmp_path)]) == 0
    text = capsys.readouterr().out
    assert f"a = {A:g} m, x_wall = {X_WALL:g} m" in text
    printed = float(re.search(r"max relative error for 1 <= T <= 3: ([0-9.]+) %", text).group(1))
    assert printed == pytest.approx(100 * dambreak.compare(tmp_path, A, X_WALL).max_rel_error, abs=0.01)
    width, height = _png_size(tmp_path / "dambreak_front.png")
    assert width > height > 300


def test_dambreak_cli_needs_geometry(tmp_path: Path) -> None:
    dambreak_run(tmp_path)
    (tmp_path / "case.nml").write_text("&run\n case_name = 'x'\n/\n")
    with pytest.raises(SystemExit):
        dambreak.main([str(tmp_path)])
    assert dambreak.main([str(tmp_path), "--a", str(A), "--x-wall", str(X_WALL),
                          "--out", str(tmp_path / "f.png")]) == 0
    assert (tmp_path / "f.png").stat().st_size > 0


# ------------------------------------------------------------------- hydrostatic


def test_hydrostatic_profile_and_bed_pressure(tank: Path) -> None:
    snap = read_snapshot(tank / "snap_00004.h5")
    ys = hydrostatic.sample_heights(snap, 0.0, TANK_H)
    assert ys[0] == pytest.approx(2 * snap.h) and ys[-1] == pytest.approx(TANK_H - 2 * snap.h)
    p = hydrostatic.profile(snap, 0.2, ys)
    np.testing.assert_allclose(p, RHO0 * G * (TANK_H - ys), rtol=1e-3)
    fit = hydrostatic.bed_pressure(ys, p, 0.0)
    assert fit.slope == pytest.approx(-RHO0 * G, rel=1e-3)
    assert fit.p_bed == pytest.approx(RHO0 * G * TANK_H, rel=1e-3)


def test_hydrostatic_cli(tank: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert hydrostatic.main([str(tank), "--x", "0.2"]) == 0
    text = capsys.readouterr().out
    depth = float(re.search(r"depth H = ([0-9.eE+-]+) m", text).group(1))
    assert depth == pytest.approx(TANK_H, abs=DP)
    p_bed = float(re.search(r"bed pressure \(linear fit\) = ([0-9.eE+-]+) Pa", text).group(1))
    assert p_bed == pytest.approx(RHO0 * G * TANK_H, rel=1e-2)
    assert _png_size(tank / "hydrostatic.png")[1] > 300
    assert hydrostatic.main([str(tank), "--x", "0.2", "--depth", "0.2", "--time", "0.05",
                             "--out", str(tank / "h.png")]) == 0
    assert "snap_00001.h5" in capsys.readouterr().out


# ------------------------------------------------------------------- unreadable input

ROOT_DIR = Path(__file__).resolve().parents[1]

# each post tool with the arguments it needs besides the output folder
POST_TOOLS = {
    "armour": [], "waves": [], "plot_field": [], "dambreak": [], "stability": [],
    "hydrostatic": ["--x", "0.1", "--depth", "0.1"],
}


def run_tool(tool: str, args: list[str]):
    import subprocess
    return subprocess.run([sys.executable, "-m", f"post.{tool}", *args], cwd=ROOT_DIR, capture_output=True,
                          text=True, timeout=120, stdin=subprocess.DEVNULL)


def assert_one_line_error(proc, tool: str, needle: str) -> None:
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    assert proc.returncode == 2, f"exit {proc.returncode}\n{proc.stderr}"
    assert len(lines) == 1 and "Traceback" not in proc.stderr, proc.stderr
    assert lines[0].startswith(f"python -m post.{tool}: error: "), lines[0]
    assert needle in lines[0], f"the message should name {needle!r}: {lines[0]}"


@pytest.mark.parametrize("tool", sorted(POST_TOOLS))
def test_post_tool_on_missing_folder(tool: str, tmp_path: Path) -> None:
    missing = tmp_path / "no_such_run"
    proc = run_tool(tool, [str(missing), *POST_TOOLS[tool]])
    assert_one_line_error(proc, tool, str(missing))


@pytest.mark.parametrize("tool", sorted(POST_TOOLS))
def test_post_tool_on_empty_folder(tool: str, tmp_path: Path) -> None:
    proc = run_tool(tool, [str(tmp_path), *POST_TOOLS[tool]])
    assert_one_line_error(proc, tool, str(tmp_path))


def test_installed_command_runs_from_any_folder(tmp_path: Path) -> None:
    """`pip install -e .` (tools/deps.sh) installs `mbsph-post` and the package: from a
    folder outside the repository, with no PYTHONPATH, the command lists every tool, runs
    one, and its bad input ends in one line and exit 2 as `python -m post.<tool>` does."""
    import os
    import subprocess

    from post.__main__ import TOOLS
    command = Path(sys.executable).parent / "mbsph-post"
    assert command.is_file(), f"{command} is missing: `make deps` installs the post package (pyproject.toml)"
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}

    def run(*args: str) -> subprocess.CompletedProcess:
        return subprocess.run([str(command), *args], cwd=tmp_path, env=env, capture_output=True, text=True,
                              timeout=120, stdin=subprocess.DEVNULL)
    listing = run("--help")
    assert listing.returncode == 0, listing.stderr
    for tool in TOOLS:
        assert f"  {tool} " in listing.stdout, listing.stdout
        assert (ROOT_DIR / "post" / f"{tool}.py").is_file()
    assert run("validation_cases").returncode == 0
    missing = run("waves", "no_such_run")
    lines = [ln for ln in missing.stderr.splitlines() if ln.strip()]
    assert missing.returncode == 2 and len(lines) == 1, missing.stderr
    assert lines[0].startswith("mbsph-post waves: error: no_such_run"), lines[0]
    unknown = run("no_such_tool")
    assert unknown.returncode == 2 and "no tool 'no_such_tool'" in unknown.stderr
    where = subprocess.run([sys.executable, "-c", "import post; print(post.__file__)"], cwd=tmp_path, env=env,
                           capture_output=True, text=True, timeout=60)
    assert Path(where.stdout.strip()) == ROOT_DIR / "post" / "__init__.py", where.stderr


def test_truncated_snapshot_is_named_not_plotted(tank: Path) -> None:
    # a run stopped while writing its last snapshot: the tool names that file and draws nothing
    last = sorted(tank.glob("snap_*.h5"))[-1]
    data = last.read_bytes()
    last.write_bytes(data[: len(data) // 3])
    proc = run_tool("plot_field", [str(tank)])
    assert_one_line_error(proc, "plot_field", last.name)
    assert "truncated" in proc.stderr
    assert not list(tank.glob("*.png"))


# ------------------------------------------------------------------- records cut short, runs stopped early

GAUGES_TEXT = """\
# id,kind,x,y
# 1,pressure,0.100000,0.010000
time,p_1
0.00,1957.25
0.01,1957.31
0.02,1957.18
"""


def test_a_gauge_row_cut_short_is_left_out(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from post.waves import read_gauges
    # the run was killed while writing the row of t = 0.03: its pressure 1957.40 reads
    # as 1.9 (the minimum of the record fell from ~1957 Pa to 1.96 Pa)
    path = tmp_path / "gauges.csv"
    path.write_text(GAUGES_TEXT + "0.03,1.9")
    _, time, columns = read_gauges(path)
    assert list(time) == [0.0, 0.01, 0.02]
    assert columns["p_1"].min() == pytest.approx(1957.18)
    err = capsys.readouterr().err
    assert "gauges.csv" in err and "incomplete" in err and "left out" in err, err
    # a whole file is read whole, silently
    path.write_text(GAUGES_TEXT)
    _, time, _ = read_gauges(path)
    assert len(time) == 3 and capsys.readouterr().err == ""


def test_a_csv_row_cut_short_is_left_out(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    path = tmp_path / "energy.csv"
    path.write_text("time,e_kin\n0.0,1.0\n0.1,2.0\n0.2,3")
    d = read_csv(path)
    assert list(d["time"]) == [0.0, 0.1] and list(d["e_kin"]) == [1.0, 2.0]
    assert "incomplete" in capsys.readouterr().err


def test_series_ending_before_t_end_is_stated(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    from post.io import note_end
    # bodies.csv of a run that stopped after one step of a 12 s case: post.armour's Nod 0
    # is the damage of t <= 1e-4 s, and says so
    note_end(tmp_path / "bodies.csv", np.array([0.0, 1.0e-4]), 12.0)
    err = capsys.readouterr().err
    assert "records end at t = 0.0001 s" in err and "t_end = 12 s" in err, err
    # a series that reaches t_end within its own interval: nothing to say
    note_end(tmp_path / "bodies.csv", np.arange(0.0, 12.0 + 1e-9, 0.05), 12.0)
    note_end(tmp_path / "bodies.csv", np.arange(0.0, 11.99, 0.05), 12.0)
    assert capsys.readouterr().err == ""


def test_breakwater_core_normal_force_is_the_outward_projection(tmp_path: Path) -> None:
    """post.breakwater_core takes the fluid force on a unit along the slope's outward
    normal (-sin a, cos a): a force straight up of F has the share F cos a, one pointing
    down the slope's normal the share -|F|; rows come back in time order."""
    import math

    from post.breakwater_core import normal_force
    a = math.atan(1 / 1.5)
    n = np.array([-math.sin(a), math.cos(a)])
    rows = ["time,body,fx_fluid,fy_fluid",
            "0.2,3,0.0,10.0",
            "0.0,3,1.0,0.0",
            "0.1,3," + f"{-5 * n[0]},{-5 * n[1]}",
            "0.1,4,7.0,7.0"]
    (tmp_path / "bodies.csv").write_text("\n".join(rows) + "\n")
    bodies = read_csv(tmp_path / "bodies.csv")
    t, f = normal_force(bodies, 3, a)
    assert list(t) == [0.0, 0.1, 0.2]
    assert f == pytest.approx([-math.sin(a), -5.0, 10.0 * math.cos(a)], rel=1e-12)


def test_madsen_porous_breakwater_limits() -> None:
    """post.porous_waves.madsen: a structure without resistance (stones so large that the
    linearised friction vanishes) dissipates nothing, K_R^2 + K_T^2 = 1; one of zero width
    lets the wave through, K_T = 1, K_R = 0; and resistance takes energy out,
    K_R^2 + K_T^2 < 1, more with finer stones."""
    from post.porous_waves import madsen
    lossless = madsen(2.0, 0.3, 0.5, 0.45, 1.0e6, 0.03)
    assert lossless.f < 1e-6
    assert lossless.KR ** 2 + lossless.KT ** 2 == pytest.approx(1.0, abs=1e-5)
    assert 0.0 < lossless.KR < 1.0
    thin = madsen(2.0, 0.3, 1.0e-9, 0.45, 0.03, 0.03)
    assert thin.KT == pytest.approx(1.0, abs=1e-6) and thin.KR == pytest.approx(0.0, abs=1e-6)
    coarse = madsen(2.0, 0.3, 0.5, 0.45, 0.05, 0.03)
    fine = madsen(2.0, 0.3, 0.5, 0.45, 0.01, 0.03)
    assert fine.KR ** 2 + fine.KT ** 2 < coarse.KR ** 2 + coarse.KT ** 2 < 1.0
    assert fine.KT < coarse.KT
