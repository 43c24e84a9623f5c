"""Type stubs of glint's compiled module; the documented API is the ``glint`` package."""

from typing import Any, Callable, Mapping, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

__version__: str

class SceneError(ValueError):
    """A scene glint cannot read, located at ``file:line:column`` (the key path for data)."""

    file: str
    line: int
    column: int
    message: str
    kind: str

class Scene:
    """A scene description, ready to render; rendering never changes it."""

    @property
    def width(self) -> int: ...
    @property
    def height(self) -> int: ...
    @property
    def spp(self) -> int: ...
    @property
    def integrator(self) -> str: ...
    @property
    def format(self) -> str: ...
    @property
    def warnings(self) -> list[str]: ...

def load(path: str, frame: float = 0.0) -> Scene: ...
def load_dict(data: Mapping[str, Any], base_dir: str) -> Scene: ...
def default_scene() -> Scene: ...
def render_job(
    job: Job, *, threads: int = 0, progress: Optional[Callable[[int, int], Any]] = None
) -> Tuple[npt.NDArray[np.float32], str]: ...
def write(path: str, image: npt.NDArray[np.float32], transfer: str = "srgb", format: Optional[str] = None) -> None: ...
def read(path: str) -> npt.NDArray[np.float32]: ...
def encode_png(image: npt.NDArray[np.float32], transfer: str = "srgb") -> bytes: ...

class Job:
    """A scene with its render settings applied, cut into parts by a cluster render."""

    @property
    def tiles(self) -> int: ...

def prepare(
    scene: Scene,
    *,
    spp: Optional[int] = None,
    width: Optional[int] = None,
    height: Optional[int] = None,
    integrator: Optional[str] = None,
    seed: Optional[int] = None,
    samples: Optional[int] = None,
    max_depth: Union[int, str, None] = None,
    rr_depth: Optional[int] = None,
    sampler: Optional[str] = None,
    pattern: Optional[str] = None,
    filter: Optional[str] = None,
    filter_radius: Optional[float] = None,
    adaptive: Optional[Tuple[int, int, float]] = None,
    camera: Optional[int] = None,
) -> Job: ...
def render_job_part(job: Job, index: int, count: int, threads: int = 0) -> bytes: ...
def _job_from_json(json: bytes) -> Job: ...

class Merger:
    """Parts of one render added up as they arrive."""

    def __init__(self) -> None: ...
    def add(self, part: bytes) -> None: ...
    @property
    def progress(self) -> Tuple[int, int]: ...
    def finish(self) -> Tuple[npt.NDArray[np.float32], str]: ...
