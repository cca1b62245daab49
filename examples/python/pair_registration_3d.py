#!/usr/bin/env python3
"""3D pair registration with a covariance: libpointmatcher's real car scans, from Python.

What `vdtnav localize3d` does for the main job's step 20 (README, "3D, the command line"):
  vdtnav localize3d --map car_cloud400.csv --crop -40,-40,-12,40,40,20 --resolution 0.2 \\
      --scan car_cloud401.csv --multi-start
  1. the map: scan 400 (reference pose: identity) cropped to +-40 m, voxelized at 0.2 m with its
     walls thinned, and its 3D VDT (thesis Ch. 2);
  2. scan 401 localized on it from an identity guess: the 6-DOF optimizer on SE(3) (thesis
     Algorithm 1, 3.3.3), multi-start along the axes while a solution explains too little, with
     `localize3d`'s defaults (Settings.cloud(): Cauchy loss, map errors shared per 1 m cube);
  3. the pose, its 6 x 6 covariance (left perturbation (dt, dtheta) in the map frame), the
     status and the fraction of the readings the map explains there; the distance to
     carCloudList.csv's reference pose and the NEES against it (chi^2_6 95 %: 1.24-14.4).
--reverse registers 400 on a map of 401 (against the reference's inverse); --init perturbed
starts at the reference moved 0.1 m along x, with a single solve. Writes DIR/summary.csv and
DIR/pose.txt (pose and covariance).

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/pair_registration_3d.py \\
        --data ../shared/data --out out/python_pair3d
"""
import argparse
import csv
import os
import sys
import time

import numpy as np

try:
    import vdtnav
except ImportError as e:
    sys.exit("pair_registration_3d.py: cannot import vdtnav (%s): build it (-DVDTNAV_PYTHON=ON) "
             "and run with PYTHONPATH=build/release/python" % e)

CROP = (-40.0, -40.0, -12.0, 40.0, 40.0, 20.0)  # the CLI's --crop: xmin,ymin,zmin,xmax,ymax,zmax (m)


def say(text):
    print("[python pair3d] " + text, flush=True)


def reference_poses(path):
    """carCloudList.csv: file name -> 4 x 4 pose, its rotation made orthonormal (as the test)."""
    poses = {}
    with open(path) as f:
        for row in list(csv.reader(f))[1:]:
            m = np.array([float(v) for v in row[1:17]]).reshape(4, 4)
            u, _, vt = np.linalg.svd(m[:3, :3])
            m[:3, :3] = u @ vt
            poses[row[0].strip()] = m
    return poses


