"""Fixtures of the bindings' tests: the C++ reference program, the real data, generated maps."""
import os
import subprocess

import numpy as np
import pytest

DATA = os.environ.get("VDTNAV_DATA_DIR", os.path.join(os.path.dirname(__file__), "../../../shared/data"))
INTEL_LOG = os.path.join(DATA, "intel-lab", "intel.gfs.log.gz")


def cpp_reference(*args):
    """Runs python/tests/cpp_reference.cpp (the same computation through the C++ API) and returns
    its output lines as float arrays."""
    exe = os.environ.get("VDTNAV_CPP_REFERENCE")
    if not exe:
        pytest.skip("VDTNAV_CPP_REFERENCE not set (run through ctest)")
    out = subprocess.run([exe, *map(str, args)], check=True, capture_output=True, text=True).stdout
    return np.array([[float(v) for v in line.split()] for line in out.splitlines()])


def room_occupancy(nx=120, ny=80, seed=1):
    """A room with walls and a few random boxes: uint8 (ny, nx), 1 = occupied."""
    rng = np.random.default_rng(seed)
    occ = np.zeros((ny, nx), np.uint8)
    occ[[2, -3], 2:-2] = 1
    occ[2:-2, [2, -3]] = 1
    for _ in range(6):
        x, y = rng.integers(10, nx - 20), rng.integers(10, ny - 20)
        occ[y:y + rng.integers(3, 9), x:x + rng.integers(3, 9)] = 1
    return occ


@pytest.fixture(scope="session")
def room_map_yaml(tmp_path_factory):
    """A generated room saved as a ROS map (both sides read the same file)."""
    import vdtnav
    d = tmp_path_factory.mktemp("room")
    m = vdtnav.Map2(room_occupancy(), 0.05, origin=[-1.0, 2.0])
    m.save_ros(str(d / "room"))
    return str(d / "room.yaml")


@pytest.fixture(scope="session")
def intel_map_yaml(tmp_path_factory):
    """The Intel map drawn from the corrected poses of the log's last 300 scans."""
    import vdtnav
    if not os.path.exists(INTEL_LOG):
        pytest.skip(f"no data at {INTEL_LOG}")
    log = vdtnav.read_carmen_log(INTEL_LOG)
    n = len(log)
    m = vdtnav.build_occupancy_map(log.poses[n - 300:], [log.scan(i) for i in range(n - 300, n)], 0.05)
    d = tmp_path_factory.mktemp("intel")
    m.save_ros(str(d / "intel"))
    return str(d / "intel.yaml")
