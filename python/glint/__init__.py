"""glint, the ray tracer, from Python.

    import glint
    image = glint.render(glint.load("scenes/cornell-path.glint"), spp=16, width=320, height=240)
    glint.write("cornell.png", image)

Scenes come from a file of any format glint reads (:func:`load`), from plain Python data
with the native format's names (:func:`load_dict`) or built in (:func:`default_scene`).
:func:`render` returns an :class:`Image`: a float32 numpy array (height, width, 3) of
linear RGB that shows itself in Jupyter. Settings given to :func:`render` mean exactly
what the ``glint render`` flags of the same names mean, so both give the same pixels.
See docs/python.md.
"""

from __future__ import annotations

import errno
import os
import warnings
from typing import Any, Callable, Mapping, Optional, Tuple, Union

import numpy as np

from . import _glint
from ._glint import Scene, SceneError

__all__ = [
    "Image",
    "Scene",
    "SceneError",
    "SceneWarning",
    "default_scene",
    "load",
    "load_dict",
    "read",
    "render",
    "write",
]
__version__: str = _glint.__version__

PathLike = Union[str, "os.PathLike[str]"]
Progress = Union[bool, None, Callable[[int, int], Any]]


class SceneWarning(UserWarning):
    """Something harmless that glint skipped while reading a scene (an unknown element)."""


class Image(np.ndarray):
    """Linear RGB pixels: a float32 numpy array of shape (height, width, 3), row 0 on top.

    It is a numpy array in every way. It also carries ``transfer``, the scene's way of
    turning values into 8/16-bit pixels (``"srgb"``, or ``"identity"`` for the course
    formats), which :func:`write` and the notebook display use, and it shows itself as a
    picture in Jupyter. ``Image(array)`` wraps any such array for display.
    """

    transfer: str

    def __new__(cls, pixels: Any, transfer: str = "srgb") -> "Image":
        image = np.asarray(pixels, dtype=np.float32).view(cls)
        image.transfer = transfer
        return image

    def __array_finalize__(self, obj: Any) -> None:
        # Slices, copies and arithmetic keep the transfer of the image they came from.
        self.transfer = getattr(obj, "transfer", "srgb")

    def __array_wrap__(self, array: Any, *args: Any, **kwargs: Any) -> Any:
        # A reduction (image.mean(), image.max()) is a number, not an image.
        result = super().__array_wrap__(array, *args, **kwargs)
        if isinstance(result, Image) and not _is_picture(result):
            return result.view(np.ndarray)
        return result

    def _repr_png_(self) -> Optional[bytes]:
        """The picture Jupyter shows: 8-bit PNG, encoded as ``write`` would encode it."""
        if not _is_picture(self):
            return None
        return _glint.encode_png(_plain(self), self.transfer)


def _is_picture(array: np.ndarray) -> bool:
    return array.ndim == 3 and array.shape[2] == 3 and array.shape[0] > 0 and array.shape[1] > 0


def _plain(image: Any) -> np.ndarray:
    """A C-contiguous float32 base-class array, as the extension reads images."""
    return np.ascontiguousarray(np.asarray(image, dtype=np.float32)).view(np.ndarray)


def load(path: PathLike, frame: float = 0) -> Scene:
    """Reads a scene file of any format glint reads, recognised by its content: native
    ``.glint``, CS123/CS1230 course XML or JSON, Ray Tracer Challenge YAML, Mitsuba 3 XML,
    or a mesh (OBJ, PLY, glTF) framed by a fitted camera and two lights. An animated
    ``.glint`` scene is read at ``frame`` (fractions allowed).

    Raises ``FileNotFoundError`` when the file does not exist, and :class:`SceneError`
    (a ``ValueError``) for a mistake in it, with ``file:line:column`` in its message and
    attributes. Harmless oddities become :class:`SceneWarning` warnings.
    """
    name = os.fspath(path)
    if not os.path.exists(name):
        raise FileNotFoundError(errno.ENOENT, "no such scene file", name)
    scene = _glint.load(name, float(frame))
    for warning in scene.warnings:
        warnings.warn(f"{name}: {warning}", SceneWarning, stacklevel=2)
    return scene


def load_dict(data: Mapping[str, Any], base_dir: PathLike = ".") -> Scene:
    """Builds a scene from plain Python data with the native format's names.

    The top-level keys are ``include``, ``settings``, ``camera``, ``textures``,
    ``materials``, ``meshes``, ``lights``, ``defines`` and ``objects``; inside them a
    dict is a block of properties, a list of numbers a vector, a list of values several
    values (``"rotate": [[0, 1, 0], 30]``), ``None`` a node with nothing after it, and
    a list of dicts a block whose names may repeat. docs/python.md has the full rules::

        glint.load_dict({
            "settings": {"width": 64, "height": 48, "integrator": {"path": {"max_depth": 6}}},
            "camera": {"eye": [0, 1, 5], "look_at": [0, 0.5, 0]},
            "materials": {"red": {"diffuse": [0.8, 0.1, 0.1]}},
            "lights": [{"point": {"position": [2, 4, 3]}}],
            "objects": [{"sphere": {"material": "red"}}, {"plane": None}],
        })

    Relative file paths (textures, meshes, includes) are found from ``base_dir``.
    A mistake raises :class:`SceneError` whose message starts with the key path, e.g.
    ``objects[0].sphere.materail: unknown property 'materail' in 'sphere'; …``; a value
    that has no place in a scene (a set, an object) raises ``TypeError`` naming its path.
    """
    return _glint.load_dict(data, os.fspath(base_dir))


