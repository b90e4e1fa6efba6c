import os
from typing import Any, Callable, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

PathLike = Union[str, os.PathLike[str]]

class Scene:
    """A loaded scene and the render settings its file gives."""

    @classmethod
    def from_dict(
        cls, description: Mapping[str, Any], base_dir: Optional[PathLike] = None
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
    ) -> npt.NDArray[np.float32]:
        """Render; linear radiance, float32, shape H×W×3."""
        ...

def load(path: PathLike, two_sided: bool = False) -> Scene: ...
def demo() -> Scene: ...
def write_exr(path: PathLike, image: npt.ArrayLike) -> None: ...
def write_png(path: PathLike, image: npt.ArrayLike, exposure: float = 0.0) -> None: ...
