"""Tests of the wave and armour post-processing (post/waves.py, post/armour.py) on synthetic
signals and output folders written here: no solver run.

Every expected value is analytic: heights and periods of sums of sines, the variance of a
random-phase JONSWAP sea synthesised on the record's Fourier grid, incident and reflected
linear waves with a known reflection coefficient, and the damage of a layer in which one
unit is moved by a known distance.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))  # the package post/ at the repository root

from post import armour, waves  # noqa: E402

G = 9.81
DEPTH = 0.5


# ------------------------------------------------------------------ synthetic seas


def jonswap(f: np.ndarray, hs: float, tp: float, gamma: float = 3.3) -> np.ndarray:
    """JONSWAP variance density in the form of Goda (m2/Hz)."""
    sigma = np.where(f <= 1.0 / tp, 0.07, 0.09)
    beta = 0.0624 / (0.230 + 0.0336 * gamma - 0.185 / (1.9 + gamma)) * (1.094 - 0.01915 * math.log(gamma))
    return (beta * hs**2 * tp**-4 * f**-5 * np.exp(-1.25 * (tp * f) ** -4)
            * gamma ** np.exp(-((tp * f - 1.0) ** 2) / (2.0 * sigma**2)))


def random_sea(duration: float, hs: float, tp: float, seed: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Frequencies on the record's Fourier grid (every component periodic in ``duration``),
    amplitudes from JONSWAP scaled so that the variance is exactly (hs/4)^2, random phases."""
    rng = np.random.default_rng(seed)
    f = np.arange(1, int(4.0 * duration / tp)) / duration
    a = np.sqrt(2.0 * jonswap(f, hs, tp) / duration)
    a *= (hs / 4.0) / math.sqrt(np.sum(a * a) / 2.0)
    return f, a, rng.uniform(0.0, 2.0 * math.pi, len(f))


def linear_waves(t: np.ndarray, x: float, f: np.ndarray, a: np.ndarray, phase: np.ndarray, kr: float,
                 x_wall: float = 6.0) -> np.ndarray:
    """Incident waves travelling to +x plus their reflection ``kr`` times as high from a wall at
    ``x_wall`` (each reflected component keeps its incident phase at the wall, shifted by 0.7 rad)."""
    w = 2.0 * math.pi * np.asarray(f, dtype=float)
    k = waves.wavenumber(w, DEPTH)
    phr = phase - 2.0 * k * x_wall + 0.7
    arg_i = np.outer(w, t) - (k * x)[:, None] + np.asarray(phase)[:, None]
    arg_r = np.outer(w, t) + (k * x)[:, None] + phr[:, None]
    amp = np.asarray(a, dtype=float)[:, None]
    return np.sum(amp * np.cos(arg_i) + kr * amp * np.cos(arg_r), axis=0)


# ------------------------------------------------------------------------ reading

GAUGES_CSV = """# id,kind,x,y
# 1,elevation,2.000000,nan
# 2,elevation,2.300000,nan
# 3,pressure,4.000000,0.050000
time,eta_1,eta_2,p_3
0.000000000000000e+00,1.2e-3,-4.0e-4,4.415e+03
5.000000000000000e-02,1.5e-3,-1.0e-4,4.420e+03
1.000000000000000e-01,1.1e-3,2.0e-4,4.418e+03
"""


def test_read_gauges_exact_format(tmp_path: Path) -> None:
    (tmp_path / "gauges.csv").write_text(GAUGES_CSV)
    gauges, time, cols = waves.read_gauges(tmp_path)  # the folder or the file
    assert [(g.id, g.kind, g.x) for g in gauges] == [(1, "elevation", 2.0), (2, "elevation", 2.3),
                                                       (3, "pressure", 4.0)]
    assert math.isnan(gauges[0].y) and gauges[2].y == 0.05
    assert [g.column for g in gauges] == ["eta_1", "eta_2", "p_3"]
    np.testing.assert_array_equal(time, [0.0, 0.05, 0.1])
    np.testing.assert_array_equal(cols["eta_1"], [1.2e-3, 1.5e-3, 1.1e-3])
    np.testing.assert_array_equal(cols["p_3"], [4415.0, 4420.0, 4418.0])
    g, col = waves.gauge_column(gauges, cols, 2)
    assert g.x == 2.3 and col[2] == 2.0e-4
    bad = tmp_path / "bad.csv"
    bad.write_text(GAUGES_CSV.replace("time,eta_1,eta_2,p_3", "time,eta_1,p_3"))
    with pytest.raises(ValueError):
        waves.read_gauges(bad)


