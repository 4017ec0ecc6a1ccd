"""Shared helpers of the Python tests: the repository's folders and the `pbdda` binary that
`cargo build --release` makes (the CLI the package is compared with)."""

import csv
import os
import shutil
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"


@pytest.fixture(scope="session")
def cli() -> str:
    """The pbdda command line: $PBDDA_BIN, else target/release/pbdda of this checkout, else
    `pbdda` on the PATH. .ci/run builds it before the Python tests."""
    for candidate in (os.environ.get("PBDDA_BIN"), ROOT / "target" / "release" / "pbdda", shutil.which("pbdda")):
        if candidate and Path(candidate).is_file():
            return str(candidate)
    pytest.fail("no pbdda binary: run `cargo build --release` first (or set PBDDA_BIN)")


def read_rows(path: Path) -> list:
    """The rows of a CSV file as dicts (the csv module's reading, independent of pbdda's)."""
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def as_array_of(rows: list, like: np.ndarray) -> np.ndarray:
    """CSV rows as an array of `like`'s dtype: numbers parsed by Python, '' as NaN."""
    out = np.empty(len(rows), dtype=like.dtype)
    for name in like.dtype.names:
        kind = like.dtype[name].kind
        if kind == "U":
            out[name] = [r[name] for r in rows]
        elif kind == "i":
            out[name] = [int(r[name]) for r in rows]
        else:
            out[name] = [float(r[name]) if r[name] != "" else np.nan for r in rows]
    return out


def assert_same_table(got: np.ndarray, rows: list, what: str) -> None:
    """`got` holds the values of `rows`, column for column, bit for bit (NaN for empty cells)."""
    expected = as_array_of(rows, got)
    assert len(got) == len(expected), f"{what}: {len(got)} rows, the CSV has {len(expected)}"
    for name in got.dtype.names:
        if got.dtype[name].kind == "f":
            same = np.array_equal(got[name], expected[name], equal_nan=True)
        else:
            same = np.array_equal(got[name], expected[name])
        assert same, f"{what}: column {name}: {got[name]} != {expected[name]}"
