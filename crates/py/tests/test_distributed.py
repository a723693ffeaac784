"""mcrender.distributed on a local Ray cluster that the test starts (`ray start --head` on
127.0.0.1, 2 CPUs, no dashboard) and stops: the distributed image is bit-identical to the
single-process one, also when a worker process is killed during the render."""

from __future__ import annotations

import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mcrender

ray = pytest.importorskip("ray")
import mcrender.distributed as dist  # noqa: E402


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture(scope="module")
def cluster():
    """A Ray head node on loopback with 2 worker CPUs; yields its address."""
    port = free_port()
    temp = tempfile.mkdtemp(prefix="rmc")
    ray_bin = Path(sys.executable).with_name("ray")
    head = subprocess.Popen(
        [str(ray_bin), "start", "--head", "--block", "--node-ip-address=127.0.0.1", f"--port={port}",
         "--num-cpus=2", "--include-dashboard=false", "--disable-usage-stats", f"--temp-dir={temp}"],
        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )
    address = f"127.0.0.1:{port}"
    try:
        deadline = time.monotonic() + 120
        while True:
            try:
                ray.init(address=address, log_to_driver=False)
                break
            except Exception:
                if head.poll() is not None or time.monotonic() > deadline:
                    raise
                time.sleep(1)
        yield address
    finally:
        ray.shutdown()
        # Stop the head we started: SIGINT makes `ray start --block` stop the processes it
        # spawned (a few seconds); whatever is left of its process group is then killed.
        try:
            head.send_signal(signal.SIGINT)
            head.wait(timeout=30)
        except subprocess.TimeoutExpired:
            pass
        try:
            os.killpg(head.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
        head.wait()
        shutil.rmtree(temp, ignore_errors=True)


def test_scene_files_ship_the_include_and_the_mesh(scene_path):
    files, main = dist.scene_files(scene_path)
    assert main == "main.pbrt"
    assert set(files) == {"main.pbrt", os.path.join("parts", "world.pbrt"), os.path.join("meshes", "occluder.ply")}


def test_distributed_render_is_bit_identical(cluster, scene_path, tmp_path):
    local = mcrender.load(scene_path).render(spp=16, seed=5, progress=False)
    image = dist.render(scene_path, spp=16, seed=5, chunks=5, progress=False)
    assert image.dtype == np.float32 and image.shape == local.shape
    assert image.tobytes() == local.tobytes()
    # The command line writes the same image.
    out = tmp_path / "dist.exr"
    subprocess.run([sys.executable, "-m", "mcrender.distributed", str(scene_path), "-o", str(out),
                    "--address", cluster, "--spp", "16", "--seed", "5", "--chunks", "3", "-q"], check=True)
    assert mcrender.read_image(out).tobytes() == local.tobytes()


def test_distributed_bdpt_with_splats_is_bit_identical(cluster, scene_path):
    """BDPT splats land on pixels of other bands: the exact splat sums keep the bits."""
    scene = mcrender.load(scene_path)
    scene.integrator = "bdpt"
    local = scene.render(spp=4, seed=2, progress=False)
    scene.seed = 2
    # The same settings through distributed: the file says "path", so write one saying bdpt.
    text = Path(scene_path).read_text().replace('Integrator "path"', 'Integrator "bdpt"')
    bdpt_path = Path(scene_path).with_name("main-bdpt.pbrt")
    bdpt_path.write_text(text)
    try:
        image = dist.render(bdpt_path, spp=4, seed=2, chunks=3, progress=False)
    finally:
        bdpt_path.unlink()
    assert image.tobytes() == local.tobytes()


@pytest.mark.parametrize("integrator", ["sppm", "mlt"])
def test_distributed_whole_image_integrators_are_refused(cluster, scene_path, integrator):
    text = Path(scene_path).read_text().replace('Integrator "path"', f'Integrator "{integrator}"')
    path = Path(scene_path).with_name(f"main-{integrator}.pbrt")
    path.write_text(text)
    try:
        with pytest.raises(ValueError, match=integrator):
            dist.render(path, progress=False)
    finally:
        path.unlink()


def chunk_workers() -> list[int]:
    """Pids of the Ray worker processes running a chunk now (Ray titles them ray::NAME)."""
    ps = subprocess.run(["ps", "-eo", "pid=,args="], capture_output=True, text=True, check=True)
    return [int(line.split(None, 1)[0]) for line in ps.stdout.splitlines()
            if "ray::mcrender_chunk" in line and "ps -eo" not in line]


def test_a_killed_worker_is_retried_and_the_image_is_unchanged(cluster, scene_path):
    # Chunks of about a second each on one core, so that the killer below sees one running
    # and kills it in its middle (at 96x72 and 96 spp a chunk took 0.1 s, and once the
    # whole render ended before `ps` ever showed a chunk).
    settings = dict(spp=256, seed=11, resolution=(192, 144))
    scene = mcrender.load(scene_path)
    scene.resolution = settings["resolution"]
    local = scene.render(spp=settings["spp"], seed=settings["seed"], progress=False)

    killed: list[int] = []
    stop = threading.Event()

    def killer():
        while not stop.is_set() and not killed:
            pids = chunk_workers()
            if pids:
                time.sleep(0.3)  # let it get well into its chunk
                # Only a worker still running its chunk counts: killing an idle one would
                # test no retry.
                if pids[0] in chunk_workers():
                    os.kill(pids[0], signal.SIGKILL)
                    killed.append(pids[0])
            time.sleep(0.05)

    thread = threading.Thread(target=killer)
    thread.start()
    finished = []
    try:
        image = dist.render(scene_path, chunks=4, max_retries=3,
                            progress=lambda done, total: finished.append((done, total)), **settings)
    finally:
        stop.set()
        thread.join()
    assert killed, "no worker was killed while running a chunk"
    assert finished[-1] == (4, 4)
    assert image.tobytes() == local.tobytes()
