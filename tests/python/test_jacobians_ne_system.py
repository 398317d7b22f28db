# The kernels' Jacobians and Newton-Euler systems from Python (issue 23) against the numeric
# reference solver (m.solver(), the same interface), against finite differences of
# point_positions, and against the sweep's own velocities, reactions and efforts.
import numpy as np
import pytest

import mechgen
from conftest import model_path


def motion(table, drivers):
    return [np.stack([table[f"{d}.{s}"] for d in drivers], axis=1) for s in ("q", "qd", "qdd")]


def close(a, b, rel):
    # Equal to `rel` of the largest entry (a structurally zero entry has no scale of its own).
    scale = max(np.max(np.abs(b)), 1e-300)
    assert np.max(np.abs(a - b)) <= rel * scale, (np.max(np.abs(a - b)), scale)


@pytest.mark.parametrize("name", ["leg6", "rsur", "quadruped_leg"])
def test_spatial_ne_system_equals_the_numeric_solver(name):
    m = mechgen.Model(model_path(name))
    k, s = m.kernel(), m.solver()
    table = k.sweep(samples=12)
    q, qd, qdd = motion(table, k.drivers)
    A, b, status = k.ne_system(q, qd, qdd, t=table["t"])
    An, bn, status_n = s.ne_system(q, qd, qdd, t=table["t"])
    assert np.all(status == mechgen.OK) and np.all(status_n == mechgen.OK)
    assert k.ne_unknowns == s.ne_unknowns
    assert A.shape == An.shape and A.shape[0] == 12 and A.shape[2] == len(k.ne_unknowns)
    assert np.max(np.abs(b)) > 1e-3
    close(A, An, 1e-9)
    close(b, bn, 1e-9)
    # The kernel's own reactions and efforts (the sweep's columns) solve its system.
    x = np.stack([table[u] for u in k.ne_unknowns], axis=1)
    residual = np.einsum("nrc,nc->nr", A, x) - b
    terms = max(np.max(np.abs(A * x[:, None, :])), np.max(np.abs(b)))
    assert np.max(np.abs(residual)) <= 1e-10 * terms
    # At the model's own motion (t alone): the same system.
    At, bt, status_t = k.ne_system(t=table["t"])
    assert np.all(status_t == mechgen.OK)
    close(At, A, 1e-9)
    close(bt, b, 1e-9)


@pytest.mark.parametrize("name", ["chebyshev", "pasibot"])
def test_planar_ne_system_has_the_numeric_solution(name):
    # The planar kernel takes each moment about its body's first pin (an exact row operation of
    # the numeric solver's moments about the centre of mass): the systems differ, their solution
    # is one, and it is the sweep's reactions and efforts.
    m = mechgen.Model(model_path(name))
    k, s = m.kernel(), m.solver()
    table = k.sweep(samples=9)
    q, qd, qdd = motion(table, k.drivers)
    A, b, status = k.ne_system(q, qd, qdd, t=table["t"])
    An, bn, status_n = s.ne_system(q, qd, qdd, t=table["t"])
    assert np.all(status == mechgen.OK) and np.all(status_n == mechgen.OK)
    assert sorted(k.ne_unknowns) == sorted(s.ne_unknowns)
    x = np.linalg.solve(A, b)
    xn = np.linalg.solve(An, bn)
    order = [s.ne_unknowns.index(u) for u in k.ne_unknowns]
    close(x, xn[:, order], 1e-9)
    # The sweep's columns of the same name (a pin in a slot's normal force is no column).
    named = [c for c, u in enumerate(k.ne_unknowns) if u in table]
    assert len(named) >= len(k.ne_unknowns) - 2 and f"{k.drivers[0]}.effort" in table
    close(x[:, named], np.stack([table[k.ne_unknowns[c]] for c in named], axis=1), 1e-9)


@pytest.mark.parametrize("name", ["leg6", "rsur", "quadruped_leg"])
def test_jacobians_equal_the_numeric_solver(name):
    m = mechgen.Model(model_path(name))
    k, s = m.kernel(), m.solver()
    table = k.sweep(samples=10)
    q, _, _ = motion(table, k.drivers)
    bodies, points, status = k.jacobians(q, t=table["t"])
    bodies_n, points_n, status_n = s.jacobians(q, t=table["t"])
    assert np.all(status == mechgen.OK) and np.all(status_n == mechgen.OK)
    assert list(bodies) == list(bodies_n) and list(points) == list(points_n)
    assert len(bodies) > 0 and len(points) > 0
    for name_, J in bodies.items():
        assert J.shape == (10, 6, len(k.drivers))
        close(J, bodies_n[name_], 1e-9)
    for name_, J in points.items():
        assert J.shape == (10, 3, len(k.drivers))
        close(J, points_n[name_], 1e-9)
    assert min(np.max(np.abs(J)) for J in bodies.values()) > 1e-3
    assert max(np.max(np.abs(J)) for J in points.values()) > 1e-3


@pytest.mark.parametrize("name", ["leg6", "quadruped_leg"])
def test_point_jacobians_are_finite_differences_of_point_positions(name):
    k = mechgen.Model(model_path(name)).kernel()
    table = k.sweep(samples=6)
    q, _, _ = motion(table, k.drivers)
    _, points, status = k.jacobians(q, t=table["t"])
    assert np.all(status == mechgen.OK)
    h = 1e-6
    n = len(k.drivers)
    for i in range(len(q)):
        # q + h e_j and q - h e_j, adjacent (a closed chain warm-starts each from the last).
        steps = np.repeat(q[i:i + 1], 2 * n, axis=0)
        for j in range(n):
            steps[2 * j, j] += h
            steps[2 * j + 1, j] -= h
        pos, pstatus = k.point_positions(steps)
        assert np.all(pstatus == mechgen.OK)
        for c, point in enumerate(k.points):
            if point not in points:
                continue
            fd = np.stack([(pos[2 * j, c] - pos[2 * j + 1, c]) / (2 * h) for j in range(n)],
                          axis=1)
            scale = max(np.max(np.abs(fd)), 1e-3)
            assert np.max(np.abs(points[point][i] - fd)) <= 1e-6 * scale, (point, i)


