"""Tests of the tyndall Python package (run by .ci/run in a fresh venv)."""

import os
import signal
import subprocess
import sys
import threading
from pathlib import Path

import numpy as np
import pytest

import tyndall

REPO = Path(__file__).resolve().parents[3]
FOCUS = REPO / "scenes" / "glass-sphere-focus.toml"
SMALL = dict(width=24, height=16, spp=2)


def test_demo_renders_a_float32_image():
    image = tyndall.demo().render(**SMALL, integrator="single")
    assert image.dtype == np.float32
    assert image.shape == (16, 24, 3)
    assert np.isfinite(image).all()
    assert image.max() > 0.0


def test_scene_file_settings_and_overrides():
    scene = tyndall.load(FOCUS)
    assert (scene.width, scene.height, scene.integrator) == (480, 480, "volpath")
    image = scene.render(width=20, height=10, spp=1)
    assert image.shape == (10, 20, 3)


def test_same_image_for_any_thread_count():
    scene = tyndall.load(FOCUS)  # volpath with caustic light paths
    one = scene.render(width=24, height=20, spp=2, threads=1)
    two = scene.render(width=24, height=20, spp=2, threads=2)
    assert one.tobytes() == two.tobytes()
    other_seed = scene.render(width=24, height=20, spp=2, threads=2, seed=5)
    assert other_seed.tobytes() != one.tobytes()


def test_tiles_stack_into_the_full_image_and_sample_ranges_average_to_it():
    scene = tyndall.demo()  # no light paths: a tile is exactly its rows
    opts = dict(width=24, height=20, spp=3, integrator="volpath")
    full = scene.render(**opts)
    tiles = [scene.render(**opts, tile=(i, 3)) for i in range(3)]
    assert [t.shape[0] for t in tiles] == [6, 7, 7]  # rows ⌊i·20/3⌋
    assert np.vstack(tiles).tobytes() == full.tobytes()
    a = scene.render(**opts, samples=(0, 1)).astype(np.float64)
    b = scene.render(**opts, samples=(1, 3)).astype(np.float64)
    # float32 means of 1 and 2 samples: equal to the mean of 3 to f32 rounding.
    np.testing.assert_allclose((a + 2 * b) / 3, full, rtol=1e-5, atol=1e-7)
    assert not np.array_equal(a.astype(np.float32), full)


def test_a_tile_of_a_caustic_scene_estimates_its_light_paths_from_its_share():
    scene = tyndall.load(FOCUS)  # volpath with light paths
    opts = dict(width=24, height=20, spp=2)
    full = scene.render(**opts)
    tile = scene.render(**opts, tile=(1, 2))
    assert tile.shape == (10, 24, 3)
    assert np.isfinite(tile).all()
    # Same camera paths, a different (half) set of light paths.
    assert tile.tobytes() != full[10:].tobytes()


def test_write_exr_and_png(tmp_path):
    image = tyndall.demo().render(**SMALL)
    exr, png = tmp_path / "a.exr", tmp_path / "a.png"
    tyndall.write_exr(exr, image)
    tyndall.write_png(png, image, exposure=1.0)
    assert exr.read_bytes()[:4] == bytes([0x76, 0x2F, 0x31, 0x01])
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="H×W×3"):
        tyndall.write_exr(tmp_path / "b.exr", np.zeros((4, 4)))
    with pytest.raises(ValueError, match=".png"):
        tyndall.write_png(tmp_path / "b.exr", image)


def test_bad_input_raises_clear_errors(tmp_path):
    with pytest.raises(ValueError, match="missing.toml"):
        tyndall.load(tmp_path / "missing.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[camera]\nposition = [0, 0\n")
    with pytest.raises(ValueError, match=r"bad.toml:2:"):
        tyndall.load(bad)
    scene = tyndall.demo()
    with pytest.raises(ValueError, match="unknown integrator"):
        scene.render(**SMALL, integrator="magic")
    with pytest.raises(ValueError, match="numbered from 0"):
        scene.render(**SMALL, tile=(3, 3))
    with pytest.raises(ValueError, match="samples per pixel"):
        scene.render(width=8, height=8, spp=0)


