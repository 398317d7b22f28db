# The Python module against the command line (the CSV and info JSON of build/mechgen) and against
# itself through other kernel entries (issue 23's tests).
import gc
import threading
import tracemalloc

import numpy as np
import pytest

import mechgen
from conftest import model_path

# A planar closed chain, a spatial open chain and a spatial closed chain.
MODELS = ["chebyshev", "leg6", "rsur"]


@pytest.mark.parametrize("name", MODELS)
def test_info_is_the_cli_json(cli, name):
    m = mechgen.Model(model_path(name))
    assert m.info() == cli["info"](name)
    assert m.name == name


@pytest.mark.parametrize("name", MODELS)
def test_sweep_columns_equal_the_cli_csv(cli, tmp_path, name):
    expected, header = cli["sweep"](tmp_path, name, "--samples", "37")
    got = mechgen.Model(model_path(name)).kernel().sweep(samples=37)
    assert list(got) == header
    for column in header:
        assert np.array_equal(got[column], expected[column]), column


def test_sweep_options_and_params_are_the_cli_ones(cli, tmp_path):
    m = mechgen.Model(model_path("pasibot"))
    l8 = m.parameters["l8"]["value"] * 1.05
    expected, header = cli["sweep"](tmp_path, "pasibot", "--samples", "25", "--t0", "0.1", "--t1",
                                    "2", "--set", f"l8={l8!r}")
    got = m.kernel().sweep(samples=25, t0=0.1, t1=2, params={"l8": l8})
    assert list(got) == header
    for column in header:
        assert np.array_equal(got[column], expected[column]), column
    # The parameter changed the motion: not the default sweep.
    default = m.kernel().sweep(samples=25, t0=0.1, t1=2)
    assert not np.array_equal(default["l8.x"], got["l8.x"]) or not np.array_equal(
        default["theta8.effort"], got["theta8.effort"])


@pytest.mark.parametrize("name", ["chebyshev", "rsur"])
def test_numeric_solver_sweep_is_the_cli_one(cli, tmp_path, name):
    expected, header = cli["sweep"](tmp_path, name, "--samples", "9", "--solver", "numeric")
    got = mechgen.Model(model_path(name)).solver().sweep(samples=9)
    assert list(got) == header
    for column in header:
        assert np.array_equal(got[column], expected[column]), column


def driver_motion(table, drivers):
    return [np.stack([table[f"{d}.{s}"] for d in drivers], axis=1) for s in ("q", "qd", "qdd")]


@pytest.mark.parametrize("name", ["chebyshev", "pasibot", "leg6"])
def test_batch_equals_scalar_rows(name):
    # The vectorised batch entry at times t, then the scalar driven entry at the drivers' (q, qd,
    # qdd) those rows report: the same rows.
    k = mechgen.Model(model_path(name)).kernel()
    t = np.linspace(0.0, 1.0, 64)
    rows, status = k.evaluate(t=t)
    assert status.shape == (64,) and np.all(status == mechgen.OK)
    q, qd, qdd = driver_motion(rows, k.drivers)
    again, status2 = k.evaluate(q=q, qd=qd, qdd=qdd, t=t)
    assert np.all(status2 == mechgen.OK)
    for column in k.columns:
        np.testing.assert_allclose(again[column], rows[column], rtol=1e-9, atol=1e-9,
                                   err_msg=column)
    block, status3 = k.evaluate(q=q, qd=qd, qdd=qdd, t=t, as_array=True)
    assert block.shape == (len(k.columns), 64) and np.all(status3 == mechgen.OK)
    assert np.array_equal(block[k.columns.index(k.drivers[0] + ".effort")],
                          again[k.drivers[0] + ".effort"])
    # One sample per call gives the batch's values too.
    for i in (0, 17, 63):
        one, s = k.evaluate(q=q[i:i + 1], qd=qd[i:i + 1], qdd=qdd[i:i + 1], t=t[i])
        assert s[0] == mechgen.OK
        for column in k.columns:
            assert one[column][0] == again[column][i], column


def test_batch_at_sweep_times_is_the_csv(cli, tmp_path):
    expected, header = cli["sweep"](tmp_path, "chebyshev", "--samples", "50")
    k = mechgen.Model(model_path("chebyshev")).kernel()
    rows, status = k.evaluate(t=expected["t"])
    assert np.all(status == mechgen.OK)
    for column in header:
        np.testing.assert_allclose(rows[column], expected[column], rtol=1e-12, atol=1e-12,
                                   err_msg=column)


def test_failed_sample_has_its_status_and_the_rest_stay_valid():
    k = mechgen.Model(model_path("quadruped_leg")).kernel()
    table = k.sweep(samples=8)
    q, qd, qdd = driver_motion(table, k.drivers)
    q_bad = q.copy()
    q_bad[3, 0] = 10.0  # a 10 m cylinder: the loop cannot close
    rows, status = k.evaluate(q=q_bad, qd=qd, qdd=qdd, t=table["t"])
    assert status[3] == mechgen.UNREACHABLE
    assert np.all(np.delete(status, 3) == mechgen.OK)
    for column in ("D.x", "D.z", "l1.effort"):
        np.testing.assert_allclose(np.delete(rows[column], 3), np.delete(table[column], 3),
                                   rtol=1e-9, atol=1e-12)
    pts, pstatus = k.point_positions(q_bad)
    assert pstatus[3] == mechgen.UNREACHABLE and np.all(np.delete(pstatus, 3) == mechgen.OK)