# --------------------------------------------------------------------- dispersion


def test_wavenumber_solves_dispersion_and_limits() -> None:
    omega = np.array([0.5, 2.0, 4.0, 8.0, 20.0])
    k = waves.wavenumber(omega, DEPTH)
    np.testing.assert_allclose(G * k * np.tanh(k * DEPTH), omega**2, rtol=1e-12)
    # shallow water: k = omega / sqrt(g h); deep water: k = omega^2 / g
    assert waves.wavenumber(1e-3, DEPTH) == pytest.approx(1e-3 / math.sqrt(G * DEPTH), rel=1e-6)
    assert waves.wavenumber(30.0, DEPTH) == pytest.approx(900.0 / G, rel=1e-12)
    assert waves.wavenumber(0.0, DEPTH) == 0.0


# ------------------------------------------------------------------ zero crossing


def test_zero_crossing_regular_sine() -> None:
    a, T, dt = 0.05, 1.2, 0.01
    t = np.arange(0.0, 30.0, dt)
    zc = waves.zero_crossing(t, a * np.sin(2 * math.pi * t / T + 0.3))
    # 25 periods; the partial waves before the first and after the last up-crossing are dropped
    assert zc.count == 24
    np.testing.assert_allclose(zc.heights, 2 * a, rtol=1e-3)
    np.testing.assert_allclose(zc.periods, T, rtol=1e-3)
    for value in (zc.H_mean, zc.H_1_3, zc.H_max):
        assert value == pytest.approx(2 * a, rel=1e-3)
    assert zc.T_mean == pytest.approx(T, rel=1e-3)


def test_zero_crossing_sum_of_two_sines() -> None:
    a, b, T, dt = 0.05, 0.004, 1.2, 0.01
    w = 2 * math.pi / T
    t = np.arange(0.0, 30.0, dt)
    # a cos + b cos(3 .) with b < a/9 has its extremes at 0 and T/2: H = 2 (a + b)
    zc = waves.zero_crossing(t, a * np.cos(w * t) + b * np.cos(3 * w * t))
    np.testing.assert_allclose(zc.heights, 2 * (a + b), rtol=1e-3)
    np.testing.assert_allclose(zc.periods, T, rtol=1e-3)
    # a second harmonic out of phase: crest and trough from a dense evaluation of the formula
    c, phi = 0.012, 0.9
    def eta(tt):
        return a * np.cos(w * tt) + c * np.cos(2 * w * tt + phi)
    dense = eta(np.linspace(0.0, T, 400001))
    zc = waves.zero_crossing(t, eta(t))
    np.testing.assert_allclose(zc.heights, dense.max() - dense.min(), rtol=1e-3)
    np.testing.assert_allclose(zc.periods, T, rtol=1e-3)
    assert zc.H_1_3 == pytest.approx(dense.max() - dense.min(), rel=1e-3)


# ----------------------------------------------------------------------- spectra


