"""Particle shifting (``&numerics shifting = 'fickian'``, doc/theory.md#particle-shifting)
in the dam break of test_cases.py (column a = 0.146 m, 30 particles across, to
T = t sqrt(2g/a) = 3.2):

- the particle arrangement stays more even: the share of fluid particles whose nearest
  neighbour is closer than 0.7 dp (clumps that the flow's shear packs together), in the
  mean over the outputs from T = 1 on, falls by a fifth at least (measured: by half);
- the surge front keeps Martin and Moyce's speed within the dam break's 5 % bar and its
  lead within 0.4 a (test_cases.py says why those bars);
- a free-surface particle is not shifted: in still water shifting moves nothing (the
  tank variant in test_cases.py).
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import cKDTree

from conftest import assert_ok, dambreak_text, run_case, snapshots
from post import dambreak
from post.io import read_snapshot

pytestmark = pytest.mark.usefixtures("mbsph")

A = 0.146                 # column width (m), as test_cases.py's dam break
DP = A / 30
G = 9.81
T_END = 3.2 / math.sqrt(2.0 * G / A) + 0.005


def run_dam(tmp_path_factory: pytest.TempPathFactory, mbsph: Path, shifting: str) -> Path:
    text = dambreak_text(a=A, dp=DP, t_end=T_END, dt_out=0.01, numerics={"shifting": shifting})
    proc, out = run_case(text, tmp_path_factory.mktemp(f"dam_{shifting}"), binary=mbsph)
    assert_ok(proc)
    return out


@pytest.fixture(scope="module")
def dams(tmp_path_factory: pytest.TempPathFactory, mbsph: Path) -> dict[str, Path]:
    return {s: run_dam(tmp_path_factory, mbsph, s) for s in ("none", "fickian")}


def close_share(out: Path) -> dict[float, float]:
    """Per snapshot from T = 1 on: the share of fluid particles whose nearest
    neighbour is closer than 0.7 dp."""
    shares = {}
    for path in snapshots(out):
        s = read_snapshot(path)
        if s.time * math.sqrt(2.0 * G / A) < 1.0:
            continue
        f = s.position[s.fluid]
        dist, _ = cKDTree(f).query(f, k=2)
        shares[round(s.time, 3)] = float(np.mean(dist[:, 1] < 0.7 * DP))
    return shares


def test_shifting_evens_the_particles(dams: dict[str, Path]) -> None:
    plain, shifted = close_share(dams["none"]), close_share(dams["fickian"])
    assert plain.keys() == shifted.keys() and len(plain) >= 15
    ratio = np.mean(list(shifted.values())) / np.mean(list(plain.values()))
    # a fifth at least, on the mean over the outputs: what shifting is for (without it
    # the share grows to 13 %; single outputs around the impact on the wall differ less)
    assert ratio <= 0.8, (f"mean share with shifting {ratio:.2f} of that without; per output (%): "
                          f"{ {t: (round(100 * plain[t], 1), round(100 * shifted[t], 1)) for t in plain} }")


def test_shifted_front_keeps_the_experiment_speed(dams: dict[str, Path]) -> None:
    r = dambreak.compare(dams["fickian"], A, 0.0, g=G)
    lo, hi = dambreak.ERROR_WINDOW
    w = (r.T >= lo - 1e-9) & (r.T <= hi + 1e-9) & np.isfinite(r.Z_exp)
    speed = np.polyfit(r.T[w], r.Z_sim[w], 1)[0] / np.polyfit(r.T[w], r.Z_exp[w], 1)[0] - 1.0
    lead = float(np.mean(r.Z_sim[w] - r.Z_exp[w]))
    # the dam break's bars (test_cases.py): speed within 5 %, lead 0 to 0.4 a
    assert abs(speed) <= 0.05 and 0.0 <= lead <= 0.4, f"front speed {100 * speed:+.1f} %, lead {lead:.3f} a"
