"""pbdda.sweep equals `pbdda sweep`: on a Dask LocalCluster of two worker processes (each case
a task) and in this process, sweep.csv is the CLI's byte for byte except the wall_seconds
column (the cases are deterministic, tests/determinism.rs, and their results are stored with
round-trip formatting, src/cli/sweep/plan.rs). The sweep is tests/io/sweep_plan.rs's: the bolted
slope's three bolt strengths over every bolt (a wildcard), 60 steps each."""

import subprocess

import pytest

import pbdda
from conftest import EXAMPLES

SCENE = EXAMPLES / "bolted_slope.toml"


def without_wall(path):
    lines = path.read_text().splitlines()
    wall = lines[0].split(",").index("wall_seconds")
    return [",".join(c for i, c in enumerate(l.split(",")) if i != wall) for l in lines]


@pytest.fixture(scope="module")
def cli_sweep(cli, tmp_path_factory):
    out = tmp_path_factory.mktemp("cli")
    subprocess.run(
        [cli, "sweep", str(SCENE), "--set", "connector[*].strength=1e5,2e5,5e5", "--set", "time.steps=60",
         "-q", "--out", str(out)],
        check=True,
        capture_output=True,
    )
    expected = without_wall(out / "sweep.csv")
    # a header and one row per case
    assert len(expected) == 4
    return expected, sorted(p.name for p in out.iterdir())


def run(out, **kw):
    return pbdda.sweep(
        SCENE, {"connector[*].strength": ["1e5", "2e5", "5e5"]}, set={"time.steps": 60}, out=out, **kw
    )


def test_dask_sweep_equals_the_cli(cli_sweep, tmp_path):
    import dask.distributed as distributed

    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            assert len(client.scheduler_info()["workers"]) == 2
            path = run(tmp_path / "dask", client=client, plan=tmp_path / "plan")
    assert without_wall(path) == cli_sweep[0]
    # the workers wrote every case's result into the plan
    assert len(list((tmp_path / "plan" / "results").glob("case-*.toml"))) == 3


def test_in_process_sweep_equals_the_cli(cli_sweep, tmp_path):
    path = run(tmp_path / "here")
    assert without_wall(path) == cli_sweep[0]
    # the same files as the CLI's folder: the temporary plan is gone
    assert sorted(p.name for p in (tmp_path / "here").iterdir()) == cli_sweep[1]


def test_sweep_errors_name_what_is_wrong(tmp_path):
    with pytest.raises(pbdda.SweepError) as info:
        pbdda.sweep(SCENE, {}, out=tmp_path)
    assert "empty grid" in str(info.value)
    with pytest.raises(pbdda.SceneError) as info:
        pbdda.sweep(SCENE, {"time.step": ["fast", "slow"]}, out=tmp_path)
    assert "case 0 (time.step=fast)" in str(info.value)
    assert info.value.key == "time.step"
