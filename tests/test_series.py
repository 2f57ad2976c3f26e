"""The test-series tool (post/series.py): its file is checked, its steps follow one
another as restarts under new waves, and its wave analysis at the toe separates a known
incident sea from its reflection."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from post import armour, series, waves

BASE = """\
[series]
case = "input/breakwater/irregular_porous.nml"
out = "{out}"
settle = 1.0
tp = 1.4
waves = 50
rest = 2.0
toe_gauges = [2.2, 2.4, 2.65]

[patch]
armour = {{ seed = 8 }}

[[step]]
hs = 0.06
[[step]]
hs = 0.08
seed = 11
"""


def write(tmp_path: Path, text: str) -> Path:
    p = tmp_path / "s.toml"
    p.write_text(text.format(out=tmp_path / "out"))
    return p


def test_steps_follow_one_another(tmp_path: Path) -> None:
    """Step k starts where step k - 1 ended; its wave lasts `waves` Tm02 and rests
    `rest` after; the step files restart the settling run with the step's sea."""
    import f90nml
    ser = series.load_series(write(tmp_path, BASE))
    t = series.schedule(ser)
    assert t[0].start == pytest.approx(1.0)
    assert t[1].start == pytest.approx(t[0].end)
    assert t[0].end - t[0].wave_end == pytest.approx(2.0)
    # Tm02 / Tp of JONSWAP (gamma 3.3) in the band 0.5-3 fp is near 0.78
    assert (t[0].wave_end - t[0].start) / (50 * 1.4) == pytest.approx(series.tm02_over_tp(3.3), rel=1e-12)
    assert 0.74 < series.tm02_over_tp(3.3) < 0.82
    for k in (0, 1, 2):
        text = series.step_text(ser, k)
        case = tmp_path / f"step{k}.nml"
        case.write_text(text)
        nml = f90nml.read(str(case))
        assert nml["run"]["restart"] is (k > 0)
        assert nml["armour"]["seed"] == 8
        wm = nml["wavemaker"]
        assert wm["wave"] == "irregular" and wm["absorb"] is True
        step = max(k, 1) - 1
        assert wm["hs"] == ser.steps[step].hs and wm["seed"] == ser.steps[step].seed
        assert wm["t_start"] == pytest.approx(t[step].start)
        xs = [g["x"] for g in nml["gauge"] if g["kind"] == "elevation"]
        assert all(any(abs(x - g) < 1e-12 for x in xs) for g in ser.toe_gauges)
    assert ser.steps[0].seed == 1 and ser.steps[1].seed == 11


@pytest.mark.parametrize("edit,words", [
    (("waves = 50", "waves = 0"), ("waves",)),
    (("hs = 0.06", "hs = -0.06"), ("[[step]] 1", "hs")),
    (("toe_gauges = [2.2, 2.4, 2.65]", "toe_gauges = [2.2, 2.65]"), ("toe_gauges",)),
    (("[patch]", "[patch]\nrun = {{ t_end = 3.0 }}"), ("&run",)),
    (("tp = 1.4", "tq = 1.4"), ("unknown key", "tq")),
    (("rest = 2.0", "rest = 2.0\ncount_from = \"placed\""), ("count_from", "settle")),
])
def test_bad_series_file(edit: tuple[str, str], words: tuple[str, ...], tmp_path: Path) -> None:
    with pytest.raises(series.SeriesError) as e:
        series.load_series(write(tmp_path, BASE.replace(*edit)))
    assert "s.toml" in str(e.value)
    for w in words:
        assert w in str(e.value), str(e.value)


