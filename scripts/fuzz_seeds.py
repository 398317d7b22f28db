#!/usr/bin/env python3
"""Seed corpora of the libFuzzer targets (tests/fuzz/), written by scripts/fuzz.sh:
  python3 scripts/fuzz_seeds.py ROOT CORPUS_DIR [--robots]
CORPUS_DIR/spatial_kernel: inputs of spatial_kernel_fuzzer as `mechgen sweep models/rsur.yaml
  --set NAME=VALUE` would give them: the first byte 2 (keep the assembly as the warm start), then
  rsur's parameters in model order as doubles (its defaults, read from the model, one of them
  halved, doubled, zero or negated), then the time t.
CORPUS_DIR/import: inputs of import_fuzzer: byte 0 + a URDF (+ NUL + its closures' YAML) or
  byte 1 + an MJCF file, from ROOT/tests/data; with --robots also ROOT/../shared/robots/*/ when
  it is there (their assembly takes 9 to 26 s each under the sanitizers: for long runs only).
"""
import glob
import os
import re
import struct
import sys


def rsur_parameters(root):
    """(name, default) in model order from models/rsur.yaml's parameters block."""
    found, inside = [], False
    with open(os.path.join(root, "models", "rsur.yaml")) as f:
        for line in f:
            if re.match(r"^parameters:", line):
                inside = True
            elif inside and re.match(r"^\S", line):
                break
            elif inside:
                m = re.match(r"^\s+(\w+):\s*\{value:\s*([-0-9.eE+]+)", line)
                if m:
                    found.append((m.group(1), float(m.group(2))))
    if not found:
        sys.exit("fuzz_seeds.py: no parameters read from models/rsur.yaml")
    return found


def kernel_seeds(root, out):
    params = rsur_parameters(root)
    w = dict(params).get("w", 2.0)
    times = [0.0, 0.9 / w, 3.0 / w]
    variants = [("default", None, 1.0)]
    for i, (name, _) in enumerate(params):
        for label, factor in (("half", 0.5), ("double", 2.0), ("zero", 0.0), ("negated", -1.0)):
            variants.append((f"{name}_{label}", i, factor))
    os.makedirs(out, exist_ok=True)
    for label, index, factor in variants:
        values = [v * (factor if i == index else 1.0) for i, (_, v) in enumerate(params)]
        for k, t in enumerate(times):
            data = bytes([2]) + struct.pack(f"<{len(values) + 1}d", *values, t)
            with open(os.path.join(out, f"set_{label}_t{k}"), "wb") as f:
                f.write(data)


def import_seeds(root, out, robots):
    os.makedirs(out, exist_ok=True)
    data = os.path.join(root, "tests", "data")
    pairs = []  # (label, urdf, closures or None)
    for urdf in sorted(glob.glob(os.path.join(data, "*.urdf"))):
        stem = os.path.splitext(os.path.basename(urdf))[0]
        pairs.append((stem, urdf, None))
        for yaml in sorted(glob.glob(os.path.join(data, stem + "_*.yaml"))):
            pairs.append((os.path.splitext(os.path.basename(yaml))[0], urdf, yaml))
    shared = os.path.join(root, "..", "shared", "robots", "*", "robot.urdf")
    for robot in sorted(glob.glob(shared)) if robots else []:
        folder = os.path.dirname(robot)
        yaml = os.path.join(folder, "robot.yaml")
        pairs.append((os.path.basename(folder), robot, yaml if os.path.exists(yaml) else None))
    for label, urdf, yaml in pairs:
        with open(urdf, "rb") as f:
            body = f.read()
        if yaml:
            with open(yaml, "rb") as f:
                body += b"\0" + f.read()
        with open(os.path.join(out, "urdf_" + label), "wb") as f:
            f.write(b"\0" + body)
    for mjcf in sorted(glob.glob(os.path.join(data, "*.xml"))):
        with open(mjcf, "rb") as f:
            body = f.read()
        with open(os.path.join(out, os.path.basename(mjcf)), "wb") as f:
            f.write(b"\1" + body)


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4) or sys.argv[3:] not in ([], ["--robots"]):
        sys.exit("usage: fuzz_seeds.py ROOT CORPUS_DIR [--robots]")
    kernel_seeds(sys.argv[1], os.path.join(sys.argv[2], "spatial_kernel"))
    import_seeds(sys.argv[1], os.path.join(sys.argv[2], "import"), len(sys.argv) == 4)
