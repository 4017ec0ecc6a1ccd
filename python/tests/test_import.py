"""The package imports, and a scene file loads to the bodies it lists."""

import tomllib

import numpy as np

import pbdda
from conftest import EXAMPLES


def test_import_and_api():
    for name in ("load", "from_dict", "from_toml", "to_toml", "run", "sweep", "Simulation", "SceneError"):
        assert hasattr(pbdda, name), name
    assert issubclass(pbdda.SceneError, pbdda.PbddaError)


def test_load_lists_the_scene_files_bodies():
    """bodies() has one row per [[body]] of the file, in its order, at step 0 and t = 0."""
    path = EXAMPLES / "7_6_sliding_block_cohesion.toml"
    scene = tomllib.loads(path.read_text())
    sim = pbdda.load(path)
    bodies = sim.bodies()
    assert list(bodies["body"]) == [b["name"] for b in scene["body"]]
    assert (sim.step_index, sim.time, sim.steps) == (0, 0.0, scene["time"]["steps"])
    assert np.all(bodies["step"] == 0)
    # the fixed base's centroid is the centre of its rectangle [-2, 4] x [-1, 0]
    base = bodies[bodies["body"] == "base"][0]
    # (shoelace formula in floating point: 1e-12 m covers its rounding)
    assert abs(base["x"] - 1.0) < 1e-12 and abs(base["y"] + 0.5) < 1e-12
    assert len(sim.contacts()) == 0 and len(sim.connectors()) == 0
