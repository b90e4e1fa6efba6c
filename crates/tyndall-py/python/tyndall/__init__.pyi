import os
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import distributed as distributed

PathLike = Union[str, os.PathLike[str]]
Recipe = Tuple[Any, ...]

class Scene:
    """A loaded scene and the render settings its file gives.

    Pickles as the recipe it was made from (file path, ``from_dict``
    description, or the demo); unpickling loads it again.
    """

    def __reduce__(self) -> Tuple[Any, Tuple[Recipe]]: ...

    @classmethod
    def from_dict(
        cls,
        description: Mapping[str, Any],
        base_dir: Optional[PathLike] = None,
        frame: Optional[int] = None,
    ) -> "Scene":
        """A scene from a dict with the structure of a native TOML file."""
        ...

    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def spp(self) -> int: ...
    @property
    def integrator(self) -> str: ...
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
    ) -> Union[npt.NDArray[np.float32], Dict[str, npt.NDArray[np.float32]]]:
        """Render; linear radiance, float32, shape H×W×3 (with `aovs`, a dict
        of arrays: "beauty" and each AOV); `denoise` runs Open Image Denoise."""
        ...
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
        """Render a part; the bytes of the OpenEXR part file `tyndall render --tile` writes."""
        ...

AOVS: Tuple[str, ...]

def load(path: PathLike, two_sided: bool = False, frame: Optional[int] = None) -> Scene: ...
def demo() -> Scene: ...
def merge_parts(
    parts: Sequence[Union[bytes, PathLike]], output: Optional[PathLike] = None
) -> npt.NDArray[np.float32]:
    """Merge render parts (bytes or part files) with the checks of `tyndall merge`."""
    ...

def write_exr(path: PathLike, image: npt.ArrayLike) -> None: ...
def write_png(path: PathLike, image: npt.ArrayLike, exposure: float = 0.0) -> None: ...
