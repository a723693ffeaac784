"""Rendering one scene across a Ray cluster.

``render(scene_path, spp, seed, address, chunks)`` cuts the image into bands of rows
(chunks), renders all samples of each band as a Ray task, and combines the bands' films
exactly, so the image is bit for bit the one a single-process ``Scene.render`` gives for the
same scene, seed and spp. Every sample depends on seed, pixel and sample index only; each
pixel's samples are accumulated in index order by the one task that renders it; and the
splats of light tracing and BDPT, which land on any pixel, are kept in exact fixed-point
sums that add in any order (``Film.combined``). Workers need no shared file system: the
scene file and every file it references (``Include``/``Import``, PLY and OBJ meshes, image
textures and environment maps: every quoted string in the scene files that names an
existing file) travel through Ray's object store once, and each worker writes them into a
temporary directory and loads the scene from there. A worker that dies mid-task is retried
by Ray (``max_retries``); a band's result depends only on the band, so the image stays the
same. SPPM (photon passes over the whole image) cannot be split this way and is refused.

From a shell::

    python -m mcrender.distributed SCENE.pbrt -o OUT.exr --address HOST:PORT [--spp N]
"""

from __future__ import annotations

import argparse
import gzip
import hashlib
import os
import sys
import tempfile
from pathlib import Path
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from . import Film, Scene, SceneError, load, write_image

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[bool, None, Callable[[int, int], Any]]

__all__ = ["render", "render_film", "scene_files", "main"]


def _quoted_strings(text: str, hash_comments: bool = True) -> List[str]:
    """The quoted strings of a scene file: a pbrt-v4 file's with comments (``#`` to the end
    of the line) left out, or (``hash_comments=False``) an XML file's attribute values."""
    out: List[str] = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "#" and hash_comments:
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif c == '"':
            j = text.find('"', i + 1)
            if j < 0:
                break
            out.append(text[i + 1 : j])
            i = j + 1
        else:
            i += 1
    return out


def _scene_text(data: bytes) -> str:
    if data[:2] == b"\x1f\x8b":
        data = gzip.decompress(data)
    return data.decode("utf-8", errors="replace")


def _is_scene_file(path: Path) -> bool:
    name = path.name.lower()
    return name.endswith((".pbrt", ".pbrt.gz", ".xml"))


def scene_files(scene_path: PathLike) -> Tuple[Dict[str, bytes], str]:
    """The scene file and every file it references, as ``({relative path: bytes}, relative
    path of the scene file)``, paths relative to the deepest directory holding them all.

    A quoted string is taken as a file reference when it names an existing file relative to
    the scene file's directory or to the directory of the file it appears in (the loader's
    rule); referenced ``.pbrt`` files are searched in turn."""
    main = Path(scene_path).resolve()
    search_dir = main.parent
    found: Dict[Path, bytes] = {}
    pending = [main]
    while pending:
        path = pending.pop()
        if path in found:
            continue
        data = path.read_bytes()
        found[path] = data
        if path != main and not _is_scene_file(path):
            continue
        xml = path.name.lower().endswith(".xml")
        for name in _quoted_strings(_scene_text(data), hash_comments=not xml):
            if not name or "\n" in name:
                continue
            for candidate in (search_dir / name, path.parent / name):
                try:
                    if candidate.is_file():
                        pending.append(candidate.resolve())
                        break
                except OSError:
                    pass
    root = Path(os.path.commonpath([str(p.parent) for p in found]))
    files = {str(p.relative_to(root)): data for p, data in found.items()}
    return files, str(main.relative_to(root))


# One loaded scene per worker process, keyed by the files' digest, so a worker rendering
# several chunks of one scene loads it once.
_cached: Dict[str, Scene] = {}


def _load_shipped(files: Dict[str, bytes], main: str, digest: str) -> Scene:
    scene = _cached.get(digest)
    if scene is not None:
        return scene
    with tempfile.TemporaryDirectory(prefix="mcrender-") as tmp:
        for rel, data in files.items():
            target = Path(tmp, rel)
            target.parent.mkdir(parents=True, exist_ok=True)
            target.write_bytes(data)
        scene = load(Path(tmp, main))
    _cached.clear()
    _cached[digest] = scene
    return scene


def _render_chunk(
    files: Dict[str, bytes],
    main: str,
    digest: str,
    settings: Dict[str, Any],
    window: Tuple[int, int, int, int],
    threads: int,
) -> Film:
    """A Ray task: render every sample of the pixels of ``window`` of the shipped scene."""
    scene = _load_shipped(files, main, digest)
    for name, value in settings.items():
        setattr(scene, name, value)
    return scene.render_film(threads=threads, progress=False, window=window)


