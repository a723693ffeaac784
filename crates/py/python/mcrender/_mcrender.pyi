"""Type stubs of the native module (crates/py/src)."""

import os
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

_Path = Union[str, "os.PathLike[str]"]
_Image = npt.NDArray[np.float32]
_Progress = Union[bool, None, Callable[[int, int], Any]]

class SceneError(Exception):
    """A scene file could not be loaded; ``str(e)`` reads ``file:line:col: message``."""

    file: str
    line: Optional[int]
    column: Optional[int]
    kind: str
    message: str

class Film:
    """A render's per-pixel sums. Films of disjoint windows rendered with the same samples
    combine exactly (``combined``); films of consecutive sample ranges merge in order
    (``merged``, equal to one render up to rounding)."""

    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def samples(self) -> int: ...
    def merged(self, other: Film) -> Film: ...
    def combined(self, other: Film) -> Film: ...
    def image(self) -> _Image: ...
    def variance(self) -> _Image: ...
    def to_bytes(self) -> bytes: ...
    @staticmethod
    def from_bytes(data: bytes) -> Film: ...

class Scene:
    """A loaded scene; change its properties, then render."""

    @property
    def path(self) -> str: ...
    @property
    def warnings(self) -> List[str]: ...
    resolution: Tuple[int, int]
    spp: int
    seed: int
    max_depth: int
    integrator: str
    """"path", "direct", "bdpt", "lightpath", "sppm" or "mlt"."""
    reconstruction: str
    """"sample" (filter importance sampling, pbrt's) or "splat" (Mitsuba's filter splatting)."""
    mutations_per_pixel: int
    """MLT's length (the mlt integrator ignores spp)."""
    direct: str
    def render(
        self,
        spp: Optional[int] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        progress: _Progress = True,
    ) -> _Image: ...
    def render_with_variance(
        self,
        spp: Optional[int] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        progress: _Progress = True,
    ) -> Tuple[_Image, _Image]: ...
    def render_samples(
        self,
        start: int,
        end: int,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        progress: _Progress = True,
    ) -> _Image: ...
    def render_film(
        self,
        start: int = 0,
        end: Optional[int] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        progress: _Progress = False,
        window: Optional[Tuple[int, int, int, int]] = None,
    ) -> Film: ...

def load(path: _Path) -> Scene: ...
def read_image(path: _Path) -> _Image: ...
def write_image(path: _Path, array: _Image) -> None: ...
def compare(
    scene: Scene,
    techniques: Optional[List[str]] = None,
    spp: Optional[int] = None,
    reference: Union[None, str, _Image] = None,
    threads: Optional[int] = None,
    integrators: Optional[List[str]] = None,
    time_budget: Optional[float] = None,
) -> List[Dict[str, Any]]: ...
def pi(
    samples: Optional[List[int]] = None,
    seed: int = 1,
    trials: Optional[int] = None,
) -> Dict[str, Any]: ...