def test_incident_sea_separated_at_three_gauges() -> None:
    """A JONSWAP-like sea (Hm0 0.08 m, Tp 1.4 s, depth 0.3 m) and its reflection (Kr 0.4,
    phase shifted) at three gauges 0.2 and 0.45 m apart: the incident Hm0 within 2 %,
    Kr within 0.03, and H2% of the rebuilt incident series equal to that of the true
    incident series within 3 %."""
    rng = np.random.default_rng(5)
    depth, tp, dt, n = 0.3, 1.4, 0.02, 2 ** 14
    t = np.arange(n) * dt
    f = np.fft.rfftfreq(n, dt)[1:]
    fp = 1.0 / tp
    s = np.where((f > 0.5 * fp) & (f < 3.0 * fp), f ** -5 * np.exp(-1.25 * (f / fp) ** -4), 0.0)
    a = np.sqrt(2.0 * s * (f[1] - f[0]))
    a *= 0.08 / (4.0 * math.sqrt(0.5 * np.sum(a ** 2)))
    phi = rng.uniform(0, 2 * np.pi, len(f))
    k = waves.wavenumber(2 * np.pi * f, depth)
    xs = [0.0, 0.2, 0.45]
    def series_of(c: np.ndarray) -> np.ndarray:
        # sum of |c| cos(2 pi f t + arg c) over the bins, by an inverse FFT
        return np.fft.irfft(np.concatenate([[0.0], c]) * (n / 2.0), n)

    etas = []
    for x in xs:
        inc = series_of(a * np.exp(1j * (phi - k * x)))
        etas.append(inc + series_of(0.4 * a * np.exp(1j * (phi + k * x + 1.0))))
        if x == 0.0:
            true_inc = inc
    tu, eta_i, hm0_i, hm0_r = series.incident_series(t, etas, xs, depth)
    assert hm0_i == pytest.approx(0.08, rel=0.02)
    assert hm0_r / hm0_i == pytest.approx(0.4, abs=0.03)
    assert series.h2_percent(tu, eta_i) == pytest.approx(series.h2_percent(t, true_inc), rel=0.03)


def test_van_der_meer_cube_formula() -> None:
    """Van der Meer's double-layer cube formula solved for Nod: back in the formula it
    gives the Ns it came from; no damage below s_om^-0.1; more waves, more damage."""
    from post.armour import van_der_meer_cubes_nod
    n, s = 1000.0, 0.04
    nod = float(van_der_meer_cubes_nod(2.3, n, s))
    assert (6.7 * nod ** 0.4 / n ** 0.3 + 1.0) * s ** -0.1 == pytest.approx(2.3, rel=1e-12)
    assert float(van_der_meer_cubes_nod(0.99 * s ** -0.1, n, s)) == 0.0
    assert float(van_der_meer_cubes_nod(2.3, 3000.0, s)) > nod


def test_damage_counted_from_the_placed_or_the_settled_layer() -> None:
    """A unit that slides 0.9 dn while the layer settles and 0.3 dn more under the waves
    is displaced (1.2 dn > 1 dn) counted from its placed position and not (0.3 dn)
    counted from the settled layer; one that leaves by 1.5 dn under the waves is
    displaced either way; one that turns 8 degrees and back within the step rocks."""
    dn, settle = 0.04, 1.0
    t = np.linspace(0.0, 6.0, 61)
    tt = series.StepTimes(start=1.0, wave_end=5.0, end=6.0)

    def unit(body: int, s: np.ndarray, rot: np.ndarray) -> armour.UnitMotion:
        # down a 1:1.5 slope, the displacement column from the placed position
        cx, cy = 1.5 / math.sqrt(3.25), 1.0 / math.sqrt(3.25)
        return armour.UnitMotion(body=body, time=t, x=2.0 - cx * s, y=0.5 - cy * s, displacement=np.abs(s),
                                 rotation=rot)

    settling = np.where(t <= settle, 0.9 * dn * t / settle, 0.9 * dn + 0.3 * dn * np.minimum(t - settle, 1.0))
    leaving = np.where(t <= 2.0, 0.0, 1.5 * dn * np.minimum(t - 2.0, 1.0))
    rocking = np.radians(8.0) * np.sin(np.pi * np.clip((t - 2.0) / 2.0, 0.0, 1.0))
    still = np.zeros_like(t)
    motions = [unit(1, settling, still), unit(2, leaving, still), unit(3, still, rocking)]
    n, rock, worst = series.count_damage(motions, dn, 5.0, tt, None)
    assert (n, rock) == (2, 1)
    assert worst == pytest.approx(1.5 * dn, rel=1e-12)
    n, rock, worst = series.count_damage(motions, dn, 5.0, tt, settle)
    assert (n, rock) == (1, 1)
    assert series.displacement_from(motions[0], settle)[-1] == pytest.approx(0.3 * dn, rel=1e-9)
    with pytest.raises(series.SeriesError, match="body 1"):
        series.displacement_from(motions[0], -1.0)