def test_spectrum_of_jonswap_sea() -> None:
    hs, tp, duration, dt = 0.06, 1.6, 600.0, 0.05
    t = np.arange(0.0, duration, dt)
    f, a, phase = random_sea(duration, hs, tp, seed=1)
    eta = np.sum(a[:, None] * np.cos(2 * math.pi * np.outer(f, t) + phase[:, None]), axis=0)
    sp = waves.spectrum(t, eta)
    assert sp.Hm0 == pytest.approx(hs, rel=0.03)
    # the peak of the Welch estimate within one bin of the JONSWAP peak frequency
    assert abs(1.0 / sp.Tp - 1.0 / tp) <= sp.df * (1.0 + 1e-9)
    # segments of about 20 peak periods
    assert 15.0 < 1.0 / (sp.df * tp) < 25.0
    # the mean periods against the moments of the synthesised components
    m = {n: float(np.sum(a * a / 2.0 * f**n)) for n in (-1, 0, 2)}
    assert sp.Tm_10 == pytest.approx(m[-1] / m[0], rel=0.03)
    assert sp.Tm02 == pytest.approx(math.sqrt(m[0] / m[2]), rel=0.03)
    assert not waves.is_regular(t, eta)


def test_spectrum_of_sine_holds_its_variance() -> None:
    a, T, dt = 0.03, 1.5, 0.02
    t = np.arange(0.0, 60.0, dt)
    eta = a * np.cos(2 * math.pi * t / T + 0.4)
    sp = waves.spectrum(t, eta, nseg=1)
    # Hann periodogram of 40 whole periods: m0 = a^2/2 exactly, peak at 1/T
    assert sp.m0 == pytest.approx(a * a / 2.0, rel=1e-6)
    assert sp.Tp == pytest.approx(T, rel=1e-9)
    assert waves.is_regular(t, eta)


