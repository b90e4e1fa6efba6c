"""Render parts from Python (Scene.render_part, merge_parts) and pickled
scenes: the pieces tyndall.distributed is made of, tested without Ray."""

import pickle
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

import tyndall

REPO = Path(__file__).resolve().parents[3]
FOCUS = REPO / "scenes" / "glass-sphere-focus.toml"
OPTS = dict(width=40, height=30, spp=2)  # volpath: caustic light paths


def test_merged_tile_parts_equal_the_single_render_bit_for_bit():
    scene = tyndall.load(FOCUS)
    full = scene.render(**OPTS)
    parts = [scene.render_part(**OPTS, tile=(i, 3)) for i in range(3)]
    assert all(p[:4] == bytes([0x76, 0x2F, 0x31, 0x01]) for p in parts)  # OpenEXR
    merged = tyndall.merge_parts(list(reversed(parts)))  # any order
    assert merged.dtype == np.float32 and merged.shape == full.shape
    assert np.array_equal(merged, full) and merged.tobytes() == full.tobytes()
    # Stacking the tiles' own images is not the same: each tile's caustic
    # light is estimated from its share of the light paths only.
    stacked = np.vstack([scene.render(**OPTS, tile=(i, 3)) for i in range(3)])
    assert stacked.tobytes() != full.tobytes()


def test_merged_sample_ranges_equal_the_render_to_rounding(tmp_path):
    scene = tyndall.demo()
    opts = dict(width=24, height=20, spp=3, integrator="volpath")
    full = scene.render(**opts)
    parts = [scene.render_part(**opts, samples=(0, 1)), scene.render_part(**opts, samples=(1, 3))]
    merged = tyndall.merge_parts(parts, output=tmp_path / "merged.exr")
    np.testing.assert_allclose(merged, full, rtol=1e-6, atol=1e-9)
    # The merged part written to disk merges again (alone: one rectangle).
    again = tyndall.merge_parts([tmp_path / "merged.exr"])
    assert again.tobytes() == merged.tobytes()


def test_parts_that_do_not_fit_are_refused_with_the_merge_checks():
    scene = tyndall.load(FOCUS)
    parts = [scene.render_part(**OPTS, tile=(i, 3)) for i in range(3)]
    with pytest.raises(ValueError, match="some tiles are missing"):
        tyndall.merge_parts(parts[:2])
    with pytest.raises(ValueError, match=r"part 0 .* and part 1 .* overlap"):
        tyndall.merge_parts([parts[0], parts[0], parts[1], parts[2]])
    other_seed = scene.render_part(**OPTS, seed=99, tile=(2, 3))
    with pytest.raises(ValueError, match="different scenes or settings"):
        tyndall.merge_parts(parts[:2] + [other_seed])
    with pytest.raises(ValueError, match="part 0"):
        tyndall.merge_parts([b"not an exr"])
    with pytest.raises(ValueError, match="no parts"):
        tyndall.merge_parts([])
    with pytest.raises(TypeError, match="part 0 is int"):
        tyndall.merge_parts([3])


def test_python_parts_are_the_command_lines_part_files(tmp_path):
    # The command line must be built from the same source as the extension
    # (.ci/run builds both): the scene hash covers the Tyndall version and
    # the runtime scene's layout.
    cli = REPO / "target" / "release" / "tyndall"
    if not cli.exists():
        cli = shutil.which("tyndall")
    if cli is None:
        pytest.skip("no tyndall command line built (cargo build --release -p tyndall-cli)")
    scene = tyndall.load(FOCUS)
    (tmp_path / "py.exr").write_bytes(scene.render_part(**OPTS, tile=(0, 2)))
    subprocess.run(
        [str(cli), "render", str(FOCUS), "--width", "40", "--height", "30", "--spp", "2",
         "--tile", "1/2", "-o", str(tmp_path / "cli.exr"), "--quiet"],
        check=True,
    )
    merged = tyndall.merge_parts([tmp_path / "py.exr", tmp_path / "cli.exr"])
    assert merged.tobytes() == scene.render(**OPTS).tobytes()


@pytest.mark.parametrize(
    "make",
    [
        lambda: tyndall.demo(),
        lambda: tyndall.load(FOCUS),
        lambda: tyndall.Scene.from_dict(
            {
                "camera": {"position": [0, 1, 5], "look_at": [0, 1, 0], "fov_y_deg": 40.0},
                "lights": [{"type": "point", "position": [0, 3, 0], "intensity": 5.0}],
                "fog": {"sigma_t": 0.1, "albedo": 0.8},
            }
        ),
    ],
    ids=["demo", "file", "dict"],
)
def test_scenes_pickle_as_their_recipe_and_render_the_same(make):
    scene = make()
    again = pickle.loads(pickle.dumps(scene))
    opts = dict(width=16, height=12, spp=1)
    assert again.render(**opts).tobytes() == scene.render(**opts).tobytes()
