"""pbdda from Python: particle-block discontinuous deformation analysis (PB-DDA).

Load a scene file or build one from dicts (the keys and tables of a scene file,
docs/scene-format.md), step it, read its bodies, contacts and connectors as numpy
structured arrays whose fields are the columns of bodies.csv, contacts.csv and
connectors.csv, write the results folder that ``pbdda run`` writes, and run sweeps,
in this process or on a Dask cluster::

    import pbdda
    sim = pbdda.load("examples/7_6_sliding_block_cohesion.toml", set={"time.steps": 50})
    sim.step(10)
    sim.bodies()["x"]                  # the bodies' centroid x after 10 steps
    sim.run_to(0.3)                    # steps until t >= 0.3 s (or the run's end)
    pbdda.run("scene.toml", "out")     # the whole run into out/, as `pbdda run`

Errors are exceptions carrying the reader's message: ``SceneError`` (with ``file``,
``line``, ``column``, ``key`` and ``message``), ``StepError``, ``OutputError`` and
``SweepError``, all subclasses of ``PbddaError``.
"""

from __future__ import annotations

import json
import math
import os
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _pbdda
from ._pbdda import OutputError, PbddaError, SceneError, StepError, SweepError

__version__ = _pbdda.__version__
__all__ = [
    "Simulation",
    "load",
    "from_dict",
    "from_toml",
    "to_toml",
    "run",
    "sweep",
    "PbddaError",
    "SceneError",
    "StepError",
    "OutputError",
    "SweepError",
]

PathLike = Union[str, "os.PathLike[str]"]
Overrides = Union[None, Mapping[str, Any], Iterable[str]]


def literal(value: Any) -> str:
    """A Python value as the VALUE of ``--set KEY=VALUE``: a str as it is (the command line's
    bare word: ``"rock"``, ``"1e-3"``), a bool, number or list as its TOML literal."""
    if isinstance(value, str):
        return value
    if isinstance(value, (bool, np.bool_)):
        return "true" if value else "false"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    if isinstance(value, (float, np.floating)):
        x = float(value)
        if math.isnan(x):
            return "nan"
        if math.isinf(x):
            return "inf" if x > 0 else "-inf"
        return repr(x)
    if isinstance(value, Mapping):
        items = ", ".join(f"{json.dumps(str(k))} = {_toml(v)}" for k, v in value.items())
        return "{ " + items + " }"
    if isinstance(value, (list, tuple, np.ndarray)):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    raise TypeError(f"cannot write a {type(value).__name__} as a scene value")


def _toml(value: Any) -> str:
    """A value inside an array or inline table: strings quoted."""
    if isinstance(value, str):
        return json.dumps(value)
    return literal(value)


def _overrides(set: Overrides) -> list:
    if set is None:
        return []
    if isinstance(set, str):
        return [set]
    if isinstance(set, Mapping):
        return [f"{k}={literal(v)}" for k, v in set.items()]
    return [str(s) for s in set]


def _structured(names: Sequence[str], columns: Sequence[Any]) -> np.ndarray:
    """A numpy structured array of the table's columns (text columns as fixed-width str)."""
    n = len(columns[0]) if columns else 0
    dtype = []
    for name, column in zip(names, columns):
        if isinstance(column, list):
            width = max((len(s) for s in column), default=1) or 1
            dtype.append((name, f"U{width}"))
        else:
            dtype.append((name, column.dtype))
    table = np.empty(n, dtype=dtype)
    for name, column in zip(names, columns):
        table[name] = column
    return table


