"""Bad input: every case below must stop before any particle output with exit code 2
and one message on stderr of the form

    mbsph: error: FILE: &group: variable: message

naming the file, the group, the variable (where there is one) and the allowed range
or choices (src/errors.f90, src/input_check.f90). Each case changes one thing in the
valid case BASE, which test_base_case_is_valid shows to run.
"""

from __future__ import annotations

import os
import re
import resource
import subprocess
from dataclasses import dataclass, field
from pathlib import Path

import pytest

from conftest import COLUMN_ON_FLOOR, EXIT_INPUT, assert_ok, describe, run_case

pytestmark = pytest.mark.usefixtures("mbsph")

CASE = "case.nml"

# A valid case (conftest.COLUMN_ON_FLOOR): a small water column on the floor of a domain
# 0.6 m wide. One step is enough to show that it runs.
BASE = COLUMN_ON_FLOOR


def edit(old: str, new: str, text: str = BASE) -> str:
    """``text`` with ``old`` replaced once by ``new``; ``old`` must be there."""
    assert text.count(old) == 1, f"the test's own edit {old!r} does not match BASE once"
    return text.replace(old, new)


def drop_group(name: str) -> str:
    """BASE without the group &name (from its opening line to its closing '/')."""
    out = re.sub(rf"(?ms)^&{name}\b.*?^/\n", "", BASE)
    assert out != BASE and f"&{name}" not in out
    return out


@dataclass(frozen=True)
class Bad:
    text: str
    group: str                      # as the message names it: 'numerics', 'box #1', ...
    var: str = ""                   # '' when the error is about the whole group
    range: tuple[float, float] | None = None      # allowed [lo, hi] the message must state
    choices: tuple[str, ...] = ()   # allowed values the message must list
    words: tuple[str, ...] = field(default_factory=tuple)   # other fragments the message must hold


POLYGON_2 = "&polygon role = 'solid', nvert = 2, x = 0.2, 0.3, y = 0.1, 0.1 /\n"
# a quadrilateral whose second and fourth edges cross (non-zero signed area, so it
# is the crossing, not a zero area, that must be reported)
POLYGON_CROSSED = "&polygon role = 'solid', nvert = 4, x = 0.2, 0.4, 0.4, 0.2, y = 0.1, 0.3, 0.1, 0.2 /\n"

# a porous region beside the water column, on the floor; the cases below fill in its values
POROUS = "&porous {}, xmin = 0.2, xmax = 0.4, ymin = 0.0, ymax = 0.2 /\n"

# a filter line across the floor's right part; the cases below fill in its values
FILTER = "&slope role = 'filter', x0 = 0.2, y0 = 0.1, x1 = 0.4, y1 = 0.1{} /\n"

# a box body clear of the water and the floor; the cases below give it an oscillation
BODY = "&body shape = 'box', x = 0.3, y = 0.2, width = 0.06, height = 0.06, {} /\n"

