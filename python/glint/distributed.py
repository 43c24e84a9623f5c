"""Rendering on a cluster with Dask distributed: the same image as :func:`glint.render`,
bit for bit, from parts rendered on many machines.

    from dask.distributed import Client
    import glint, glint.distributed
    client = Client("scheduler:8786")            # or LocalCluster(), SLURMCluster(), KubeCluster()
    image = glint.distributed.render("scene.glint", client, parts=64, spp=256)

The scene, with its settings applied, is sent to every worker once (``client.scatter``
with ``broadcast=True``); each worker builds its BVH once and renders parts of it — part
``i`` of ``n`` traces every ``n``-th tile of 16×16 pixels — and returns the part's
weighted sums, which are added up here as they arrive. A worker lost mid-render costs
only its parts: Dask runs them again elsewhere, and since a part is a pure function of
the scene, the image is the same. The code is the same on a laptop's ``LocalCluster``,
on Slurm (``dask_jobqueue.SLURMCluster``) and on Kubernetes (``dask_kubernetes``).
"""

from __future__ import annotations

import os
import uuid
from typing import Any, Iterable, List, Mapping, Optional, Sequence, Union

from . import Image, Scene, _as_scene, _glint, _progress_callback, write

__all__ = ["render", "render_frames"]


def _default_parts(client: Any, tiles: int) -> int:
    """Four parts per worker thread (so a slow or lost worker holds back little), at
    most one per tile."""
    threads = sum(client.nthreads().values()) or 1
    return max(1, min(tiles, 4 * threads))


def _render_part(job: Any, index: int, count: int) -> bytes:
    # One task per worker thread at a time: each renders its part on one thread.
    return _glint.render_job_part(job, index, count, threads=1)


def render(
    scene: Union[Scene, str, "os.PathLike[str]", Mapping[str, Any]],
    client: Any,
    parts: Optional[int] = None,
    *,
    progress: Any = True,
    retries: int = 3,
    **overrides: Any,
) -> Image:
    """Renders ``scene`` on the workers of the Dask ``client`` and returns what
    :func:`glint.render` returns for the same scene and ``overrides`` (``spp``, ``width``,
    ``height``, ``integrator``, ``seed``, …): the same pixels, bit for bit.

    ``parts`` (default: four per worker thread, at most one per tile) is how many pieces
    the image is cut into. ``progress`` is as in :func:`glint.render`, counting parts.
    ``retries`` is how often a part whose worker died is run again.
    """
    job = _glint.prepare(_as_scene(scene), **overrides)
    count = parts if parts is not None else _default_parts(client, job.tiles)
    if not 1 <= count <= job.tiles:
        raise ValueError(f"parts must be from 1 to the image's {job.tiles} tiles, got {count}")
    # A key of its own (hash=False): two renders of the same job must not share one,
    # or the first to finish would release the other's copy.
    shared = client.scatter(job, broadcast=True, hash=False)
    token = uuid.uuid4().hex
    futures = [
        client.submit(_render_part, shared, index, count, key=f"glint-part-{token}-{index}", retries=retries)
        for index in range(count)
    ]
    return _merge_as_completed(futures, progress)


def _merge_as_completed(futures: Sequence[Any], progress: Any) -> Image:
    from dask.distributed import as_completed

    callback, close = _progress_callback(progress)
    merger = _glint.Merger()
    try:
        for done, future in enumerate(as_completed(futures), start=1):
            merger.add(future.result())
            if callback is not None:
                callback(done, len(futures))
    finally:
        close()
    pixels, transfer = merger.finish()
    return Image(pixels, transfer)


def _render_frame(job: Any) -> bytes:
    return _glint.render_job_part(job, 0, 1, threads=1)


def render_frames(
    path: Union[str, "os.PathLike[str]"],
    client: Any,
    frames: Iterable[int],
    output: Optional[str] = None,
    *,
    progress: Any = True,
    retries: int = 3,
    **overrides: Any,
) -> List[Image]:
    """Renders frames of the animated scene at ``path`` on the workers of ``client``, one
    task per frame, each frame the scene at its own time as ``glint render --frames``
    reads it. Returns the images in frame order; with ``output`` (a path with a run of
    ``#``, as ``out_####.png``) each frame is also written there as it arrives.
    """
    frames = list(frames)
    jobs = [_glint.prepare(_glint.load(os.fspath(path), float(frame)), **overrides) for frame in frames]
    token = uuid.uuid4().hex
    futures = [
        client.submit(_render_frame, job, key=f"glint-frame-{token}-{frame}", retries=retries)
        for frame, job in zip(frames, jobs)
    ]
    from dask.distributed import as_completed

    callback, close = _progress_callback(progress)
    images: List[Optional[Image]] = [None] * len(frames)
    try:
        for done, future in enumerate(as_completed(futures), start=1):
            at = futures.index(future)
            merger = _glint.Merger()
            merger.add(future.result())
            pixels, transfer = merger.finish()
            images[at] = Image(pixels, transfer)
            if output is not None:
                write(frame_path(output, frames[at]), images[at])
            if callback is not None:
                callback(done, len(futures))
    finally:
        close()
    return [image for image in images if image is not None]


def frame_path(pattern: str, frame: int) -> str:
    """``pattern`` with the last run of ``#`` in its file name replaced by ``frame``,
    padded with zeros to the run's length, as ``glint render -o out_####.png`` names
    frames."""
    head, name = os.path.split(pattern)
    end = name.rfind("#")
    if end < 0:
        raise ValueError(f"the output '{pattern}' needs a run of # for the frame number, as in out_####.png")
    start = len(name[:end + 1].rstrip("#"))
    width = end + 1 - start
    return os.path.join(head, f"{name[:start]}{frame:0{width}d}{name[end + 1:]}")
