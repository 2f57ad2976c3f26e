"""SPH interpolation of particle fields at arbitrary points.

Only fluid particles (``kind == 1``) contribute. With the particle volume
``V_j = m_j / rho_j`` and the Wendland C2 kernel ``W`` of support ``2h``:

- the kernel sum (the "fluid fraction") is ``S(x) = sum_j V_j W(x - x_j)``:
  about 1 inside the water, 1/2 on the free surface, 0 outside;
- a field is interpolated with Shepard normalisation,
  ``f(x) = sum_j f_j V_j W(x - x_j) / S(x)``, which reproduces constant fields
  exactly and linear fields to high accuracy away from the free surface.

Neighbours are found with k-d trees (``scipy.spatial.cKDTree``), over chunks of
points. A 3D snapshot (positions of three components, ``build/mbsph3d``) takes
points of three coordinates and the kernel's 3D normalisation; a height scan
(``free_surface_height``) runs along the vertical line at ``(x, z)``.
"""

from __future__ import annotations

from typing import Sequence

import numpy as np
from scipy.spatial import cKDTree

from .io import Snapshot

__all__ = [
    "wendland_c2",
    "kernel_sum",
    "mass_sum",
    "interpolate",
    "free_surface_height",
    "line_points",
    "mid_width",
    "SURFACE_LEVEL",
    "MIN_SUPPORT",
]

#: Kernel sum on the free surface: half of the kernel lies in the water.
SURFACE_LEVEL = 0.5
#: Default kernel sum below which a point is taken to be outside the water.
MIN_SUPPORT = 0.1

_POINTS_PER_CHUNK = 8192


def wendland_c2(r: np.ndarray | float, h: float, ndim: int = 2) -> np.ndarray:
    """Wendland C2 kernel: ``a (1 - q/2)^4 (2q + 1)`` for ``q = r/h < 2``, else 0, with
    ``a = 7/(4 pi h^2)`` in 2D and ``21/(16 pi h^3)`` in 3D (``ndim``)."""
    q = np.asarray(r, dtype=float) / h
    t = np.clip(1.0 - 0.5 * q, 0.0, None)
    norm = 7.0 / (4.0 * np.pi * h * h) if ndim == 2 else 21.0 / (16.0 * np.pi * h**3)
    return norm * t**4 * (2.0 * q + 1.0)


def _as_points(points: Sequence[float] | np.ndarray, ndim: int = 2) -> np.ndarray:
    """Return points as an ``(M, ndim)`` float array (one point is accepted)."""
    pts = np.asarray(points, dtype=float)
    if pts.shape == (ndim,):
        pts = pts[None, :]
    if pts.ndim != 2 or pts.shape[1] != ndim:
        raise ValueError(f"points must have shape (M, {ndim}) for a {ndim}D snapshot, got {pts.shape}")
    return pts


def mid_width(snapshot: Snapshot) -> float:
    """The middle of the water across the width of a 3D snapshot (z, m)."""
    z = snapshot.position[snapshot.fluid, 2]
    return 0.5 * (float(z.min()) + float(z.max())) if z.size else 0.0


def line_points(snapshot: Snapshot, x: np.ndarray, ys: np.ndarray, z: float | None = None) -> np.ndarray:
    """The points ``(x_i, y_i)`` of a 2D snapshot, or ``(x_i, y_i, z)`` of a 3D one (``z``
    default: mid-width), for equal-length ``x`` and ``ys``."""
    cols = [np.asarray(x, dtype=float), np.asarray(ys, dtype=float)]
    if snapshot.position.shape[1] == 3:
        cols.append(np.full(cols[1].shape, mid_width(snapshot) if z is None else z))
    return np.column_stack(cols)


def _weighted_sums(points: np.ndarray, xj: np.ndarray, weights: np.ndarray, h: float) -> np.ndarray:
    """Return ``sum_j W(|points_i - xj_j|) weights_jk`` with shape ``(M, K)``.

    ``weights`` has shape ``(N, K)``. The (point, particle) pairs closer than the kernel
    support ``2h`` come from k-d trees of both (``scipy.spatial.cKDTree``), a chunk of
    points at a time so that the pair list stays small.
    """
    m, n = points.shape[0], xj.shape[0]
    out = np.zeros((m, weights.shape[1]))
    if m == 0 or n == 0:
        return out
    particles = cKDTree(xj)
    for start in range(0, m, _POINTS_PER_CHUNK):
        stop = min(start + _POINTS_PER_CHUNK, m)
        # output_type 'ndarray' keeps the pairs at distance zero, which a sparse matrix drops
        pairs = cKDTree(points[start:stop]).sparse_distance_matrix(particles, 2.0 * h, output_type="ndarray")
        if pairs.size == 0:
            continue
        w = wendland_c2(pairs["v"], h, xj.shape[1])
        for k in range(weights.shape[1]):
            out[start:stop, k] += np.bincount(pairs["i"], weights=w * weights[pairs["j"], k], minlength=stop - start)
    return out