CASES: dict[str, Bad] = {
    "unknown_variable": Bad(edit("  dp = 0.02\n", "  dp = 0.02\n  smoothing = 1.5\n"), "numerics", "smoothing",
                            words=("unknown variable",)),
    "missing_run": Bad(drop_group("run"), "run", words=("missing",)),
    "missing_domain": Bad(drop_group("domain"), "domain", words=("missing",)),
    "missing_numerics": Bad(drop_group("numerics"), "numerics", words=("missing",)),
    "missing_dp": Bad(edit("  dp = 0.02\n", ""), "numerics", "dp", words=("required", "> 0")),
    # dp: (0, 1e3] m (src/input_numerics.f90)
    "dp_zero": Bad(edit("dp = 0.02", "dp = 0.0"), "numerics", "dp", range=(0.0, 1.0e3)),
    "dp_negative": Bad(edit("dp = 0.02", "dp = -0.01"), "numerics", "dp", range=(0.0, 1.0e3)),
    # h_over_dp: [1, 2]
    "h_over_dp_3": Bad(edit("dp = 0.02", "dp = 0.02, h_over_dp = 3.0"), "numerics", "h_over_dp",
                       range=(1.0, 2.0)),
    "kgc_continuity_without_correction": Bad(edit("dp = 0.02", "dp = 0.02, kgc_continuity = .false."), "numerics",
                                             "kgc_continuity", words=("gradient",)),
    "kernel_gauss": Bad(edit("kernel = 'wendland'", "kernel = 'gauss'"), "numerics", "kernel",
                        choices=("wendland", "cubic"), words=("gauss",)),
    "integrator_euler": Bad(edit("integrator = 'symplectic'", "integrator = 'euler'"), "numerics", "integrator",
                            choices=("symplectic", "predictor_corrector", "verlet"), words=("euler",)),
    # cfl: (0, 0.5]
    "cfl_0.9": Bad(edit("cfl = 0.2", "cfl = 0.9"), "numerics", "cfl", range=(0.0, 0.5)),
    # dt_fixed: [0, 1e3] s
    "dt_fixed_negative": Bad(edit("cfl = 0.2", "cfl = 0.2, dt_fixed = -1.0e-4"), "numerics", "dt_fixed",
                             range=(0.0, 1.0e3)),
    # the fluid box reaches y = 0.7 above the domain's ymax = 0.5: the message gives the
    # domain [-0.1, 0.5] x [-0.1, 0.5]
    "fluid_outside_domain": Bad(edit("ymin = 0.0, ymax = 0.2", "ymin = 0.0, ymax = 0.7"), "box #1",
                                range=(-0.1, 0.5), words=("outside", "&domain")),
    # the fluid box goes 0.02 m into the floor (&box #2)
    "fluid_overlaps_wall": Bad(edit("ymin = 0.0, ymax = 0.2", "ymin = -0.02, ymax = 0.2"), "box #1",
                               words=("overlaps", "box #2")),
    "restart_without_checkpoint": Bad(edit("max_steps = 1\n", "max_steps = 1\n  restart = .true.\n"), "run",
                                      "restart", words=("checkpoint.h5",)),
    "box_xmax_below_xmin": Bad(edit("xmin = 0.0, xmax = 0.1", "xmin = 0.1, xmax = 0.0"), "box #1", "xmax",
                               words=("xmin",)),
    # nvert: [3, 100]
    "polygon_nvert_2": Bad(BASE + POLYGON_2, "polygon #1", "nvert", range=(3, 100)),
    "polygon_crosses_itself": Bad(BASE + POLYGON_CROSSED, "polygon #1", "x, y", words=("crosses itself",)),
    # t_end: (0, 1e6] s
    "t_end_negative": Bad(edit("t_end = 0.01", "t_end = -1.0"), "run", "t_end", range=(0.0, 1.0e6)),
    # gamma: [1, 10]
    "gamma_zero": Bad(edit("gamma = 7.0", "gamma = 0.0"), "fluid", "gamma", range=(1.0, 10.0)),
    "dp_malformed": Bad(edit("dp = 0.02", "dp = 'abc'"), "numerics", "dp"),
    "run_twice": Bad(BASE + "&run case_name = 'again' /\n", "run", words=("more than once",)),
    # an STL solid is for the 3D build
    "stl_in_2d": Bad(BASE + "&stl stl_file = 'wall.stl' /\n", "stl #1", "stl_file", words=("3D build",)),
    # a prescribed body's oscillation needs period in (0, 1e4] s
    "body_amplitude_without_period": Bad(BASE + BODY.format("motion = 'prescribed', amplitude_x = 0.01"),
                                         "body #1", "period", range=(0.0, 1.0e4), words=("amplitude",)),
    # only a prescribed body oscillates
    "body_amplitude_on_floating": Bad(BASE + BODY.format("density = 500.0, amplitude_y = 0.01, period = 1.0"),
                                      "body #1", "amplitude_y", words=("prescribed", "floating")),
    # one out-of-range value or unknown choice in every group (ranges as in doc/input.md)
    "rho0_zero": Bad(edit("rho0 = 1000.0", "rho0 = 0.0"), "fluid", "rho0", range=(1.0, 1.0e5)),
    "coef_zero": Bad(edit("rho0 = 1000.0", "rho0 = 1000.0, coef = 0.0"), "fluid", "coef", range=(5.0, 100.0)),
    "gravity_negative": Bad(edit("rho0 = 1000.0", "rho0 = 1000.0, gravity = -9.81"), "fluid", "gravity",
                            range=(0.0, 100.0)),
    "gamma_11": Bad(edit("gamma = 7.0", "gamma = 11.0"), "fluid", "gamma", range=(1.0, 10.0)),
    "h_over_dp_half": Bad(edit("dp = 0.02", "dp = 0.02, h_over_dp = 0.5"), "numerics", "h_over_dp",
                          range=(1.0, 2.0)),
    "alpha_negative": Bad(edit("cfl = 0.2", "cfl = 0.2, alpha = -0.1"), "numerics", "alpha", range=(0.0, 1.0)),
    "delta_5": Bad(edit("cfl = 0.2", "cfl = 0.2, delta = 5.0"), "numerics", "delta", range=(0.0, 1.0)),
    "viscosity_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, viscosity = 'sticky'"), "numerics", "viscosity",
                             choices=("artificial", "laminar_sps")),
    "diffusion_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, diffusion = 'fast'"), "numerics", "diffusion",
                             choices=("none", "molteni", "fourtakas")),
    "boundary_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'soft'"), "numerics", "boundary",
                            choices=("dynamic", "repulsive", "mdbc")),
    "shifting_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, shifting = 'lind'"), "numerics", "shifting",
                            choices=("none", "fickian")),
    "shift_coef_20": Bad(edit("cfl = 0.2", "cfl = 0.2, shifting = 'fickian', shift_coef = 20.0"), "numerics",
                         "shift_coef", range=(0.0, 10.0)),
    "shifting_with_repulsive": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'repulsive', diffusion = 'none', "
                                        "shifting = 'fickian'"), "numerics", "shifting", choices=("none",)),
    "mdbc_slip_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'mdbc', mdbc_slip = 'sticky'"), "numerics",
                             "mdbc_slip", choices=("wall", "noslip", "freeslip")),
    "particle_mass_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, particle_mass = 'dense'"), "numerics",
                                 "particle_mass", choices=("rho0", "hydrostatic")),
    "kernel_correction_unknown": Bad(edit("cfl = 0.2", "cfl = 0.2, kernel_correction = 'full'"), "numerics",
                                     "kernel_correction", choices=("none", "gradient", "shepard")),
    "verlet_every_zero": Bad(edit("cfl = 0.2", "cfl = 0.2, verlet_every = 0"), "numerics", "verlet_every",
                             range=(1, 1000)),
    "dt_out_zero": Bad(edit("dt_out = 0.01", "dt_out = 0.0"), "run", "dt_out", range=(0.0, float("inf"))),
    "checkpoint_every_negative": Bad(edit("max_steps = 1", "max_steps = 1, checkpoint_every = -1"), "run",
                                     "checkpoint_every", range=(0, 2147483647)),
    "max_steps_negative": Bad(edit("max_steps = 1", "max_steps = -5"), "run", "max_steps", range=(0, 2147483647)),
    "max_lost_fraction_2": Bad(edit("max_steps = 1", "max_steps = 1, max_lost_fraction = 2.0"), "run",
                               "max_lost_fraction", range=(0.0, 1.0)),
    "gauge_interval_zero": Bad(edit("max_steps = 1", "max_steps = 1, gauge_interval = 0.0"), "run",
                               "gauge_interval", range=(0.0, float("inf"))),
    "balance_every_negative": Bad(edit("max_steps = 1", "max_steps = 1, balance_every = -1"), "run",
                                  "balance_every", range=(0, 2147483647)),
    "case_name_empty": Bad(edit("case_name = 'bad_input'", "case_name = ''"), "run", "case_name",
                           words=("must not be empty",)),
    "domain_ymax_below_ymin": Bad(edit("ymin = -0.1, ymax = 0.5", "ymin = 0.5, ymax = -0.1"), "domain", "ymax",
                                  words=("greater than ymin",)),
    "box_role_gas": Bad(edit("&box role = 'fluid'", "&box role = 'gas'"), "box #1", "role",
                        choices=("solid", "fluid")),
    "box_motion_spin": Bad(edit("&box role = 'solid'", "&box role = 'solid', motion = 'spin'"), "box #2", "motion",
                           choices=("fixed", "oscillate")),
    "body_shape_star": Bad(BASE + BODY.format("density = 500.0").replace("shape = 'box'", "shape = 'star'"),
                           "body #1", "shape", choices=("circle", "box", "wedge", "polygon")),
    "body_density_negative": Bad(BASE + BODY.format("density = -500.0"), "body #1", "density",
                                 range=(1.0, 1.0e5)),
    "body_mu_negative": Bad(BASE + BODY.format("density = 500.0, mu = -0.5"), "body #1", "mu", range=(0.0, 10.0)),
    "contact_model_glue": Bad(BASE + "&contact model = 'glue' /\n", "contact", "model",
                              choices=("dynamic", "repulsive", "noncohesive", "noncohesive_spring", "hertz")),
    "contact_core_overlap_with_hertz": Bad(BASE + "&contact model = 'hertz', core_overlap = 0.01 /\n", "contact",
                                           "core_overlap", words=("'hertz'", "leave it out")),
    "contact_core_overlap_too_small": Bad(BASE + "&contact core_overlap = 1.0e-6 /\n", "contact", "core_overlap", range=(1.0e-4, 0.5)),
    "gauge_kind_velocity": Bad(BASE + "&gauge kind = 'velocity', x = 0.1 /\n", "gauge #1", "kind",
                               choices=("elevation", "pressure")),
    "damping_strength_negative": Bad(BASE + "&damping x0 = 0.3, x1 = 0.4, strength = -1.0 /\n", "damping",
                                     "strength", range=(0.0, 1.0e4)),
    "wavemaker_paddle_wedge": Bad(BASE + "&wavemaker paddle = 'wedge' /\n", "wavemaker", "paddle",
                                  choices=("piston", "flap")),
    # &porous: porosity (0, 1], d50 (0, 100] m, alpha [0, 1e6], beta [0, 1e3], gamma [0, 10]
    "porous_porosity_zero": Bad(BASE + POROUS.format("porosity = 0.0, d50 = 0.05"), "porous #1", "porosity",
                                range=(0.0, 1.0)),
    "porous_porosity_above_one": Bad(BASE + POROUS.format("porosity = 1.2, d50 = 0.05"), "porous #1",
                                     "porosity", range=(0.0, 1.0)),
    "porous_porosity_missing": Bad(BASE + POROUS.format("d50 = 0.05"), "porous #1", "porosity",
                                   words=("required",)),
    "porous_d50_zero": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.0"), "porous #1", "d50",
                           range=(0.0, 100.0)),
    "porous_d50_missing": Bad(BASE + POROUS.format("porosity = 0.4"), "porous #1", "d50", words=("required",)),
    "porous_alpha_negative": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.05, alpha = -1.0"), "porous #1",
                                 "alpha", range=(0.0, 1.0e6)),
    "porous_beta_negative": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.05, beta = -1.0"), "porous #1",
                                "beta", range=(0.0, 1.0e3)),
    "porous_gamma_negative": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.05, gamma = -0.3"), "porous #1",
                                 "gamma", range=(0.0, 10.0)),
    # the region reaches x = 0.7 beyond the domain's xmax = 0.5
    "porous_outside_domain": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.05").replace("xmax = 0.4",
                                 "xmax = 0.7"), "porous #1", "xmin, xmax, ymin, ymax", range=(-0.1, 0.5),
                                 words=("outside", "&domain")),
    "porous_overlap": Bad(BASE + POROUS.format("porosity = 0.4, d50 = 0.05")
                          + POROUS.format("porosity = 0.5, d50 = 0.02").replace("xmin = 0.2", "xmin = 0.3"),
                          "porous #2", words=("overlaps", "porous #1")),
    "porous_with_verlet": Bad(edit("integrator = 'symplectic'", "integrator = 'verlet'")
                              + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics", "integrator",
                              choices=("symplectic", "predictor_corrector"), words=("porous",)),
    "porous_with_shepard": Bad(edit("cfl = 0.2", "cfl = 0.2, kernel_correction = 'shepard'")
                               + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics", "kernel_correction",
                               choices=("none",), words=("porous",)),
    "porous_with_gradient_correction": Bad(edit("cfl = 0.2", "cfl = 0.2, kernel_correction = 'gradient'")
                                           + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics",
                                           "kernel_correction", choices=("none",), words=("porous",)),
    "porous_with_sps": Bad(edit("cfl = 0.2", "cfl = 0.2, viscosity = 'laminar_sps'")
                           + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics", "viscosity",
                           choices=("artificial",), words=("porous",)),
    "porous_with_repulsive": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'repulsive', diffusion = 'none'")
                                 + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics", "boundary",
                                 choices=("dynamic",), words=("porous",)),
    "porous_with_shifting": Bad(edit("cfl = 0.2", "cfl = 0.2, shifting = 'fickian'")
                                + POROUS.format("porosity = 0.4, d50 = 0.05"), "numerics", "shifting",
                                choices=("none",), words=("porous",)),
    # the modified dynamic boundary: not with a contact model that acts through the solids'
    # own density, nor with walls too thin for its ghost points
    "mdbc_thin_wall": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'mdbc'")
                          + "&box role = 'solid', xmin = 0.12, xmax = 0.14, ymin = 0.0, ymax = 0.2 /\n",
                          "numerics", "boundary", choices=("dynamic",), words=("thick", "&box #3")),
    "mdbc_with_dynamic_contact": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'mdbc'") + BODY.format("density = 500.0")
                                     + "&contact model = 'dynamic' /\n", "contact", "model",
                                     choices=("noncohesive_spring", "hertz"), words=("mdbc",)),
    # &slope role = 'filter': one row, a contact model that does not act through the water
    "filter_role_unknown": Bad(BASE + FILTER.format("").replace("'filter'", "'sieve'"), "slope #1", "role",
                               choices=("solid", "filter")),
    "filter_role_on_a_box": Bad(edit("&box role = 'fluid'", "&box role = 'filter'"), "box #1", "role",
                                choices=("solid", "fluid")),
    "filter_two_layers": Bad(BASE + FILTER.format(", layers = 2"), "slope #1", "layers", range=(0.0, 1.0),
                             words=("one row",)),
    "filter_with_repulsive": Bad(edit("cfl = 0.2", "cfl = 0.2, boundary = 'repulsive', diffusion = 'none'")
                                 + FILTER.format(""), "numerics", "boundary", choices=("dynamic",),
                                 words=("filter",)),
    "filter_with_dynamic_contact": Bad(BASE + FILTER.format("") + "&contact model = 'dynamic' /\n", "contact",
                                       "model", choices=("noncohesive_spring", "hertz"), words=("filter",)),
}

