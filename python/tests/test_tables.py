"""The package's tables equal the CSVs that `pbdda run` writes, and its results folder equals
the CLI's.

One example with bodies, contacts and connectors (examples/connector_bolt.toml, a bolt across
two blocks) run for 20 steps with a row every step: after every step, bodies(), contacts() and
connectors() hold the values of that step's rows of the CLI's bodies.csv, contacts.csv and
connectors.csv, read with Python's csv module, bit for bit (both come from the same f64; the
files write them in shortest round-trip form, which parses back to the same bits). The folder
that pbdda.run writes equals the CLI's byte for byte, but for the wall-time values (steps.csv's
wall_seconds column and run.log's closing line) and the digits they move (docs/scene-format.md,
Row layout): steps.csv is compared value for value without that column; run.log's lines are
equal up to their wall times, its `overrides:` line (the record of the --set options) included.
monitors() holds monitors.csv's rows of every step of an example with a monitor point
(examples/7_6_sliding_block_cohesion.toml), bit for bit.
"""

import subprocess
from pathlib import Path

import numpy as np

import pbdda
from conftest import EXAMPLES, assert_same_table, read_rows

SCENE = EXAMPLES / "connector_bolt.toml"
SET = {"time.steps": 20, "output.every": 1}
CLI_SET = ["--set", "time.steps=20", "--set", "output.every=1"]


def by_step(rows):
    out = {}
    for r in rows:
        out.setdefault(int(r["step"]), []).append(r)
    return out


def test_tables_equal_the_clis_csvs(cli, tmp_path):
    out = tmp_path / "cli"
    subprocess.run([cli, "run", "-q", str(SCENE), "--out", str(out), *CLI_SET], check=True)
    files = {name: by_step(read_rows(out / f"{name}.csv")) for name in ("bodies", "contacts", "connectors")}
    assert max(files["bodies"]) == 20
    sim = pbdda.load(SCENE, set=SET)
    seen = {"contacts": 0, "connectors": 0}
    for step in range(1, 21):
        assert sim.step() == 1
        for name in files:
            rows = files[name].get(step, [])
            table = sim.table(name)
            assert_same_table(table, rows, f"{name}.csv step {step}")
            seen[name] = seen.get(name, 0) + len(rows)
    # the example exercises every table
    assert seen["contacts"] > 0 and seen["connectors"] == 20
    assert sim.finished


def test_monitors_equal_the_clis_csv(cli, tmp_path):
    scene = EXAMPLES / "7_6_sliding_block_cohesion.toml"
    out = tmp_path / "cli"
    subprocess.run([cli, "run", "-q", str(scene), "--out", str(out), *CLI_SET], check=True)
    rows = by_step(read_rows(out / "monitors.csv"))
    sim = pbdda.load(scene, set=SET)
    for step in range(1, 21):
        sim.step()
        assert len(rows[step]) == 1
        assert_same_table(sim.monitors(), rows[step], f"monitors.csv step {step}")


def numbers_without_wall(path: Path):
    rows = read_rows(path)
    return [{k: v for k, v in r.items() if k != "wall_seconds"} for r in rows]


def test_results_folder_equals_the_clis(cli, tmp_path):
    a, b = tmp_path / "cli", tmp_path / "py"
    subprocess.run([cli, "run", "-q", str(SCENE), "--out", str(a), *CLI_SET], check=True)
    sim = pbdda.run(SCENE, b, set=SET)
    assert sim.finished and sim.output_dir == b
    listing = lambda d: sorted(str(p.relative_to(d)) for p in d.rglob("*") if p.is_file())
    assert listing(a) == listing(b)
    for rel in listing(a):
        if rel in ("steps.csv", "run.log"):
            continue
        assert (a / rel).read_bytes() == (b / rel).read_bytes(), rel
    assert numbers_without_wall(a / "steps.csv") == numbers_without_wall(b / "steps.csv")
    log = lambda d: (d / "run.log").read_text().splitlines()
    assert log(b)[0] == "overrides: --set time.steps=20 --set output.every=1"
    assert [l.split(" in ")[0] for l in log(a)] == [l.split(" in ")[0] for l in log(b)]
    assert log(b)[-1].startswith("completed 20 steps")


def test_writing_starts_before_the_first_step(tmp_path):
    """Results are written from step 1 on: write_to after a step is refused (OutputError)."""
    sim = pbdda.load(SCENE, set=SET)
    sim.step()
    try:
        sim.write_to(tmp_path / "late")
    except pbdda.OutputError as e:
        assert "at step 1" in str(e)
    else:
        raise AssertionError("write_to after a step was accepted")
    # and a folder with an earlier run's files is refused without overwrite, as --overwrite
    pbdda.run(SCENE, tmp_path / "r", set={"time.steps": 2})
    try:
        pbdda.run(SCENE, tmp_path / "r", set={"time.steps": 2})
    except pbdda.OutputError as e:
        assert "holds results of an earlier run" in str(e)
    else:
        raise AssertionError("an earlier run's folder was overwritten")
    pbdda.run(SCENE, tmp_path / "r", set={"time.steps": 2}, overwrite=True)
