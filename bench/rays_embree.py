"""Embree 4 (PyPI `embreex`) fed the same files as `mcrender bench-rays`: a binary PLY as
written by rays_gen.py and a RAYS.bin (float32 x 7 per ray). Prints one JSON line (build
seconds, best trace seconds, rays per second) and writes the hits in bench-rays' format
(t in units of the direction's length, +inf for a miss; any-hit: 0 or +inf).

embreex traces a batch in one call on one thread and holds Python's GIL while doing so, so
with --threads N the batch is cut into N parts traced by N forked processes, each with its
own copy of the scene (built before the clock starts), started together at a barrier; the
time is from the barrier to the last part finished (CLOCK_MONOTONIC is shared).

Usage: rays_embree.py MESH.ply RAYS.bin [--query closest|any] [--threads N] [--repeat K] [--hits OUT.bin]
"""
import argparse
import json
import multiprocessing as mp
import time

import numpy as np
from embreex import rtcore_scene, mesh_construction


def read_ply(path):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode().split("\n")
    nv = nf = 0
    for line in header:
        if line.startswith("element vertex"):
            nv = int(line.split()[2])
        if line.startswith("element face"):
            nf = int(line.split()[2])
    assert "format binary_little_endian 1.0" in header, "expects rays_gen.py's PLY layout"
    pos = np.frombuffer(data, "<f4", 3 * nv, end).reshape(nv, 3)
    face = np.frombuffer(data, [("n", "u1"), ("v", "<i4", 3)], nf, end + 12 * nv)
    assert (face["n"] == 3).all()
    return np.ascontiguousarray(pos), np.ascontiguousarray(face["v"])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("mesh")
    ap.add_argument("rays")
    ap.add_argument("--query", default="closest", choices=["closest", "any"])
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--repeat", type=int, default=1)
    ap.add_argument("--hits")
    a = ap.parse_args()
    pos, tris = read_ply(a.mesh)
    rays = np.fromfile(a.rays, "<f4").reshape(-1, 7)
    o = np.ascontiguousarray(rays[:, :3])
    d = np.ascontiguousarray(rays[:, 3:6])
    t_max = np.ascontiguousarray(rays[:, 6])

    def build():
        scene = rtcore_scene.EmbreeScene()
        mesh_construction.TriangleMesh(scene, pos, tris)
        # The scene is committed (the BVH built) by the first query.
        scene.run(o[:1], d[:1], dists=t_max[:1].copy())
        return scene

    start = time.perf_counter()
    scene = build()
    build_s = time.perf_counter() - start

    query = "DISTANCE" if a.query == "closest" else "OCCLUDED"
    bounds = np.linspace(0, len(o), a.threads + 1).astype(int)

    def trace(scene, k):
        lo, hi = bounds[k], bounds[k + 1]
        return np.asarray(scene.run(o[lo:hi], d[lo:hi], dists=t_max[lo:hi].copy(), query=query))

    best = float("inf")
    if a.threads == 1:
        for _ in range(a.repeat):
            start = time.perf_counter()
            res = trace(scene, 0)
            best = min(best, time.perf_counter() - start)
    else:
        ctx = mp.get_context("fork")
        barrier = ctx.Barrier(a.threads)
        queue = ctx.Queue()

        def child(k):
            sc = build()
            times = []
            for _ in range(a.repeat):
                barrier.wait()
                t0 = time.perf_counter()
                r = trace(sc, k)
                times.append((t0, time.perf_counter()))
            queue.put((k, times, r))

        procs = [ctx.Process(target=child, args=(k,)) for k in range(a.threads)]
        for p in procs:
            p.start()
        got = sorted(queue.get() for _ in procs)
        for p in procs:
            p.join()
        for rep in range(a.repeat):
            t0 = min(g[1][rep][0] for g in got)
            t1 = max(g[1][rep][1] for g in got)
            best = min(best, t1 - t0)
        res = np.concatenate([g[2] for g in got])
    if a.query == "closest":
        # DISTANCE returns tfar, left at t_max for a miss.
        hits = np.where(res < t_max, res, np.inf).astype("<f4")
    else:
        # OCCLUDED returns -1 for a free ray.
        blocked = res != -1
        hits = np.where(blocked, 0.0, np.inf).astype("<f4")
    if a.hits:
        hits.tofile(a.hits)
    print(json.dumps({
        "build_s": build_s, "triangles": len(tris), "trace_s": best, "rays": len(o),
        "m_rays_per_s": len(o) / best / 1e6, "hit": int(np.isfinite(hits).sum()), "threads": a.threads,
    }))


if __name__ == "__main__":
    main()
