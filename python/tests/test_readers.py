"""Readers: the real files of ../shared/data through the bindings, against what their READMEs and
the C++ readers say of them."""
import os

import numpy as np
import pytest

import vdtnav
from conftest import DATA, INTEL_LOG

BAGS = os.path.join(DATA, "rosbags")


def need(path):
    if not os.path.exists(path):
        pytest.skip(f"no data at {path}")
    return path


def test_carmen_log_and_relations_as_arrays():
    log = vdtnav.read_carmen_log(need(INTEL_LOG))
    assert len(log) == 910 and log.ranges.shape == (910, 180)
    # The GMapping log's own stamps go back four times (the joined table's do not).
    assert log.poses.shape == (910, 3) and (np.diff(log.times) <= 0).sum() == 4
    s = log.scan(5)
    np.testing.assert_array_equal(s.ranges, log.ranges[5])
    assert s.angles[0] == pytest.approx(-np.pi / 2) and s.range_max == 80.0
    rel = vdtnav.read_relations(need(os.path.join(DATA, "intel-lab", "intel.relations")))
    assert rel.shape[1] == 5 and len(rel) > 58


def test_paths_and_negative_indices_as_python_has_them(tmp_path):
    import pathlib
    log = vdtnav.read_carmen_log(pathlib.Path(need(INTEL_LOG)))
    np.testing.assert_array_equal(log.scan(-1).ranges, log.ranges[-1])
    with pytest.raises(IndexError):
        log.scan(910)
    vdtnav.write_tum(tmp_path / "p.tum", [0.0], np.eye(4)[None])
    assert vdtnav.read_tum(tmp_path / "p.tum").shape == (1, 8)


def test_tum_round_trip(tmp_path):
    t = np.array([1.0, 2.5])
    p = np.array([[1.0, 2.0, 0.5], [-1.0, 0.25, -3.0]])
    vdtnav.write_tum(str(tmp_path / "t.tum"), t, p)
    back = vdtnav.read_tum(str(tmp_path / "t.tum"))
    np.testing.assert_array_equal(back[:, 0], t)
    np.testing.assert_allclose(back[:, 1:3], p[:, :2], atol=1e-12)
    yaw = 2 * np.arctan2(back[:, 6], back[:, 7])
    np.testing.assert_allclose(np.angle(np.exp(1j * (yaw - p[:, 2]))), 0, atol=1e-9)


@pytest.mark.skipif(not hasattr(vdtnav, "read_bag_scans"), reason="built without vdtnav::ros")
def test_a_ros1_bag_run_as_its_readme_describes_it():
    path = need(os.path.join(BAGS, "ist-pioneer3dx", "test1.bag"))
    topics = {t["name"]: t for t in vdtnav.bag_topics(path)}
    assert topics["/scan"]["count"] == 311 and topics["/scan"]["type"] == "sensor_msgs/LaserScan"
    run = vdtnav.read_bag_scans(path, laser_pose=[0, 0, 0])
    n = len(run["scans"]) + run["skipped_no_odometry"]
    assert n == 311 and len(run["scans"]) > 300
    assert run["odometry"].shape == (len(run["scans"]), 3)
    assert len(run["scans"][0].ranges) == 726
    assert np.all(np.diff(run["times"]) > 0)


@pytest.mark.skipif(not hasattr(vdtnav, "read_bag_clouds"), reason="built without vdtnav::ros")
def test_point_clouds_of_an_lz4_bag():
    path = need(os.path.join(BAGS, "embag-lz4", "test.bag"))
    # The bag has no TF (a simulator's): the cloud frame is the robot's.
    with pytest.raises(vdtnav.ConfigError, match="no transform base_link -> luminar_lidar"):
        vdtnav.read_bag_clouds(path, odom_topic="none", max_clouds=2)
    clouds = vdtnav.read_bag_clouds(path, odom_topic="none", lidar_pose=np.eye(4), max_clouds=2)
    assert len(clouds) == 2
    assert clouds[0]["points"].shape[1] == 3 and len(clouds[0]["points"]) <= 35707
    r = np.linalg.norm(clouds[0]["points"], axis=1)
    assert 6.0 < r.min() and r.max() < 260.0  # the README: 6.9-250 m


@pytest.mark.skipif(not hasattr(vdtnav, "read_bag_scans"), reason="built without vdtnav::ros")
def test_an_old_bag_format_is_refused_with_the_file_named():
    path = need(os.path.join(BAGS, "scan-tools-demo", "old_format_v1.2.bag"))
    with pytest.raises(vdtnav.Error, match="old_format_v1.2.bag"):
        vdtnav.bag_topics(path)