def test_body_jacobians_give_the_sweep_velocities():
    # A body's twist J qd (angular velocity, velocity of the body point at the ground origin)
    # moved to the centre of mass is the sweep's velocity columns.
    k = mechgen.Model(model_path("leg6")).kernel()
    table = k.sweep(samples=8)
    q, qd, _ = motion(table, k.drivers)
    bodies, _, status = k.jacobians(q, t=table["t"])
    assert np.all(status == mechgen.OK)
    for body, J in bodies.items():
        twist = np.einsum("nrc,nc->nr", J, qd)
        w, v0 = twist[:, :3], twist[:, 3:]
        com = np.stack([table[f"{body}.{a}"] for a in "xyz"], axis=1)
        v = v0 + np.cross(w, com)
        close(w, np.stack([table[f"{body}.w{a}"] for a in "xyz"], axis=1), 1e-9)
        close(v, np.stack([table[f"{body}.v{a}"] for a in "xyz"], axis=1), 1e-9)


def test_failed_sample_and_planar_kernels():
    k = mechgen.Model(model_path("quadruped_leg")).kernel()
    table = k.sweep(samples=5)
    q, qd, qdd = motion(table, k.drivers)
    q[2, 0] = 10.0  # a 10 m cylinder: the loop cannot close
    bodies, points, status = k.jacobians(q, t=table["t"])
    assert status[2] == mechgen.UNREACHABLE and np.all(np.delete(status, 2) == mechgen.OK)
    assert all(np.all(J[2] == 0) for J in points.values())
    A, b, ne_status = k.ne_system(q, qd, qdd, t=table["t"])
    assert ne_status[2] == mechgen.UNREACHABLE and np.all(np.delete(ne_status, 2) == mechgen.OK)
    assert np.all(A[2] == 0) and np.all(b[2] == 0)
    planar = mechgen.Model(model_path("chebyshev"))
    with pytest.raises(TypeError, match="planar"):
        planar.kernel().jacobians(np.zeros((1, 1)))
    with pytest.raises(TypeError, match="planar"):
        planar.solver().jacobians(np.zeros((1, 1)))
    with pytest.raises(ValueError, match="shape"):
        k.ne_system(np.zeros((2, 7)))


def test_kernel_built_on_demand_has_the_same_entries(tmp_path, monkeypatch):
    # A spatial closed chain the build did not compile in (rsur renamed): built on demand as a
    # shared library with the ABI's new entries, which give the compiled-in kernel's values.
    monkeypatch.setenv("MECHGEN_CACHE", str(tmp_path / "cache"))
    text = open(model_path("rsur")).read().replace("name: rsur", "name: rsur_on_demand", 1)
    copy = tmp_path / "rsur_on_demand.yaml"
    copy.write_text(text)
    shipped = mechgen.Model(model_path("rsur")).kernel()
    built = mechgen.Model(str(copy)).kernel()
    t = np.linspace(0.0, 1.0, 7)
    for a, b in zip(shipped.jacobians(t=t), built.jacobians(t=t)):
        if isinstance(a, dict):
            assert list(a) == list(b) and len(a) > 0
            for name in a:
                close(b[name], a[name], 1e-12)
        else:
            assert np.all(a == mechgen.OK) and np.all(b == mechgen.OK)
    A, b, status = shipped.ne_system(t=t)
    A2, b2, status2 = built.ne_system(t=t)
    assert np.all(status == mechgen.OK) and np.all(status2 == mechgen.OK)
    assert built.ne_unknowns == shipped.ne_unknowns
    close(A2, A, 1e-12)
    close(b2, b, 1e-12)


@pytest.mark.parametrize("name", ["chebyshev", "pasibot"])
def test_planar_driven_batch_is_the_vectorised_entry(name):
    # evaluate(q=...) of a planar kernel runs the vectorised driven entry: at the drivers' own
    # motion it is the time batch bit for bit, and the CSV's rows (the scalar entry) to 1e-12;
    # a sample whose input is not finite fails alone.
    k = mechgen.Model(model_path(name)).kernel()
    t = np.linspace(0.0, 1.0, 40)
    rows, status = k.evaluate(t=t, as_array=True)
    names = k.columns
    q, qd, qdd = (np.stack([rows[names.index(f"{d}.{s}")] for d in k.drivers], axis=1)
                  for s in ("q", "qd", "qdd"))
    driven, dstatus = k.evaluate(q=q, qd=qd, qdd=qdd, t=t, as_array=True)
    assert np.all(status == mechgen.OK) and np.all(dstatus == mechgen.OK)
    assert np.array_equal(driven, rows)
    table = k.sweep(samples=40, t0=0.0, t1=1.0)
    for c, column in enumerate(names):
        np.testing.assert_allclose(driven[c], table[column], rtol=1e-12, atol=1e-12,
                                   err_msg=column)
    q[5, 0] = np.nan
    bad, bstatus = k.evaluate(q=q, qd=qd, qdd=qdd, t=t, as_array=True)
    assert bstatus[5] == mechgen.UNREACHABLE and np.all(np.delete(bstatus, 5) == mechgen.OK)
    assert np.array_equal(np.delete(bad, 5, axis=1), np.delete(rows, 5, axis=1))