def test_progress_is_reported_per_pass_and_can_stop_a_render():
    calls = []
    tyndall.demo().render(**SMALL, progress=lambda done, total: calls.append((done, total)))
    assert calls == [(1, 2), (2, 2)]

    def stop(done, total):
        raise RuntimeError(f"stop at {done}")

    with pytest.raises(RuntimeError, match="stop at 1"):
        tyndall.demo().render(width=8, height=8, spp=50, progress=stop)


def test_the_gil_is_released_while_rendering():
    ticks = 0
    done = threading.Event()

    def count():
        nonlocal ticks
        while not done.is_set():
            ticks += 1

    counter = threading.Thread(target=count)
    counter.start()
    before = ticks
    try:
        tyndall.demo().render(width=64, height=36, spp=8, integrator="volpath", threads=1)
        during = ticks - before
    finally:
        done.set()
        counter.join()
    # With the GIL held for the whole render the counter would stand still
    # (at most one switch interval of counting).
    assert during > 10_000


def test_ctrl_c_stops_a_render_cleanly():
    # The child takes Python's own Ctrl-C handler and unblocks SIGINT
    # first: a process started in the background by a non-interactive
    # shell (as CI may start this suite) inherits SIGINT ignored, and
    # Python then installs no KeyboardInterrupt handler. What is under
    # test is how a render answers Ctrl-C where Python does handle it.
    script = (
        "import signal\n"
        "signal.signal(signal.SIGINT, signal.default_int_handler)\n"
        "signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})\n"
        "import tyndall\n"
        "def progress(done, total):\n"
        "    if done == 1:\n"
        "        print('rendering', flush=True)\n"
        "tyndall.demo().render(width=16, height=8, spp=1_000_000, progress=progress)\n"
    )
    child = subprocess.Popen(
        [sys.executable, "-c", script],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    assert child.stdout.readline().strip() == "rendering"
    child.send_signal(signal.SIGINT)
    try:
        _, err = child.communicate(timeout=60)
    except subprocess.TimeoutExpired:
        child.kill()
        _, err = child.communicate()
        raise AssertionError(f"Ctrl-C did not stop the render; its stderr: {err!r}")
    assert child.returncode != 0
    assert "KeyboardInterrupt" in err


def test_from_dict_reads_as_the_toml_file_does():
    tomllib = pytest.importorskip("tomllib")
    description = tomllib.loads(FOCUS.read_text())
    from_file = tyndall.load(FOCUS).render(width=20, height=16, spp=2)
    from_dict = tyndall.Scene.from_dict(description).render(width=20, height=16, spp=2)
    assert from_dict.tobytes() == from_file.tobytes()


def test_from_dict_errors_name_the_key_path():
    camera = {"position": [0, 1, 5], "look_at": [0, 1, 0], "fov_y_deg": 40.0}
    spot = {
        "type": "spot",
        "position": [0, 3, 0],
        "direction": [0, -1, 0],
        "cutoff_deg": 120.0,
        "intensity": 5.0,
    }
    with pytest.raises(ValueError, match=r"lights\[1\]"):
        tyndall.Scene.from_dict({"camera": camera, "lights": [dict(spot, cutoff_deg=20.0), spot]})
    with pytest.raises(ValueError, match=r"camera"):
        tyndall.Scene.from_dict({"camera": {"position": [0, 1, 5]}})
    with pytest.raises(ValueError, match=r"fog.sigma_t: NoneType is not a scene value"):
        tyndall.Scene.from_dict({"camera": camera, "fog": {"sigma_t": None}})
    scene = tyndall.Scene.from_dict(
        {"camera": camera, "lights": [dict(spot, cutoff_deg=20.0)], "fog": {"sigma_t": 0.1, "albedo": 0.8}}
    )
    assert scene.render(width=8, height=8, spp=1).max() > 0


def test_a_mesh_in_numpy_arrays_reads_as_the_same_lists():
    """A `triangles` shape given as flat NumPy arrays (float32 positions,
    int64 indices: what the Blender add-on passes) is the same scene as
    the same numbers in Python lists, to the bit."""
    positions = np.array([-2, 0, -2, 2, 0, -2, 2, 0, 2, -2, 0, 2], dtype=np.float32) + np.float32(0.1)
    indices = np.array([0, 2, 1, 0, 3, 2], dtype=np.int64)

    def scene(p, i):
        return tyndall.Scene.from_dict(
            {
                "camera": {"position": [0, 3, 4], "look_at": [0, 0, 0], "fov_y_deg": 50.0},
                "materials": {"floor": {"type": "principled", "base_color": 0.7}},
                "shapes": [{"type": "triangles", "positions": p, "indices": i, "material": "floor"}],
                "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 3.0}],
            }
        )

    arrays = scene(positions, indices).render(width=16, height=12, spp=2)
    lists = scene(positions.tolist(), indices.tolist()).render(width=16, height=12, spp=2)
    assert arrays.max() > 0
    assert arrays.tobytes() == lists.tobytes()


def test_numpy_scalars_read_as_plain_numbers():
    """NumPy scalars anywhere in a description (np.float64 is a float
    subclass whose repr in NumPy 2 is "np.float64(…)"; np.float32 and
    np.int64 are not Python numbers) read as the plain numbers do."""

    def scene(number, integer):
        return tyndall.Scene.from_dict(
            {
                "camera": {"position": [0, 3, 4], "look_at": [0, 0, 0], "fov_y_deg": number(50.0)},
                "render": {"width": integer(16), "height": integer(12), "spp": integer(2)},
                "materials": {"floor": {"type": "diffuse", "reflectance": [number(0.7), number(0.5), number(0.3)]}},
                "shapes": [
                    {"type": "quad", "corners": [[-2, 0, -2], [-2, 0, 2], [2, 0, 2], [2, 0, -2]], "material": "floor"}
                ],
                "lights": [{"type": "point", "position": [0, number(2.0), 0], "intensity": [number(3.0)] * 3}],
            }
        )

    plain = scene(float, int).render()
    assert plain.max() > 0
    for number in (np.float64, np.float32):
        assert scene(number, np.int64).render().tobytes() == plain.tobytes()


def test_large_mesh_arrays_go_beside_the_text_and_read_the_same():
    """A floor of 2·24² triangles as NumPy arrays (past the size that
    `from_dict` hands over as bytes beside the TOML text, "@array:K")
    renders to the bit as the same numbers in Python lists (written as
    text), and so does the scene after a pickle round trip (the recipe
    keeps the arrays)."""
    import pickle

    n = 24
    xs = np.linspace(-2, 2, n + 1, dtype=np.float32)
    grid = np.stack(np.meshgrid(xs, xs, indexing="ij"), -1).reshape(-1, 2)
    positions = np.zeros((len(grid), 3), np.float32)
    positions[:, 0], positions[:, 2] = grid[:, 0], grid[:, 1]
    positions[:, 1] = 0.05 * np.sin(3 * grid[:, 0]) * np.cos(2 * grid[:, 1])
    i, j = np.meshgrid(np.arange(n), np.arange(n), indexing="ij")
    a = (i * (n + 1) + j).ravel()
    quads = np.stack([a, a + 1, a + n + 2, a, a + n + 2, a + n + 1], -1)
    indices = quads.reshape(-1).astype(np.int64)
    normals = np.tile(np.array([0, 1, 0], np.float32), len(grid))

    def scene(p, i, nrm):
        return tyndall.Scene.from_dict(
            {
                "camera": {"position": [0, 3, 4], "look_at": [0, 0, 0], "fov_y_deg": 50.0},
                "materials": {"floor": {"type": "principled", "base_color": 0.7}},
                "shapes": [{"type": "triangles", "positions": p, "indices": i, "normals": nrm, "material": "floor"}],
                "lights": [{"type": "point", "position": [0, 2, 0], "intensity": 3.0}],
            }
        )

    beside = scene(positions.reshape(-1), indices, normals)
    assert '"@array:0"' in beside._recipe[1] and len(beside._recipe[4]) == 3
    arrays = beside.render(width=16, height=12, spp=2)
    lists = scene(positions.reshape(-1).tolist(), indices.tolist(), normals.tolist()).render(width=16, height=12, spp=2)
    assert arrays.max() > 0
    assert arrays.tobytes() == lists.tobytes()
    again = pickle.loads(pickle.dumps(beside)).render(width=16, height=12, spp=2)
    assert again.tobytes() == arrays.tobytes()
    # An index past the vertices is still an error naming the key.
    bad = indices.copy()
    bad[7] = len(grid)
    with pytest.raises(ValueError, match="indices"):
        scene(positions.reshape(-1), bad, normals)


def test_frame_picks_the_file_of_a_sequence(tmp_path):
    """A cache's `####` sequence: `frame=` picks the file (issue 21); a
    missing frame, or the file of a frame that is not there, is a
    ValueError naming what is wrong."""
    smoke = (REPO / "scenes" / "smoke.toml").read_text()
    (tmp_path / "cache").mkdir()
    grid = (REPO / "scenes" / "smoke" / "plume.tgrid").read_bytes()
    (tmp_path / "cache" / "plume_0012.tgrid").write_bytes(grid)
    scene_file = tmp_path / "smoke.toml"
    scene_file.write_text(smoke.replace('file = "smoke/plume.tgrid"', 'file = "cache/plume_####.tgrid"'))
    sequenced = tyndall.load(scene_file, frame=12).render(**SMALL)
    plain = tyndall.load(REPO / "scenes" / "smoke.toml").render(**SMALL)
    assert sequenced.tobytes() == plain.tobytes()
    with pytest.raises(ValueError, match="frame sequence"):
        tyndall.load(scene_file)
    with pytest.raises(ValueError, match="plume_0013.tgrid"):
        tyndall.load(scene_file, frame=13)
    with pytest.raises(ValueError, match="whole number"):
        tyndall.load(scene_file, frame=-1)
    described = tyndall.Scene.from_dict(
        {"camera": {"position": [0, 2, 8], "look_at": [0, 1.95, 0], "fov_y_deg": 36},
         "render": {"integrator": "volpath"},
         "media": [{"sigma_t": 9.0, "albedo": 0.9, "box": {"min": [-1.2, 0, -1.2], "max": [1.2, 4, 1.2]},
                    "density": "grid", "file": "cache/plume_####.tgrid"}]},
        base_dir=tmp_path,
        frame=12,
    )
    assert described.render(**SMALL).max() >= 0.0


WALL = {
    "camera": {"position": [0.0, 0.0, 5.0], "look_at": [0.0, 0.0, 0.0], "fov_y_deg": 40.0},
    "render": {"width": 21, "height": 15, "spp": 2, "integrator": "single"},
    "materials": {"wall": {"type": "diffuse", "reflectance": [0.2, 0.5, 0.7]}},
    "shapes": [
        {
            "type": "quad",
            "corners": [[-50.0, -50.0, 0.0], [50.0, -50.0, 0.0], [50.0, 50.0, 0.0], [-50.0, 50.0, 0.0]],
            "material": "wall",
        }
    ],
    "lights": [{"type": "point", "position": [0.0, 0.0, 4.0], "intensity": 1.0}],
}


def test_aovs_come_back_as_a_dict_of_arrays():
    scene = tyndall.Scene.from_dict(WALL)
    plain = scene.render()
    out = scene.render(aovs=["albedo", "normal", "depth", "position"])
    assert sorted(out) == ["albedo", "beauty", "depth", "normal", "position"]
    # The radiance does not change when the AOVs are kept.
    assert out["beauty"].tobytes() == plain.tobytes()
    assert out["albedo"].shape == (15, 21, 3) and out["depth"].shape == (15, 21)
    assert np.array_equal(out["albedo"], np.broadcast_to(np.float32([0.2, 0.5, 0.7]), (15, 21, 3)))
    assert np.array_equal(out["normal"], np.broadcast_to(np.float32([0.0, 0.0, 1.0]), (15, 21, 3)))
    # The wall is 5 away straight ahead. The centre pixel's rays leave the
    # axis by at most tan(20°)/15 = 0.0243 in each film direction, so its
    # depth is between 5 and 5·√(1 + 2·0.0243²) = 5.0030.
    assert 5.0 <= out["depth"][7, 10] <= 5.003
    assert np.abs(out["position"][:, :, 2]).max() < 1e-5
    with pytest.raises(ValueError, match="unknown AOV 'shadow'"):
        scene.render(aovs=["albedo", "shadow"])
    with pytest.raises(TypeError, match="sequence of names"):
        scene.render(aovs="albedo")


def _oidn_available() -> bool:
    return tyndall._oidn_library() is not None


def test_denoise_without_a_library_says_how_to_get_one(monkeypatch):
    monkeypatch.setenv("TYNDALL_OIDN", "/nonexistent/oidn")
    with pytest.raises(OSError, match="/nonexistent/oidn"):
        tyndall.Scene.from_dict(WALL).render(denoise=True)


@pytest.mark.skipif(not _oidn_available(), reason="Open Image Denoise not installed (pip install pyoidn, or set TYNDALL_OIDN)")
def test_denoising_brings_a_noisy_render_closer_to_a_clean_one():
    scene = tyndall.load(REPO / "scenes" / "reference" / "cornell-surfaces.toml")
    size = dict(width=80, height=60)
    clean = scene.render(spp=256, **size)
    noisy = scene.render(spp=2, seed=3, **size)
    denoised = scene.render(spp=2, seed=3, denoise=True, **size)

    def rel_mse(a):
        return float(np.mean((a - clean) ** 2 / (clean**2 + 1e-2)))

    assert rel_mse(denoised) < rel_mse(noisy)


def test_the_components_sum_to_the_beauty():
    scene = tyndall.load(REPO / "scenes" / "reference" / "fog-room-multi.toml")
    out = scene.render(width=32, height=24, spp=2, aovs=["emission", "direct", "indirect", "volume"])
    total = out["emission"] + out["direct"] + out["indirect"] + out["volume"]
    assert np.allclose(total, out["beauty"], rtol=1e-5, atol=1e-7)
    for name in ("direct", "indirect", "volume"):
        assert out[name].max() > 0.0, name
    with pytest.raises(ValueError, match="light paths"):
        tyndall.load(FOCUS).render(width=8, height=8, spp=1, aovs=["volume"])


def test_environment_light_from_dict(tmp_path):
    """An environment light in a dict (issue 22): the sky a camera ray
    escapes to is its radiance exactly; a map is read relative to
    ``base_dir``; and a white sphere under a uniform sky of radiance 0.5 is
    0.5 on average (the furnace test), within 4 standard errors of its
    pixels' scatter."""
    camera = {"position": [0, 0, 4], "look_at": [0, 0, 0], "fov_y_deg": 30.0}
    sphere = {"type": "sphere", "center": [0, 0, 0], "radius": 1.0, "material": "white"}
    description = {
        "camera": camera,
        "materials": {"white": {"type": "diffuse", "reflectance": 1.0}},
        "shapes": [sphere],
        "lights": [{"type": "environment", "radiance": 0.5}],
    }
    image = tyndall.Scene.from_dict(description).render(width=24, height=18, spp=64)
    assert np.all(image[0, 0] == np.float32(0.5))
    standard_error = image.std() / np.sqrt(image.size)
    assert abs(image.mean() - 0.5) <= 4 * standard_error + 1e-6
    tyndall.write_exr(tmp_path / "sky.exr", np.full((4, 8, 3), 0.25, dtype=np.float32))
    mapped = dict(description, lights=[{"type": "environment", "map": "sky.exr"}])
    image = tyndall.Scene.from_dict(mapped, base_dir=tmp_path).render(width=8, height=6, spp=1)
    assert np.allclose(image[0, 0], 0.25, atol=1e-6)
    with pytest.raises(ValueError, match="lights\\[0\\]"):
        tyndall.Scene.from_dict(dict(description, lights=[{"type": "environment"}]))
