"""Still water around an immersed &stl solid (doc/3d.md, "STL solids"): a cube or an
icosphere held in a tank of water, run with build/mbsph3d, and how near the water next to
the mesh keeps the hydrostatic pressure.

The tank is 0.2 m long and 0.1 m wide, the water `--depth` deep, dp = 0.01 m; the solid
(a cube of side 2r or a sphere of radius r, `--radius`, 0.03 m by default; 1280 triangles) is centred at mid
length and mid width, `--centre` above the floor. Over the second half of the run it
prints, as fractions of rho g depth and averaged over the outputs:

  near   the mean pressure of the water within 2h of the mesh, less the pressure of the
         water far from it at the same height (a straight line fitted to the water more
         than 3 dp beyond the solid's footprint and 2 dp from the walls);
  bed    the floor's pressure under the solid less the floor's far from it;
  (cube) the first difference for the water next to each face alone;

the largest speed of the water over the same outputs, in m/s (the same tank without the
solid: 0.02 m/s at 0.15 m depth); and, over the whole run, the least distance of a water
particle from the mesh in dp (< 0: inside it).

    .venv/bin/python tools/stl_still_water.py OUT_DIR --shape cube|sphere
        [--depth 0.1] [--centre 0.05] [--radius 0.03] [--t-end 1.0] [--numerics "kernel_correction = 'gradient'"]
        [--binary build/mbsph3d]
"""
from __future__ import annotations

import argparse
import struct
import subprocess
import sys
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parent.parent
DP = 0.01
R = 0.03


def cube_triangles(side: float) -> np.ndarray:
    p = np.array([[sx, sy, sz] for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)], dtype=float) * 0.5 * side
    faces = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
    return np.array([p[[a, b, c]] for a, b, c, d in faces] + [p[[a, c, d]] for a, b, c, d in faces])


