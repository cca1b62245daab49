"""2D and 3D localization: equal to the C++ API on the same inputs, settings, errors, the GIL."""
import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import vdtnav
from conftest import INTEL_LOG, cpp_reference, room_occupancy

N_SCANS = 40
# LocalizationStatus in its C++ order (cpp_reference prints the enum's value).
STATUS = ["converged", "not_converged", "too_few_observations", "diverged", "refused", "lost",
          "bridged"]


def python_run(map_yaml, method, n=N_SCANS, settings=None):
    """What cpp_reference's `localize` does, through the bindings."""
    m = vdtnav.load_map(map_yaml)
    log = vdtnav.read_carmen_log(INTEL_LOG)
    idx = list(range(n))
    steps = vdtnav.odometry_steps(log.times[:n], vdtnav.log_odometry(log, idx))
    loc = vdtnav.make_localizer(method, m, settings)
    loc.reset(log.poses[0], np.diag([0.01, 0.01, 0.0025]))
    rows = []
    for k in idx:
        scan = log.scan(k)
        scan.sigma_range = 0.02
        r = loc.update(steps[k], scan)
        rows.append(np.concatenate([r.pose, r.covariance.ravel(), [STATUS.index(r.status),
                                    r.iterations, r.work["solves"], r.work["window_searches"]]]))
    return np.array(rows), r


@pytest.mark.parametrize("method", ["vdt-opt", "vdt-ekf", "udt-opt", "pf"])
def test_2d_localizers_equal_the_cpp_api(intel_map_yaml, method):
    ref = cpp_reference("localize", intel_map_yaml, INTEL_LOG, method, N_SCANS)
    got, last = python_run(intel_map_yaml, method)
    np.testing.assert_allclose(got[:, :12], ref[:, :12], rtol=0, atol=1e-12)
    # Status, iterations and the work of each update: the same integers.
    np.testing.assert_array_equal(got[:, 12:], ref[:, 12:])
    assert last.status == "converged" or method in ("pf", "udt-opt")
    if method == "vdt-opt":
        assert last.iterations > 0 and 0.5 < last.explained <= 1.0 and last.has_covariance


def test_settings_from_a_dict_equal_the_same_yaml_file(intel_map_yaml, tmp_path):
    keys = {"vdt-opt": {"loss": "huber", "loss_scale": 0.1}}
    (tmp_path / "s.yaml").write_text("vdt-opt:\n  loss: huber\n  loss_scale: 0.1\n")
    a, _ = python_run(intel_map_yaml, "vdt-opt", n=10, settings=keys)
    b, _ = python_run(intel_map_yaml, "vdt-opt", n=10, settings=str(tmp_path / "s.yaml"))
    c, _ = python_run(intel_map_yaml, "vdt-opt", n=10)
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).max() > 0  # the keys took effect
    s = vdtnav.Settings.log().updated(keys)
    assert "loss: huber" in s.yaml("vdt-opt")


def test_bad_settings_and_methods_raise_the_cpp_messages():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    with pytest.raises(vdtnav.ConfigError, match=r"<dict>:\d+: vdt-opt\.los: unknown key"):
        vdtnav.make_localizer("vdt-opt", m, {"vdt-opt": {"los": "huber"}})
    with pytest.raises(vdtnav.ConfigError, match="vdt-opt, vdt-ekf"):
        vdtnav.make_localizer("amcl", m)
    with pytest.raises(vdtnav.ConfigError, match="cannot read the settings file .no_such.yaml"):
        vdtnav.make_localizer("vdt-opt", m, "no_such.yaml")
    with pytest.raises(TypeError):
        vdtnav.make_localizer("vdt-opt", None)
    with pytest.raises(ValueError, match="3 ranges but 2 angles"):
        vdtnav.LaserScan([1.0, 2.0, 3.0], [0.0, 0.1])
    scan = vdtnav.LaserScan([1.0, 2.0], [0.0, 0.1])
    scan.ranges = [1.0, 2.0, 3.0]
    with pytest.raises(ValueError, match="3 ranges but 2 angles"):
        scan.points()
    loc = vdtnav.make_localizer("vdt-opt", m)
    with pytest.raises(ValueError, match="3 ranges but 2 angles"):
        loc.update([0, 0, 0], scan)
    with pytest.raises(ValueError, match="covariance: expected a 3 x 3 array"):
        loc.reset([0, 0, 0], np.eye(2))
    with pytest.raises(ValueError, match="angle_min and angle_increment"):
        loc.update([0, 0, 0], ranges=np.ones(10))


