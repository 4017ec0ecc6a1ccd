"""meshio and VTK's own XML reader read every example's .vtu files, and their values equal the
run's CSVs (scripts/check-vtu.py's checks, listed in its docstring: bit for bit, as both are
written from the same f64). Every example runs 4 steps with a file every 2 steps through
pbdda.run, which writes the folder `pbdda run` writes (test_tables.py)."""

import importlib.util

import pytest

import pbdda
from conftest import EXAMPLES, ROOT

spec = importlib.util.spec_from_file_location("check_vtu", ROOT / "scripts" / "check-vtu.py")
check_vtu = importlib.util.module_from_spec(spec)
spec.loader.exec_module(check_vtu)

SCENES = sorted(EXAMPLES.glob("*.toml"))


def test_examples_are_all_here():
    # tests/io/vtk_output.rs counts the examples too
    assert len(SCENES) == 28


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_vtu_files_read_back_to_the_csvs(scene, tmp_path):
    out = tmp_path / scene.stem
    pbdda.run(scene, out, set={"time.steps": 4, "output.every": 2})
    # steps 2 and 4, one file each (as tests/io/vtk_output.rs)
    assert check_vtu.check_dir(out) == 2
    assert sorted(p.name for p in (out / "vtk").glob("*.vtu")) == ["step_000002.vtu", "step_000004.vtu"]