class Simulation:
    """A scene's world, stepped from Python. Make one with :func:`load`, :func:`from_dict` or
    :func:`from_toml`."""

    def __init__(self, inner: "_pbdda.Simulation"):
        self._sim = inner

    # --- stepping -----------------------------------------------------------------------
    def step(self, n: int = 1) -> int:
        """Takes ``n`` steps (fewer at the end of the run); returns how many it took."""
        if n < 0:
            raise ValueError(f"step({n}): the number of steps must be >= 0")
        return self._sim.step(int(n))

    def run_to(self, time: float) -> int:
        """Steps until the simulated time reaches ``time`` (within 1e-9 of a step) or the run
        ends; returns how many steps it took."""
        taken = 0
        while not self._sim.finished and self._sim.time < time - 1e-9 * self._sim.dt:
            if self._sim.step(1) == 0:
                break
            taken += 1
        return taken

    def run(self) -> int:
        """Steps to the end of the run (``time.steps``); returns how many steps it took."""
        return self._sim.step(self._sim.steps - self._sim.step_index)

    # --- state --------------------------------------------------------------------------
    @property
    def time(self) -> float:
        """Simulated time [s]."""
        return self._sim.time

    @property
    def step_index(self) -> int:
        """Steps taken so far."""
        return self._sim.step_index

    @property
    def steps(self) -> int:
        """Steps of the whole run (``time.steps``)."""
        return self._sim.steps

    @property
    def dt(self) -> float:
        """The time step [s] the next step starts with."""
        return self._sim.dt

    @property
    def finished(self) -> bool:
        return self._sim.finished

    def table(self, name: str) -> np.ndarray:
        """The rows ``pbdda run`` writes for the current step into ``NAME.csv`` (``bodies``,
        ``contacts``, ``connectors`` or ``monitors``) as a structured array: one field per column, int64
        for integer columns, float64 for numbers (NaN where the cell is empty), str for text."""
        names, columns = self._sim.table(name)
        return _structured(names, columns)

    def bodies(self) -> np.ndarray:
        """bodies.csv's rows of the current step (fields step, time, body, x, y, rotation, ...)."""
        return self.table("bodies")

    def contacts(self) -> np.ndarray:
        """contacts.csv's rows of the last step (none before the first step)."""
        return self.table("contacts")

    def connectors(self) -> np.ndarray:
        """connectors.csv's rows of the current step (empty for a scene without connectors)."""
        return self.table("connectors")

    def monitors(self) -> np.ndarray:
        """monitors.csv's rows of the current step (empty for a scene without monitors)."""
        return self.table("monitors")

    def csv(self, name: str) -> str:
        """The current step's rows of ``NAME.csv`` as CSV text, with the header."""
        return self._sim.table_csv(name)

    # --- results ------------------------------------------------------------------------
    def write_to(self, out: PathLike, overwrite: bool = False) -> "Simulation":
        """Writes every step from now on into the folder ``out`` as ``pbdda run --out`` does
        (CSVs, geometry.csv, run.log, vtk/). Only before the first step."""
        self._sim.write_to(os.fspath(out), overwrite)
        return self

    def close(self) -> None:
        """Writes run.log's closing line now (the run's last step does it by itself)."""
        self._sim.close()

    @property
    def output_dir(self) -> Optional[Path]:
        d = self._sim.output_dir
        return None if d is None else Path(d)

    def __repr__(self) -> str:
        return f"<pbdda.Simulation step {self.step_index}/{self.steps}, t = {self.time:g} s>"


def load(path: PathLike, set: Overrides = None) -> Simulation:
    """The scene file at ``path``; ``set`` overrides keys as ``--set`` does, given as a dict
    ``{"time.step": 1e-3}`` or as ``["time.step=1e-3"]``."""
    return Simulation(_pbdda.Simulation.load(os.fspath(path), _overrides(set)))


def from_toml(text: str, file: str = "<scene>", set: Overrides = None) -> Simulation:
    """A scene from its TOML text; ``file`` names it in errors, and relative paths in it (a
    mesh's ``file``) are those of ``file``'s folder."""
    return Simulation(_pbdda.Simulation.parse(text, file, _overrides(set)))


def to_toml(scene: Mapping[str, Any]) -> str:
    """The TOML text of a scene given as dicts and lists (``{"time": {...}, "body": [{...}]}``);
    the text that :func:`from_dict` reads, whose lines its errors name."""
    return _pbdda.to_toml_text(dict(scene))


def from_dict(scene: Mapping[str, Any], file: str = "<dict>", set: Overrides = None) -> Simulation:
    """A scene from dicts with the keys of a scene file: tables as dicts, arrays of tables
    (``body``, ``material``, ...) as lists of dicts. It is written as TOML (:func:`to_toml`)
    and read as a scene file named ``file``, so errors name the key (and the line of that
    text)."""
    return from_toml(to_toml(scene), file, set)


def run(scene: PathLike, out: PathLike, set: Overrides = None, overwrite: bool = False) -> Simulation:
    """Runs the scene file to its end writing ``out`` as ``pbdda run SCENE --out OUT`` does;
    returns the finished simulation."""
    sim = load(scene, set).write_to(out, overwrite)
    sim.run()
    return sim


from ._sweep import sweep  # noqa: E402  (uses the names above)
