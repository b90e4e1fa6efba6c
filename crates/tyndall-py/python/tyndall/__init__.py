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

To split a render over processes or machines, render parts instead:
``scene.render_part(tile=(i, n))`` returns the bytes of the OpenEXR part
file ``tyndall render --tile i/n`` writes (exact sums, the tile's share of
the light paths), and ``tyndall.merge_parts(parts)`` checks and assembles
them into exactly the image of the single render, as ``tyndall merge`` does.
A ``Scene`` pickles as the recipe it was made from (a path, a
``from_dict`` description, or the demo), so it can be sent to other
processes; ``tyndall.distributed.render`` renders the tiles as Ray tasks.
"""

from __future__ import annotations

import json
import math
import os
import re
from typing import Any, Callable, Dict, List, Mapping, Optional, Sequence, Tuple, Union

import numpy as np

from . import _tyndall

__all__ = ["AOVS", "Scene", "load", "demo", "merge_parts", "write_exr", "write_png"]

PathLike = Union[str, "os.PathLike[str]"]

# How a scene was made, enough to make it again in another process:
# ("load", absolute path, two_sided, frame), ("toml", text, name, frame,
# arrays) or ("demo",).
Recipe = Tuple[Any, ...]


def _build(recipe: Recipe) -> "_tyndall.NativeScene":
    kind = recipe[0]
    if kind == "load":
        return _tyndall.load(recipe[1], recipe[2], recipe[3])
    if kind == "toml":
        return _tyndall.parse_toml(recipe[1], recipe[2], recipe[3], recipe[4])
    if kind == "demo":
        return _tyndall.demo()
    raise ValueError(f"not a scene recipe: {recipe!r}")


def _rebuild(recipe: Recipe) -> "Scene":
    """Unpickles a scene: makes it again from its recipe."""
    return Scene(_build(recipe), recipe)


class Scene:
    """A loaded scene and the render settings its file gives.

    A scene remembers how it was made (its file's absolute path, the text
    of a ``from_dict`` description, or the demo) and pickles as that
    recipe: unpickling loads it again, so the other process must see the
    same files (a shared folder on a cluster).
    """

    def __init__(self, native: "_tyndall.NativeScene", recipe: Optional[Recipe] = None) -> None:
        self._native = native
        self._recipe = recipe

    def __reduce__(self) -> Tuple[Any, Tuple[Recipe]]:
        if self._recipe is None:
            raise TypeError("this Scene was not made by tyndall.load, demo or Scene.from_dict: it cannot be pickled")
        return (_rebuild, (self._recipe,))

    @classmethod
    def from_dict(
        cls,
        description: Mapping[str, Any],
        base_dir: Optional[PathLike] = None,
        frame: Optional[int] = None,
    ) -> "Scene":
        """Build a scene from a dict with the same structure as a native TOML file.

        ``{"camera": {...}, "lights": [{...}], "materials": {"glass": {...}}}``
        reads exactly as the TOML file with those tables would (see
        docs/scene-format.md). Relative paths (mesh files, grids) are relative
        to ``base_dir`` (default: the current folder); a file sequence
        (``"fluid_data_####.vdb"``) is read at ``frame``. Errors raise
        ``ValueError`` naming the key path, e.g. ``lights[0].cutoff_deg``.
        """
        arrays: List[bytes] = []
        text, paths = _to_toml(description, arrays)
        folder = os.path.abspath(os.fspath(base_dir)) if base_dir is not None else os.getcwd()
        name = os.path.join(folder, "<dict>")
        try:
            frame = _frame(frame)
            native = _tyndall.parse_toml(text, name, frame, arrays)
            return cls(native, ("toml", text, name, frame, arrays))
        except ValueError as e:
            raise ValueError(_name_key_path(str(e), name, paths)) from None

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
        aovs: Optional[Sequence[str]] = None,
        denoise: bool = False,
    ) -> Union[np.ndarray, Dict[str, np.ndarray]]:
        """Render the scene; returns linear radiance, ``float32``, shape H×W×3.

        ``aovs`` (names from ``AOVS``: the first-surface ``albedo``,
        ``normal``, ``depth``, ``position``, the radiance's components
        ``emission``, ``direct``, ``indirect``, ``volume``, which sum to it,
        and ``light_groups``) asks for these outputs too: the result is then
        a dict of arrays, ``"beauty"`` the radiance and one entry per AOV
        (H×W×3; ``depth`` H×W, ``inf`` where the ray meets nothing); for
        ``light_groups``, one entry ``"light_group.<name>"`` per light group
        of the scene (``light_group = "..."`` on lights and emissive shapes;
        ``"light_group.other"`` holds the light of every other emitter),
        which sum to the beauty too (see docs/scene-format.md, "AOVs and
        denoising"). The AOVs are never denoised; the components and light
        groups cannot be split for renders that trace light paths
        (caustics: ``ValueError``). ``denoise=True`` denoises the radiance
        with Intel Open Image Denoise guided by the albedo and normal; the
        library is the one ``TYNDALL_OIDN`` names, else the ``pyoidn``
        package's (``pip install pyoidn``), else a system install, and
        ``OSError`` says how to get it when none loads (before rendering).

        Arguments left ``None`` keep the scene file's settings. ``tile=(i, n)``
        returns only tile ``i``'s rows; ``samples=(a, b)`` averages sample
        indices ``a`` to ``b - 1`` only. When the render traces light paths
        (``volpath`` with a dielectric and a point or spot light), a tile
        traces only its share of them, so its caustic light is an estimate
        from fewer paths; the exact whole image comes from merging parts
        (:meth:`render_part` then :func:`merge_parts`, or
        ``tyndall render --tile`` then ``tyndall merge``). ``progress(done, total)`` is called
        after each whole pass (one sample per pixel); an exception it raises
        stops the render and propagates. Raises ``ValueError`` for invalid
        settings.
        """
        names = _aov_names(aovs)
        data, h, w, layers = self._native.render(
            spp,
            integrator,
            width,
            height,
            seed,
            threads,
            None if tile is None else (int(tile[0]), int(tile[1])),
            None if samples is None else (int(samples[0]), int(samples[1])),
            progress,
            names,
            bool(denoise),
            _oidn_library() if denoise else None,
        )
        beauty = _image_array(data, h, w)
        if aovs is None:
            return beauty
        result = {"beauty": beauty}
        for name, layer, channels in layers:
            image = _image_array(layer, h, w)
            result[name] = image[:, :, 0].copy() if channels == 1 else image
        return result

    def render_part(
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
    ) -> bytes:
        """Render a part for merging; returns the bytes of its OpenEXR part file.

        Takes the same arguments as :meth:`render`. The bytes are exactly the
        file ``tyndall render --tile i/n --samples a..b`` writes for the same
        scene and settings: the exact per-pixel sums of the tile's samples,
        the tile's share of the light paths (which may splat anywhere in the
        image), and the scene hash, seed, rectangle and sample range that
        :func:`merge_parts` and ``tyndall merge`` check. Save them to a
        ``.exr`` file to merge with the command line.
        """
        return self._native.render_part(
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


#: The AOVs ``Scene.render(aovs=...)`` can return.
AOVS = (
    "albedo",
    "normal",
    "depth",
    "position",
    "emission",
    "direct",
    "indirect",
    "volume",
    "light_groups",
)


def _aov_names(aovs: Optional[Sequence[str]]) -> List[str]:
    """The AOV names asked for, checked (unknown or repeated: ValueError)."""
    if aovs is None:
        return []
    if isinstance(aovs, str):
        raise TypeError("aovs is a sequence of names, e.g. ['albedo', 'depth'], not one string")
    names = [str(a) for a in aovs]
    for name in names:
        if name not in AOVS:
            raise ValueError(f"unknown AOV {name!r} (known: {', '.join(AOVS)})")
    if len(set(names)) != len(names):
        raise ValueError(f"an AOV is named twice in {names!r}")
    return names


def _oidn_library() -> Optional[str]:
    """The Open Image Denoise library folder to load: ``TYNDALL_OIDN``'s,
    else the ``pyoidn`` package's (found without importing it), else None
    (the native side then searches the system)."""
    named = os.environ.get("TYNDALL_OIDN")
    if named:
        return named
    import importlib.util

    spec = importlib.util.find_spec("pyoidn")
    if spec is None or not spec.submodule_search_locations:
        return None
    folder = os.path.join(list(spec.submodule_search_locations)[0], "oidn", "lib")
    return folder if os.path.isdir(folder) else None


def load(path: PathLike, two_sided: bool = False, frame: Optional[int] = None) -> Scene:
    """Load a scene file by its ending: native (``.toml``), the paper's legacy
    format (``.obj``) or glTF 2.0 (``.gltf``, ``.glb``).

    ``two_sided`` loads legacy quads as two-sided. ``frame`` picks the frame
    of the scene's file sequences: a ``[[media]]`` ``file`` such as a
    Blender fluid cache's ``"cache/data/fluid_data_####.vdb"`` reads
    ``fluid_data_0012.vdb`` at ``frame=12``. Raises ``ValueError`` naming
    the file, line and column of any error.
    """
    path = os.path.abspath(os.fspath(path))
    two_sided = bool(two_sided)
    frame = _frame(frame)
    return Scene(_tyndall.load(path, two_sided, frame), ("load", path, two_sided, frame))


def _frame(frame: Optional[int]) -> Optional[int]:
    """A frame number: a whole number from 0 to 2³² − 1, or None."""
    if frame is None:
        return None
    if isinstance(frame, bool) or not isinstance(frame, int) or not 0 <= frame < 2**32:
        raise ValueError(f"frame must be a whole number from 0 to 4294967295, got {frame!r}")
    return frame


def demo() -> Scene:
    """The built-in demo: a stained-glass window in a dusty room."""
    return Scene(_tyndall.demo(), ("demo",))


def merge_parts(parts: Sequence[Union[bytes, PathLike]], output: Optional[PathLike] = None) -> np.ndarray:
    """Merge render parts into one image; returns linear radiance, ``float32``, H×W×3.

    Each part is the bytes :meth:`Scene.render_part` returns or the path of
    a part file (``tyndall render --tile/--samples``). The checks are those
    of ``tyndall merge``: the parts must come from the same scene and
    settings (scene hash, seed, size), tiles must not overlap and must cover
    the image, and sample ranges of the same pixels must follow each other
    without gap or overlap; otherwise ``ValueError`` says which parts do not
    fit. Merged tiles equal the single render bit for bit, light paths
    included; merged sample ranges equal it to float rounding. One tile's
    sample ranges alone merge into that tile. ``output`` also writes the
    merged part (``.exr``, mergeable again) or its image (``.png``).
    """
    items: List[Union[bytes, str]] = []
    for i, p in enumerate(parts):
        if isinstance(p, (bytes, bytearray, memoryview)):
            items.append(bytes(p))
        elif isinstance(p, (str, os.PathLike)):
            items.append(os.fspath(p))
        else:
            raise TypeError(f"merge_parts: part {i} is {type(p).__name__}, not bytes or a path")
    data, h, w = _tyndall.merge_parts(items, None if output is None else os.fspath(output))
    return _image_array(data, h, w)


def _image_array(data: bytes, h: int, w: int) -> np.ndarray:
    return np.frombuffer(data, dtype="<f4").reshape(h, w, 3).astype(np.float32)


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


_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")


def _key(k: Any, path: str) -> str:
    if not isinstance(k, str):
        raise ValueError(f"Scene.from_dict: {path or 'the scene'}: key {k!r} is not a string")
    return k if _BARE_KEY.match(k) else json.dumps(k)


def _number(v: Union[int, float]) -> str:
    if isinstance(v, int):
        return str(int(v))
    # As a plain float: NumPy 2 writes its float64 (a float subclass) as
    # "np.float64(…)".
    v = float(v)
    if math.isnan(v):
        return "nan"
    if math.isinf(v):
        return "inf" if v > 0 else "-inf"
    return repr(v)


# The mesh arrays `from_dict` hands over as bytes beside the text
# (native::parse_with_arrays), not as numbers written out: float32 for
# these keys, uint32 for `indices`. Shorter arrays are written as text.
_FLOAT_ARRAYS = ("positions", "normals", "uvs")
_ARRAY_BESIDE_MIN = 64


def _array_beside(v: Any, path: str, arrays: Optional[List[bytes]]) -> Optional[str]:
    """`"@array:K"` for a mesh array of NumPy numbers that goes beside the
    text (appended to `arrays`), else None."""
    if arrays is None or not isinstance(v, np.ndarray) or v.ndim != 1 or len(v) < _ARRAY_BESIDE_MIN:
        return None
    key = path.rsplit(".", 1)[-1]
    if key in _FLOAT_ARRAYS and v.dtype.kind in "iuf":
        data = np.ascontiguousarray(v, dtype="<f4").tobytes()
    elif key == "indices" and v.dtype.kind in "iu" and v.min() >= 0 and v.max() < 2**32:
        data = np.ascontiguousarray(v, dtype="<u4").tobytes()
    else:
        return None
    arrays.append(data)
    return json.dumps(f"@array:{len(arrays) - 1}")


def _value(v: Any, path: str, arrays: Optional[List[bytes]] = None) -> str:
    beside = _array_beside(v, path, arrays)
    if beside is not None:
        return beside
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return _number(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, Mapping):
        items = ", ".join(f"{_key(k, path)} = {_value(x, f'{path}.{k}', arrays)}" for k, x in v.items())
        return "{" + items + "}"
    if isinstance(v, np.ndarray) and v.ndim == 1 and v.dtype.kind in "iuf":
        # Flat numeric arrays (a mesh's `positions`, `indices`): written
        # whole, not element by element; float32 with the 9 significant
        # digits that give back the same float32.
        if v.dtype == np.float32:
            return "[" + ", ".join(map("{:.9g}".format, v.tolist())) + "]"
        return "[" + ", ".join(map(_number, v.tolist())) + "]"
    if isinstance(v, np.generic) or (isinstance(v, np.ndarray) and v.ndim == 0):
        # NumPy scalars (which have `tolist` and `ndim` too) as Python's.
        return _value(v.item(), path)
    if isinstance(v, (list, tuple)) or (hasattr(v, "tolist") and hasattr(v, "ndim")):
        seq = v.tolist() if hasattr(v, "tolist") else v
        return "[" + ", ".join(_value(x, f"{path}[{i}]") for i, x in enumerate(seq)) + "]"
    if hasattr(v, "item"):  # other array libraries' scalars
        return _value(v.item(), path)
    raise ValueError(f"Scene.from_dict: {path}: {type(v).__name__} is not a scene value")


def _is_table_list(v: Any) -> bool:
    return isinstance(v, (list, tuple)) and len(v) > 0 and all(isinstance(x, Mapping) for x in v)


def _to_toml(description: Mapping[str, Any], arrays: Optional[List[bytes]] = None) -> Tuple[str, List[str]]:
    """TOML text for a scene dict, and the key path of each of its lines;
    with `arrays`, large mesh arrays go there instead (`_array_beside`)."""
    if not isinstance(description, Mapping):
        raise ValueError("Scene.from_dict: the description must be a dict")
    lines: List[str] = []
    paths: List[str] = []

    def emit(line: str, path: str) -> None:
        lines.append(line)
        paths.append(path)

    def table(d: Mapping[str, Any], header: str, path: str) -> None:
        # Scalars and inline values first, then sub-tables, as TOML needs.
        for k, v in d.items():
            if not isinstance(v, Mapping) and not _is_table_list(v):
                p = f"{path}.{k}" if path else str(k)
                emit(f"{_key(k, path)} = {_value(v, p, arrays)}", p)
        for k, v in d.items():
            p = f"{path}.{k}" if path else str(k)
            h = f"{header}.{_key(k, path)}" if header else _key(k, path)
            if isinstance(v, Mapping):
                emit(f"[{h}]", p)
                table(v, h, p)
            elif _is_table_list(v):
                for i, item in enumerate(v):
                    emit(f"[[{h}]]", f"{p}[{i}]")
                    table(item, h, f"{p}[{i}]")

    table(description, "", "")
    return "\n".join(lines) + "\n", paths


def _name_key_path(message: str, name: str, paths: List[str]) -> str:
    """Replaces `<dict>:LINE:COL:` in an error with the key path of LINE."""
    m = re.match(re.escape(name) + r":(\d+):(\d+):\s*(.*)", message, re.S)
    if not m:
        return f"Scene.from_dict: {message.replace(name, 'the scene')}"
    line = int(m.group(1))
    path = paths[line - 1] if 1 <= line <= len(paths) else "the scene"
    return f"Scene.from_dict: {path or 'the scene'}: {m.group(3)}"


from . import distributed  # noqa: E402  (imports Ray only when used)
