"""PASIBOT's hip centre of mass (hip_cx, hip_cy, in units of the crank length l8) placed, within
the hip plate, where the motor's RMS torque over a step is least: scipy.optimize over generated
sweeps, each a call of the kernel with other parameters (no regeneration).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/optimise_hip.py [--samples N]
"""
import argparse
import pathlib

import numpy as np
from scipy.optimize import minimize

import mechgen

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=361, help="samples per sweep")
    parser.add_argument("--model", default=str(ROOT / "models" / "pasibot.yaml"))
    args = parser.parse_args()

    model = mechgen.Model(args.model)
    kernel = model.kernel()
    evaluations = 0

    def rms_torque(x):
        nonlocal evaluations
        evaluations += 1
        sweep = kernel.sweep(samples=args.samples, params={"hip_cx": x[0], "hip_cy": x[1]})
        return float(np.sqrt(np.mean(sweep["theta8.effort"] ** 2)))

    start = np.array([model.parameters["hip_cx"]["value"], model.parameters["hip_cy"]["value"]])
    plate = [(-6.0, 6.0), (-8.0, -2.0)]  # where the hip's mass can sit (units of l8)
    result = minimize(rms_torque, start, method="L-BFGS-B", bounds=plate)
    print(f"RMS motor torque at the description's hip: {rms_torque(start):.6f} N m")
    print(f"least RMS motor torque: {result.fun:.6f} N m at hip_cx = {result.x[0]:.4f}, "
          f"hip_cy = {result.x[1]:.4f} ({evaluations} sweeps of {args.samples} samples)")


if __name__ == "__main__":
    main()
