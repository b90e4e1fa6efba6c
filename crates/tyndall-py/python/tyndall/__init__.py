"""Tyndall: light in participating media, from Python.

Load a scene, render it to a NumPy array, write EXR or PNG::

    import tyndall
    scene = tyndall.load("scenes/fig07-spot-sphere.toml")
    image = scene.render(spp=16, width=320, height=240)   # float32, H×W×3
    tyndall.write_exr("fig7.exr", image)

Renders are deterministic: the same scene, seed and settings give the same
array whatever ``threads`` is. ``tile=(i, n)`` renders tile ``i`` of ``n``
(horizontal bands of rows, as ``tyndall render --tile``) and
``samples=(a, b)`` the sample indices ``a..b`` of each pixel, as the
command line does. The GIL is released while rendering; Ctrl-C stops a
render after the pass in progress and raises ``KeyboardInterrupt``.
"""

from __future__ import annotations

import os
from typing import Callable, Optional, Tuple, Union

import numpy as np

from . import _tyndall

__all__ = ["Scene", "load", "demo", "write_exr", "write_png"]

PathLike = Union[str, "os.PathLike[str]"]


class Scene:
    """A loaded scene and the render settings its file gives."""

    def __init__(self, native: "_tyndall.NativeScene") -> None:
        self._native = native

    @property
    def width(self) -> int:
        """Image width in pixels from the scene file."""
        return self._native.settings()[0]

    @property
    def height(self) -> int:
        """Image height in pixels from the scene file."""
        return self._native.settings()[1]

    @property
    def spp(self) -> int:
        """Samples per pixel from the scene file."""
        return self._native.settings()[2]

    @property
    def integrator(self) -> str:
        """Integrator named by the scene file: ``march``, ``single`` or ``volpath``."""
        return self._native.settings()[3]

    def render(
        self,
        spp: Optional[int] = None,
        integrator: Optional[str] = None,
        width: Optional[int] = None,
        height: Optional[int] = None,
        seed: Optional[int] = None,
        threads: Optional[int] = None,
        tile: Optional[Tuple[int, int]] = None,
        samples: Optional[Tuple[int, int]] = None,
        progress: Optional[Callable[[int, int], None]] = None,
    ) -> np.ndarray:
        """Render the scene; returns linear radiance, ``float32``, shape H×W×3.

        Arguments left ``None`` keep the scene file's settings. ``tile=(i, n)``
        returns only tile ``i``'s rows; ``samples=(a, b)`` averages sample
        indices ``a`` to ``b - 1`` only. ``progress(done, total)`` is called
        after each whole pass (one sample per pixel); an exception it raises
        stops the render and propagates. Raises ``ValueError`` for invalid
        settings.
        """
        data, h, w = self._native.render(
            spp,
            integrator,
            width,
            height,
            seed,
            threads,
            None if tile is None else (int(tile[0]), int(tile[1])),
            None if samples is None else (int(samples[0]), int(samples[1])),
            progress,
        )
        return np.frombuffer(data, dtype="<f4").reshape(h, w, 3).astype(np.float32)


def load(path: PathLike, two_sided: bool = False) -> Scene:
    """Load a native (``.toml``) or legacy (``.obj``) scene file.

    ``two_sided`` loads legacy quads as two-sided. Raises ``ValueError``
    naming the file, line and column of any error.
    """
    return Scene(_tyndall.load(os.fspath(path), two_sided))


def demo() -> Scene:
    """The built-in demo: a stained-glass window in a dusty room."""
    return Scene(_tyndall.demo())


def _image_bytes(image: np.ndarray) -> Tuple[bytes, int, int]:
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] != 3:
        raise ValueError(f"expected an H×W×3 image, got shape {a.shape}")
    return np.ascontiguousarray(a, dtype="<f4").tobytes(), a.shape[0], a.shape[1]


def write_exr(path: PathLike, image: np.ndarray) -> None:
    """Write an H×W×3 linear-radiance image to an OpenEXR file (float32)."""
    if not os.fspath(path).lower().endswith(".exr"):
        raise ValueError(f"{os.fspath(path)}: write_exr needs a file name ending in .exr")
    data, h, w = _image_bytes(image)
    _tyndall.write_image(os.fspath(path), data, h, w, 0.0)


def write_png(path: PathLike, image: np.ndarray, exposure: float = 0.0) -> None:
    """Write an H×W×3 image to an 8-bit sRGB PNG after scaling by ``2**exposure``."""
    if not os.fspath(path).lower().endswith(".png"):
        raise ValueError(f"{os.fspath(path)}: write_png needs a file name ending in .png")
    data, h, w = _image_bytes(image)
    _tyndall.write_image(os.fspath(path), data, h, w, float(exposure))