def rpy_deg(r):
    """(roll, pitch, yaw) of R = Rz(yaw) Ry(pitch) Rx(roll), degrees."""
    return np.degrees([np.arctan2(r[2, 1], r[2, 2]), -np.arcsin(np.clip(r[2, 0], -1, 1)),
                       np.arctan2(r[1, 0], r[0, 0])])


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="folder with 3d/libpointmatcher/")
    ap.add_argument("--out", default="out/python_pair3d", help="output folder")
    ap.add_argument("--resolution", type=float, default=0.2, help="map voxel edge, metres")
    ap.add_argument("--reverse", action="store_true", help="scan 400 on a map of scan 401")
    ap.add_argument("--init", choices=["identity", "perturbed"], default="identity",
                    help="identity (multi-start, as the CLI) or the reference moved 0.1 m in x")
    args = ap.parse_args()

    d = os.path.join(args.data, "3d", "libpointmatcher")
    names = ["car_cloud400.csv", "car_cloud401.csv"]
    missing = [f for f in names + ["carCloudList.csv"] if not os.path.isfile(os.path.join(d, f))]
    if missing:
        print("pair_registration_3d.py: the libpointmatcher data is missing in %s: %s" %
              (d, ", ".join(missing)), file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)
    map_name, scan_name = names[::-1] if args.reverse else names
    ref = reference_poses(os.path.join(d, "carCloudList.csv"))
    # The scan's pose in the map's frame: T_map^-1 T_scan (401 on 400: 401's reference itself).
    truth = np.linalg.inv(ref[map_name]) @ ref[scan_name]

    t0 = time.perf_counter()
    # The map's cloud cropped to CROP (load_map's crop, the CLI's --crop) and voxelized.
    vdt_map = vdtnav.load_map(os.path.join(d, map_name), resolution=args.resolution, crop=CROP)
    say("map %s cropped to %s: %d x %d x %d voxels of %.2f m, %.0f MB, built in %.2f s" % (
        (map_name, ",".join("%g" % v for v in CROP)) + tuple(vdt_map.frame["size"]) + (
            vdt_map.resolution, vdt_map.memory_bytes * 1e-6, time.perf_counter() - t0)))

    cloud = vdtnav.read_point_cloud(os.path.join(d, scan_name))
    if args.init == "identity":
        init, settings = np.eye(4), {"localize3d": {"multi_start": {"enabled": True}}}
    else:
        init, settings = truth.copy(), None
        init[0, 3] += 0.1
    t0 = time.perf_counter()
    r = vdtnav.localize3d(vdt_map, cloud, init=init, dof=6, settings=settings)
    solve_s = time.perf_counter() - t0
    pose, cov = r.pose, r.covariance
    sd = np.sqrt(np.diag(cov))
    say("%s (%d points) from %s: %s, %.0f %% explained, %d iterations, %.2f s" % (
        scan_name, len(cloud), args.init, r.status, 100 * r.explained, r.iterations, solve_s))
    say("pose xyz %.3f %.3f %.3f m, rpy %.2f %.2f %.2f deg" % (tuple(pose[:3, 3]) +
                                                              tuple(rpy_deg(pose[:3, :3]))))
    say("sigmas x y z %.4f %.4f %.4f m, rx ry rz %.3f %.3f %.3f deg; sd %.3f m %.2f deg" % (
        tuple(sd[:3]) + tuple(np.degrees(sd[3:])) +
        (np.sqrt(np.trace(cov[:3, :3])), np.degrees(np.sqrt(np.trace(cov[3:, 3:]))))))

    # Against the reference: the translation's distance, the rotation's angle (|Log(R R*^T)|),
    # and e^T P^-1 e with e the left perturbation from the reference (eval/nees.hpp).
    dt = np.linalg.norm(pose[:3, 3] - truth[:3, 3])
    c = (np.trace(pose[:3, :3] @ truth[:3, :3].T) - 1.0) / 2.0
    da = np.degrees(np.arccos(np.clip(c, -1.0, 1.0)))
    nees = vdtnav.nees(pose, truth, cov) if r.has_covariance else float("nan")
    say("against carCloudList.csv's reference: %.4f m, %.3f deg, NEES %.2f (chi^2_6 95 %%: "
        "1.24-14.4)" % (dt, da, nees))

    with open(os.path.join(args.out, "summary.csv"), "w", newline="") as f:
        w = csv.writer(f, lineterminator="\n")
        w.writerow(["map", "scan", "init", "status", "explained", "iterations", "solve_s", "x",
                    "y", "z", "roll_deg", "pitch_deg", "yaw_deg", "sd_x", "sd_y", "sd_z",
                    "sd_rx_deg", "sd_ry_deg", "sd_rz_deg", "ref_dist_m", "ref_angle_deg", "nees"])
        w.writerow([map_name, scan_name, args.init, r.status, "%.4f" % r.explained,
                    r.iterations, "%.3f" % solve_s] +
                   ["%.6f" % v for v in np.r_[pose[:3, 3], rpy_deg(pose[:3, :3]), sd[:3],
                                              np.degrees(sd[3:]), dt, da, nees]])
    with open(os.path.join(args.out, "pose.txt"), "w") as f:
        f.write("# %s on the map of %s: pose (4 x 4, map point = pose * scan point)\n" %
                (scan_name, map_name))
        np.savetxt(f, pose, fmt="%.9f")
        f.write("# covariance (6 x 6) of (dx, dy, dz, dtheta_x, dtheta_y, dtheta_z): the left "
                "perturbation in the map frame, m^2 and rad^2\n")
        np.savetxt(f, cov, fmt="%.9e")
    say("wrote %s/summary.csv and pose.txt" % args.out)
    return 0 if r.status == "converged" else 3  # as the CLI: completed, nothing localized


if __name__ == "__main__":
    sys.exit(main())
