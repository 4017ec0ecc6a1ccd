#!/usr/bin/env python3
"""Read every step of a pbdda run's ParaView time series with VTK's own reader and with meshio, and
compare both with the run's CSVs. Needs the Python packages `vtk`, `meshio` and `numpy`
(`pip install vtk meshio numpy`); the Python tests (python/tests/test_vtu.py, run by `.ci/run`)
run its checks on a short run of every example.

    scripts/check-vtu.py RESULTS_DIR [RESULTS_DIR ...]

For each `.vtu` listed in `RESULTS_DIR/vtk/scene.pvd`, read with `vtkXMLUnstructuredGridReader`:
- the reader reports no error or warning;
- one cell per body, then one line cell per `contacts.csv` row of that step (kind 10-15);
- the bodies' `rotation` and `angular_velocity` cell data equal the `bodies.csv` columns
  `rotation` and `omega` of that step, bit for bit (both are written from the same f64);
- the contact lines' `normal_force` and `shear_force` equal the `contacts.csv` columns, bit for bit;
- the connector lines (kind 20, after the contacts) have the `axial_force` of `connectors.csv`;
- meshio reads the file to the same points, the same number of cells and the same cell data (its
  cell blocks, concatenated in order, are VTK's cells), every array sized to the cells.
"""
import csv
import re
import sys
from pathlib import Path

import meshio
import numpy as np
import vtk
from vtk.util.numpy_support import vtk_to_numpy


class Messages:
    """Collects the reader's errors and warnings."""

    def __init__(self):
        self.seen = []

    def __call__(self, obj, event):
        self.seen.append(event)


def rows_by_step(path):
    by_step = {}
    with open(path, newline="") as f:
        for row in csv.DictReader(f):
            by_step.setdefault(int(row["step"]), []).append(row)
    return by_step


def number(text):
    return float(text) if text else 0.0


def check_dir(results):
    bodies = rows_by_step(results / "bodies.csv")
    contacts = rows_by_step(results / "contacts.csv")
    connectors_csv = results / "connectors.csv"
    connectors = rows_by_step(connectors_csv) if connectors_csv.exists() else {}
    pvd = (results / "vtk" / "scene.pvd").read_text()
    files = re.findall(r'file="([^"]+)"', pvd)
    for name in files:
        step = int(re.search(r"(\d+)", name).group(1))
        reader = vtk.vtkXMLUnstructuredGridReader()
        messages = Messages()
        for event in ("ErrorEvent", "WarningEvent"):
            reader.AddObserver(event, messages)
        reader.SetFileName(str(results / "vtk" / name))
        reader.Update()
        assert not messages.seen, f"{name}: {messages.seen}"
        grid = reader.GetOutput()
        cells = grid.GetCellData()
        array = lambda key: vtk_to_numpy(cells.GetArray(key))
        b, c = bodies.get(step, []), contacts.get(step, [])
        kind = array("kind")
        assert all(k < 10 for k in kind[: len(b)]), name
        assert all(10 <= k < 20 for k in kind[len(b) : len(b) + len(c)]), name
        for key, column in (("rotation", "rotation"), ("angular_velocity", "omega")):
            assert list(array(key)[: len(b)]) == [number(r[column]) for r in b], (name, key)
        for key in ("normal_force", "shear_force"):
            got = list(array(key)[len(b) : len(b) + len(c)])
            assert got == [number(r[key]) for r in c], (name, key)
        k = connectors.get(step, [])
        lines = slice(len(b) + len(c), len(b) + len(c) + len(k))
        assert all(x == 20 for x in kind[lines]), name
        assert list(array("axial_force")[lines]) == [number(r["axial_force"]) for r in k], name
        check_meshio(results / "vtk" / name, grid, cells)
    return len(files)


def check_meshio(path, grid, cells):
    """meshio reads `path` to what VTK's reader gave: points, cell count, every cell array."""
    mesh = meshio.read(path)
    points = vtk_to_numpy(grid.GetPoints().GetData())
    assert np.array_equal(mesh.points, points), path
    n = grid.GetNumberOfCells()
    assert sum(len(block.data) for block in mesh.cells) == n, path
    for i in range(cells.GetNumberOfArrays()):
        key = cells.GetArrayName(i)
        ours = np.concatenate([np.asarray(a).reshape(len(a), -1) for a in mesh.cell_data[key]])
        assert len(ours) == n, (path, key)
        assert np.array_equal(ours, vtk_to_numpy(cells.GetArray(key)).reshape(n, -1)), (path, key)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for d in sys.argv[1:]:
        n = check_dir(Path(d))
        print(f"ok   {d}: {n} files")


if __name__ == "__main__":
    main()
