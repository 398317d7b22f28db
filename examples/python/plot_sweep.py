"""A figure of one sweep: PASIBOT's foot path and the motor torque over a step (matplotlib, no
display needed).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/plot_sweep.py --out pasibot.png
"""
import argparse
import pathlib

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402 (after the backend)

import mechgen  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="pasibot_sweep.png")
    parser.add_argument("--samples", type=int, default=721)
    parser.add_argument("--model", default=str(ROOT / "models" / "pasibot.yaml"))
    parser.add_argument("--point", default="Ep", help="the point whose path is drawn (swing foot)")
    parser.add_argument("--driver", default="theta8")
    args = parser.parse_args()

    sweep = mechgen.Model(args.model).kernel().sweep(samples=args.samples)
    fig, (path, torque) = plt.subplots(1, 2, figsize=(10, 4))
    path.plot(sweep[f"{args.point}.x"], sweep[f"{args.point}.y"])
    path.set(xlabel="x [m]", ylabel="y [m]", title=f"path of {args.point}", aspect="equal")
    torque.plot(sweep["t"], sweep[f"{args.driver}.effort"])
    torque.set(xlabel="t [s]", ylabel="effort [N m]", title=f"{args.driver} effort")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    print(f"{len(sweep['t'])} samples -> {args.out}")


if __name__ == "__main__":
    main()
