"""Sweeps from Python: the cases of ``pbdda sweep`` written as a plan (``--plan``), run in this
process or as tasks of a Dask cluster (each task is ``--run-plan DIR --shard K/N`` for one
case K), and collected into the same sweep.csv (``--collect``)."""

from __future__ import annotations

import os
import shutil
import tempfile
from pathlib import Path
from typing import Any, Mapping, Optional, Sequence

from . import _pbdda
from . import literal, _overrides


def _run_case(plan: str, k: int, n: int) -> int:
    """Runs case ``k`` of the ``n`` cases of the plan in ``plan`` (a Dask task); a finished
    case is skipped, so a task that is run again does nothing."""
    _pbdda.run_shard(plan, k, n, True)
    return k


def sweep(
    scene: "os.PathLike[str] | str",
    sweep: Mapping[str, Sequence[Any]],
    set: Any = None,
    out: "os.PathLike[str] | str" = ".",
    zip: bool = False,
    reference: Any = None,
    exact: Optional[str] = None,
    sizes: Optional[Sequence[float]] = None,
    plan: "os.PathLike[str] | str | None" = None,
    client: Any = None,
) -> Path:
    """Runs a sweep of the scene file ``scene`` and writes ``out``/sweep.csv (and sweep.png),
    as ``pbdda sweep`` does; returns the path of sweep.csv.

    ``sweep`` maps each swept key to its values (several keys make a grid, the first key
    slowest; ``zip=True`` pairs them); a value that is a str is used as the command line
    would take it (``"1e-3"``), other values as TOML literals. ``set`` holds the overrides of
    every case, ``reference``, ``exact`` and ``sizes`` are ``--reference``, ``--exact`` and
    ``--sizes``.

    ``client``: a ``dask.distributed.Client``; each case is then a task on its cluster (the
    workers must see ``plan``'s folder and the scene). ``plan``: the folder of the plan
    (``pbdda sweep --plan``); a folder that holds a plan already is taken as it is and only
    its unfinished cases run. Without it, a temporary folder inside ``out`` is used and
    removed at the end.
    """
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    axes = [(str(key), [literal(v) for v in values]) for key, values in sweep.items()]
    temporary = plan is None
    plan_dir = Path(tempfile.mkdtemp(prefix=".plan-", dir=out)) if temporary else Path(plan)
    try:
        if (plan_dir / "plan.toml").exists():
            n = _pbdda.plan_cases(os.fspath(plan_dir))
        else:
            if temporary:
                plan_dir.rmdir()  # the plan writer creates it
            n = _pbdda.plan_sweep(
                os.fspath(plan_dir),
                os.fspath(scene),
                axes,
                _overrides(set),
                bool(zip),
                None if reference is None else literal(reference),
                exact,
                None if sizes is None else [float(h) for h in sizes],
            )
        if client is None:
            _pbdda.run_shard(os.fspath(plan_dir), 0, 1, True)
        else:
            futures = [client.submit(_run_case, os.fspath(plan_dir), k, n, pure=False) for k in range(n)]
            client.gather(futures)
        _pbdda.collect_sweep(os.fspath(plan_dir), os.fspath(out))
    finally:
        if temporary:
            shutil.rmtree(plan_dir, ignore_errors=True)
    return out / "sweep.csv"
