"""Fixtures of the mcrender Python tests: the repository, the CLI binary (built when
missing) and a small scene spread over several files (an Include and a PLY mesh), so the
distributed tests also check that every referenced file reaches the workers."""

from __future__ import annotations

import os
import signal
import subprocess
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[3]

MAIN = """# Test scene: the estimator lab's occluder, spread over three files.
LookAt 2.5 2.2 4.0   0.1 0.2 0   0 1 0
Camera "perspective" "float fov" [ 45 ]
Film "rgb" "integer xresolution" [ 64 ] "integer yresolution" [ 48 ]
Sampler "independent" "integer pixelsamples" [ 8 ]
PixelFilter "box"
Integrator "path" "integer maxdepth" [ 3 ] "string direct" [ "mis" ]
WorldBegin
Include "parts/world.pbrt"
"""

WORLD = """# Ground and light; the occluder is a PLY mesh.
Material "diffuse" "rgb reflectance" [ 0.6 0.6 0.6 ]
Shape "trianglemesh"
    "point3 P" [ -5 0 -5   5 0 -5   5 0 5   -5 0 5 ]
    "integer indices" [ 0 2 1  0 3 2 ]
Material "diffuse" "rgb reflectance" [ 0.3 0.3 0.6 ]
Shape "plymesh" "string filename" [ "meshes/occluder.ply" ]
AttributeBegin
    AreaLightSource "diffuse" "rgb L" [ 8 8 8 ]
    Material "diffuse" "rgb reflectance" [ 0 0 0 ]
    Shape "trianglemesh"
        "point3 P" [ -0.5 2.5 -0.5   0.5 2.5 -0.5   0.5 2.5 0.5   -0.5 2.5 0.5 ]
        "integer indices" [ 0 1 2  0 2 3 ]
AttributeEnd
"""

PLY = """ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
end_header
-0.3 1 -0.5
0.7 1 -0.5
0.7 1 0.5
-0.3 1 0.5
3 0 1 2
3 0 2 3
"""


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


@pytest.fixture(scope="session")
def cli() -> Path:
    """The `mcrender` binary: $MCRENDER_BIN, else target/release/mcrender (built if absent)."""
    env = os.environ.get("MCRENDER_BIN")
    if env:
        return Path(env)
    binary = REPO / "target" / "release" / "mcrender"
    if not binary.exists():
        subprocess.run(["cargo", "build", "--release", "-p", "mcrender"], cwd=REPO, check=True)
    return binary


@pytest.fixture(scope="session")
def scene_path(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("scene")
    (root / "parts").mkdir()
    (root / "meshes").mkdir()
    (root / "main.pbrt").write_text(MAIN)
    (root / "parts" / "world.pbrt").write_text(WORLD)
    (root / "meshes" / "occluder.ply").write_text(PLY)
    return root / "main.pbrt"


@pytest.fixture
def sigint_raises():
    """SIGINT raises KeyboardInterrupt during the test, however pytest was started: a shell
    running a job in the background (`cmd &` without job control) starts it with SIGINT
    ignored, and Python then installs no handler of its own."""
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    yield
    signal.signal(signal.SIGINT, previous)
