# The mechgen command line built with the module (ctest sets MECHGEN_BUILD_DIR), the repository's
# models, and the CLI's CSV read back as columns: what the module's results are checked against.
import csv
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(os.environ.get("MECHGEN_BUILD_DIR", ROOT / "build"))


def model_path(name):
    return str(ROOT / "models" / f"{name}.yaml")


def run_cli(*args):
    return subprocess.run([str(BUILD / "mechgen"), *args], check=True, capture_output=True,
                          text=True).stdout


def cli_info(name):
    return json.loads(run_cli("info", model_path(name), "--json"))


def cli_sweep(tmp_path, name, *options):
    out = tmp_path / f"{name}.csv"
    run_cli("sweep", model_path(name), "--out", str(out), *options)
    with open(out, newline="") as f:
        rows = list(csv.reader(f))
    header, body = rows[0], np.array(rows[1:], dtype=float)
    return {c: body[:, i] for i, c in enumerate(header)}, header


@pytest.fixture
def cli():
    if not (BUILD / "mechgen").exists():
        pytest.fail(f"no mechgen binary in {BUILD}")
    return {"info": cli_info, "sweep": cli_sweep, "path": model_path}
