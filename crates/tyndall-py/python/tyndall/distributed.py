"""Renders split over a Ray cluster: :func:`render`.

``tyndall.distributed.render(scene, tiles=8)`` renders the scene's tiles
as Ray tasks, on a local Ray cluster or on one it joins by address, and
merges the render parts they return into the image ``scene.render`` gives,
bit for bit. Each task rebuilds the scene from the recipe the ``Scene``
remembers (its file's path, a ``from_dict`` description, or the demo), so
on a cluster of several machines the scene's files must be at the same
path on every machine; a task whose rebuilt scene is not the caller's
(its scene hash differs: a file changed, or differs on that machine)
raises ``ValueError`` instead of rendering. A task whose worker process dies (crash, killed,
machine lost) is run again, up to ``max_retries`` times; tiles are
deterministic, so the image does not change.

Needs Ray (``pip install "ray>=2"``), imported only when :func:`render` is
called.
"""

from __future__ import annotations

import hashlib
import operator
import os
import signal
from typing import Any, Callable, Dict, List, Optional, Tuple, Union

import numpy as np

from . import PathLike, Recipe, Scene, _rebuild, load, merge_parts

__all__ = ["render", "OPTIONS"]

#: The keyword options of :func:`render`, as those of ``Scene.render``.
OPTIONS = ("spp", "integrator", "width", "height", "seed", "threads", "samples")

#: Fault injection for tests: when a worker's environment sets this to a
#: folder, the first attempt of tile 0 of each distinct render kills its own
#: worker process (SIGKILL) after rendering, leaving a file in that folder;
#: Ray then retries the task on another worker.
FAULT_ENV = "TYNDALL_RAY_KILL_ONCE_DIR"

_remote_tile: Any = None


def render(
    scene_or_path: Union[Scene, PathLike],
    tiles: Optional[int] = None,
    address: Optional[str] = None,
    *,
    two_sided: bool = False,
    max_retries: int = 3,
    cpus_per_task: int = 1,
    progress: Optional[Callable[[int, int], None]] = None,
    **options: Any,
) -> np.ndarray:
    """Render ``tiles`` tiles as Ray tasks and merge them; returns float32, H×W×3.

    ``scene_or_path`` is a :class:`tyndall.Scene` or the path of a scene file
    (loaded with ``two_sided``). ``options`` are those of ``Scene.render``
    (``spp``, ``integrator``, ``width``, ``height``, ``seed``, ``threads``,
    ``samples``); the result equals ``scene.render(**options)`` bit for bit,
    light-traced caustics included, because each task returns its tile's
    render part (``Scene.render_part``: exact sums and its share of the light
    paths) and :func:`tyndall.merge_parts` assembles them with the checks of
    ``tyndall merge``.

    ``tiles`` defaults to the cluster's CPU count; tiles are bands of whole
    rows, so at most the image height. If this process is not connected to
    Ray yet, ``ray.init(address=address)`` is called: ``None`` starts a local
    cluster (or joins the one ``RAY_ADDRESS`` names), ``"auto"`` or
    ``"ray://host:10001"`` joins a running one; the connection stays open for
    later calls (``ray.shutdown()`` ends it). Each task asks for
    ``cpus_per_task`` CPUs and renders with that many threads unless
    ``threads`` is given. A task whose worker dies is retried up to
    ``max_retries`` times; an error in the render itself (e.g. ``ValueError``
    for invalid settings) is raised, not retried. ``progress(done, total)``
    is called in this process as tiles finish.
    """
    try:
        import ray
    except ImportError as e:  # pragma: no cover - depends on the environment
        raise ImportError('tyndall.distributed needs Ray: pip install "ray>=2"') from e

    for name in options:
        if name not in OPTIONS:
            why = "tiles are chosen by `tiles`" if name == "tile" else "not an option of Scene.render"
            raise TypeError(f"tyndall.distributed.render: `{name}`: {why}")
    scene = scene_or_path if isinstance(scene_or_path, Scene) else load(scene_or_path, two_sided)
    recipe = scene._recipe
    if recipe is None:
        raise TypeError("tyndall.distributed.render: the scene was not made by tyndall.load, demo or Scene.from_dict")
    if max_retries < 0 or cpus_per_task < 1:
        raise ValueError("tyndall.distributed.render: max_retries must be ≥ 0 and cpus_per_task ≥ 1")

    if not ray.is_initialized():
        ray.init(address=address)
    if tiles is None:
        tiles = max(1, int(ray.cluster_resources().get("CPU", 1)))
    height = options.get("height") or scene.height
    try:
        tiles = operator.index(tiles)  # ints, NumPy integers; not floats
    except TypeError:
        pass
    if not isinstance(tiles, int) or not 1 <= tiles <= height:
        raise ValueError(f"tyndall.distributed.render: tiles must be 1 to the image height {height}, not {tiles!r}")
    task_options: Dict[str, Any] = dict(options)
    task_options.setdefault("threads", cpus_per_task)
    # Also checks the options here, before any task starts.
    expected = _scene_hash(scene, task_options)

    global _remote_tile
    if _remote_tile is None:
        _remote_tile = ray.remote(_render_tile)
    task = _remote_tile.options(num_cpus=cpus_per_task, max_retries=max_retries, retry_exceptions=False)
    recipe_ref = ray.put(recipe)
    refs = [task.remote(recipe_ref, expected, (i, tiles), task_options) for i in range(tiles)]
    if progress is not None:
        pending = list(refs)
        while pending:
            done, pending = ray.wait(pending, num_returns=1)
            progress(tiles - len(pending), tiles)
    parts: List[bytes] = ray.get(refs)
    return merge_parts(parts)


def _scene_hash(scene: Scene, options: Dict[str, Any]) -> int:
    """The scene hash every part of this render must record."""
    o = options.get
    return scene._native.scene_hash(o("spp"), o("integrator"), o("width"), o("height"), o("seed"), o("threads"))


def _render_tile(recipe: Recipe, expected: int, tile: Tuple[int, int], options: Dict[str, Any]) -> bytes:
    """The Ray task: rebuilds the scene, checks that it is the caller's
    (same scene hash: the files did not change or differ on this machine),
    and renders one tile's part."""
    scene = _rebuild(recipe)
    found = _scene_hash(scene, options)
    if found != expected:
        raise ValueError(
            f"tyndall.distributed.render: the scene this worker made from {_origin(recipe)} "
            f"is not the caller's (scene hash {found:016x}, expected {expected:016x}): "
            "its files changed or differ on this machine"
        )
    part = scene.render_part(tile=tile, **options)
    _kill_once_if_asked(recipe, tile, options)
    return part


def _origin(recipe: Recipe) -> str:
    """Where a recipe's scene comes from, for messages."""
    kind = recipe[0]
    if kind == "load":
        return recipe[1]
    return "a from_dict description" if kind == "toml" else "the demo"


def _kill_once_if_asked(recipe: Recipe, tile: Tuple[int, int], options: Dict[str, Any]) -> None:
    """The fault injection of :data:`FAULT_ENV`."""
    folder = os.environ.get(FAULT_ENV)
    if not folder or tile[0] != 0:
        return
    key = hashlib.sha256(repr((recipe, tile, sorted(options.items()))).encode()).hexdigest()[:16]
    try:
        fd = os.open(os.path.join(folder, f"killed-{key}"), os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return  # killed once already: this is the retry
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    if hasattr(signal, "SIGKILL"):
        os.kill(os.getpid(), signal.SIGKILL)
    os._exit(1)
