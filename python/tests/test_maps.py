"""Maps and lookups: against the C++ lookups, finite differences, and without a copy of the input."""
import numpy as np
import pytest

import vdtnav
from conftest import cpp_reference, room_occupancy


def random_points(m, n, seed=2):
    f = m.frame
    lo = np.asarray(f["origin"])
    hi = lo + np.asarray(f["size"]) * f["resolution"]
    return np.random.default_rng(seed).uniform(lo - 0.3, hi + 0.3, size=(n, 2))


def test_lookup_equals_the_cpp_lookup(room_map_yaml, tmp_path):
    m = vdtnav.load_map(room_map_yaml)
    p = random_points(m, 3001)
    np.savetxt(tmp_path / "p.txt", p, fmt="%.17g")
    ref = cpp_reference("lookup", room_map_yaml, tmp_path / "p.txt")
    r = m.lookup(p)
    np.testing.assert_allclose(r.value, ref[:, 0:2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.jacobian.reshape(-1, 4), ref[:, 2:6], rtol=0, atol=1e-12)
    np.testing.assert_array_equal(r.inside, ref[:, 6] == 1)
    np.testing.assert_allclose(r.distance, np.linalg.norm(ref[:, 0:2], axis=1), rtol=0, atol=1e-12)
    assert not r.inside.all() and r.inside.any()  # the points straddle the map's border


def test_lookup_reads_the_input_in_place_whatever_its_layout():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    p = random_points(m, 1000)
    ref = m.lookup(p)
    assert ref.points is p  # the array itself: no conversion, no copy
    f = np.asfortranarray(p)
    wide = np.zeros((1000, 5))
    wide[:, 1:3] = p
    strided = wide[:, 1:3]  # a view with a row stride of 5 doubles
    for q in (f, strided):
        r = m.lookup(q)
        assert r.points is q
        assert r.points.__array_interface__["data"][0] == q.__array_interface__["data"][0]
        np.testing.assert_array_equal(r.value, ref.value)
        np.testing.assert_array_equal(r.jacobian, ref.jacobian)
    p32 = p.astype(np.float32)
    r32 = m.lookup(p32)
    assert r32.points is p32
    np.testing.assert_array_equal(r32.value, m.lookup(p32.astype(np.float64)).value)
    # Reversed rows (a negative stride).
    np.testing.assert_array_equal(m.lookup(p[::-1]).value, ref.value[::-1])


def test_lookup_values_only_and_hessians_against_finite_differences():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    # Away from the border (the lookup clamps outside the map: finite differences across it fail).
    p = np.random.default_rng(5).uniform([0.3, 0.3], [120 * 0.05 - 0.3, 80 * 0.05 - 0.3], (200, 2))
    v = m.lookup(p, jacobian=False)
    np.testing.assert_array_equal(v.value, m.lookup(p).value)
    r = m.lookup(p, hessian=True)
    # The spline is C^2 with third derivatives that jump at its knots (cell boundaries), and the
    # batch Jacobians carry float32 rounding (~1e-6): a central difference of step h is good to
    # ~1e-6 / h + h |d3f| away from the knots. Nearly every point agrees; a wrong Hessian
    # (component or axis swapped) disagrees at most of them.
    h = 3e-4
    bad = np.zeros(len(p), bool)
    for a in range(2):
        e = np.zeros(2)
        e[a] = h
        dj = (m.lookup(p + e).jacobian - m.lookup(p - e).jacobian) / (2 * h)
        # hessian[k, c, :, a] = d/dp_a of row c of the Jacobian.
        err = np.abs(r.hessian[:, :, :, a] - dj).max(axis=(1, 2))
        bad |= err > 0.1 + 0.01 * np.abs(dj).max(axis=(1, 2))
    assert bad.sum() <= 3, np.flatnonzero(bad)
    assert np.abs(r.hessian).max() > 1.0  # not a field of zeros
    # The gradient of the distance is J^T DT_v / |DT_v|.
    g = np.einsum("kca,kc->ka", r.jacobian, r.value) / r.distance[:, None]
    np.testing.assert_allclose(r.gradient, g, rtol=1e-12, atol=1e-12)


def test_the_vdt_of_a_single_obstacle_is_the_vector_to_it():
    occ = np.zeros((40, 40), bool)
    occ[20, 20] = True  # the cell centred at (1.025, 1.025)
    m = vdtnav.Map2(occ, 0.05)
    p = np.array([[0.5, 0.5], [1.5, 1.2], [1.03, 0.4]])
    r = m.lookup(p)
    np.testing.assert_allclose(r.value, p - 1.025, atol=2e-3)  # thesis eq. 2.5: p - c(p)


def test_3d_maps_look_up_like_2d_ones():
    occ = np.zeros((20, 30, 30), np.uint8)
    occ[0] = 1  # the floor: z in [0, 0.1)
    m = vdtnav.Map3(occ, 0.1)
    p = np.array([[1.0, 1.5, 0.8], [2.0, 0.7, 1.2]])
    r = m.lookup(p)
    np.testing.assert_allclose(r.value[:, 2], p[:, 2] - 0.05, atol=1e-3)
    np.testing.assert_allclose(r.value[:, :2], 0, atol=1e-3)
    # The sparse map holds bricks near the surfaces: near the floor it is the dense map.
    s = vdtnav.Map3(occ, 0.1, sparse=True)
    near = p * [1, 1, 0.2]
    np.testing.assert_allclose(s.lookup(near).value, m.lookup(near).value, atol=1e-3)
    assert r.jacobian.shape == (2, 3, 3)


def test_bad_points_raise_with_what_was_expected():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    with pytest.raises(ValueError, match=r"points: expected an N x 2 array, got shape \(4, 3\)"):
        m.lookup(np.zeros((4, 3)))
    with pytest.raises(ValueError, match="float32 or float64"):
        m.lookup(np.zeros((4, 2), np.int64))
    with pytest.raises(ValueError, match="bool or uint8"):
        vdtnav.Map2(np.zeros((4, 4), np.float64), 0.05)
    with pytest.raises(vdtnav.ConfigError, match="resolution"):
        vdtnav.Map2(room_occupancy(), -1.0)


def test_nan_points_come_back_outside_not_as_an_error():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    r = m.lookup(np.array([[np.nan, 1.0], [1.0, 1.0]]))
    assert r.value.shape == (2, 2)


def test_map_files_load_with_the_cli_readers(room_map_yaml, tmp_path):
    m = vdtnav.load_map(room_map_yaml)
    assert isinstance(m, vdtnav.Map2)
    m.save_vdt(str(tmp_path / "room.vdt"))
    v = vdtnav.load_map(str(tmp_path / "room.vdt"))
    assert isinstance(v, vdtnav.Map2)
    p = random_points(m, 500)
    np.testing.assert_array_equal(v.lookup(p).value, m.lookup(p).value)
    (tmp_path / "bad.yaml").write_text("image: nothing.pgm\nresolution: 0.05\n")
    with pytest.raises(vdtnav.Error, match="bad.yaml"):
        vdtnav.load_map(str(tmp_path / "bad.yaml"))


def test_the_thread_count_changes_no_result():
    # A map large enough that its build is cut into pieces for the pool: the same lookups at one
    # thread and at three; the count is process-wide and refused below 0.
    occ = np.zeros((700, 650), dtype=bool)
    occ[[0, -1], :] = occ[:, [0, -1]] = True
    occ[300, 100:500] = True
    p = np.random.default_rng(4).uniform(0.0, 32.0, size=(2000, 2))
    try:
        vdtnav.set_threads(1)
        assert vdtnav.threads() == 1
        one = vdtnav.Map2(occ, 0.05).lookup(p)
        vdtnav.set_threads(3)
        assert vdtnav.threads() == 3
        three = vdtnav.Map2(occ, 0.05).lookup(p)
        np.testing.assert_array_equal(one.value, three.value)
        np.testing.assert_array_equal(one.jacobian, three.jacobian)
        with pytest.raises(vdtnav.ConfigError, match="thread count"):
            vdtnav.set_threads(-1)
    finally:
        vdtnav.set_threads(0)
    assert vdtnav.threads() >= 1
