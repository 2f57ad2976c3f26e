"""The moment of the SPH pressure gradient that a particle next to a repulsive wall keeps
(doc/theory.md, "What the repulsive wall cannot do"; doc/3d.md): the sum over the water
alone of V_j (y_j - y_i) dW_ij/dy_i on a square (cubic) lattice of spacing dp, Wendland
kernel at h = sqrt(2) dp, in 2D and 3D (and in 3D at a vertical corner of two walls). A full support gives about 1; a cut one the share
of the vertical pressure gradient the particle feels from its neighbours.

    .venv/bin/python tools/cut_kernel_moments.py
"""
from __future__ import annotations

import itertools
import math

import numpy as np


def wendland_dwdr(r: np.ndarray, h: float, dim: int) -> np.ndarray:
    """dW/dr of the Wendland C2 kernel, W = a (1 - q/2)^4 (2q + 1), q = r/h."""
    a = 7.0 / (4.0 * math.pi * h * h) if dim == 2 else 21.0 / (16.0 * math.pi * h ** 3)
    q = r / h
    return np.where(q < 2.0, -5.0 * a * q * (1.0 - 0.5 * q) ** 3 / h, 0.0)


def moment(dim: int, keep, h_over_dp: float = math.sqrt(2.0)) -> float:
    """sum_j V_j (y_j - y_i) dW_ij/dy_i over the lattice points j the filter keep holds
    (the particle i at the origin, dp = 1)."""
    h = h_over_dp
    pts = np.array([p for p in itertools.product(range(-4, 5), repeat=dim) if any(p) and keep(p)], dtype=float)
    r = np.linalg.norm(pts, axis=1)
    dwdy_i = wendland_dwdr(r, h, dim) * (-pts[:, 1]) / r       # d/dy_i of W(|x_i - x_j|)
    return float(np.sum(pts[:, 1] * dwdy_i))


def main() -> None:
    cases = [("full support", lambda p: True),
             ("first column at a vertical wall (water x >= 0)", lambda p: p[0] >= 0),
             ("first row above a floor (water y >= 0)", lambda p: p[1] >= 0),
             ("second row above a floor (water y >= -dp)", lambda p: p[1] >= -1)]
    print(f"{'where':50s} {'2D':>7s} {'3D':>7s}")
    for name, keep in cases:
        print(f"{name:50s} {moment(2, keep):7.4f} {moment(3, keep):7.4f}")
    # a vertical corner, where a side wall meets an end wall, has no 2D counterpart
    corner = moment(3, lambda p: p[0] >= 0 and p[2] >= 0)
    print(f"{'vertical corner of two walls (water x, z >= 0)':50s} {'-':>7s} {corner:7.4f}")


if __name__ == "__main__":
    main()
