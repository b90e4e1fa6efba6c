from typing import Any, Callable, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import PathLike, Scene

OPTIONS: Tuple[str, ...]
FAULT_ENV: str

def render(
    scene_or_path: Union[Scene, PathLike],
    tiles: Optional[int] = None,
    address: Optional[str] = None,
    *,
    two_sided: bool = False,
    max_retries: int = 3,
    cpus_per_task: int = 1,
    progress: Optional[Callable[[int, int], None]] = None,
    spp: Optional[int] = None,
    integrator: Optional[str] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    seed: Optional[int] = None,
    threads: Optional[int] = None,
    samples: Optional[Tuple[int, int]] = None,
) -> npt.NDArray[np.float32]:
    """Render the tiles as Ray tasks and merge them: equals `Scene.render` bit for bit."""
    ...
