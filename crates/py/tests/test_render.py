"""mcrender from Python: the same bits as the CLI, arrays of the right shape, variance that
measures the noise, sample ranges that merge, errors as exceptions, Ctrl-C, the lab."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mcrender


def run_cli(cli: Path, *args: object) -> subprocess.CompletedProcess:
    return subprocess.run([str(cli), *map(str, args)], check=True, capture_output=True, text=True)


def test_render_equals_the_cli_exr_bit_for_bit(cli, scene_path, tmp_path):
    out, var = tmp_path / "cli.exr", tmp_path / "cli-var.exr"
    run_cli(cli, "render", scene_path, "--spp", 8, "--seed", 3, "-o", out, "--variance-output", var, "-q")
    scene = mcrender.load(scene_path)
    image, variance = scene.render_with_variance(spp=8, seed=3, progress=False)
    assert image.tobytes() == mcrender.read_image(out).tobytes()
    assert variance.tobytes() == mcrender.read_image(var).tobytes()
    assert scene.render(spp=8, seed=3, threads=1, progress=False).tobytes() == image.tobytes()


def test_cornell_box_sobol_sampler_equals_the_cli(cli, repo, tmp_path):
    path = repo / "scenes" / "cornell-box" / "scene-v4.pbrt"
    out = tmp_path / "cbox.exr"
    run_cli(cli, "render", path, "--spp", 4, "--resolution", "40x30", "--max-depth", 4, "-o", out, "-q")
    scene = mcrender.load(path)
    scene.resolution = (40, 30)
    scene.max_depth = 4
    assert scene.render(spp=4, progress=False).tobytes() == mcrender.read_image(out).tobytes()


def test_shape_dtype_and_properties(scene_path):
    scene = mcrender.load(scene_path)
    assert (scene.resolution, scene.spp, scene.integrator, scene.max_depth) == ((64, 48), 8, "path", 3)
    scene.resolution = (20, 10)
    scene.spp = 2
    scene.seed = 7
    scene.integrator = "direct"
    scene.direct = "light-area"
    image = scene.render(progress=False)
    assert image.shape == (10, 20, 3)
    assert image.dtype == np.float32
    assert image.flags["C_CONTIGUOUS"]
    assert np.isfinite(image).all() and image.mean() > 0
    assert (scene.seed, scene.integrator, scene.direct) == (7, "direct", "light-area")


def test_variance_predicts_the_spread_over_seeds(scene_path):
    # Independent sampler: the per-pixel variance estimate is unbiased for the variance of
    # the pixel's estimate, so its average must match the spread over independent seeds.
    scene = mcrender.load(scene_path)
    scene.resolution = (32, 24)
    renders, predicted = [], []
    for seed in range(24):
        image, variance = scene.render_with_variance(spp=4, seed=seed, progress=False)
        renders.append(image.astype(np.float64))
        predicted.append(variance.astype(np.float64))
    measured = np.stack(renders).var(axis=0, ddof=1).mean()
    expected = np.stack(predicted).mean()
    assert expected > 0
    assert 0.8 < measured / expected < 1.25, (measured, expected)


def test_sample_ranges_merge_into_the_full_render(scene_path):
    scene = mcrender.load(scene_path)
    full = scene.render(spp=8, seed=1, progress=False)
    scene.seed = 1
    merged = scene.render_film(0, 3).merged(scene.render_film(3, 8))
    assert merged.samples == 8
    assert merged.image().tobytes() == full.tobytes()
    assert scene.render_samples(0, 8, progress=False).tobytes() == full.tobytes()
    late = scene.render_samples(3, 8, progress=False)
    assert late.shape == full.shape and not np.array_equal(late, full)
    import pickle

    assert pickle.loads(pickle.dumps(merged)) == merged


def test_malformed_scene_raises_scene_error_with_line_and_column(tmp_path):
    bad = tmp_path / "bad.pbrt"
    bad.write_text('WorldBegin\n# a comment\nShape "sphere" "float radius" [ abc ]\n')
    with pytest.raises(mcrender.SceneError) as info:
        mcrender.load(bad)
    e = info.value
    assert e.file == str(bad)
    assert e.line == 3
    assert e.column == 33  # the "a" of abc
    assert str(e).startswith(f"{bad}:3:33: ")
    with pytest.raises(mcrender.SceneError) as info:
        mcrender.load(tmp_path / "missing.pbrt")
    assert info.value.kind == "io" and info.value.line is None


def test_bad_arguments_raise_value_error(scene_path, tmp_path):
    scene = mcrender.load(scene_path)
    with pytest.raises(ValueError):
        scene.spp = 0
    with pytest.raises(ValueError):
        scene.integrator = "bidirectional"
    with pytest.raises(ValueError):
        scene.direct = "guess"
    with pytest.raises(ValueError):
        scene.resolution = (0, 10)
    with pytest.raises(ValueError):
        scene.render_samples(5, 2, progress=False)
    with pytest.raises(ValueError):
        scene.render(threads=0, progress=False)
    with pytest.raises(TypeError):
        scene.render(progress="yes please")
    scene.resolution = (100_000, 100_000)
    with pytest.raises(ValueError):
        scene.render(progress=False)
    with pytest.raises(ValueError):
        mcrender.write_image(tmp_path / "x.exr", np.zeros((4, 4)))
    with pytest.raises(ValueError):
        mcrender.write_image(tmp_path / "x.bmp", np.zeros((4, 4, 3)))
    with pytest.raises(ValueError):
        mcrender.compare(mcrender.load(scene_path), ["nope"])
    with pytest.raises(ValueError):
        mcrender.pi([10], trials=1)


def test_keyboard_interrupt_cancels_the_render(scene_path, sigint_raises):
    scene = mcrender.load(scene_path)
    scene.resolution = (32, 24)
    calls = []
    rendering = threading.Event()

    def progress(done, total):
        calls.append((done, total))
        if done > 0:
            rendering.set()

    # The interrupt comes 0.3 s after the render has reported progress (not after a fixed
    # time from the start: on a loaded machine the render may not have begun by then).
    def interrupt():
        if rendering.wait(60):
            time.sleep(0.3)
            os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Thread(target=interrupt, daemon=True)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        # About a minute of work on an idle core: only the interrupt ends it early.
        scene.render(spp=200_000, threads=1, progress=progress)
    assert rendering.is_set()
    assert time.monotonic() - start < 20
    assert calls and all(total == 32 * 24 * 200_000 for _, total in calls)
    assert [d for d, _ in calls] == sorted(d for d, _ in calls)
    # The module still works afterwards.
    assert scene.render(spp=1, progress=False).shape == (24, 32, 3)


@pytest.mark.parametrize(
    "how",
    [
        {"techniques": ["uniform-hemisphere", "mis"], "spp": 200_000},
        {"integrators": ["path", "bdpt"], "spp": 200_000},
        {"integrators": ["sppm"], "spp": 1_000_000},
        {"integrators": ["mlt"], "time_budget": 600.0},
    ],
    ids=["techniques", "path-bdpt", "sppm", "mlt"],
)
def test_keyboard_interrupt_cancels_a_comparison(scene_path, how, sigint_raises):
    """Each of these would run for minutes: only the interrupt ends it early."""
    scene = mcrender.load(scene_path)
    scene.resolution = (32, 24)
    reference = np.zeros((24, 32, 3), dtype=np.float32) + 0.1
    timer = threading.Timer(1.0, os.kill, (os.getpid(), signal.SIGINT))
    start = time.monotonic()
    timer.start()
    try:
        with pytest.raises(KeyboardInterrupt):
            mcrender.compare(scene, reference=reference, threads=1, **how)
    finally:
        timer.cancel()
    assert time.monotonic() - start < 10
    assert mcrender.compare(scene, ["mis"], spp=1, threads=1)[0]["spp"] == 1


def test_the_gil_is_released_while_rendering(scene_path):
    scene = mcrender.load(scene_path)
    result = {}
    worker = threading.Thread(target=lambda: result.setdefault("image", scene.render(spp=64, threads=1, progress=False)))
    ticks = 0
    worker.start()
    while worker.is_alive():
        ticks += 1
        time.sleep(0.001)
    worker.join()
    assert result["image"].shape == (48, 64, 3)
    assert ticks > 20


def test_progress_bar_and_callback(scene_path):
    pytest.importorskip("tqdm")
    scene = mcrender.load(scene_path)
    assert scene.render(spp=2, progress=True).shape == (48, 64, 3)
    seen = []
    scene.render(spp=2, progress=lambda d, t: seen.append((d, t)))
    assert seen[-1] == (64 * 48 * 2, 64 * 48 * 2)


def test_a_failing_progress_callback_stops_the_render(scene_path):
    scene = mcrender.load(scene_path)

    def fail(done, total):
        raise RuntimeError("stop here")

    with pytest.raises(RuntimeError, match="stop here"):
        scene.render(spp=64, progress=fail)


def test_images_round_trip(tmp_path):
    rng = np.random.default_rng(1)
    image = rng.random((5, 7, 3), dtype=np.float32)
    mcrender.write_image(tmp_path / "a.exr", image)
    assert mcrender.read_image(tmp_path / "a.exr").tobytes() == image.tobytes()
    mcrender.write_image(tmp_path / "a.png", image.astype(np.float64))
    png = mcrender.read_image(tmp_path / "a.png")
    assert png.shape == (5, 7, 3) and np.abs(png - image).max() < 0.01
    with pytest.raises(OSError):
        mcrender.read_image(tmp_path / "missing.exr")


def test_compare_has_the_figures_of_the_cli_json(cli, repo, tmp_path):
    path = repo / "scenes" / "occluder" / "occluder.pbrt"
    techniques = ["cosine-hemisphere", "light-area", "mis"]
    done = run_cli(cli, "compare", path, "--spp", 4, "--resolution", "40x30",
                   "--techniques", ",".join(techniques), "--json", "-o", tmp_path / "cmp")
    cli_rows = json.loads(done.stdout)["techniques"]
    scene = mcrender.load(path)
    scene.resolution = (40, 30)
    reference = scene.render(spp=16, seed=99, progress=False)
    rows = mcrender.compare(scene, techniques, spp=4)
    assert [r["technique"] for r in rows] == techniques
    for mine, theirs in zip(rows, cli_rows):
        assert set(theirs) <= set(mine)
        # Figures that do not depend on the clock are identical.
        for key in ("technique", "spp", "rays", "variance", "rel_mse"):
            assert mine[key] == theirs[key], key
        assert np.float32(mine["mean_luminance"]) == np.float32(theirs["mean_luminance"])
        assert np.allclose(mine["mean_radiance"], theirs["mean_radiance"], rtol=1e-6)
        assert mine["image"].shape == (30, 40, 3)
        assert [n for n, _ in mine["convergence"]] == [1, 2, 4]
    # Light sampling beats cosine-weighted hemisphere sampling on the occluder.
    assert rows[1]["variance"] < rows[0]["variance"]
    with_ref = mcrender.compare(scene, ["mis"], spp=4, reference=reference)
    assert with_ref[0]["rel_mse"] > 0


def test_pi_equals_the_cli_json(cli):
    done = run_cli(cli, "pi", "--samples", "10,1000", "--trials", 20, "--seed", 4, "--json")
    assert mcrender.pi([10, 1000], seed=4, trials=20) == json.loads(done.stdout)


def test_light_tracing_and_sppm_equal_the_cli(cli, scene_path, tmp_path):
    out = tmp_path / "lightpath.exr"
    run_cli(cli, "render", scene_path, "--integrator", "lightpath", "--spp", 2, "--resolution", "32x24", "-o", out, "-q")
    scene = mcrender.load(scene_path)
    scene.integrator = "lightpath"
    scene.resolution = (32, 24)
    assert scene.render(spp=2, progress=False).tobytes() == mcrender.read_image(out).tobytes()
    # SPPM runs its own driver (iterations of camera and photon passes).
    out = tmp_path / "sppm.exr"
    run_cli(cli, "render", scene_path, "--integrator", "sppm", "--resolution", "32x24", "-o", out, "-q")
    scene.integrator = "sppm"
    assert scene.integrator == "sppm"
    calls = []
    image = scene.render(progress=lambda done, total: calls.append((done, total)))
    assert image.tobytes() == mcrender.read_image(out).tobytes()
    assert calls and calls[-1][0] == calls[-1][1]
    assert float(image.mean()) > 0
    with pytest.raises(ValueError, match="sppm"):
        scene.render_film(0, 1)
    with pytest.raises(ValueError, match="sppm"):
        scene.render_film(window=(0, 0, 8, 8))
    with pytest.raises(ValueError):
        scene.integrator = "photon"


def test_mlt_equals_the_cli(cli, scene_path, tmp_path):
    """MLT runs its own driver (bootstrap, then Markov chains); its length is the
    mutations per pixel, so `spp=` is refused for it, as are sample ranges and windows."""
    mlt_path = Path(scene_path).with_name("main-mlt.pbrt")
    mlt_path.write_text(
        Path(scene_path).read_text().replace(
            'Integrator "path"',
            'Integrator "mlt" "integer mutationsperpixel" [ 3 ] "integer bootstrapsamples" [ 2000 ] '
            '"integer chains" [ 40 ]',
        )
    )
    try:
        out = tmp_path / "mlt.exr"
        run_cli(cli, "render", mlt_path, "--resolution", "32x24", "--seed", 5, "-o", out, "-q")
        scene = mcrender.load(mlt_path)
    finally:
        mlt_path.unlink()
    assert scene.integrator == "mlt" and scene.mutations_per_pixel == 3
    scene.resolution = (32, 24)
    calls = []
    image = scene.render(seed=5, threads=2, progress=lambda done, total: calls.append((done, total)))
    assert image.tobytes() == mcrender.read_image(out).tobytes()
    assert calls and calls[-1][0] == calls[-1][1] == 3 * 32 * 24
    assert float(image.mean()) > 0
    # More mutations: a different (still positive) estimate of the same image.
    scene.mutations_per_pixel = 6
    longer = scene.render(seed=5, progress=False)
    assert longer.tobytes() != image.tobytes()
    assert abs(float(longer.mean()) / float(image.mean()) - 1) < 0.5
    with pytest.raises(ValueError, match="mutations per pixel"):
        scene.render(spp=4, progress=False)
    with pytest.raises(ValueError, match="mlt"):
        scene.render_film(0, 1)
    with pytest.raises(ValueError, match="mlt"):
        scene.render_film(window=(0, 0, 8, 8))
    with pytest.raises(ValueError, match="mutations_per_pixel"):
        scene.mutations_per_pixel = 0
    scene.integrator = "path"
    scene.integrator = "mlt"


@pytest.mark.parametrize("integrator,reconstruction",
                         [("path", "sample"), ("bdpt", "sample"), ("lightpath", "sample"),
                          ("path", "splat"), ("bdpt", "splat")])
def test_windows_combine_into_the_whole_render_bit_for_bit(scene_path, integrator, reconstruction):
    """Disjoint windows (any shapes, combined in any order) give the whole image's bits,
    also for the integrators whose splats land outside the window that made them, and
    under filter splatting, whose samples reach the pixels around their own."""
    scene = mcrender.load(scene_path)
    scene.integrator = integrator
    scene.reconstruction = reconstruction
    assert scene.reconstruction == reconstruction
    scene.resolution = (40, 30)
    scene.seed = 3
    whole = scene.render_film(0, 4)
    windows = [(0, 0, 40, 7), (0, 7, 13, 30), (13, 7, 40, 19), (13, 19, 40, 30)]
    films = [scene.render_film(0, 4, window=w) for w in windows]
    for order in ([0, 1, 2, 3], [3, 1, 0, 2]):
        film = films[order[0]]
        for i in order[1:]:
            film = film.combined(films[i])
        assert film == whole
        assert film.image().tobytes() == whole.image().tobytes()
        assert film.variance().tobytes() == whole.variance().tobytes()
    if integrator != "path":
        # The splats of one window reach pixels outside it.
        outside = films[0].image()[7:]
        assert float(outside.sum()) > 0
    with pytest.raises(ValueError, match="both"):
        films[0].combined(films[0])
    with pytest.raises(ValueError, match="window"):
        scene.render_film(0, 4, window=(0, 0, 41, 5))
    assert (whole.to_bytes() == mcrender.Film.from_bytes(whole.to_bytes()).to_bytes())
    with pytest.raises(ValueError, match="reconstruction"):
        scene.reconstruction = "blur"


def test_compare_integrators_has_the_figures_of_the_cli_json(cli, repo, tmp_path):
    path = repo / "scenes" / "cornell-box" / "scene-v4.pbrt"
    scene = mcrender.load(path)
    scene.resolution = (16, 16)
    mcrender.write_image(str(tmp_path / "ref.exr"), scene.render(spp=32, seed=7, progress=False))
    integrators = ["path", "bdpt", "sppm"]
    done = run_cli(cli, "compare", path, "--spp", 2, "--resolution", "16x16", "--integrators",
                   ",".join(integrators), "--reference", tmp_path / "ref.exr", "--json", "-o", tmp_path / "cmp")
    cli_rows = json.loads(done.stdout)["integrators"]
    rows = mcrender.compare(scene, integrators=integrators, spp=2, reference=str(tmp_path / "ref.exr"))
    assert [r["integrator"] for r in rows] == integrators
    for mine, theirs in zip(rows, cli_rows):
        assert set(theirs) <= set(mine)
        for key in ("integrator", "samples", "sample_unit", "rays", "variance", "rel_mse"):
            assert mine[key] == theirs[key], key
        assert mine["reference"] == "given"
    with pytest.raises(ValueError, match="\"photon\""):
        mcrender.compare(scene, integrators=["photon"], spp=1)