def default_scene() -> Scene:
    """The built-in scene ``glint render`` draws when given no file: mirror and glass
    spheres over a checkered floor."""
    return _glint.default_scene()


def render(
    scene: Union[Scene, PathLike, Mapping[str, Any]],
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
    threads: int = 0,
    progress: Progress = True,
) -> Image:
    """Renders a scene on every core and returns its linear RGB pixels as an :class:`Image`,
    a float32 numpy array of shape (height, width, 3).

    ``scene`` is a :class:`Scene`, a path (read by :func:`load`) or a dict (read by
    :func:`load_dict`). Each setting given replaces the scene's and means what the
    ``glint render`` flag of the same name means: ``spp`` samples per pixel in total;
    ``width``/``height`` in pixels; ``integrator`` ``"whitted"`` or ``"path"`` (a
    path-traced scene keeps its path settings); ``seed``; ``samples`` per axis;
    ``max_depth`` (-1 or ``"unlimited"`` for the path integrator); ``rr_depth`` and
    ``sampler`` (``"sobol"``/``"independent"``) for the path integrator; ``pattern``
    (``"grid"``, ``"corners"``, ``"jittered"``, ``"sobol"``); ``filter`` (``"box"``,
    ``"tent"``, ``"gaussian"``, ``"mitchell"``, ``"lanczos"``) and ``filter_radius``;
    ``adaptive`` as ``(min, max, threshold)``; ``camera`` picks one of the file's
    cameras (a glTF model or a pbrt-v4 scene may hold several), from 0. ``threads`` = 0
    uses every core; the image is the same for any count.

    The GIL is released while tracing, so other Python threads run. Ctrl-C stops the
    render between tiles and raises ``KeyboardInterrupt``. ``progress=True`` shows a
    ``tqdm`` bar when tqdm is installed, ``False`` shows none, and a callable is called
    as ``progress(done_tiles, total_tiles)`` on the calling thread.

    Raises ``ValueError`` for a setting glint does not know or that does not apply (such
    as ``rr_depth`` with the Whitted integrator), and :class:`SceneError` for a scene
    that cannot be rendered (a degenerate camera, an image too large).
    """
    callback, close = _progress_callback(progress)
    try:
        job = _glint.prepare(
            _as_scene(scene),
            spp=spp,
            width=width,
            height=height,
            integrator=integrator,
            seed=seed,
            samples=samples,
            max_depth=max_depth,
            rr_depth=rr_depth,
            sampler=sampler,
            pattern=pattern,
            filter=filter,
            filter_radius=filter_radius,
            adaptive=adaptive,
            camera=camera,
        )
        pixels, transfer = _glint.render_job(job, threads=threads, progress=callback)
    finally:
        close()
    return Image(pixels, transfer)


def _as_scene(scene: Union[Scene, PathLike, Mapping[str, Any]]) -> Scene:
    """A :class:`Scene` as given, a dict read by :func:`load_dict`, or a path by :func:`load`."""
    if isinstance(scene, Scene):
        return scene
    if isinstance(scene, Mapping):
        return load_dict(scene)
    return load(scene)


def _progress_callback(
    progress: Progress,
) -> Tuple[Optional[Callable[[int, int], Any]], Callable[[], None]]:
    """The per-tile callback for ``progress`` and what closes it after the render."""
    if callable(progress):
        return progress, lambda: None
    if not progress:
        return None, lambda: None
    try:
        from tqdm.auto import tqdm
    except ImportError:
        return None, lambda: None
    bars = []

    def update(done: int, total: int) -> None:
        if not bars:
            bars.append(tqdm(total=total, unit="tile", desc="rendering", leave=False))
        bars[0].update(done - bars[0].n)

    def close() -> None:
        for bar in bars:
            bar.close()

    return update, close


def write(
    path: PathLike,
    image: Any,
    *,
    transfer: Optional[str] = None,
    format: Optional[str] = None,
) -> None:
    """Writes an (height, width, 3) array of linear RGB to ``path`` with glint's writers,
    atomically (a failed write never leaves a half-written file under the name).

    The format follows ``format`` (``"png"``, ``"png16"``, ``"exr"``, ``"ppm"``) or else
    the extension (.png 8-bit, .exr 32-bit float linear, .ppm 8-bit). ``transfer``
    (``"srgb"`` or ``"identity"``) encodes the 8/16-bit formats; by default the image's
    own (:attr:`Image.transfer`), else sRGB, as ``glint render`` writes the scene.
    """
    if transfer is None:
        transfer = getattr(image, "transfer", "srgb")
    pixels = _plain(image)
    if not _is_picture(pixels):
        raise ValueError(f"expected an image of shape (height, width, 3), found {pixels.shape}")
    _glint.write(os.fspath(path), pixels, transfer, format)


def read(path: PathLike) -> Image:
    """Reads a PNG, PPM or EXR image as linear RGB (8/16-bit ones decoded from sRGB): the
    inverse of :func:`write`, for comparing renders."""
    name = os.fspath(path)
    if not os.path.exists(name):
        raise FileNotFoundError(errno.ENOENT, "no such image file", name)
    return Image(_glint.read(name))
