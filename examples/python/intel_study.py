#!/usr/bin/env python3
"""The Intel Research Lab study (thesis 3.4.2, Dataset 2) from Python: examples/intel_lab's runs.

The same C++ calls as build/release/examples/intel_lab/vdtnav_intel_lab, through the module:
  1. join the GMapping-corrected log with the raw-odometry table (`vdtnav join-odometry`);
  2. build an occupancy map (log-odds ray casting, 0.05 m) from the corrected poses of the last
     third of the scans, and its VDT (thesis Ch. 2, eqs. 2.5-2.9);
  3. localize the first two thirds with the raw odometry and the scans (vdt-opt: thesis
     Algorithm 1, with `vdtnav localize`'s defaults, Settings.log()), starting at the corrected
     pose of scan 0;
  4. score against the Kuemmerle et al. (2009) relations whose both ends are localized scans
     (exact stamps), with the relation NEES, and against the corrected poses (ANEES, chi^2_3).
Writes DIR/traj_METHOD.tum, DIR/table.csv, DIR/trajectories.png and DIR/errors_METHOD.png.

    PYTHONPATH=build/release/python /usr/bin/python3 examples/python/intel_study.py \
        --data ../shared/data --out out/python_intel
"""
import argparse
import csv
import os
import sys
import time

import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

try:
    import vdtnav
except ImportError as e:
    sys.exit("intel_study.py: cannot import vdtnav (%s): build it (-DVDTNAV_PYTHON=ON) and run "
             "with PYTHONPATH=build/release/python" % e)


def say(text):
    print("[python intel] " + text, flush=True)


def wrap(a):
    return (a + np.pi) % (2.0 * np.pi) - np.pi


def row(method, rel, rel_nees=None, anees=None, ms=None):
    """One row of the table: the relation metric, relation NEES, ANEES and the ms per scan (mean,
    median, 99th percentile by nearest rank as the C++ studies report it, maximum)."""
    ms = np.asarray(ms if ms is not None else [np.nan])
    return {"method": method, "relations": rel.used, "trans_mean_m": rel.translation_mean,
            "rot_mean_deg": np.degrees(rel.rotation_mean),
            "rel_nees_used": rel_nees.used if rel_nees else 0,
            "rel_nees_mean": rel_nees.mean if rel_nees else np.nan,
            "rel_nees_inside_pct": 100 * rel_nees.fraction_inside if rel_nees else np.nan,
            "anees": anees.anees if anees else np.nan,
            "anees_lo": anees.interval[0] if anees else np.nan,
            "anees_hi": anees.interval[1] if anees else np.nan, "ms_per_scan": ms.mean(),
            "ms_median": np.median(ms), "ms_p99": np.percentile(ms, 99, method="inverted_cdf"),
            "ms_max": ms.max()}