def test_readers_raise_file_line_and_what_was_expected(tmp_path):
    bad = tmp_path / "bad.log"
    bad.write_text("FLASER 3 1.0 2.0\n")
    with pytest.raises(vdtnav.FormatError, match=r"bad\.log:1: FLASER"):
        vdtnav.read_carmen_log(str(bad))
    with pytest.raises(vdtnav.IoError):
        vdtnav.read_carmen_log(str(tmp_path / "missing.log"))
    tum = tmp_path / "t.tum"
    tum.write_text("1 2 3\n")
    with pytest.raises(vdtnav.FormatError, match=r"t\.tum:1: expected 8 fields"):
        vdtnav.read_tum(str(tum))


def test_scans_from_ranges_equal_laser_scans_and_drop_nan():
    m = vdtnav.Map2(room_occupancy(), 0.05)
    angles = np.linspace(-np.pi / 2, np.pi / 2, 181)
    ranges = np.full(181, 1.5)
    ranges[::7] = np.nan
    ranges[::11] = np.inf
    a = vdtnav.make_localizer("vdt-opt", m)
    b = vdtnav.make_localizer("vdt-opt", m)
    for loc in (a, b):
        loc.reset([2.5, 1.5, 0.0], np.diag([0.01, 0.01, 0.0025]))
    ra = a.update([0, 0, 0], ranges=ranges, angles=angles)
    rb = b.update(vdtnav.OdometryStep([0, 0, 0]), vdtnav.LaserScan(ranges, angles))
    np.testing.assert_array_equal(ra.pose, rb.pose)
    assert np.isfinite(ra.pose).all()
    scan = vdtnav.LaserScan(ranges, angles)
    assert len(scan.points()) == 181 - len(set(range(0, 181, 7)) | set(range(0, 181, 11)))


def test_the_gil_is_released_during_a_solve(intel_map_yaml):
    """Two threads: while one is inside a global localization (C++), the other runs Python."""
    m = vdtnav.load_map(intel_map_yaml)
    log = vdtnav.read_carmen_log(INTEL_LOG)
    scan = log.scan(len(log) - 100)
    inside = []

    def profile(frame, event, arg):  # the C call's entry and exit, in this thread
        if event in ("c_call", "c_return") and getattr(arg, "__name__", "") == "global_localize":
            inside.append(time.monotonic())

    results = {}

    def solve(name):
        sys.setprofile(profile)
        results[name] = vdtnav.global_localize(m, scan)
        sys.setprofile(None)

    ticks = []
    t = threading.Thread(target=solve, args=("a",))
    t.start()
    while t.is_alive():
        ticks.append(time.monotonic())
        time.sleep(0.001)
    t.join()
    assert len(inside) == 2, inside
    during = [x for x in ticks if inside[0] < x < inside[1]]
    assert len(during) >= 3, (inside, len(ticks))  # Python ran while the solve was in C++
    # Two threads solving at once give what one thread gives alone.
    results.clear()
    ts = [threading.Thread(target=solve, args=(k,)) for k in ("a", "b")]
    for x in ts:
        x.start()
    for x in ts:
        x.join()
    alone = vdtnav.global_localize(m, scan)
    for k in ("a", "b"):
        np.testing.assert_array_equal(results[k].result.pose, alone.result.pose)
    assert alone.result.status == "converged"
    np.testing.assert_allclose(alone.result.pose[:2], log.poses[len(log) - 100][:2], atol=0.2)


def write_cloud(path, points):
    np.savetxt(path, points, delimiter=",", header="x,y,z", comments="", fmt="%.9g")


def room3d_points(rng, n):
    """Points on the walls, floor and ceiling of a 6 x 5 x 3 m room with a box in it."""
    faces = []
    for _ in range(n):
        f = rng.integers(0, 7)
        u, v = rng.uniform(0, 1, 2)
        faces.append([(0, 5 * u, 3 * v), (6, 5 * u, 3 * v), (6 * u, 0, 3 * v), (6 * u, 5, 3 * v),
                      (6 * u, 5 * v, 0), (6 * u, 5 * v, 3), (2 + 0.8 * u, 1.5, 1.2 * v)][f])
    return np.array(faces, float)


