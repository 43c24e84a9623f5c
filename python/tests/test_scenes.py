"""glint.load and glint.load_dict: every format, plain data, and errors that point at the mistake."""

import numpy as np
import pytest

import glint

SMALL = {"width": 32, "height": 24, "spp": 1, "progress": False}

TEXT = """\
settings { width 40 height 30 background [0.1 0.2 0.3] integrator path { max_depth 5 } }
camera { eye [0 1 5] look_at [0 0.5 0] fov 40 }
texture "checks" checker { cells [4 4] }
material "floor" { diffuse 1 texture "checks" }
material "red" { diffuse [0.8 0.1 0.1] bsdf plastic { roughness 0.2 } }
material "lamp" { emission [4 4 4] }
light point { position [2 4 3] color 1 }
define "ball" { sphere { material "red" scale 0.5 } }
plane { material "floor" }
use "ball" { translate [0 0.5 0] }
group { rotate [0 1 0] 30 translate [1 0 0] cube { scale 0.2 } }
rectangle { material "lamp" scale 0.5 rotate [1 0 0] 180 translate [0 3 0] }
"""

DATA = {
    "settings": {"width": 40, "height": 30, "background": [0.1, 0.2, 0.3], "integrator": {"path": {"max_depth": 5}}},
    "camera": {"eye": [0, 1, 5], "look_at": [0, 0.5, 0], "fov": 40},
    "textures": {"checks": {"checker": {"cells": [4, 4]}}},
    "materials": {
        "floor": {"diffuse": 1, "texture": "checks"},
        "red": {"diffuse": [0.8, 0.1, 0.1], "bsdf": {"plastic": {"roughness": 0.2}}},
        "lamp": {"emission": [4, 4, 4]},
    },
    "lights": [{"point": {"position": [2, 4, 3], "color": 1}}],
    "defines": {"ball": {"sphere": {"material": "red", "scale": 0.5}}},
    "objects": [
        {"plane": {"material": "floor"}},
        {"use": ["ball", {"translate": [0, 0.5, 0]}]},
        {"group": {"rotate": [[0, 1, 0], 30], "translate": [1, 0, 0], "cube": {"scale": 0.2}}},
        {"rectangle": {"material": "lamp", "scale": 0.5, "rotate": [[1, 0, 0], 180], "translate": [0, 3, 0]}},
    ],
}


def test_a_dict_renders_as_the_same_scene_written_as_text(tmp_path):
    path = tmp_path / "scene.glint"
    path.write_text(TEXT)
    from_text = glint.load(path)
    from_data = glint.load_dict(DATA)
    assert (from_data.width, from_data.height, from_data.integrator) == (40, 30, "path")
    assert from_data.format == "data" and from_text.format == "native"
    assert np.array_equal(glint.render(from_text, **SMALL), glint.render(from_data, **SMALL))
    assert np.array_equal(glint.render(DATA, **SMALL), glint.render(from_data, **SMALL))


def test_a_wrong_key_raises_naming_it():
    data = {"objects": [{"cube": None}, {"sphere": {"materail": "red"}}]}
    with pytest.raises(glint.SceneError) as caught:
        glint.load_dict(data)
    error = caught.value
    assert str(error).startswith("objects[1].sphere.materail: unknown property 'materail'"), str(error)
    assert error.file == "objects[1].sphere.materail"
    assert isinstance(error, ValueError)
    with pytest.raises(glint.SceneError, match=r"^lightz: unknown key 'lightz' of a scene"):
        glint.load_dict({"lightz": []})
    with pytest.raises(glint.SceneError, match=r"^settings\.width: "):
        glint.load_dict({"settings": {"width": "wide"}})
    with pytest.raises(glint.SceneError, match=r"^materials\.red\.bsdf\.plastik: "):
        glint.load_dict({"materials": {"red": {"bsdf": {"plastik": {}}}}})
    with pytest.raises(TypeError, match=r"objects\[0\]\.sphere\.scale: a set has no place"):
        glint.load_dict({"objects": [{"sphere": {"scale": {1, 2}}}]})


def test_numpy_values_are_plain_data():
    scene = glint.load_dict({"camera": {"eye": np.array([0.0, 1.0, 5.0])}, "settings": {"width": np.int64(16)}})
    assert scene.width == 16


def test_a_missing_file_raises_file_not_found_naming_it(tmp_path):
    missing = tmp_path / "nowhere.glint"
    with pytest.raises(FileNotFoundError, match="nowhere.glint"):
        glint.load(missing)
    with pytest.raises(FileNotFoundError, match="nowhere.glint"):
        glint.render(missing)


def test_errors_in_a_file_carry_file_line_and_column(tmp_path):
    path = tmp_path / "bad.glint"
    path.write_text("settings { width 32 }\nsphere { radus 2 }\n")
    with pytest.raises(glint.SceneError) as caught:
        glint.load(path)
    error = caught.value
    assert str(error).startswith(f"{path}:2:10: unknown property 'radus'"), str(error)
    assert (error.file, error.line, error.column, error.kind) == (str(path), 2, 10, "invalid")
    texture = tmp_path / "texture.glint"
    texture.write_text('texture "t" image {\n  file "missing.png"\n}\n')
    with pytest.raises(glint.SceneError, match=r"texture\.glint:2:\d+: .*missing\.png"):
        glint.load(texture)


def test_every_format_loads(scenes):
    for path in sorted((scenes / "challenge").glob("*.yml"))[:1]:
        scene = glint.load(path)
        assert scene.format == "challenge-yaml"
        assert glint.render(scene, **SMALL).shape == (24, 32, 3)
    assert glint.default_scene().format == "default"
    assert "glint.Scene" in repr(glint.default_scene())