def test_point_positions_are_the_sweep_points():
    k = mechgen.Model(model_path("leg6")).kernel()
    table = k.sweep(samples=20)
    q, _, _ = driver_motion(table, k.drivers)
    pts, status = k.point_positions(q)
    assert pts.shape == (20, len(k.points), 3) and np.all(status == mechgen.OK)
    for p, point in enumerate(k.points):
        for a, axis in enumerate("xyz"):
            np.testing.assert_allclose(pts[:, p, a], table[f"{point}.{axis}"], rtol=1e-12,
                                       atol=1e-12)


def test_mass_matrix_bias_and_forward_dynamics_agree_with_the_sweep():
    k = mechgen.Model(model_path("leg6")).kernel()
    table = k.sweep(samples=10, mass_matrix=True)
    q, qd, qdd = driver_motion(table, k.drivers)
    M, status = k.mass_matrix(q, qd)
    h, status_h = k.bias(q, qd)
    assert np.all(status == mechgen.OK) and np.all(status_h == mechgen.OK)
    n = len(k.drivers)
    for a in range(n):
        np.testing.assert_allclose(h[:, a], table[f"h.{k.drivers[a]}"], rtol=1e-9, atol=1e-12)
        for b in range(a, n):
            np.testing.assert_allclose(M[:, a, b], table[f"M.{k.drivers[a]}.{k.drivers[b]}"],
                                       rtol=1e-9, atol=1e-12)
    # The efforts of the sweep's own accelerations give those accelerations back.
    effort = np.stack([table[f"{d}.effort"] for d in k.drivers], axis=1)
    back, fstatus = k.forward_dynamics(q, effort, qd=qd)
    assert np.all(fstatus == mechgen.OK)
    np.testing.assert_allclose(back, qdd, rtol=1e-6, atol=1e-6)


def test_bad_description_raises_with_its_location(tmp_path):
    text = open(model_path("chebyshev")).read().splitlines()
    line = next(i for i, s in enumerate(text) if "first: ground" in s)
    text[line] = text[line].replace("first: ground", "first: no_such_body")
    bad = tmp_path / "bad.yaml"
    bad.write_text("\n".join(text) + "\n")
    with pytest.raises(mechgen.ModelError) as error:
        mechgen.Model(str(bad))
    assert str(error.value).startswith(f"{bad}:{line + 1}:")
    assert isinstance(error.value, ValueError)
    syntax = tmp_path / "syntax.yaml"
    syntax.write_text("name: x\nparameters: [1, 2\n")
    with pytest.raises(mechgen.ModelError, match=rf"^{syntax}:\d+:\d+: error: "):
        mechgen.Model(str(syntax))


def test_unknown_parameter_is_an_error():
    k = mechgen.Model(model_path("chebyshev")).kernel()
    with pytest.raises(mechgen.ModelError, match="no_such"):
        k.sweep(samples=3, params={"no_such": 1.0})


def rss_kib():
    with open("/proc/self/status") as f:
        return next(int(s.split()[1]) for s in f if s.startswith("VmRSS:"))


def test_no_leak_over_ten_thousand_calls():
    m = mechgen.Model(model_path("leg6"))
    k = m.kernel()
    q = np.zeros((4, len(k.drivers)))

    def calls(n):
        for i in range(n):
            rows, status = k.evaluate(q=q)
            pts, s = k.point_positions(q)
            if i % 20 == 0:  # a spatial sweep sets up a solver: milliseconds
                table = k.sweep(samples=3)
        return rows, pts, table

    calls(1000)
    tracemalloc.start()
    before_py = tracemalloc.get_traced_memory()[0]
    before = rss_kib()
    calls(10000)
    after = rss_kib()
    after_py = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    assert after_py - before_py < 64 * 1024
    assert after - before < 2048  # KiB: 10^4 calls of a few KiB each would show


def test_no_reference_cycles():
    gc.collect()
    gc.disable()
    try:
        m = mechgen.Model(model_path("rsur"))
        k = m.kernel()
        s = m.solver()
        table = k.sweep(samples=5)
        rows, status = k.evaluate(t=np.linspace(0, 1, 5))
        del m, k, s, table, rows, status
        assert gc.collect() == 0
    finally:
        gc.enable()


@pytest.mark.parametrize("name", ["pasibot", "rsur"])
def test_four_threads_sweeping_give_the_same_results(name):
    m = mechgen.Model(model_path(name))
    k = m.kernel()
    expected = k.sweep(samples=400)
    results = [None] * 4

    def work(i):
        results[i] = [k.sweep(samples=400) for _ in range(3)]

    threads = [threading.Thread(target=work, args=(i,)) for i in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for runs in results:
        for run in runs:
            for column in expected:
                assert np.array_equal(run[column], expected[column]), column
