"""tyndall.distributed.render on a local Ray cluster of two worker
processes, one of which is killed mid-render: the merged image must still
equal the single-process render byte for byte."""

import os
from pathlib import Path

import numpy as np
import pytest

import tyndall

ray = pytest.importorskip("ray", reason="Ray is not installed (pip install ray): tyndall.distributed is not tested")

REPO = Path(__file__).resolve().parents[3]
FOCUS = REPO / "scenes" / "glass-sphere-focus.toml"
SMALL = dict(width=48, height=36, spp=2)


@pytest.fixture(scope="module")
def kill_dir(tmp_path_factory):
    """A local Ray cluster with two CPUs (two task workers) for the module,
    whose workers kill themselves once per render (FAULT_ENV); yields the
    folder where each kill leaves a file."""
    folder = tmp_path_factory.mktemp("ray-kills")
    ray.init(
        num_cpus=2,
        include_dashboard=False,
        log_to_driver=False,
        configure_logging=False,
        runtime_env={"env_vars": {tyndall.distributed.FAULT_ENV: str(folder)}},
    )
    try:
        yield folder
    finally:
        ray.shutdown()


@pytest.mark.parametrize(
    "make, options",
    [
        (lambda: tyndall.load(FOCUS), dict(SMALL, integrator="volpath")),  # caustic light paths
        (tyndall.demo, dict(SMALL, integrator="volpath")),
    ],
    ids=["glass-sphere-focus-volpath", "demo"],
)
def test_a_killed_worker_is_retried_and_the_image_is_bit_identical(kill_dir, make, options):
    scene = make()
    kills_before = set(os.listdir(kill_dir))
    done = []
    image = tyndall.distributed.render(
        scene, tiles=4, progress=lambda d, n: done.append((d, n)), **options
    )
    kills = set(os.listdir(kill_dir)) - kills_before
    assert len(kills) == 1, "the first attempt of tile 0 should have killed its worker"
    assert done[-1] == (4, 4)
    single = scene.render(**options)
    assert image.dtype == np.float32 and image.shape == single.shape
    assert np.array_equal(image, single)
    assert image.tobytes() == single.tobytes()


def test_a_path_and_options_as_scene_render(kill_dir):
    image = tyndall.distributed.render(str(FOCUS), tiles=3, width=24, height=18, spp=1, seed=3)
    single = tyndall.load(FOCUS).render(width=24, height=18, spp=1, seed=3)
    assert image.tobytes() == single.tobytes()


def test_render_errors_are_raised_not_retried(kill_dir):
    with pytest.raises(ValueError, match="unknown integrator"):
        tyndall.distributed.render(tyndall.demo(), tiles=2, width=8, height=8, spp=1, integrator="magic")
    with pytest.raises(ValueError, match="tiles must be"):
        tyndall.distributed.render(tyndall.demo(), tiles=9, width=8, height=8, spp=1)
    with pytest.raises(TypeError, match="tiles are chosen"):
        tyndall.distributed.render(tyndall.demo(), tiles=2, tile=(0, 2))


def test_a_scene_file_changed_after_loading_is_refused_not_rendered(kill_dir, tmp_path):
    path = tmp_path / "focus.toml"
    path.write_text(FOCUS.read_text())
    scene = tyndall.load(path)
    path.write_text(FOCUS.read_text().replace("radius = 0.5", "radius = 0.6"))
    with pytest.raises(ValueError, match="its files changed or differ on this machine"):
        tyndall.distributed.render(scene, tiles=2, width=8, height=8, spp=1)