@pytest.mark.parametrize("length", [200, 201])
def test_spectrum_is_the_welch_estimate_it_documents(length: int) -> None:
    """spectrum() against Welch's estimate written out by hand from its docstring: segments
    of ``length`` samples starting every floor(length/2), each with its mean removed and a
    periodic Hann window, densities 2 |X|^2 / (fs sum w^2), not doubled at 0 and at the
    Nyquist frequency. Any change in the library call's options shows here (bar 1e-12)."""
    rng = np.random.default_rng(3)
    dt = 0.05
    t = dt * np.arange(1003)
    eta = 0.02 * np.cos(2 * math.pi * 0.7 * t) + 0.005 * rng.standard_normal(t.size) + 0.01
    sp = waves.spectrum(t, eta, segment=length * dt)
    w = 0.5 - 0.5 * np.cos(2 * math.pi * np.arange(length) / length)
    starts = range(0, t.size - length + 1, length // 2)
    X = np.array([np.fft.rfft((eta[s:s + length] - eta[s:s + length].mean()) * w) for s in starts])
    S = np.mean(np.abs(X) ** 2, axis=0) / (np.sum(w * w) / dt)
    S[1:] *= 2.0
    if length % 2 == 0:
        S[-1] /= 2.0
    np.testing.assert_allclose(sp.f, np.fft.rfftfreq(length, dt), rtol=0, atol=1e-12)
    np.testing.assert_allclose(sp.S, S, rtol=1e-12, atol=1e-12 * S.max())
    assert sp.m0 == pytest.approx(np.sum(S[1:]) * sp.df, rel=1e-12)


# ------------------------------------------------------------------ regular waves


def test_regular_wave_height_with_harmonic_and_noise() -> None:
    a, T, dt = 0.04, 1.3, 0.02
    w = 2 * math.pi / T
    t = np.arange(0.0, 40.0, dt)
    rng = np.random.default_rng(5)
    eta = a * np.cos(w * t + 0.2) + 0.2 * a * np.cos(2 * w * t + 0.5) + rng.normal(0.0, 0.1 * a, len(t))
    rw = waves.regular_wave_height(t, eta, T, t_start=3.1, t_end=39.0)
    assert rw.n_periods == 27 and rw.t_end == pytest.approx(3.1 + 27 * T)
    assert rw.H == pytest.approx(2 * a, rel=0.01)
    assert rw.amplitudes[1] == pytest.approx(0.2 * a, rel=0.05)
    assert rw.T_fit == pytest.approx(T, rel=0.01)
    # a period 5 % off: the fit finds the true one
    rw_off = waves.regular_wave_height(t, eta, 1.05 * T, t_start=3.1)
    assert rw_off.T_fit == pytest.approx(T, rel=0.01)
    # without noise the zero-crossing mean agrees with the crest-to-trough height and the period
    clean = a * np.cos(w * t) + 0.2 * a * np.cos(2 * w * t)
    rw = waves.regular_wave_height(t, clean, T)
    assert rw.H == pytest.approx(2 * a, rel=1e-9)
    assert rw.T_fit == pytest.approx(T, rel=1e-6)
    # crest and trough of a cos + 0.2 a cos 2(.) from a dense evaluation of the formula
    phase = np.linspace(0.0, 2 * math.pi, 200001)
    dense = a * np.cos(phase) + 0.2 * a * np.cos(2 * phase)
    assert rw.H_zero_crossing == pytest.approx(dense.max() - dense.min(), rel=1e-3)
    # the crest-to-trough height of the fit is that of the formula, and of the noisy record
    # within the noise's share (0.1 a over 27 periods of 65 samples)
    assert rw.H_crest_trough == pytest.approx(dense.max() - dense.min(), rel=1e-8)
    noisy = waves.regular_wave_height(t, eta, T, t_start=3.1, t_end=39.0)
    dense = a * np.cos(phase + 0.2) + 0.2 * a * np.cos(2 * phase + 0.5)
    assert noisy.H_crest_trough == pytest.approx(dense.max() - dense.min(), rel=0.01)
    assert rw.T_zero_crossing == pytest.approx(T, rel=1e-3)


# -------------------------------------------------------------------- reflection

GAUGE_X = (2.0, 2.3, 2.75)


@pytest.mark.parametrize("kr", [0.3, 0.05, 0.0])
def test_reflection_regular_waves(kr: float) -> None:
    T, a, dt = 1.5, 0.03, 0.02
    t = np.arange(0.0, 41.37, dt)  # not a whole number of periods
    etas = [linear_waves(t, x, [1.0 / T], [a], [0.3], kr) for x in GAUGE_X]
    f = 1.0 / waves.regular_wave_height(t, etas[0], T).T_fit
    r2 = waves.reflection_two_gauge(t, etas[0], etas[1], GAUGE_X[1] - GAUGE_X[0], DEPTH, frequency=f)
    r3 = waves.reflection_three_gauge(t, *etas, *GAUGE_X, DEPTH, frequency=f)
    # spectral path too, band below the second harmonic
    s2 = waves.reflection_two_gauge(t, etas[0], etas[1], GAUGE_X[1] - GAUGE_X[0], DEPTH, band=(0.5, 1.5))
    s3 = waves.reflection_three_gauge(t, *etas, *GAUGE_X, DEPTH, band=(0.5, 1.5))
    for r in (r2, r3, s2, s3):
        if kr > 0:
            assert r.Kr == pytest.approx(kr, abs=0.02)
        else:
            assert r.Kr < 0.02
    assert r2.Hm0_i / math.sqrt(2.0) == pytest.approx(2 * a, rel=1e-3)  # incident height


@pytest.mark.parametrize("kr", [0.3, 0.05, 0.0])
def test_reflection_irregular_waves(kr: float) -> None:
    duration, dt = 300.0, 0.05
    t = np.arange(0.0, duration, dt)
    f, a, phase = random_sea(duration, 0.05, 1.5, seed=3)
    etas = [linear_waves(t, x, f, a, phase, kr) for x in GAUGE_X]
    r2 = waves.reflection_two_gauge(t, etas[0], etas[1], GAUGE_X[1] - GAUGE_X[0], DEPTH)
    r3 = waves.reflection_three_gauge(t, *etas, *GAUGE_X, DEPTH)
    for r in (r2, r3):
        if kr > 0:
            assert r.Kr == pytest.approx(kr, abs=0.02)
        else:
            assert r.Kr < 0.02
        assert len(r.f) > 50
    # the used frequencies keep 0.05 < dx/L < 0.45; the band holds some that do not
    ratio = waves.wavenumber(2 * math.pi * r2.f, DEPTH) * 0.3 / (2 * math.pi)
    assert np.all((ratio > 0.05) & (ratio < 0.45))
    masked = waves.wavenumber(2 * math.pi * r2.f_masked, DEPTH) * 0.3 / (2 * math.pi)
    assert len(masked) > 0 and np.all((masked <= 0.05) | (masked >= 0.45))


def test_decaying_wave_fit_recovers_decay_and_reflection() -> None:
    """An incident wave decaying by 1.2 %/m and a reflected one of a tenth of its
    height, with a second harmonic and noise of 1.5 % of the amplitude, at 15 gauges a
    quarter wavelength apart: the fit gets the height at the paddle within 0.5 %, the
    decay rate within 0.001 /m, Kr within 0.01 and k within 0.5 %; without noise the
    height and the decay within 1e-5 (the grid's last refinement)."""
    T, k, kappa, A, B = 1.0, 4.9, 0.012, 0.02, 0.002
    w = 2.0 * math.pi / T
    t = np.arange(0.0, 3.0 * T, T / 40.0)
    xs = (0.5 + 0.25 * np.arange(15)) * 2.0 * math.pi / k
    rng = np.random.default_rng(3)

    def records(noise: float) -> list[np.ndarray]:
        out = []
        for x in xs:
            a1 = A * np.exp(-(kappa + 1j * k) * x) + B * np.exp(1j * (k * x + 0.7))
            eta = np.real(a1 * np.exp(1j * w * t)) + 0.1 * abs(a1) * np.cos(2.0 * (w * t - k * x))
            out.append(eta + noise * A * rng.standard_normal(len(t)))
        return out

    fit = waves.decaying_wave_fit(t, records(0.015), xs, T, 0.96 * k)
    assert fit.H0 == pytest.approx(2.0 * A, rel=0.005)
    assert fit.kappa == pytest.approx(kappa, abs=0.001)
    assert fit.Kr == pytest.approx(B / A, abs=0.01)
    assert fit.k == pytest.approx(k, rel=0.005)
    assert fit.height(2.0) == pytest.approx(2.0 * A * math.exp(-2.0 * kappa), rel=0.006)
    exact = waves.decaying_wave_fit(t, records(0.0), xs, T, 0.96 * k)
    assert exact.H0 == pytest.approx(2.0 * A, rel=1e-5) and exact.kappa == pytest.approx(kappa, abs=1e-5)
    assert exact.residual < 1e-3
    with pytest.raises(ValueError, match="at least 4 gauges"):
        waves.decaying_wave_fit(t, records(0.0)[:3], xs[:3], T, k)


def test_reflection_gauges_half_a_wavelength_apart_give_no_answer() -> None:
    T, dt = 1.5, 0.02
    L = float(waves.wavelength(T, DEPTH))
    t = np.arange(0.0, 30.0, dt)
    etas = [linear_waves(t, x, [1.0 / T], [0.03], [0.0], 0.3) for x in (2.0, 2.0 + 0.5 * L)]
    r = waves.reflection_two_gauge(t, etas[0], etas[1], 0.5 * L, DEPTH, frequency=1.0 / T)
    assert math.isnan(r.Kr) and len(r.f) == 0


# ----------------------------------------------------------------------- CLI waves


def write_gauges(path: Path, t: np.ndarray, etas: list[np.ndarray], xs: tuple[float, ...]) -> None:
    head = ["# id,kind,x,y"] + [f"# {i},elevation,{x:.6f},nan" for i, x in enumerate(xs, start=1)]
    names = ",".join(["time"] + [f"eta_{i}" for i in range(1, len(xs) + 1)])
    rows = [",".join(f"{v:.15e}" for v in row) for row in np.column_stack([t] + etas)]
    path.write_text("\n".join(head + [names] + rows) + "\n")


def test_waves_cli_regular(tmp_path: Path, capsys) -> None:
    T, a, dt = 1.5, 0.03, 0.02
    t = np.arange(0.0, 30.0, dt)
    etas = [linear_waves(t, x, [1.0 / T], [a], [0.3], 0.3) for x in GAUGE_X]
    write_gauges(tmp_path / "gauges.csv", t, etas, GAUGE_X)
    assert waves.main([str(tmp_path), "--depth", str(DEPTH), "--pair", "1,2", "--triple", "1,2,3"]) == 0
    text = capsys.readouterr().out
    assert text.count("Kr = 0.3000") == 2
    assert (tmp_path / "gauges.png").stat().st_size > 0 and (tmp_path / "spectrum.png").stat().st_size > 0


# ------------------------------------------------------------------------ armour

DN, DENSITY, RHO_W = 0.04, 2300.0, 1000.0
SLOPE = math.degrees(math.atan(1 / 1.5))


def write_armour_run(out: Path, moved_unit: int = 3, move_dn: float = 1.5, units: int = 6,
                     wavemaker_h: float | None = 0.1) -> None:
    """A single layer of ``units`` cubes on a 1:1.5 slope; ``moved_unit`` slides ``move_dn`` dn
    down the slope over 10 s, the others rock by at most 0.2 dn and come back."""
    out.mkdir(parents=True, exist_ok=True)
    th = math.radians(SLOPE)
    d, n = np.array([math.cos(th), math.sin(th)]), np.array([-math.sin(th), math.cos(th)])
    centres = [np.array([3.0, 0.2]) + (i * 1.05 * DN) * d + 0.5 * DN * n for i in range(units)]
    lines = [f"# dn={DN:.6f},density={DENSITY:.6f},rho_water={RHO_W:.6f},placement=irregular,"
             f"porosity_target=0.250000,porosity=0.248100,threshold=1.000000,slope_angle_deg={SLOPE:.6f},seed=7",
             "unit,body,x0,y0,angle0"]
    lines += [f"{i + 1},{i + 2},{c[0]:.4f},{c[1]:.4f},{SLOPE:.4f}" for i, c in enumerate(centres)]
    (out / "armour.csv").write_text("\n".join(lines) + "\n")
    header = ("time,body,x,y,angle,u,v,omega,fx_fluid,fy_fluid,torque_fluid,fx_contact,fy_contact,"
              "torque_contact,fx_friction,fy_friction,torque_friction,fx_gravity,fy_gravity,displacement,rotation")
    rows = []
    for time in np.linspace(0.0, 10.0, 51):
        for i, c in enumerate(centres):
            if i + 1 == moved_unit:
                s = move_dn * DN * min(time / 8.0, 1.0)
                pos, rot = c - s * d, 0.3 * min(time / 8.0, 1.0)
            else:
                s = 0.2 * DN * math.sin(math.pi * time / 10.0) ** 2  # out and back
                pos, rot = c + s * n, 0.0
            disp = float(np.linalg.norm(pos - c))
            rows.append(f"{time:.6e},{i + 2},{pos[0]:.9e},{pos[1]:.9e},{math.radians(SLOPE) + rot:.9e},"
                        + ",".join(["0.0"] * 14) + f",{disp:.9e},{rot:.9e}")
    (out / "bodies.csv").write_text(header + "\n" + "\n".join(rows) + "\n")
    wm = f"&wavemaker\n  h = {wavemaker_h}\n  period = 1.5\n  kind = 'regular'\n/\n" if wavemaker_h else ""
    (out / "case.nml").write_text(f"&fluid\n  rho0 = {RHO_W}\n/\n" + wm)


def test_armour_damage_and_figures(tmp_path: Path) -> None:
    out = tmp_path / "run_a"
    write_armour_run(out)
    r = armour.analyse(out)
    assert r.units == 6 and r.n_displaced == 1 and r.Nod == 1.0
    assert list(np.nonzero(r.displaced)[0]) == [2]
    assert r.final_displacement[2] / DN == pytest.approx(1.5, rel=1e-6)
    assert np.max(r.max_displacement[[0, 1, 3, 4, 5]]) / DN == pytest.approx(0.2, rel=1e-6)
    delta = DENSITY / RHO_W - 1.0
    assert r.H == 0.1 and r.H_source == "&wavemaker"
    assert r.Ns == pytest.approx(0.1 / (delta * DN), rel=1e-12)
    # --H wins over the namelist
    assert armour.analyse(out, H=0.2).Ns == pytest.approx(0.2 / (delta * DN), rel=1e-12)
    # the unit moved back along the slope: final pose drawn where bodies.csv puts it
    xf, yf, af = armour._final_poses(r)
    assert xf[2] == pytest.approx(r.layer.x0[2] - 1.5 * DN * math.cos(math.radians(SLOPE)), abs=1e-6)
    assert af[2] == pytest.approx(math.radians(SLOPE) + 0.3, abs=1e-6)
    for name, draw in (("armour_layer.png", armour.plot_layer), ("armour_displacement.png", armour.plot_displacement)):
        assert draw(r, tmp_path / name).stat().st_size > 0


def test_armour_height_from_gauge_and_table(tmp_path: Path, capsys) -> None:
    runs = [tmp_path / "regular_a", tmp_path / "regular_b"]
    write_armour_run(runs[0], wavemaker_h=None)
    write_armour_run(runs[1], move_dn=0.5, wavemaker_h=None)  # below the threshold: no damage
    T, H, dt = 1.5, 0.12, 0.02
    t = np.arange(0.0, 30.0, dt)
    for run in runs:
        write_gauges(run / "gauges.csv", t, [0.5 * H * np.cos(2 * math.pi * t / T)], (2.0,))
    table = tmp_path / "doc" / "armour.md"
    assert armour.main([str(r) for r in runs] + ["--gauge", "1", "--table", str(table)]) == 0
    ns = H / ((DENSITY / RHO_W - 1.0) * DN)
    text = table.read_text()
    row_a = next(line for line in text.splitlines() if line.startswith("| regular_a"))
    row_b = next(line for line in text.splitlines() if line.startswith("| regular_b"))
    cells_a = [c.strip() for c in row_a.strip("|").split("|")]
    cells_b = [c.strip() for c in row_b.strip("|").split("|")]
    assert cells_a[1] == "irregular" and cells_a[2] == "0.248 (0.250)"
    assert float(cells_a[3]) == pytest.approx(H, abs=1e-4) and "gauge 1" in cells_a[4]
    assert float(cells_a[5]) == pytest.approx(ns, abs=0.005)
    assert cells_a[6:9] == ["6", "1", "1"] and cells_b[6:9] == ["6", "0", "0"]
    assert float(cells_a[9]) == pytest.approx(1.5, abs=1e-3) and float(cells_b[9]) == pytest.approx(0.5, abs=1e-3)
    assert "Van Gent (2003): start of damage | 2.9-3.0" in text
    for run in runs:
        assert (run / "armour_layer.png").exists() and (run / "armour_displacement.png").exists()
    assert (table.parent / "armour_ns.png").stat().st_size > 0
    assert armour.laboratory_verdict(ns).startswith("below start of damage")
    assert armour.laboratory_verdict(4.0).startswith("beyond failure")
    assert armour.laboratory_verdict(2.95) == "start of damage (lab Nod = 0)"


def test_armour_gauge_window_outside_the_record(tmp_path: Path, capsys) -> None:
    """A gauge window after the end of the run (say --t-start 5 on a run of 2 s) is a
    clear error naming the file, the window and the record's span, exit code 2."""
    run = tmp_path / "short"
    write_armour_run(run, wavemaker_h=None)
    t = np.arange(0.0, 2.0, 0.02)
    write_gauges(run / "gauges.csv", t, [0.05 * np.cos(2 * math.pi * t / 1.5)], (2.0,))
    assert armour.main([str(run), "--gauge", "1", "--t-start", "5"]) == 2
    err = capsys.readouterr().err
    assert "gauges.csv" in err and "[5.0, None]" in err and "0 to 1.98 s" in err and "--t-start" in err
