"""The quadruped leg's foot workspace: random cylinder lengths within the drivers' ranges, every
sample's points in one call of the kernel's point_positions entry.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/quadruped_workspace.py [--samples N]
"""
import argparse
import pathlib
import time

import numpy as np

import mechgen

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000)
    parser.add_argument("--model", default=str(ROOT / "models" / "quadruped_leg.yaml"))
    parser.add_argument("--point", default="D", help="the foot")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()

    model = mechgen.Model(args.model)
    kernel = model.kernel()
    ranges = model.driver_ranges()
    rng = np.random.default_rng(args.seed)
    q = np.stack([rng.uniform(*ranges[d], args.samples) for d in kernel.drivers], axis=1)
    start = time.perf_counter()
    points, status = kernel.point_positions(q)
    elapsed = time.perf_counter() - start
    foot = points[status == mechgen.OK, kernel.points.index(args.point)]
    print(f"{args.samples} samples in {elapsed:.3f} s; {len(foot)} assembled, "
          f"{np.count_nonzero(status == mechgen.UNREACHABLE)} unreachable")
    for axis, name in enumerate("xyz"):
        print(f"  {args.point}.{name}: {foot[:, axis].min():.4f} .. {foot[:, axis].max():.4f} m")


if __name__ == "__main__":
    main()
