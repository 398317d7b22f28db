# Run by the ctest test python_installed (runtime/python/CMakeLists.txt) with only the installed
# module on PYTHONPATH: python3 installed_check.py PREFIX_DIR MODEL.yaml... where PREFIX_DIR holds
# prefix/ (the cmake --install) and MODEL.csv (the installed mechgen's sweep --samples 5).
import csv
import pathlib
import sys

import numpy as np

import mechgen

folder = pathlib.Path(sys.argv[1])
prefix = folder / "prefix"
assert pathlib.Path(mechgen.__file__).is_relative_to(prefix), mechgen.__file__
assert pathlib.Path(mechgen.templates_dir()) == prefix / "share/mechgen/templates", \
    mechgen.templates_dir()
for model in sys.argv[2:]:
    table = mechgen.Model(model).kernel().sweep(samples=5)
    with open(folder / (pathlib.Path(model).stem + ".csv"), newline="") as f:
        rows = list(csv.reader(f))
    assert len(rows) == 6 and list(table) == rows[0], (model, list(table), rows[0])
    for i, column in enumerate(rows[0]):
        expected = np.array([float(r[i]) for r in rows[1:]])
        assert np.array_equal(table[column], expected), (model, column)
    print(f"{model}: the installed module's sweep equals the installed mechgen's CSV")