def sphere_triangles(radius: float, level: int = 3) -> np.ndarray:
    """An icosphere: the icosahedron's faces split in four `level` times."""
    g = (1 + 5 ** 0.5) / 2
    v = np.array([[-1, g, 0], [1, g, 0], [-1, -g, 0], [1, -g, 0], [0, -1, g], [0, 1, g], [0, -1, -g], [0, 1, -g],
                  [g, 0, -1], [g, 0, 1], [-g, 0, -1], [-g, 0, 1]], dtype=float)
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6),
         (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10),
         (8, 6, 7), (9, 8, 1)]
    tri = v[np.array(f)]
    for _ in range(level):
        a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
        ab, bc, ca = (a + b) / 2, (b + c) / 2, (c + a) / 2
        tri = np.concatenate([np.stack(x, axis=1) for x in ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    return radius * tri / np.linalg.norm(tri, axis=2, keepdims=True)


def write_binary_stl(path: Path, tri: np.ndarray) -> None:
    with open(path, "wb") as f:
        f.write(b"mbsph mesh".ljust(80, b" "))
        f.write(struct.pack("<I", len(tri)))
        for t in tri:
            f.write(struct.pack("<12fH", 0.0, 0.0, 0.0, *t.reshape(9), 0))


def case_text(out: Path, depth: float, t_end: float, numerics: str) -> str:
    top = depth + 0.04
    extra = f", {numerics}" if numerics else ""
    return (f"&run case_name = 'stl_still', t_end = {t_end}, dt_out = 0.05, out_dir = '{out.name}' /\n"
            f"&domain xmin = -0.04, xmax = 0.24, ymin = -0.04, ymax = {top + 0.02}, zmin = -0.04, zmax = 0.14 /\n"
            "&fluid rho0 = 1000.0, gamma = 7.0, coef = 10.0, gravity = 9.81 /\n"
            f"&numerics dp = {DP}, boundary = 'mdbc'{extra} /\n"
            f"&box role = 'fluid', xmin = 0.0, xmax = 0.2, ymin = 0.0, ymax = {depth}, zmin = 0.0, zmax = 0.1 /\n"
            "&box role = 'solid', xmin = -0.03, xmax = 0.23, ymin = -0.03, ymax = 0.0, zmin = -0.03, zmax = 0.13 /\n"
            f"&box role = 'solid', xmin = -0.03, xmax = 0.0, ymin = 0.0, ymax = {top}, zmin = -0.03, zmax = 0.13 /\n"
            f"&box role = 'solid', xmin = 0.2, xmax = 0.23, ymin = 0.0, ymax = {top}, zmin = -0.03, zmax = 0.13 /\n"
            f"&box role = 'solid', xmin = 0.0, xmax = 0.2, ymin = 0.0, ymax = {top}, zmin = -0.03, zmax = 0.0 /\n"
            f"&box role = 'solid', xmin = 0.0, xmax = 0.2, ymin = 0.0, ymax = {top}, zmin = 0.1, zmax = 0.13 /\n"
            "&stl stl_file = 'solid.stl' /\n")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("out", type=Path, help="the run's folder (made next to the case file it writes)")
    ap.add_argument("--shape", choices=("cube", "sphere"), required=True)
    ap.add_argument("--depth", type=float, default=0.1)
    ap.add_argument("--centre", type=float, default=0.05, help="the solid's centre above the floor [m]")
    ap.add_argument("--radius", type=float, default=R, help="half the cube's side, or the sphere's radius [m]")
    ap.add_argument("--t-end", type=float, default=1.0)
    ap.add_argument("--numerics", default="", help="more &numerics settings, e.g. \"kernel_correction = 'gradient'\"")
    ap.add_argument("--binary", type=Path, default=ROOT / "build" / "mbsph3d")
    a = ap.parse_args()
    out = a.out.resolve()
    work = out.parent
    work.mkdir(parents=True, exist_ok=True)
    c = np.array([0.1, a.centre, 0.05])
    r = a.radius
    tri = cube_triangles(2 * r) if a.shape == "cube" else sphere_triangles(r)
    write_binary_stl(work / f"{out.name}.stl", tri + c)
    case = work / f"{out.name}.nml"
    case.write_text(case_text(out, a.depth, a.t_end, a.numerics).replace("solid.stl", f"{out.name}.stl"))
    proc = subprocess.run([str(a.binary.resolve()), case.name], cwd=work, capture_output=True, text=True)
    if proc.returncode != 0:
        sys.exit(f"the run failed:\n{proc.stdout[-2000:]}\n{proc.stderr[-2000:]}")

    rgh = 1000.0 * 9.81 * a.depth
    h = DP * np.sqrt(2.0)
    near, bed, gap, vmax = [], [], np.inf, 0.0
    per_face: list[list[float]] = [[] for _ in range(6)]
    for path in sorted(out.glob("snap_*.h5")):
        with h5py.File(path, "r") as f:
            t = float(f.attrs["time"])
            kind, x, p, v = f["kind"][()], f["position"][()], f["pressure"][()], f["velocity"][()]
        fl = kind == 1
        x, p, v = x[fl], p[fl], v[fl]
        if a.shape == "cube":
            outside = np.linalg.norm(np.maximum(np.abs(x - c) - r, 0.0), axis=1)
            dist = np.where(outside > 0.0, outside, -np.min(r - np.abs(x - c), axis=1))
            rad = np.max(np.abs(x[:, [0, 2]] - c[[0, 2]]), axis=1)
        else:
            dist = np.linalg.norm(x - c, axis=1) - r
            rad = np.hypot(x[:, 0] - c[0], x[:, 2] - c[2])
        gap = min(gap, float(dist.min()))
        if t < 0.5 * a.t_end:
            continue
        vmax = max(vmax, float(np.linalg.norm(v, axis=1).max()))
        walls = np.min([x[:, 0], 0.2 - x[:, 0], x[:, 2], 0.1 - x[:, 2]], axis=0)
        far = (rad > r + 3 * DP) & (x[:, 1] < a.depth - 3 * DP) & (walls > 2 * DP)
        ref = np.polyval(np.polyfit(x[far, 1], p[far], 1), x[:, 1])
        m = (dist > 0.0) & (dist < 2 * h)
        near.append(float(np.mean(p[m] - ref[m])) / rgh)
        if a.shape == "cube":
            # each face's water: the axis along which it lies farthest out, and the side
            rel = x - c
            ax = np.argmax(np.abs(rel), axis=1)
            face = 2 * ax + (rel[np.arange(len(x)), ax] > 0.0)
            for q in range(6):
                per_face[q].append(float(np.mean((p - ref)[m & (face == q)])) / rgh)
        under = (x[:, 1] < DP) & (rad < r)
        if under.any():
            bed.append((float(np.mean(p[under])) - float(np.mean(p[(x[:, 1] < DP) & far]))) / rgh)
    print(f"{a.shape}, depth {a.depth} m, centre {a.centre} m above the floor, {len(near)} outputs from "
          f"{0.5 * a.t_end:g} s: near {np.mean(near):+.2%}, bed {np.mean(bed) if bed else float('nan'):+.2%} "
          f"of rho g depth; largest speed {vmax:.3f} m/s; least distance from the mesh {gap / DP:+.3f} dp")
    if a.shape == "cube":
        print("near each face (-x, +x, -y, +y, -z, +z): " + ", ".join(f"{np.mean(f):+.2%}" for f in per_face))


if __name__ == "__main__":
    main()