def test_localize3d_equals_the_cpp_api(tmp_path):
    rng = np.random.default_rng(3)
    write_cloud(tmp_path / "map.csv", room3d_points(rng, 40000))
    truth = np.eye(4)
    truth[:3, 3] = [3.0, 2.5, 1.2]
    world = room3d_points(rng, 3000)
    cloud = world - truth[:3, 3]  # the sensor frame (no rotation)
    write_cloud(tmp_path / "scan.csv", cloud)
    m = vdtnav.load_map(str(tmp_path / "map.csv"), resolution=0.1)
    assert isinstance(m, vdtnav.Map3)
    init = np.eye(4)
    init[:3, 3] = [3.25, 2.3, 1.3]
    for dof in (6, 4):
        cloud_read = vdtnav.read_point_cloud(str(tmp_path / "scan.csv"))
        r = vdtnav.localize3d(m, cloud_read, init, dof=dof)
        ref = cpp_reference("localize3d", tmp_path / "map.csv", tmp_path / "scan.csv", dof,
                            3.25, 2.3, 1.3, 0, 0, 0)[0]
        np.testing.assert_allclose(r.pose.ravel(), ref[:16], rtol=0, atol=1e-12)
        np.testing.assert_allclose(r.covariance.ravel(), ref[16:52], rtol=0, atol=1e-12,
                                   equal_nan=True)
        assert r.status == "converged"
        # Within the map's voxelization (surfaces drawn at voxel centres: up to half a voxel).
        np.testing.assert_allclose(r.pose[:3, 3], truth[:3, 3], atol=0.06)
    # The sequential localizer tracks the same scan from its last pose.
    loc = vdtnav.make_localizer3d(m)
    loc.reset(init, np.diag([0.01] * 3 + [0.001] * 3))
    r = loc.update(np.eye(4), cloud.astype(np.float32))
    assert r.status == "converged"
    np.testing.assert_allclose(r.pose[:3, 3], truth[:3, 3], atol=0.06)
    assert r.covariance.shape == (6, 6)


def crate_points(rng, n):
    """n points on the faces of a 1 x 1 x 1.5 m crate standing in a corner of room3d_points's room."""
    lo, hi = np.array([4.5, 3.5, 0.0]), np.array([5.5, 4.5, 1.5])
    axis = rng.integers(0, 3, n)
    p = lo + rng.uniform(0, 1, (n, 3)) * (hi - lo)
    side = rng.integers(0, 2, n)
    p[np.arange(n), axis] = np.where(side == 1, hi[axis], lo[axis])
    return p


def test_global_localize3d_finds_the_cloud_with_no_prior_and_refuses_a_twin(tmp_path):
    # room3d_points's room (6 x 5 x 3 m, a small panel by one wall) is nearly its own half turn:
    # a cloud there is refused as ambiguous, the twin among the alternatives. With a crate in one
    # corner the same cloud, from (3, 2.5, 1.2) turned 0.7 rad, is found with no guess.
    rng = np.random.default_rng(5)
    yaw = 0.7
    rot = np.array([[np.cos(yaw), -np.sin(yaw), 0], [np.sin(yaw), np.cos(yaw), 0], [0, 0, 1]])
    position = np.array([3.0, 2.5, 1.2])
    room = room3d_points(rng, 40000)
    write_cloud(tmp_path / "bare.csv", room)
    write_cloud(tmp_path / "crate.csv", np.vstack([room, crate_points(rng, 6000)]))
    bare = vdtnav.load_map(str(tmp_path / "bare.csv"), resolution=0.1)
    g = vdtnav.global_localize3d(bare, (room3d_points(rng, 3000) - position) @ rot)
    assert g.result.status == "refused" and g.ambiguous
    # Seen from the room's centre: the pose and its half turn about the vertical, both there.
    headings = [np.arctan2(p[1, 0], p[0, 0]) for p in [g.result.pose] + g.alternatives]
    for want in (yaw, yaw - np.pi):
        assert min(abs(np.angle(np.exp(1j * (h - want)))) for h in headings) < 0.02, headings
    for p in [g.result.pose] + g.alternatives:
        np.testing.assert_allclose(p[:3, 3], position, atol=0.06)
    m = vdtnav.load_map(str(tmp_path / "crate.csv"), resolution=0.1)
    world = np.vstack([room3d_points(rng, 3000), crate_points(rng, 500)])
    cloud = (world - position) @ rot  # the sensor frame: R^T (p - t)
    g = vdtnav.global_localize3d(m, cloud)
    assert g.result.status == "converged", (g.explained, g.ambiguous)
    np.testing.assert_allclose(g.result.pose[:3, 3], position, atol=0.06)
    np.testing.assert_allclose(g.result.pose[:3, :3], rot, atol=0.02)
    assert g.explained > 0.9 and not g.ambiguous and g.nodes > 0 and g.seconds > 0
    with pytest.raises(TypeError):
        vdtnav.global_localize3d(None, cloud)


