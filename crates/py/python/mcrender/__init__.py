"""mcrender: a physically based Monte Carlo path tracer, from Python.

Load a pbrt-v4 scene, change its settings, render it to a numpy array::

    import mcrender
    scene = mcrender.load("scenes/occluder/occluder.pbrt")
    scene.spp = 64
    image = scene.render()                  # (H, W, 3) float32, linear RGB
    image, variance = scene.render_with_variance()
    mcrender.write_image("out.exr", image)

The image is bit for bit the one ``mcrender render`` writes for the same scene, seed and
samples per pixel. Rendering releases the GIL; Ctrl-C (KeyboardInterrupt) stops it within
a fraction of a second. ``mcrender.compare`` and ``mcrender.pi`` are the estimator lab;
``mcrender.distributed`` renders across a Ray cluster.
"""

from __future__ import annotations

import os
from typing import Any, Dict, List, Optional, Sequence, Union

import numpy as np

from ._mcrender import Film, Scene, SceneError, load, pi, read_image
from ._mcrender import compare as _compare
from ._mcrender import write_image as _write_image

__all__ = [
    "Film",
    "Scene",
    "SceneError",
    "compare",
    "load",
    "pi",
    "read_image",
    "write_image",
]

PathLike = Union[str, "os.PathLike[str]"]


def _image_array(array: Any, what: str) -> np.ndarray:
    a = np.ascontiguousarray(array, dtype=np.float32)
    if a.ndim != 3 or a.shape[2] != 3 or a.shape[0] == 0 or a.shape[1] == 0:
        raise ValueError(f"{what}: expected an array of shape (H, W, 3), found {a.shape}")
    return a


def write_image(path: PathLike, array: Any) -> None:
    """Write an (H, W, 3) array of linear RGB: ``.exr`` as 32-bit float, ``.png`` as 8-bit
    sRGB (clamped). The file appears complete or not at all."""
    _write_image(os.fspath(path), _image_array(array, "write_image"))


def compare(
    scene: Scene,
    techniques: Optional[Sequence[str]] = None,
    spp: Optional[int] = None,
    reference: Union[None, PathLike, np.ndarray] = None,
    threads: Optional[int] = None,
    integrators: Optional[Sequence[str]] = None,
    time_budget: Optional[float] = None,
) -> List[Dict[str, Any]]:
    """Compare direct-lighting techniques on ``scene`` (default: uniform-hemisphere,
    cosine-hemisphere, light-area, bsdf, mis), each at ``spp`` samples per pixel (default:
    the scene's). One dict per technique with the figures of ``mcrender compare --json``:
    technique, spp, mean_radiance, mean_luminance, variance, rel_mse (None without a
    reference), time_s, rays, efficiency (1 / (variance x time)), relative_efficiency; and
    ``image`` (the render) and ``convergence`` ([(spp, error), ...] after waves of 1, 2, 4,
    ... spp; the error is the relative MSE against the reference, else the mean variance).
    ``reference`` is an EXR path or an (H, W, 3) array.

    With ``integrators`` (e.g. ``["path", "bdpt", "sppm"]``), compares integrators as
    ``mcrender compare --integrators`` does, at ``spp`` each or at equal time with
    ``time_budget`` seconds each; the dicts have the keys of its JSON rows plus
    ``reference`` ("given" or the long render used), ``image`` and ``convergence``
    ([(seconds, rel. MSE), ...])."""
    if reference is not None and not isinstance(reference, (str, os.PathLike)):
        reference = _image_array(reference, "reference")
    elif reference is not None:
        reference = os.fspath(reference)
    return _compare(
        scene,
        list(techniques) if techniques is not None else None,
        spp,
        reference,
        threads,
        list(integrators) if integrators is not None else None,
        time_budget,
    )
