"""glint.write and glint.read, and the image's picture in Jupyter."""

import numpy as np
import pytest

import glint


def gradient():
    image = np.zeros((6, 8, 3), dtype=np.float32)
    image[..., 0] = np.linspace(0, 1, 8)
    image[..., 1] = np.linspace(0, 2, 6)[:, None]
    image[..., 2] = 0.25
    return image


def test_exr_keeps_the_floats_exactly(tmp_path):
    image = gradient()
    glint.write(tmp_path / "a.exr", image)
    assert np.array_equal(glint.read(tmp_path / "a.exr"), image)


@pytest.mark.parametrize("name, tolerance", [("a.png", 0.02), ("a.ppm", 0.02)])
def test_8_bit_formats_round_trip_within_quantisation(tmp_path, name, tolerance):
    image = gradient().clip(0, 1)
    glint.write(tmp_path / name, image)
    back = glint.read(tmp_path / name)
    assert back.shape == image.shape
    assert np.abs(back - image).max() < tolerance


def test_write_refuses_what_it_cannot_write(tmp_path):
    with pytest.raises(ValueError, match="cannot tell the image format"):
        glint.write(tmp_path / "a.tiff", gradient())
    with pytest.raises(ValueError, match="shape"):
        glint.write(tmp_path / "a.png", np.zeros((4, 4)))
    with pytest.raises(ValueError, match="transfer='gamma'"):
        glint.write(tmp_path / "a.png", gradient(), transfer="gamma")
    glint.write(tmp_path / "a.bin", gradient(), format="png16")
    assert (tmp_path / "a.bin").read_bytes()[:4] == b"\x89PNG"
    with pytest.raises(OSError):
        glint.write(tmp_path / "no" / "such" / "dir.png", gradient())


def test_an_image_shows_itself_in_jupyter(tmp_path):
    image = glint.Image(gradient())
    png = image._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    glint.write(tmp_path / "a.png", image)
    assert (tmp_path / "a.png").read_bytes() == png, "the notebook shows what write() writes"
    assert (image * 2).transfer == "srgb" and (image * 2)._repr_png_() is not None
    assert image[0]._repr_png_() is None, "a row is not a picture"


def test_the_scene_transfer_travels_with_the_image(scenes, tmp_path):
    course = next((scenes / "challenge").glob("*.yml"))
    image = glint.render(course, width=16, height=12, spp=1, progress=False)
    assert image.transfer == "identity"
    glint.write(tmp_path / "scene.png", image)
    glint.write(tmp_path / "srgb.png", image, transfer="srgb")
    assert (tmp_path / "scene.png").read_bytes() != (tmp_path / "srgb.png").read_bytes()