def test_evaluation_against_hand_computed_values():
    times = np.array([0.0, 1.0, 2.0])
    truth = np.array([[0, 0, 0], [1, 0, 0], [1, 1, np.pi / 2]], float)
    est = truth + np.array([[0, 0, 0], [0.1, 0, 0], [0.1, 0, 0]])
    rel = np.array([[0.0, 1.0, 1.0, 0.0, 0.0], [1.0, 2.0, 0.0, 1.0, np.pi / 2]])
    r = vdtnav.relation_metric(times, est, rel)
    assert r.used == 2
    np.testing.assert_allclose(r.translation_errors, [0.1, 0.0], atol=1e-12)
    cov = np.tile(np.diag([0.01, 0.01, 0.001]), (3, 1, 1))
    assert vdtnav.nees(est[1], truth[1], cov[1]) == pytest.approx(1.0)
    a = vdtnav.anees([1.0, 2.0, 3.0], 3)
    lo, hi = vdtnav.anees_interval(3, 3)
    assert a.anees == pytest.approx(2.0) and a.interval == (lo, hi)
    assert lo < 3 < hi and a.consistent
    n = vdtnav.relation_nees(times, est, cov, rel)
    assert n.used == 2 and n.values[1] == pytest.approx(0.0, abs=1e-12)
    # ATE: the estimate is the reference moved by 0.1 m along x after the first pose.
    a = vdtnav.absolute_trajectory_error(times, est, times, truth)
    assert a.unaligned_translation.max == pytest.approx(0.1)
    assert a.unaligned_translation.rmse == pytest.approx(np.sqrt(2 * 0.01 / 3))
    assert a.translation.rmse < a.unaligned_translation.rmse  # the alignment absorbs part of it
    # 4-DOF: NaN roll and pitch rows are left out of the NEES (4 degrees of freedom).
    c6 = np.diag([0.01, 0.01, 0.01, np.nan, np.nan, 0.001])
    c6[3, :] = c6[:, 3] = c6[4, :] = c6[:, 4] = np.nan
    t = np.eye(4)
    t[0, 3] = 0.1
    value, dof = vdtnav.nees(t, np.eye(4), c6, return_dof=True)
    assert dof == 4 and value == pytest.approx(1.0)


def test_a_saved_3d_vdt_map_loads_as_the_map_it_was_built_from(tmp_path):
    # `vdtnav map3d` saves the cloud's map; load_map (the library's, as the CLI loads it) reads
    # the .vdt back as a Map3 whose lookups are the cloud's own map's.
    cli = os.environ.get("VDTNAV_CLI")
    if not cli:
        pytest.skip("VDTNAV_CLI not set (run through ctest)")
    rng = np.random.default_rng(5)
    write_cloud(tmp_path / "map.csv", room3d_points(rng, 20000))
    subprocess.run([cli, "map3d", "--map", str(tmp_path / "map.csv"), "--resolution", "0.1",
                    "--out", str(tmp_path / "map.vdt"), "--quiet"], check=True)
    built = vdtnav.load_map(str(tmp_path / "map.csv"), resolution=0.1)
    saved = vdtnav.load_map(str(tmp_path / "map.vdt"))
    assert isinstance(saved, vdtnav.Map3) and not saved.sparse
    assert saved.resolution == built.resolution
    p = rng.uniform([0.5, 0.5, 0.5], [5.5, 4.5, 2.5], size=(300, 3))
    np.testing.assert_array_equal(saved.lookup(p).value, built.lookup(p).value)
    with pytest.raises(vdtnav.ConfigError, match="resolution"):
        vdtnav.load_map(str(tmp_path / "map.vdt"), resolution=0.2)
