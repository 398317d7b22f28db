"""What calling a kernel from Python costs: per sample in one batch (evaluate(t=...) against the
C++ batch entry alone, in the same process, on the same times), and per call when Python calls
once per sample.

    PYTHONPATH=build/python /usr/bin/python3 bench/python_overhead.py [--samples N] [--calls N]
"""
import argparse
import pathlib
import time

import numpy as np

import mechgen

ROOT = pathlib.Path(__file__).resolve().parents[1]


def best_of(repeats, f):
    best = float("inf")
    for _ in range(repeats):
        start = time.perf_counter()
        f()
        best = min(best, time.perf_counter() - start)
    return best


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=1_000_000, help="samples of the batch")
    parser.add_argument("--calls", type=int, default=20_000, help="single-sample calls")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("models", nargs="*", default=["leg6", "pasibot"])
    args = parser.parse_args()

    print(f"{'model':<10} {'batch N':>9} {'C++ ns/sample':>14} {'Python ns/sample':>17} "
          f"{'overhead':>9} {'call us (dict)':>15} {'call us (array)':>16}")
    for name in args.models:
        kernel = mechgen.Model(str(ROOT / "models" / f"{name}.yaml")).kernel()
        for n in (10_000, args.samples):
            t = np.linspace(0.0, 1.0, n)
            cpp = kernel.batch_entry_seconds(t, repeats=args.repeats)
            python = best_of(args.repeats, lambda: kernel.evaluate(t=t))
            one = t[:1]
            per_call = [best_of(args.repeats, lambda: [
                kernel.evaluate(t=one, as_array=as_array) for _ in range(args.calls)])
                / args.calls * 1e6 for as_array in (False, True)]
            print(f"{name:<10} {n:>9} {cpp / n * 1e9:>14.1f} {python / n * 1e9:>17.1f} "
                  f"{(python - cpp) / cpp * 100:>8.1f}% {per_call[0]:>15.2f} {per_call[1]:>16.2f}")


if __name__ == "__main__":
    main()
