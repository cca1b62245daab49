#!/usr/bin/python3
"""The overhead of calling vdtnav from Python over the same call in C++, in the same run.

Two cases, each timed from Python (time.perf_counter around the Python call) and in C++
(vdtnav._vdtnav._timing: the same library call timed with a steady clock in the module itself,
the arguments converted beforehand, as a C++ user holds them):

  lookup   a batch VDT lookup of 10^5 points (with Jacobians) on a 2D map: m.lookup(points)
           against _timing.lookup2(m, points, True, repeats): one call as a C++ program makes it
           (the points as Eigen vectors — converted when float32, as the C++ API takes doubles —,
           a new vector of samples, the lookup), for float64 and float32 points, and without
           Jacobians. For information, the lookup alone into a vector reused from call to call
           (fresh_output=False): what the library's kernel costs with nothing around it;
  scan     one vdt-opt scan solve: loc.reset(p, c); loc.update(odometry, scan) against
           _timing.update2(loc, p, c, odometry, scan, repeats).

The map and scan are the Intel Research Lab's when --data has intel-lab/ (the map drawn from the
corrected poses of the log's last third, as the Intel study does, and one of those scans
localized from near its own pose), else a generated room (a numpy occupancy array) and a scan
ray-marched in it. Python and C++ are measured in alternating blocks (a shared machine drifts),
and each side's figure is the median of its block medians. Everything runs on one thread (the
lookup and the solve are single-threaded; the GIL is released but nothing else runs).

Run (the build tree's module, Debian's interpreter, which has numpy):
    PYTHONPATH=build/release/python /usr/bin/python3 bench/python/overhead.py [--data ../shared/data]

It reports and always exits 0: it is not a test.
"""
import argparse
import os
import pathlib
import platform
import statistics
import sys
import time

import numpy as np

import vdtnav
from vdtnav import _vdtnav

timing = _vdtnav._timing

REPO = pathlib.Path(__file__).resolve().parents[2]


# ----------------------------------------------------------------------------------------------
# Data


def intel_map_and_scan(data, scan_index):
    """The Intel map drawn from the last third of the corrected log, one of its scans and the
    scan's own (corrected) pose."""
    log = vdtnav.read_carmen_log(str(data / "intel-lab" / "intel.gfs.log.gz"))
    n = len(log)
    a, b = n - n // 3, n
    poses = log.poses
    m = vdtnav.build_occupancy_map(poses[a:b], [log.scan(i) for i in range(a, b)], 0.05)
    i = scan_index if scan_index is not None else a + (b - a) // 2
    what = f"Intel Research Lab: map of scans {a}..{b - 1} at 0.05 m, scan {i} of {n}"
    return m, log.scan(i), poses[i].copy(), what


def generated_map_and_scan():
    """A 20 m x 15 m room at 0.05 m with a few pillars and a wall, and a 360-beam scan
    ray-marched in it."""
    res = 0.05
    ny, nx = 300, 400
    occ = np.zeros((ny, nx), dtype=bool)
    occ[:2, :] = occ[-2:, :] = True
    occ[:, :2] = occ[:, -2:] = True
    occ[100:103, 60:220] = True  # an inner wall
    occ[180:260, 300:303] = True
    for cy, cx in [(60, 300), (220, 100), (150, 330), (240, 200)]:  # pillars, 0.4 m square
        occ[cy - 4 : cy + 4, cx - 4 : cx + 4] = True
    m = vdtnav.Map2(occ, res)
    pose = np.array([7.3, 8.1, 0.4])
    n_beams, range_max = 360, 30.0
    angles = -np.pi + np.arange(n_beams) * (2 * np.pi / n_beams)
    step = res / 4
    t = np.arange(step, 25.0, step)
    heading = pose[2] + angles
    xs = pose[0] + np.outer(np.cos(heading), t)
    ys = pose[1] + np.outer(np.sin(heading), t)
    ix = np.clip((xs / res).astype(int), 0, nx - 1)
    iy = np.clip((ys / res).astype(int), 0, ny - 1)
    hit = occ[iy, ix]
    first = np.argmax(hit, axis=1)
    ranges = np.where(hit.any(axis=1), t[first], np.inf)
    scan = vdtnav.LaserScan(ranges, angle_min=-np.pi, angle_increment=2 * np.pi / n_beams,
                            range_max=range_max)
    what = f"generated room: {nx} x {ny} cells at {res} m, {n_beams}-beam ray-marched scan"
    return m, scan, pose, what


# ----------------------------------------------------------------------------------------------
# Timing


def python_block(f, repeats):
    """The median seconds of `repeats` calls of f() from Python."""
    t = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        f()
        t.append(time.perf_counter() - t0)
    return statistics.median(t)


def interleaved(py, cpp, blocks, repeats):
    """(Python median, C++ median), each the median of `blocks` block medians, the blocks of the
    two alternating (which goes first alternating too)."""
    py_t, cpp_t = [], []
    for b in range(blocks):
        if b % 2 == 0:
            py_t.append(python_block(py, repeats))
            cpp_t.append(cpp(repeats))
        else:
            cpp_t.append(cpp(repeats))
            py_t.append(python_block(py, repeats))
    return statistics.median(py_t), statistics.median(cpp_t), py_t, cpp_t