def kernel_sum(snapshot: Snapshot, points: Sequence[float] | np.ndarray) -> np.ndarray:
    """Return the fluid kernel sum ``sum_j V_j W(x - x_j)`` at each point, shape ``(M,)``."""
    fluid = snapshot.fluid
    weights = snapshot.volume[fluid][:, None]
    return _weighted_sums(_as_points(points, snapshot.position.shape[1]), snapshot.position[fluid], weights, snapshot.h)[:, 0]


def mass_sum(snapshot: Snapshot, points: Sequence[float] | np.ndarray) -> np.ndarray:
    """Return ``sum_j m_j W(x - x_j)`` over the fluid at each point, shape ``(M,)``: the
    density of the particles' packing, which the plain continuity equation carries."""
    fluid = snapshot.fluid
    weights = snapshot.mass[fluid][:, None]
    return _weighted_sums(_as_points(points, snapshot.position.shape[1]), snapshot.position[fluid], weights, snapshot.h)[:, 0]


def interpolate(snapshot: Snapshot, field: str | np.ndarray, points: Sequence[float] | np.ndarray,
                min_support: float = MIN_SUPPORT) -> np.ndarray:
    """Shepard-normalised SPH interpolation of a particle field at points.

    ``field`` is a snapshot field name (``"pressure"``, ``"density"``, ``"velocity"``,
    ...) or an array with one value (or one row) per particle of the snapshot.
    Returns shape ``(M,)`` for a scalar field and ``(M, K)`` for a vector field, with
    NaN at points whose kernel sum is below ``min_support`` (outside the water).
    """
    values = np.asarray(getattr(snapshot, field) if isinstance(field, str) else field, dtype=float)
    if values.shape[0] != snapshot.position.shape[0]:
        raise ValueError(f"field has {values.shape[0]} values for {snapshot.position.shape[0]} particles")
    scalar = values.ndim == 1
    fluid = snapshot.fluid
    vol = snapshot.volume[fluid]
    f = values[fluid].reshape(int(fluid.sum()), -1)
    weights = np.column_stack([vol, vol[:, None] * f])
    sums = _weighted_sums(_as_points(points, snapshot.position.shape[1]), snapshot.position[fluid], weights, snapshot.h)
    support = sums[:, :1]
    with np.errstate(invalid="ignore", divide="ignore"):
        result = np.where(support >= min_support, sums[:, 1:] / support, np.nan)
    return result[:, 0] if scalar else result


def free_surface_height(snapshot: Snapshot, x: float | Sequence[float] | np.ndarray,
                        dy: float | None = None, level: float = SURFACE_LEVEL,
                        z: float | None = None) -> float | np.ndarray:
    """Water surface elevation at horizontal position(s) ``x``.

    The kernel sum is scanned on a vertical grid of spacing ``dy`` (default ``dp / 10``)
    spanning the fluid particles; the surface is the highest height where it is at
    least ``level``, refined by linear interpolation to the crossing of ``level``.
    Returns NaN where there is no water; a float for a scalar ``x``. In a 3D snapshot the
    lines are at ``z`` (default: mid-width).
    """
    xs = np.atleast_1d(np.asarray(x, dtype=float))
    y_fluid = snapshot.position[snapshot.fluid, 1]
    if y_fluid.size == 0:
        heights = np.full(xs.shape, np.nan)
        return float(heights[0]) if np.ndim(x) == 0 else heights
    dy = snapshot.dp / 10.0 if dy is None else dy
    support = 2.0 * snapshot.h
    ys = np.arange(y_fluid.min() - support, y_fluid.max() + support + dy, dy)
    grid = line_points(snapshot, np.repeat(xs, len(ys)), np.tile(ys, len(xs)), z)
    sums = kernel_sum(snapshot, grid).reshape(len(xs), len(ys))
    heights = np.full(xs.shape, np.nan)
    for i, column in enumerate(sums):
        wet = np.nonzero(column >= level)[0]
        if wet.size == 0:
            continue
        k = wet[-1]
        if k + 1 < len(ys):
            frac = (column[k] - level) / (column[k] - column[k + 1])
            heights[i] = ys[k] + frac * dy
        else:
            heights[i] = ys[k]
    return float(heights[0]) if np.ndim(x) == 0 else heights
