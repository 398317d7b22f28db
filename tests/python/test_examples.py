# examples/python/ at small sizes: each runs and its figures hold up against the module's own.
import os
import re
import subprocess
import sys

import numpy as np

import mechgen
from conftest import ROOT, model_path


def run_example(name, *args):
    return subprocess.run([sys.executable, str(ROOT / "examples" / "python" / name), *args],
                          check=True, capture_output=True, text=True, env=os.environ).stdout


def test_optimisation_lowers_the_rms_torque():
    out = run_example("optimise_hip.py", "--samples", "61")
    start = float(re.search(r"description's hip: ([0-9.]+)", out).group(1))
    best = float(re.search(r"least RMS motor torque: ([0-9.]+)", out).group(1))
    cx, cy = (float(v) for v in re.search(r"hip_cx = ([-0-9.]+), hip_cy = ([-0-9.]+)",
                                          out).groups())
    assert best < start
    # The reported optimum is what a sweep at those parameters gives.
    sweep = mechgen.Model(model_path("pasibot")).kernel().sweep(
        samples=61, params={"hip_cx": cx, "hip_cy": cy})
    assert abs(np.sqrt(np.mean(sweep["theta8.effort"] ** 2)) - best) < 1e-5


def test_plot_writes_the_figure(tmp_path):
    import matplotlib.image

    out = tmp_path / "sweep.png"
    assert "61 samples" in run_example("plot_sweep.py", "--samples", "61", "--out", str(out))
    assert matplotlib.image.imread(str(out)).shape[:2] == (400, 1000)


def test_workspace_bounds_hold_the_step():
    out = run_example("quadruped_workspace.py", "--samples", "20000")
    assembled = int(re.search(r"s; (\d+) assembled", out).group(1))
    assert 0 < assembled <= 20000
    bounds = {axis: tuple(float(v) for v in m) for axis, *m in
              re.findall(r"D\.([xyz]): ([-0-9.]+) \.\. ([-0-9.]+)", out)}
    assert set(bounds) == {"x", "y", "z"}
    # The model's own step stays within its strokes, so the random workspace nearly contains it.
    step = mechgen.Model(model_path("quadruped_leg")).kernel().sweep(samples=50)
    for axis, (low, high) in bounds.items():
        assert low - 0.01 <= step[f"D.{axis}"].min() and step[f"D.{axis}"].max() <= high + 0.01
