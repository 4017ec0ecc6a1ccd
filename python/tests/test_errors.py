"""Bad input raises exceptions that carry the reader's message: file, line, key.

The corpus of tests/bad_inputs (each scene with its .expect sidecar listing the fragments its
error must contain, the same check as tests/bad_inputs.rs) through pbdda.load; scenes from
dicts name the key path of the bad value.
"""

from pathlib import Path

import pytest

import pbdda
from conftest import ROOT

CORPUS = ROOT / "tests" / "bad_inputs"


def test_every_bad_scene_raises_with_its_message():
    scenes = sorted(CORPUS.glob("*.toml"))
    # tests/bad_inputs.rs counts 111 scenes (and 10 meshes) in the corpus
    assert len(scenes) == 111
    for path in scenes:
        with pytest.raises(pbdda.SceneError) as info:
            pbdda.load(path)
        message = str(info.value)
        for fragment in path.with_suffix(".expect").read_text().splitlines():
            if fragment:
                assert fragment in message, (path.name, fragment, message)
        assert info.value.file == str(path)


def test_dict_scene_names_the_key():
    scene = {
        "scene": {"name": "two disks"},
        "time": {"step": 0.01, "steps": 10},
        "material": [{"name": "m", "density": 1000.0}],
        "body": [
            {"name": "a", "shape": "disk", "center": [0.0, 0.0], "radius": 1.0, "material": "m"},
            {"name": "b", "shape": "disk", "center": [5.0, 0.0], "radius": -2.0, "material": "m"},
        ],
    }
    with pytest.raises(pbdda.SceneError) as info:
        pbdda.from_dict(scene, file="study.toml")
    e = info.value
    assert e.key == "body[1].radius" and e.file == "study.toml"
    # the line is that of the key in the TOML text from_dict reads (pbdda.to_toml)
    lines = pbdda.to_toml(scene).splitlines()
    assert lines[e.line - 1].startswith("radius = -2")
    assert str(e).startswith(f"study.toml:{e.line}:")


def test_unknown_key_and_bad_override():
    with pytest.raises(pbdda.SceneError) as info:
        pbdda.from_dict({"scene": {"name": "x"}, "time": {"step": 0.01, "stepz": 3}})
    assert info.value.key == "time.stepz", str(info.value)
    path = ROOT / "examples" / "7_6_sliding_block_cohesion.toml"
    with pytest.raises(pbdda.SceneError) as info:
        pbdda.load(path, set={"time.step": "fast"})
    assert info.value.key == "time.step"
    with pytest.raises(pbdda.SceneError):
        pbdda.load(path, set=["no equals sign"])
    with pytest.raises(pbdda.SceneError) as info:
        pbdda.load(ROOT / "no_such_scene.toml")
    assert "cannot read the scene file" in str(info.value)
