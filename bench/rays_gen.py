"""Inputs for bench/rays.sh: a bumpy sphere of N triangles (binary PLY) and three ray sets
in the `mcrender bench-rays` format (little-endian float32, 7 per ray: origin, direction,
t_max).

- camera: a pinhole camera's primary rays, one per pixel of a square image (coherent);
- incoherent: random origins inside the mesh's bounds, random directions;
- shadow: from random points just off the surface towards a point light, t_max 1 (the
  direction is the light minus the origin, so t_max = 1 stops at the light).

Usage: rays_gen.py OUT_DIR [--triangles N] [--rays M] [--seed S]
"""
import argparse
import os

import numpy as np


def bumpy_sphere(n_triangles):
    """A UV sphere of about n_triangles triangles with a bumpy radius."""
    # rings x segments grid, 2 triangles per cell, segments = 2 rings.
    rings = max(4, int(round(np.sqrt(n_triangles / 4))))
    segs = 2 * rings
    theta = np.linspace(0, np.pi, rings + 1)
    phi = np.linspace(0, 2 * np.pi, segs + 1)
    th, ph = np.meshgrid(theta, phi, indexing="ij")
    r = 1.0 + 0.04 * np.sin(13 * th) * np.cos(17 * ph) + 0.02 * np.sin(41 * ph + 3 * th)
    pos = np.stack([r * np.sin(th) * np.cos(ph), r * np.cos(th), r * np.sin(th) * np.sin(ph)], -1)
    pos = pos.reshape(-1, 3).astype(np.float32)
    idx = np.arange((rings + 1) * (segs + 1)).reshape(rings + 1, segs + 1)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, :-1].ravel(), idx[1:, 1:].ravel()
    tris = np.concatenate([np.stack([a, c, b], -1), np.stack([b, c, d], -1)]).astype(np.int32)
    return pos, tris


def write_ply(path, pos, tris):
    header = (
        "ply\nformat binary_little_endian 1.0\n"
        f"element vertex {len(pos)}\nproperty float x\nproperty float y\nproperty float z\n"
        f"element face {len(tris)}\nproperty list uchar int vertex_indices\nend_header\n"
    )
    face = np.zeros(len(tris), dtype=[("n", "u1"), ("v", "<i4", 3)])
    face["n"] = 3
    face["v"] = tris
    with open(path, "wb") as f:
        f.write(header.encode())
        f.write(pos.astype("<f4").tobytes())
        f.write(face.tobytes())


def write_rays(path, o, d, t_max):
    rays = np.concatenate([o, d, t_max[:, None]], 1).astype("<f4")
    rays.tofile(path)


def unit(v):
    return v / np.linalg.norm(v, axis=1, keepdims=True)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("out")
    ap.add_argument("--triangles", type=int, default=1_000_000)
    ap.add_argument("--rays", type=int, default=1_000_000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    os.makedirs(a.out, exist_ok=True)
    rng = np.random.default_rng(a.seed)
    pos, tris = bumpy_sphere(a.triangles)
    write_ply(os.path.join(a.out, "mesh.ply"), pos, tris)
    lo, hi = pos.min(0), pos.max(0)

    # Camera: square image looking at the sphere from outside, 40 degree field of view.
    side = int(np.sqrt(a.rays))
    eye = np.array([0.6, 0.8, 3.2], np.float32)
    fwd = unit(-eye[None])[0]
    right = unit(np.cross(fwd, [0, 1, 0])[None])[0]
    up = np.cross(right, fwd)
    s = np.tan(np.radians(20))
    u = (np.arange(side) + 0.5) / side * 2 - 1
    uu, vv = np.meshgrid(u, -u)
    d = fwd + s * (uu.ravel()[:, None] * right + vv.ravel()[:, None] * up)
    o = np.broadcast_to(eye, d.shape)
    write_rays(os.path.join(a.out, "camera.bin"), o, d, np.full(len(d), np.inf, np.float32))

    # Incoherent: uniform origins in the bounds, uniform directions.
    n = a.rays
    o = lo + rng.random((n, 3)) * (hi - lo)
    d = unit(rng.normal(size=(n, 3)))
    write_rays(os.path.join(a.out, "incoherent.bin"), o, d, np.full(n, np.inf, np.float32))

    # Shadow: points on random triangles, pushed 1e-3 along the face normal, to a light.
    # Only triangles of non-zero area (the poles of the UV grid have degenerate ones).
    cross = np.cross(pos[tris[:, 1]] - pos[tris[:, 0]], pos[tris[:, 2]] - pos[tris[:, 0]])
    good = np.flatnonzero(np.linalg.norm(cross, axis=1) > 0)
    t = good[rng.integers(0, len(good), n)]
    b = rng.random((n, 2))
    flip = b.sum(1) > 1
    b[flip] = 1 - b[flip]
    p0, p1, p2 = pos[tris[t, 0]], pos[tris[t, 1]], pos[tris[t, 2]]
    p = p0 + b[:, :1] * (p1 - p0) + b[:, 1:] * (p2 - p0)
    nrm = unit(np.cross(p1 - p0, p2 - p0))
    nrm *= np.sign((nrm * p).sum(1, keepdims=True))  # outward
    o = p + 1e-3 * nrm
    light = np.array([2.0, 2.5, 1.5])
    write_rays(os.path.join(a.out, "shadow.bin"), o, light - o, np.ones(n, np.float32))
    print(f"{len(tris)} triangles, {side * side} camera rays, {n} incoherent rays, {n} shadow rays in {a.out}")


if __name__ == "__main__":
    main()
