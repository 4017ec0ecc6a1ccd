#!/usr/bin/env python3
"""Read every step of a pbdda run's ParaView time series with VTK's own reader and compare it with
the run's CSVs. Needs the Python `vtk` package (`pip install vtk`); not run by `cargo test`.

    scripts/check-vtu.py RESULTS_DIR [RESULTS_DIR ...]

For each `.vtu` listed in `RESULTS_DIR/vtk/scene.pvd`, read with `vtkXMLUnstructuredGridReader`:
- the reader reports no error or warning;
- one cell per body, then one line cell per `contacts.csv` row of that step (kind 10-15);
- the bodies' `rotation` and `angular_velocity` cell data equal the `bodies.csv` columns
  `rotation` and `omega` of that step, bit for bit (both are written from the same f64);
- the contact lines' `normal_force` and `shear_force` equal the `contacts.csv` columns, bit for bit.

Run on 2026-11-27 (VTK 9.7.2) on the output of every `examples/*.toml` and of a 10,000-disk pile
(60 steps): every file read without a message and every comparison held.
"""
import csv
import re
import sys
from pathlib import Path

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
    return len(files)


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for d in sys.argv[1:]:
        n = check_dir(Path(d))
        print(f"ok   {d}: {n} files")


if __name__ == "__main__":
    main()