def machine_note():
    cpu = "?"
    try:
        for line in open("/proc/cpuinfo", encoding="utf-8"):
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = ", ".join(f"{x:.2f}" for x in os.getloadavg()) if hasattr(os, "getloadavg") else "?"
    return (
        f"machine: {cpu}, {os.cpu_count()} cores, load average {load}; {platform.system()} "
        f"{platform.release()}; Python {platform.python_version()}, numpy {np.__version__}, "
        f"vdtnav {vdtnav.__version__}\n"
        "note: one thread, one process; a shared machine whose absolute timings vary by about "
        "+-15 % from run to run (docs/benchmarks.md): the ratio of the two sides, measured in "
        "alternating blocks of the same run, is the figure to read, not the milliseconds."
    )


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n", 1)[0])
    ap.add_argument("--data", type=pathlib.Path,
                    default=pathlib.Path(os.environ.get("VDTNAV_DATA_DIR",
                                                        REPO.parent / "shared" / "data")),
                    help="folder with intel-lab/ (default: $VDTNAV_DATA_DIR, else ../shared/data "
                         "beside the repository); without it a generated map and scan")
    ap.add_argument("--points", type=int, default=100_000, help="points per batch lookup")
    ap.add_argument("--repeats", type=int, default=30,
                    help="timed calls per case and side (split into --blocks blocks)")
    ap.add_argument("--blocks", type=int, default=6, help="alternating blocks per case")
    ap.add_argument("--scan", type=int, default=None, help="the Intel scan to localize")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()
    per_block = max(1, -(-args.repeats // args.blocks))

    t0 = time.perf_counter()
    if (args.data / "intel-lab" / "intel.gfs.log.gz").is_file():
        m, scan, pose, what = intel_map_and_scan(args.data, args.scan)
    else:
        m, scan, pose, what = generated_map_and_scan()
    print(f"data: {what}; {m!r} (prepared in {time.perf_counter() - t0:.1f} s)")

    # (a) Batch lookup: uniform points over the map's extent.
    rng = np.random.default_rng(args.seed)
    f = m.frame
    lo = np.asarray(f["origin"])
    hi = lo + np.asarray(f["size"], dtype=float) * f["resolution"]
    if abs(f["yaw"]) > 0:
        print("note: the map frame has a yaw; points drawn in its axis-aligned box")
    pts64 = lo + rng.random((args.points, 2)) * (hi - lo)
    pts32 = pts64.astype(np.float32)

    rows = []
    npts = "1e5" if args.points == 100_000 else str(args.points)
    cases = [(f"lookup {npts} float64", pts64, True, 10.0),
             (f"lookup {npts} float32", pts32, True, 10.0),
             (f"lookup {npts} f64 no-J", pts64, False, 10.0)]
    for label, pts, jac, target in cases:
        m.lookup(pts, jacobian=jac)  # warm up (page in the map, the allocator)
        timing.lookup2(m, pts, jac, 2)
        py, cpp, _, _ = interleaved(lambda: m.lookup(pts, jacobian=jac),
                                    lambda r: timing.lookup2(m, pts, jac, r),
                                    args.blocks, per_block)
        rows.append((label, cpp, py, target))
    # For information: against the kernel alone (a reused output vector, points pre-converted).
    py, cpp, _, _ = interleaved(lambda: m.lookup(pts64),
                                lambda r: timing.lookup2(m, pts64, True, r, False),
                                args.blocks, per_block)
    rows.append((f"lookup {npts} f64 vs kernel", cpp, py, None))

    # (b) One vdt-opt scan solve from near the scan's pose.
    loc = vdtnav.make_localizer("vdt-opt", m)
    start = pose + np.array([0.05, -0.04, 0.02])  # a tracking step's error: the solve iterates
    cov = np.diag([0.1**2, 0.1**2, 0.05**2])
    odo = vdtnav.OdometryStep([0.0, 0.0, 0.0], 0.1)

    def py_update():
        loc.reset(start, cov)
        return loc.update(odo, scan)

    res = py_update()
    timing.update2(loc, start, cov, odo, scan, 2)
    err = np.hypot(*(res.pose[:2] - pose[:2]))
    print(f"scan solve: {len(scan.ranges)} beams, {res.status}, {res.iterations} iterations, "
          f"explained {res.explained:.2f}, {err * 100:.1f} cm from the scan's pose")
    py, cpp, _, _ = interleaved(py_update,
                                lambda r: timing.update2(loc, start, cov, odo, scan, r),
                                args.blocks, per_block)
    rows.append(("scan solve (vdt-opt)", cpp, py, 5.0))

    print()
    print(f"medians of {args.blocks} alternating blocks of {per_block} calls per side")
    header = f"{'case':<22} {'C++ ms':>9} {'Python ms':>10} {'overhead %':>11} {'target':>8}  "
    print(header)
    print("-" * len(header))
    for label, cpp, py, target in rows:
        over = (py - cpp) / cpp * 100.0
        if target is None:
            goal, ok = "info", ""
        else:
            goal, ok = f"<= {target:g} %", "ok" if over <= target else "OVER"
        print(f"{label:<22} {cpp * 1e3:>9.3f} {py * 1e3:>10.3f} {over:>11.1f} {goal:>8}  {ok}")
    print()
    print(machine_note())
    return 0


if __name__ == "__main__":
    try:
        main()
    except Exception as e:  # it reports; it is not a test
        print(f"overhead.py: {type(e).__name__}: {e}", file=sys.stderr)
    sys.exit(0)