def localize(method, vdt_map, raw, steps, split, sigma_range, start_pose):
    """Scans 0..split-1 localized by `method`: poses, covariances (NaN where none), each scan's ms."""
    loc = vdtnav.make_localizer(method, vdt_map)  # settings None: Settings.log(), the C++ study's
    loc.reset(start_pose, np.diag([0.1**2, 0.1**2, 0.05**2]))
    poses, covs, ms = np.zeros((split, 3)), np.full((split, 3, 3), np.nan), np.zeros(split)
    for k in range(split):
        scan = raw.scan(k)  # a copy: the log keeps its own
        scan.sigma_range = sigma_range
        t0 = time.perf_counter()
        res = loc.update(steps[k], scan)  # predict with the odometry step, correct with the scan
        ms[k] = 1e3 * (time.perf_counter() - t0)
        poses[k] = res.pose
        if res.has_covariance:
            covs[k] = res.covariance
    return poses, covs, ms


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--data", default="../shared/data", help="folder with intel-lab/")
    ap.add_argument("--out", default="out/python_intel", help="output folder")
    ap.add_argument("--methods", nargs="+", default=["vdt-opt"],
                    choices=vdtnav.localizer_methods(), help="methods to run")
    ap.add_argument("--sigma-range", type=float, default=0.02, help="range noise sigma, metres")
    args = ap.parse_args()

    d = os.path.join(args.data, "intel-lab")
    files = [os.path.join(d, f) for f in
             ("intel.gfs.log.gz", "intel_910_odom_vs_corrected.txt", "intel.relations")]
    missing = [f for f in files if not os.path.isfile(f)]
    if missing:
        print("intel_study.py: the Intel data is missing: " + ", ".join(missing) +
              " (give its folder's parent with --data)", file=sys.stderr)
        return 2
    os.makedirs(args.out, exist_ok=True)

    # 1. The corrected log joined with the raw odometry: (raw, corrected) on the absolute time base.
    say("joining %s with the raw-odometry table" % files[0])
    raw, corrected = vdtnav.join_odometry_table(vdtnav.read_carmen_log(files[0]), files[1])
    n = len(raw)
    split = n - n // 3  # the last third maps, the first two thirds localize
    times = raw.times[:split]
    reference = corrected.poses[:split]

    # 2. The map from the corrected poses of scans split..n-1.
    t0 = time.perf_counter()
    vdt_map = vdtnav.build_occupancy_map(corrected.poses[split:], corrected.scans[split:], 0.05)
    say("map from scans %d..%d: %s, built in %.2f s" % (split, n - 1, vdt_map,
                                                        time.perf_counter() - t0))

    # 3. The odometry steps of scans 0..split-1 (ODOM lines interpolated, else the scans' odom).
    odom = vdtnav.log_odometry(raw, list(range(split)))
    steps = vdtnav.odometry_steps(times, odom)
    relations = vdtnav.read_relations(files[2])
    rows = [row("gmapping (reference)", vdtnav.relation_metric(times, reference, relations))]
    runs = {}
    for method in args.methods:
        say("localizing scans 0..%d with %s" % (split - 1, method))
        poses, covs, ms = localize(method, vdt_map, raw, steps, split, args.sigma_range,
                                   reference[0])
        runs[method] = (poses, covs)
        vdtnav.write_tum(os.path.join(args.out, "traj_%s.tum" % method), times, poses)
        # 4. Relations with exact stamps (one scan every ~3 s: no interpolation), relation NEES
        # (both ends' covariances through between()), NEES against the corrected poses.
        rel = vdtnav.relation_metric(times, poses, relations)
        has = np.flatnonzero(~np.isnan(covs[:, 0, 0]))
        if len(has) == 0:
            rows.append(row(method, rel, ms=ms))
            continue
        rel_nees = vdtnav.relation_nees(times, poses, covs, relations)
        anees = vdtnav.anees([vdtnav.nees(poses[k], reference[k], covs[k]) for k in has], 3)
        rows.append(row(method, rel, rel_nees, anees, ms))

    # The table: stdout and table.csv (NaN: not measured).
    say("%-20s %4s %9s %9s %16s %8s %22s %7s %7s %7s %7s" % (
        "method", "rel", "trans (m)", "rot (deg)", "rel NEES: n mean", "inside", "ANEES [95 %]",
        "ms/scan", "median", "p99", "max"))
    for r in rows:
        say("%-20s %4d %9.4f %9.2f %5d %10.2f %6.1f %% %9.2f [%.2f, %.2f] %7.3f %7.3f %7.2f %7.2f"
            % tuple(r.values()))
    with open(os.path.join(args.out, "table.csv"), "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]), lineterminator="\n")
        w.writeheader()
        w.writerows(rows)

    # Figures: the trajectories over the map, and each method's errors with +-2 sigma.
    fr = vdt_map.frame
    x0, y0 = fr["origin"]
    extent = [x0, x0 + fr["size"][0] * fr["resolution"], y0, y0 + fr["size"][1] * fr["resolution"]]
    cells = vdt_map.cells.astype(float)  # -1 unknown, 0..100 occupancy in percent
    image = np.where(cells < 0, 0.8, 1.0 - cells / 100.0)
    fig, ax = plt.subplots(figsize=(9, 9))
    ax.imshow(image, cmap="gray", vmin=0, vmax=1, origin="lower", extent=extent)
    ax.plot(reference[:, 0], reference[:, 1], "k--", lw=1.5, label="corrected (GMapping)")
    for method, (poses, _) in runs.items():
        ax.plot(poses[:, 0], poses[:, 1], lw=1.0, label=method)
    ax.set(xlabel="x [m]", ylabel="y [m]", aspect="equal",
           title="Intel lab: scans 0..%d localized on the map of the last third" % (split - 1))
    ax.legend(loc="upper right")
    fig.savefig(os.path.join(args.out, "trajectories.png"), dpi=120, bbox_inches="tight")
    plt.close(fig)
    t = times - times[0]
    for method, (poses, covs) in runs.items():
        err = poses - reference
        err[:, 2] = wrap(err[:, 2])  # pose_error(estimate, truth): (dx, dy, wrap(dphi))
        fig, axes = plt.subplots(3, 1, figsize=(11, 8), sharex=True)
        for c, (ax, name) in enumerate(zip(axes, ["x error [m]", "y error [m]", "yaw error [rad]"])):
            s2 = 2.0 * np.sqrt(np.maximum(covs[:, c, c], 0.0))
            ax.fill_between(t, -s2, s2, color="C0", alpha=0.3, label="±2σ")
            ax.plot(t, err[:, c], color="C1", lw=1.0, label="error")
            ax.set_ylabel(name)
            ax.grid(True)
        axes[0].legend(loc="upper right")
        axes[0].set_title("%s: error against the corrected poses, with ±2σ" % method)
        axes[2].set_xlabel("time [s]")
        fig.savefig(os.path.join(args.out, "errors_%s.png" % method), dpi=120, bbox_inches="tight")
        plt.close(fig)
    say("wrote %s/table.csv, trajectories.png, errors_*.png, traj_*.tum" % args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