_NUMBER = r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eEdD][-+]?\d+)?"
_RANGE_RE = re.compile(rf"([\[(])\s*({_NUMBER})\s*,\s*({_NUMBER}|infinity)\s*([\])])")


def error_line(proc) -> str:
    """The 'mbsph: error: ...' line of stderr (the test fails when there is none)."""
    lines = [ln for ln in proc.stderr.splitlines() if ln.startswith("mbsph: error: ")]
    assert lines, f"no 'mbsph: error: ' line on stderr\n{describe(proc)}"
    return lines[0]


def assert_no_output(tmp_path: Path) -> None:
    snaps = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("snap_*.h5"))
    assert not snaps, f"bad input left particle output: {snaps}"
    assert not (tmp_path / "OUT" / "snap_00000.h5").exists()


def stated_ranges(message: str) -> list[tuple[float, float]]:
    """Every interval '[lo, hi]', '(lo, hi]', ... stated in a message, as numbers."""
    out = []
    for _, lo, hi, _ in _RANGE_RE.findall(message):
        out.append((float(lo.replace("d", "e").replace("D", "e")),
                    float("inf") if hi == "infinity" else float(hi.replace("d", "e").replace("D", "e"))))
    return out


def test_base_case_is_valid(tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(BASE, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    assert (out / "snap_00000.h5").is_file()


@pytest.mark.parametrize("name", list(CASES))
def test_bad_input(name: str, tmp_path: Path, mbsph: Path) -> None:
    bad = CASES[name]
    proc, _ = run_case(bad.text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, f"expected exit code {EXIT_INPUT} for bad input\n{describe(proc)}"
    msg = error_line(proc)
    # the file, the group and the variable, in this order: 'FILE: &group: var: ...'
    where = f"{CASE}: &{bad.group}: " + (f"{bad.var}: " if bad.var else "")
    assert where in msg, f"the message should name {where!r}:\n{msg}"
    for word in bad.words:
        assert word in msg, f"the message should mention {word!r}:\n{msg}"
    if bad.choices:
        for choice in bad.choices:
            assert f"'{choice}'" in msg, f"the message should list the choice '{choice}':\n{msg}"
    if bad.range is not None:
        lo, hi = bad.range
        ranges = stated_ranges(msg)
        assert any(r == pytest.approx((lo, hi), rel=1e-5) for r in ranges), \
            f"the message should state the allowed range [{lo}, {hi}], it states {ranges}:\n{msg}"
    assert_no_output(tmp_path)


def test_error_is_one_message(tmp_path: Path, mbsph: Path) -> None:
    # doc/input.md: "The first problem found stops the program with one message on standard
    # error." Besides that message only the runtime's echo of the stop code may follow.
    proc, _ = run_case(CASES["cfl_0.9"].text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
    extra = [ln for ln in lines if not ln.startswith("mbsph: error: ") and ln.strip() != "ERROR STOP 2"]
    assert len(lines) - len(extra) >= 1 and not extra, (
        f"stderr holds {len(extra)} lines besides the error message, starting with {extra[:3]}")


def test_misspelt_group_suggests_the_right_one(tmp_path: Path, mbsph: Path) -> None:
    text = edit("&numerics\n", "&numerix\n")
    proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    line = text.splitlines().index("&numerix") + 1
    assert f"{CASE}: line {line}: " in msg, f"the message should name the file and line {line}:\n{msg}"
    assert "&numerix" in msg and "did you mean &numerics?" in msg, msg
    assert_no_output(tmp_path)


def test_missing_case_file(tmp_path: Path, mbsph: Path) -> None:
    import subprocess
    proc = subprocess.run([str(mbsph), "no_such_case.nml"], cwd=tmp_path, capture_output=True, text=True,
                          timeout=60, stdin=subprocess.DEVNULL)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert "no_such_case.nml" in msg and "cannot open" in msg, msg
    assert_no_output(tmp_path)


# ------------------------------------------------------------ output folder


def folder_state(folder: Path) -> dict[str, tuple[int, bytes]]:
    """Modification time (ns) and content of every file of a folder."""
    return {p.name: (p.stat().st_mtime_ns, p.read_bytes()) for p in sorted(folder.iterdir()) if p.is_file()}


def test_folder_holding_a_run_is_refused(tmp_path: Path, mbsph: Path) -> None:
    # three snapshots (t = 0, 0.01, 0.02) of a valid run with overwrite = .false. (the default)
    first = edit("max_steps = 1\n", "max_steps = 0\n", edit("t_end = 0.01", "t_end = 0.02"))
    proc, out = run_case(first, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    before = folder_state(out)
    assert "snap_00000.h5" in before
    proc, _ = run_case(BASE, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, f"a second run into a folder that holds a run must stop\n{describe(proc)}"
    msg = error_line(proc)
    assert f"{CASE}: &run: out_dir: " in msg and "overwrite = .true." in msg, msg
    assert folder_state(out) == before, "the refused run changed the files of the first run"


def test_folder_holding_a_run_is_replaced_with_overwrite(tmp_path: Path, mbsph: Path) -> None:
    first = edit("max_steps = 1\n", "max_steps = 0\n", edit("t_end = 0.01", "t_end = 0.02"))
    proc, out = run_case(first, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    old = {p.name for p in out.glob("snap_*.h5")}
    assert len(old) >= 3
    second = edit("max_steps = 1\n", "max_steps = 1\n  overwrite = .true.\n")
    proc, _ = run_case(second, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    # one step: the snapshot at t = 0 and the final one; the old run's later snapshots are gone
    new = sorted(p.name for p in out.glob("snap_*.h5"))
    assert new == ["snap_00000.h5", "snap_00001.h5"], f"snapshots after the overwrite: {new} (before: {sorted(old)})"
    assert "OVERWRITE=T" in (out / "case.nml").read_text().upper().replace(" ", "")


# ------------------------------------------------------------ out_dir is a path, never a command


@pytest.mark.parametrize("out_dir", ['OUT/x"; touch PWNED; echo "', "OUT/$(touch PWNED)", "OUT/`touch PWNED`",
                                     "OUT/x; touch PWNED"])
def test_out_dir_cannot_run_a_command(out_dir: str, tmp_path: Path, mbsph: Path) -> None:
    # a case file received from someone else must not execute anything: the folder is made
    # with mkdir(2), and a name with quotes or shell characters is refused at read time
    text = edit("out_dir = 'OUT'", f"out_dir = '{out_dir}'")
    proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &run: out_dir: " in msg and "not allowed" in msg, msg
    assert not list(tmp_path.rglob("PWNED")), "the case file ran a shell command"
    assert sorted(p.name for p in tmp_path.iterdir()) == [CASE], "bad input created files or folders"


def test_nested_out_dir_is_created(tmp_path: Path, mbsph: Path) -> None:
    proc, _ = run_case(edit("out_dir = 'OUT'", "out_dir = 'OUT/a/b-c/d_e.1'"), tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    assert (tmp_path / "OUT" / "a" / "b-c" / "d_e.1" / "snap_00000.h5").is_file()


def test_out_dir_too_long_is_refused(tmp_path: Path, mbsph: Path) -> None:
    # a name longer than the solver holds would be cut silently and the run would write elsewhere
    long = "OUT/" + "d" * 600
    proc, _ = run_case(edit("out_dir = 'OUT'", f"out_dir = '{long}'"), tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &run: out_dir: " in msg and "longer than" in msg, msg
    assert not (tmp_path / "OUT").exists()


# ------------------------------------------------------------ syntax: the line, the variable, what was expected


@dataclass(frozen=True)
class Syntax:
    text: str
    marker: str                     # text of the line the message must name
    group: str
    var: str                        # '' when the message names no variable
    words: tuple[str, ...]


SYNTAX: dict[str, Syntax] = {
    # the namelist reader reported this as 'unknown namelist group &fluidfluid'
    "double_equals": Syntax(edit("rho0 = 1000.0", "rho0 = = 1"), "rho0 = = 1", "fluid", "rho0",
                            ("a value is expected after =", "found =")),
    # a scalar given two values: the reader blamed another variable
    "two_values_for_a_scalar": Syntax(edit("t_end = 0.01", "t_end = 0.01, 0.1"), "t_end = 0.01, 0.1", "run",
                                      "t_end", ("takes one value", "0.01, 0.1")),
    # the reader reported 'yes&domain: unknown variable'
    "logical_yes": Syntax(edit("max_steps = 1\n", "max_steps = 1\n  overwrite = yes\n"), "overwrite = yes", "run",
                          "overwrite", ("cannot read the value 'yes'", ".true./.false.")),
    "missing_equals": Syntax(edit("dp = 0.02", "dp 0.02"), "dp 0.02", "numerics", "dp",
                             ("= is expected after the name", "0.02")),
    "missing_value": Syntax(edit("cfl = 0.2", "cfl ="), "cfl =", "numerics", "cfl", ("a value is expected",)),
    "group_not_closed": Syntax(edit("ymax = 0.5\n/\n", "ymax = 0.5\n"), "&fluid", "domain", "",
                               ("not closed", "before &fluid")),
    "string_not_closed": Syntax(edit("case_name = 'bad_input'", "case_name = 'bad_input"), "case_name = 'bad_input",
                                "run", "case_name", ("string", "not closed")),
    "unquoted_string": Syntax(edit("kernel = 'wendland'", "kernel = wendland"), "kernel = wendland", "numerics",
                              "kernel", ("cannot read the value 'wendland'", "quoted string")),
    # non-finite geometry was accepted and wrote NaN lines with exit 0: refused for every
    # variable of every group, where it is read
    "nan_body_x": Syntax(BASE + BODY.format("density = 500.0").replace("x = 0.3", "x = NaN"), "&body", "body #1",
                         "x", ("'NaN'", "not a finite number")),
    "inf_domain_xmax": Syntax(edit("xmax = 0.5", "xmax = Inf"), "xmin = -0.1, xmax = Inf", "domain", "xmax",
                              ("'Inf'", "not a finite number")),
    "overflowing_polygon_vertex": Syntax(BASE + "&polygon role = 'solid', nvert = 3, x = 0.2, 1e400, 0.3, "
                                         "y = 0.1, 0.1, 0.2 /\n", "&polygon", "polygon #1", "x",
                                         ("'1e400'", "not a finite number")),
    "nan_slope_vertex": Syntax(BASE + "&slope x0 = 0.1, y0 = 0.0, x1 = 0.4, y1 = 1*nan /\n", "&slope", "slope #1",
                               "y1", ("'1*nan'", "not a finite number")),
    "nan_gauge": Syntax(BASE + "&gauge kind = 'elevation', x = nan /\n", "&gauge", "gauge #1", "x",
                        ("not a finite number",)),
    "infinite_damping": Syntax(BASE + "&damping x0 = -Infinity, x1 = 0.4 /\n", "&damping", "damping", "x0",
                               ("not a finite number",)),
    "nan_wavemaker_x0": Syntax(BASE + "&wavemaker x0 = NaN /\n", "&wavemaker", "wavemaker", "x0",
                               ("not a finite number",)),
}


@pytest.mark.parametrize("name", list(SYNTAX))
def test_syntax_error_names_the_line(name: str, tmp_path: Path, mbsph: Path) -> None:
    bad = SYNTAX[name]
    proc, _ = run_case(bad.text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    line = next(k for k, ln in enumerate(bad.text.splitlines(), 1) if ln.strip().startswith(bad.marker))
    where = f"{CASE}: line {line}: &{bad.group}: " + (f"{bad.var}: " if bad.var else "")
    assert where in msg, f"the message should name {where!r}:\n{msg}"
    for word in bad.words:
        assert word in msg, f"the message should mention {word!r}:\n{msg}"
    assert_no_output(tmp_path)


def test_real_for_a_whole_number_names_the_variable(tmp_path: Path, mbsph: Path) -> None:
    # the reader takes 2 for max_steps and then '.5' for the next name: it reported
    # '.5: unknown variable'
    proc, _ = run_case(edit("max_steps = 1", "max_steps = 2.5"), tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &run: max_steps: " in msg and "2.5" in msg, msg
    assert_no_output(tmp_path)


def test_every_shipped_case_passes_the_syntax_check(tmp_path: Path, mbsph: Path) -> None:
    # the check must not refuse what the reader takes: every case file of input/ and
    # bench/, with a second &run appended, which the reader refuses after the syntax check
    root = Path(__file__).resolve().parents[1]
    files = sorted(root.glob("input/**/*.nml")) + sorted(root.glob("bench/*.nml"))
    assert len(files) > 10
    for f in files:
        proc, _ = run_case(f.read_text() + "\n&run case_name = 'again' /\n", tmp_path, binary=mbsph, name=CASE)
        msg = "\n".join(ln for ln in proc.stderr.splitlines() if ln.startswith("mbsph: error: "))
        assert proc.returncode == EXIT_INPUT and "more than once" in msg, f"{f.relative_to(root)}: {msg or describe(proc)}"


# ------------------------------------------------------------ a scene with nothing to simulate


NO_FLUID = edit("&box role = 'fluid', xmin = 0.0, xmax = 0.1, ymin = 0.0, ymax = 0.2 /\n", "")


def test_no_fluid_and_nothing_moving_is_refused(tmp_path: Path, mbsph: Path) -> None:
    # walls alone: the run used to go on and exit 0
    proc, _ = run_case(NO_FLUID, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: " in msg and "no fluid particles" in msg and "nothing to simulate" in msg, msg
    assert not (tmp_path / "OUT").exists(), "the refused case created its output folder"


def test_dry_case_with_a_body_runs_and_says_so(tmp_path: Path, mbsph: Path) -> None:
    # a body falling on the floor without water (as the paper's dry contact cases): allowed,
    # with a warning on the screen and in run.log
    proc, out = run_case(NO_FLUID + BODY.format("density = 500.0"), tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    for text in (proc.stdout, (out / "run.log").read_text()):
        assert "mbsph: warning: " in text and "no fluid particles" in text, text[-2000:]


# ------------------------------------------------------------ overwrite: checks first, then the old run goes


def test_refused_case_keeps_the_old_run_even_with_overwrite(tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(BASE, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    before = folder_state(out)
    # overwrite asked for, but the scene is refused after the groups were read
    second = edit("max_steps = 1\n", "max_steps = 1\n  overwrite = .true.\n", NO_FLUID)
    proc, _ = run_case(second, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    assert "nothing to simulate" in error_line(proc)
    assert folder_state(out) == before, "a refused case deleted or changed the previous run"


def test_overwrite_removes_every_file_of_the_old_run(tmp_path: Path, mbsph: Path) -> None:
    proc, out = run_case(BASE, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    # files an earlier run with gauges and armour units would have left
    (out / "gauges.csv").write_text("t,eta_1\n0.0,0.0\n")
    (out / "armour.csv").write_text("unit,x,y\n")
    (out / "figure.png").write_bytes(b"not a run file")
    proc, _ = run_case(edit("max_steps = 1\n", "max_steps = 1\n  overwrite = .true.\n"), tmp_path, binary=mbsph,
                       name=CASE)
    assert_ok(proc)
    assert not (out / "gauges.csv").exists() and not (out / "armour.csv").exists(), sorted(os.listdir(out))
    assert (out / "figure.png").exists(), "overwrite removed a file that is not the run's"


# ------------------------------------------------------------ a case too large: the estimate, not a crash


def run_limited(text: str, tmp_path: Path, binary: Path, limit_bytes: int) -> subprocess.CompletedProcess:
    """Run a case under an address-space limit, as `ulimit -v` sets it."""
    (tmp_path / CASE).write_text(text)

    def limit() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (limit_bytes, limit_bytes))

    return subprocess.run([str(binary), CASE], cwd=tmp_path, capture_output=True, text=True, timeout=120,
                          stdin=subprocess.DEVNULL, preexec_fn=limit)


def test_case_too_large_for_the_limit_stops_with_the_estimate(tmp_path: Path, mbsph: Path) -> None:
    # dp = 5e-5 m: about 2e7 particles (0.02 m^2 of water and 0.03 of floor over dp^2),
    # some 10 GB; under a 4 GB limit it crashed (SIGSEGV) after allocating; now it stops
    # before, with the estimate and what allows less
    text = edit("dp = 0.02", "dp = 5.0e-5")
    proc = run_limited(text, tmp_path, mbsph, 4 * 1024**3)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &numerics: dp: " in msg and "particles" in msg and "GB on each rank" in msg, msg
    assert "ulimit -v" in msg, msg
    found = re.search(r"about ([0-9.eE+]+) particles", msg)
    assert found and 1.0e7 < float(found.group(1)) < 4.0e7, msg
    assert not (tmp_path / "OUT").exists(), "the refused case created its output folder"


def test_domain_beyond_the_cell_numbers_is_refused(tmp_path: Path, mbsph: Path) -> None:
    # 2 km x 2 km at dp = 0.02 m: 5e9 cells of the neighbour grid, beyond 32-bit numbers
    # (a 927 m square at dp = 0.005 m overflowed them and crashed)
    text = edit("xmin = -0.1, xmax = 0.5, ymin = -0.1, ymax = 0.5", "xmin = -0.1, xmax = 2000.0, ymin = -0.1, "
                "ymax = 2000.0")
    proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &domain: " in msg and "cells of the neighbour grid" in msg, msg
    assert not (tmp_path / "OUT").exists()


# ------------------------------------------------------------ a restart checks its checkpoint against the case


RESTART = edit("max_steps = 1\n", "max_steps = 2\n  restart = .true.\n")


def first_run(text: str, tmp_path: Path, mbsph: Path) -> Path:
    """A run of text that ends with its checkpoint; returns the output folder."""
    proc, out = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)
    assert (out / "checkpoint.h5").is_file()
    return out


@pytest.mark.parametrize("change, words", [
    # a checkpoint without bodies restarted by a case with one: bodies from uninitialised memory
    ("more_bodies", ("holds 0 bodies, the case 1",)),
    ("other_dp", ("written at dp = ", "the case has dp = ")),
    # a wider water column: 138 particles made against the checkpoint's 128
    ("other_geometry", ("was written by a case of 128 particles, this case makes 138",)),
])
def test_restart_of_another_case_is_refused(change: str, words: tuple[str, ...], tmp_path: Path,
                                            mbsph: Path) -> None:
    first_run(BASE, tmp_path, mbsph)
    text = {"more_bodies": RESTART + BODY.format("density = 500.0"),
            "other_dp": edit("dp = 0.02", "dp = 0.025", RESTART),
            "other_geometry": edit("xmax = 0.1, ymin = 0.0", "xmax = 0.12, ymin = 0.0", RESTART)}[change]
    proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert "checkpoint.h5" in msg, msg
    for w in words:
        assert w in msg, msg


def test_restart_with_fewer_bodies_is_refused(tmp_path: Path, mbsph: Path) -> None:
    # a checkpoint with a body restarted by a case without it overflowed the heap
    first_run(BASE + BODY.format("density = 500.0"), tmp_path, mbsph)
    proc, _ = run_case(RESTART, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    assert "holds 1 bodies, the case 0" in error_line(proc)


def test_restart_from_a_damaged_checkpoint_is_refused(tmp_path: Path, mbsph: Path) -> None:
    import h5py
    out = first_run(BASE, tmp_path, mbsph)
    path = out / "checkpoint.h5"
    with h5py.File(path, "r") as f:
        offset = f["rho"].id.get_offset()
        n = f["rho"].shape[0]
    assert offset is not None and n > 10
    # sixteen bytes of the densities overwritten: HDF5 still reads the file
    data = bytearray(path.read_bytes())
    data[offset + 8 * (n // 2): offset + 8 * (n // 2) + 16] = bytes(range(1, 17))
    path.write_bytes(bytes(data))
    proc, _ = run_case(RESTART, tmp_path, binary=mbsph, name=CASE)
    assert proc.returncode == EXIT_INPUT, describe(proc)
    msg = error_line(proc)
    assert f"{CASE}: &run: restart: " in msg and "checksum" in msg, msg


def test_restart_of_the_same_case_still_runs(tmp_path: Path, mbsph: Path) -> None:
    first_run(BASE, tmp_path, mbsph)
    proc, _ = run_case(RESTART, tmp_path, binary=mbsph, name=CASE)
    assert_ok(proc)


# ------------------------------------------------------------ one run at a time in a folder


def test_second_run_into_a_folder_in_use_is_refused(tmp_path: Path, mbsph: Path) -> None:
    import time
    # a first run that goes on for a while
    # (the water spreads off the floor and leaves the domain: no limit on the particles lost)
    long = edit("max_steps = 1\n", "max_steps = 0\n  max_lost_fraction = 1.0\n",
                edit("t_end = 0.01", "t_end = 1000.0", edit("dt_out = 0.01", "dt_out = 100.0")))
    first_dir = tmp_path / "first"
    first_dir.mkdir()
    (first_dir / CASE).write_text(long)
    out = tmp_path / "first" / "OUT"
    first = subprocess.Popen([str(mbsph), CASE], cwd=first_dir, stdout=subprocess.DEVNULL,
                             stderr=subprocess.DEVNULL, stdin=subprocess.DEVNULL)
    try:
        # its first snapshot and index written, and renamed into place (no *.tmp of its own left
        # that it would rename itself while the second run is refused)
        for _ in range(300):
            if ((out / ".mbsph.lock").exists() and (out / "snap_00000.h5").exists()
                    and (out / "particles.xmf").exists() and not list(out.glob("*.tmp"))):
                break
            time.sleep(0.1)
        assert first.poll() is None and (out / ".mbsph.lock").exists(), "the first run holds no lock"
        before = sorted(p.name for p in out.iterdir())
        # a second case writing into the same folder, overwrite asked for
        second = edit("out_dir = 'OUT'", "out_dir = '../first/OUT'", edit("max_steps = 1\n",
                                                                         "max_steps = 1\n  overwrite = .true.\n"))
        (tmp_path / "second").mkdir()
        proc, _ = run_case(second, tmp_path / "second", binary=mbsph, name=CASE)
        assert proc.returncode == EXIT_INPUT, describe(proc)
        msg = error_line(proc)
        assert f"{CASE}: &run: out_dir: " in msg and "in use by another run" in msg and str(first.pid) in msg, msg
        assert set(before) <= {p.name for p in out.iterdir()}, "the refused run deleted files of the running one"
    finally:
        first.kill()
        first.wait()
    # killed: its lock is left, and the next run takes it over (the process is gone)
    assert (out / ".mbsph.lock").exists()
    proc, _ = run_case(edit("max_steps = 1\n", "max_steps = 1\n  overwrite = .true.\n"), first_dir, binary=mbsph,
                       name=CASE)
    assert_ok(proc)
    assert not (out / ".mbsph.lock").exists(), "a run that ended left its lock"


# ------------------------------------------------------------ a full disk: one line, the whole files named
# (the run printed some forty lines of HDF5's error stack and then crashed with SIGSEGV)


def test_full_disk_names_the_whole_files(tmp_path: Path, mbsph: Path) -> None:
    # a 1 MB file system fills after some snapshots: one line, 'no space left on device',
    # the partial snapshot removed, the last whole one named and readable
    import h5py
    small = tmp_path / "small"
    small.mkdir()
    mounted = subprocess.run(["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(small)], capture_output=True)
    if mounted.returncode != 0:
        pytest.skip("no permission to mount a small file system here")
    try:
        # dp = 5 mm: snapshots of about 90 kB every 0.01 s for 1 s
        text = edit("max_steps = 1\n", "max_steps = 0\n", edit("t_end = 0.01", "t_end = 1.0"))
        text = edit("out_dir = 'OUT'", f"out_dir = '{small}/run'", edit("dp = 0.02", "dp = 0.005", text))
        proc, _ = run_case(text, tmp_path, binary=mbsph, name=CASE)
        assert proc.returncode == 1, describe(proc)
        lines = [ln for ln in proc.stderr.splitlines() if ln.strip()]
        assert len(lines) == 1 and "no space left on device" in lines[0], proc.stderr
        found = re.search(r"the last file written whole is (\S+\.h5)", lines[0])
        assert found, lines[0]
        with h5py.File(found.group(1), "r") as f:
            assert f["position"].shape[0] > 0
        snaps = sorted((small / "run").glob("snap_*.h5"))
        assert str(snaps[-1]) == found.group(1), (snaps[-1], lines[0])
    finally:
        subprocess.run(["umount", str(small)], capture_output=True)