def test_damage_beyond_the_gaps_of_a_2d_layer() -> None:
    """Four units up a 1:1.5 slope with gaps of 0.3 dn between them: a unit that slides
    down onto its lower neighbour (closing its gap and those below it, here 0.9 dn for the
    top one) is not beyond the gaps; one lifted 1.2 dn off the slope is, and so is one
    that slides 1.1 dn past its closed-up place, or the lowest unit (no gap below it)
    sliding 1.1 dn. A 3D layer has no such count."""
    dn = 0.04
    a = math.atan(1.0 / 1.5)
    up, nrm = np.array([math.cos(a), math.sin(a)]), np.array([-math.sin(a), math.cos(a)])
    c0 = np.array([2.9, 0.45]) + np.outer(np.arange(4) * 1.3 * dn, up)
    lay = armour.ArmourLayer(meta={"dn": dn, "slope_angle_deg": math.degrees(a)}, unit=np.arange(1, 5),
                             body=np.arange(2, 6), x0=c0[:, 0], y0=c0[:, 1], angle0=np.full(4, math.degrees(a)))
    seg = series.closing_segments(lay)
    assert seg is not None
    assert np.allclose(seg[1], np.array([2.9, 0.45]) + np.outer(np.arange(4) * dn, up), atol=1e-12)
    t = np.array([0.0, 1.0])

    def moved(k: int, by: np.ndarray) -> armour.UnitMotion:
        c = np.vstack([c0[k], c0[k] + by])
        return armour.UnitMotion(body=k + 2, time=t, x=c[:, 0], y=c[:, 1],
                                 displacement=np.array([0.0, float(np.linalg.norm(by))]), rotation=np.zeros(2))

    closing = [moved(k, -0.3 * k * dn * up) for k in range(4)]
    assert series.count_closed(closing, seg, dn, 1.0) == 0
    # the lab's count takes the top unit (0.9 dn) and not the others
    assert series.count_damage(closing, 0.85 * dn, 5.0, series.StepTimes(0.0, 1.0, 1.0), None)[0] == 1
    leaving = [moved(0, -1.1 * dn * up), moved(1, 1.2 * dn * nrm), moved(2, -(0.6 + 1.1) * dn * up),
               moved(3, -0.9 * dn * up)]
    assert series.count_closed(leaving, seg, dn, 1.0) == 3
    assert series.count_closed(leaving, seg, dn, 0.5) == 0        # before they moved
    lay3 = armour.ArmourLayer(meta=lay.meta, unit=lay.unit, body=lay.body, x0=lay.x0, y0=lay.y0,
                              angle0=lay.angle0, z0=np.zeros(4))
    assert series.closing_segments(lay3) is None
    assert series.count_closed(leaving, None, dn, 1.0) == -1


def test_overlay_reads_each_series_and_names_its_layer(tmp_path: Path) -> None:
    """The overlay takes Ns and Nod from each series' CSV and labels each curve with the
    layer it tested (placement and seed, the [patch] over the base case); a series not
    yet run is named in the error."""
    a = series.load_series(write(tmp_path, BASE))
    b_path = tmp_path / "b.toml"
    b_path.write_text(BASE.replace("armour = {{ seed = 8 }}", "armour = {{ seed = 9 }}")
                      .format(out=tmp_path / "out_b"))
    b = series.load_series(b_path)
    for ser, ns, nod in ((a, "2.5,3.4", "0,2"), (b, "2.6,3.5", "1,3")):
        with pytest.raises(series.SeriesError, match=f"{ser.out.name}/series.csv: no such file"):
            series.overlay_data([a, b])
        ser.out.mkdir(parents=True)
        head = "step,hs_target,seed,t_start,t_end,Hm0_i,H2_i,Kr,Ns,displaced,rocking,max_disp_dn\n"
        rows = [f"{k + 1},0.06,1,0,1,0.05,0.06,0.3,{x},{d},0,0.5\n"
                for k, (x, d) in enumerate(zip(ns.split(","), nod.split(",")))]
        (ser.out / "series.csv").write_text(head + "".join(rows))
    data = series.overlay_data([a, b])
    assert [d[0] for d in data] == ["s: irregular placement, seed 8", "b: irregular placement, seed 9"]
    assert data[0][1].tolist() == [2.5, 3.4] and data[0][2].tolist() == [0, 2]
    assert data[1][1].tolist() == [2.6, 3.5] and data[1][2].tolist() == [1, 3]
    png = series.plot_overlay([a, b], tmp_path / "overlay.png")
    assert png.stat().st_size > 10_000
