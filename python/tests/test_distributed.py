"""Cluster rendering on Dask: parts merge into glint.render's pixels bit for bit, for
any number of parts, even when a worker dies mid-render; jobs pickle; animated frames."""

import os
import pickle

import numpy as np
import pytest

import glint
import glint.distributed

distributed = pytest.importorskip("dask.distributed")

SETTINGS = dict(width=64, height=48, spp=8)


@pytest.fixture(scope="module")
def client():
    """Two worker processes of one thread each, as two machines would be."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as c:
            yield c


def bits(image):
    return np.asarray(image, dtype=np.float32).view(np.uint32)


@pytest.mark.parametrize("parts", [1, 3, 12])
def test_parts_merge_to_the_single_render(client, scenes, parts):
    scene = glint.load(scenes / "cornell-path.glint")
    alone = glint.render(scene, progress=False, **SETTINGS)
    spread = glint.distributed.render(scene, client, parts=parts, progress=False, **SETTINGS)
    assert spread.shape == (48, 64, 3) and spread.dtype == np.float32
    assert np.array_equal(bits(spread), bits(alone))
    assert spread.transfer == alone.transfer


def test_a_worker_killed_mid_render_costs_nothing(client, scenes):
    scene = glint.load(scenes / "soft-shadows.glint")
    settings = dict(width=160, height=96)
    alone = glint.render(scene, progress=False, **settings)
    killed = []

    def kill_a_worker(done, total):
        # After the first part is in, the other worker still has parts queued or running.
        if not killed:
            worker = sorted(client.scheduler_info()["workers"])[0]
            killed.append(worker)
            try:
                client.run(os._exit, 1, workers=[worker], wait=False)
            except Exception:
                pass

    spread = glint.distributed.render(scene, client, parts=30, progress=kill_a_worker, **settings)
    assert killed, "no worker was killed"
    assert np.array_equal(bits(spread), bits(alone))


def test_jobs_pickle_and_render_the_same_part(scenes):
    job = glint._glint.prepare(glint.load(scenes / "cornell-path.glint"), **SETTINGS)
    again = pickle.loads(pickle.dumps(job))
    assert again.tiles == job.tiles == 4 * 3
    assert glint._glint.render_job_part(again, 1, 4, threads=1) == glint._glint.render_job_part(job, 1, 4, threads=1)


def test_parts_of_other_renders_are_refused(scenes):
    scene = glint.load(scenes / "cornell-path.glint")
    one = glint._glint.prepare(scene, **SETTINGS)
    other = glint._glint.prepare(scene, seed=7, **SETTINGS)
    merger = glint._glint.Merger()
    merger.add(glint._glint.render_job_part(one, 0, 2, threads=1))
    with pytest.raises(ValueError, match="another render"):
        merger.add(glint._glint.render_job_part(other, 1, 2, threads=1))
    with pytest.raises(ValueError, match="part 1 of 2 is missing"):
        merger.finish()


def test_bad_part_counts_are_named(client, scenes):
    with pytest.raises(ValueError, match="parts must be from 1"):
        glint.distributed.render(scenes / "cornell-path.glint", client, parts=0, **SETTINGS)


def test_frames_render_on_the_cluster_as_the_cli_reads_them(client, scenes, tmp_path):
    path = scenes / "bounce.glint"
    out = str(tmp_path / "f_###.png")
    images = glint.distributed.render_frames(path, client, [3, 20], out, progress=False, width=48, height=27)
    for frame, image in zip([3, 20], images):
        alone = glint.render(glint.load(path, frame=frame), progress=False, width=48, height=27)
        assert np.array_equal(bits(image), bits(alone)), f"frame {frame}"
        assert (tmp_path / f"f_{frame:03d}.png").exists()
    assert not np.array_equal(images[0], images[1]), "the ball moved between frames"