def _bands(width: int, height: int, chunks: int) -> List[Tuple[int, int, int, int]]:
    """``chunks`` windows ``(x0, y0, x1, y1)`` of whole rows covering the image (fewer if
    the image has fewer rows)."""
    chunks = max(1, min(chunks, height))
    rows = [height * i // chunks for i in range(chunks + 1)]
    return [(0, a, width, b) for a, b in zip(rows, rows[1:]) if a < b]


def _report(progress: Progress, total: int):
    """A function(done) reporting chunk progress: tqdm when progress is True and tqdm is
    installed, a callback(done, total), or nothing. Returns it and a closer."""
    if callable(progress):
        return (lambda done: progress(done, total)), (lambda: None)
    if progress is True:
        try:
            from tqdm.auto import tqdm
        except ImportError:
            return (lambda done: None), (lambda: None)
        bar = tqdm(total=total, desc="mcrender (Ray)", unit=" chunks", leave=False)

        def update(done: int) -> None:
            bar.update(done - bar.n)

        return update, bar.close
    return (lambda done: None), (lambda: None)


def render_film(
    scene_path: PathLike,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    address: Optional[str] = None,
    chunks: Optional[int] = None,
    *,
    resolution: Optional[Tuple[int, int]] = None,
    max_depth: Optional[int] = None,
    threads_per_task: int = 1,
    max_retries: int = 3,
    progress: Progress = True,
) -> Film:
    """Render on Ray and return the merged :class:`mcrender.Film` (its ``image()`` and
    ``variance()``). See :func:`render` for the arguments."""
    import ray

    if spp is not None and spp < 1:
        raise ValueError(f"spp: expected at least 1, found {spp}")
    if chunks is not None and chunks < 1:
        raise ValueError(f"chunks: expected at least 1, found {chunks}")
    if threads_per_task < 1:
        raise ValueError(f"threads_per_task: expected at least 1, found {threads_per_task}")
    if max_retries < 0:
        raise ValueError(f"max_retries: expected at least 0, found {max_retries}")
    # Load here first: a malformed scene fails now, with its SceneError, not in a worker.
    local = load(scene_path)
    settings: Dict[str, Any] = {}
    if spp is not None:
        settings["spp"] = spp
    if seed is not None:
        settings["seed"] = seed
    if resolution is not None:
        settings["resolution"] = tuple(resolution)
    if max_depth is not None:
        settings["max_depth"] = max_depth
    for name, value in settings.items():
        setattr(local, name, value)
    if local.integrator == "sppm":
        raise ValueError(
            "sppm renders in photon passes over the whole image and cannot be split into bands: "
            "render it in one process (Scene.render)"
        )
    if local.integrator == "mlt":
        raise ValueError(
            "mlt renders Markov chains over the whole image and cannot be split into bands: "
            "render it in one process (Scene.render)"
        )
    width, height = local.resolution

    files, main = scene_files(scene_path)
    h = hashlib.sha256()
    for rel in sorted(files):
        h.update(rel.encode())
        h.update(hashlib.sha256(files[rel]).digest())
    digest = h.hexdigest()

    if not ray.is_initialized():
        ray.init(address=address, log_to_driver=False)
    if chunks is None:
        cpus = int(ray.cluster_resources().get("CPU", 1))
        chunks = max(1, 2 * cpus // threads_per_task)
    windows = _bands(width, height, chunks)

    task = ray.remote(_render_chunk).options(
        num_cpus=threads_per_task,
        max_retries=max_retries,
        retry_exceptions=False,
        name="mcrender_chunk",
    )
    files_ref = ray.put(files)
    refs = [task.remote(files_ref, main, digest, settings, w, threads_per_task) for w in windows]
    update, close = _report(progress, len(refs))
    try:
        pending = list(refs)
        while pending:
            ready, pending = ray.wait(pending, num_returns=1)
            update(len(refs) - len(pending))
        films = ray.get(refs)
    finally:
        close()
    film = films[0]
    for f in films[1:]:
        film = film.combined(f)
    return film


def render(
    scene_path: PathLike,
    spp: Optional[int] = None,
    seed: Optional[int] = None,
    address: Optional[str] = None,
    chunks: Optional[int] = None,
    **options: Any,
) -> np.ndarray:
    """Render ``scene_path`` on a Ray cluster; an (H, W, 3) float32 array of linear RGB,
    the same bits as ``mcrender.load(scene_path).render(spp=spp, seed=seed)``.

    ``address``: the cluster (``"HOST:PORT"``, ``"auto"``, or None for a local one started
    by ``ray.init``); ignored when Ray is already initialised in this process. ``chunks``:
    number of bands of rows (default: twice the cluster's CPUs; at most the image height).
    Keyword options: ``resolution``, ``max_depth`` (override the file's),
    ``threads_per_task`` (render threads and Ray CPUs per chunk, default 1),
    ``max_retries`` (retries of a chunk whose worker died, default 3), ``progress`` (True:
    a tqdm bar of finished chunks; a callable progress(done, total); False)."""
    return render_film(scene_path, spp, seed, address, chunks, **options).image()


def main(argv: Optional[List[str]] = None) -> int:
    """``python -m mcrender.distributed SCENE -o OUT.exr --address ADDR``."""
    p = argparse.ArgumentParser(
        prog="python -m mcrender.distributed",
        description="Render a scene on a Ray cluster (bit-identical to a single-process render).",
    )
    p.add_argument("scene", help="scene file (pbrt-v4 or Mitsuba 3 XML)")
    p.add_argument("-o", "--output", required=True, help="output image (.exr linear float, .png 8-bit sRGB)")
    p.add_argument("--address", default=None, help="Ray cluster address HOST:PORT (default: start a local one)")
    p.add_argument("--spp", type=int, default=None, help="samples per pixel (default: the file's)")
    p.add_argument("--seed", type=int, default=None, help="random seed (default: the file's)")
    p.add_argument("--chunks", type=int, default=None, help="number of bands of rows (default: 2 x CPUs)")
    p.add_argument("--threads-per-task", type=int, default=1, help="render threads per chunk (default 1)")
    p.add_argument("--variance-output", default=None, help="also write the per-pixel variance (EXR)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")
    args = p.parse_args(argv)
    try:
        film = render_film(
            args.scene,
            args.spp,
            args.seed,
            args.address,
            args.chunks,
            threads_per_task=args.threads_per_task,
            progress=not args.quiet,
        )
        write_image(args.output, film.image())
        if args.variance_output:
            write_image(args.variance_output, film.variance())
    except (SceneError, ValueError, OSError) as e:
        print(f"mcrender.distributed: error: {e}", file=sys.stderr)
        return 2
    print(f"{args.output}: {film.width}x{film.height}, {film.samples} spp", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
