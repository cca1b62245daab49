// vdtnav map3d: builds the VDT map of a point cloud or an octree — or of a mapping run, a folder
// of clouds with their poses — once and saves it (.vdt dense, .svdt sparse), so that
// `vdtnav localize3d --map MAP.vdt` loads it in a moment instead of building it every run.
#include <cstdio>

#include "common.hpp"
#include "exit_status.hpp"
#include "parse.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/io/vdt_map_file.hpp"

namespace vdtnav::tools {

namespace {

struct Map3dArgs {
  std::string map, out, crop, lidar_pose;
  MapLoadOptions options;
  MapScanRun run;
  int threads = -1;
  bool quiet = false;
};

void run_map3d(const Map3dArgs& a) {
  apply_threads(a.threads, 0);
  if (a.map.empty() == a.run.dir.empty())
    throw UsageError("map3d: give --map FILE (a cloud or an octree) or --scans DIR --poses FILE");
  if (a.run.dir.empty() != a.run.poses.empty())
    throw UsageError("map3d: --scans DIR and --poses FILE go together");
  MapLoadOptions o = a.options;
  if (!a.crop.empty()) o.crop = parse_crop_box(a.crop, "--crop");
  const auto ends_with = [&](const std::string& e) {
    return a.out.size() > e.size() && a.out.compare(a.out.size() - e.size(), e.size(), e) == 0;
  };
  o.sparse = ends_with(".svdt");
  if (!o.sparse && !ends_with(".vdt")) {
    throw UsageError("map3d: --out must name a .vdt (dense) or .svdt (sparse) file, got '" + a.out +
                     "'");
  }
  MapScanRun run = a.run;
  if (!a.lidar_pose.empty()) run.lidar_pose = parse_pose3(a.lidar_pose, "--lidar-pose");
  if (!a.quiet) {
    o.say = say_on_stderr("map3d");
    std::fprintf(stderr, "[map3d] building the %s VDT map of %s\n", o.sparse ? "sparse" : "dense",
                 a.map.empty() ? run.dir.c_str() : a.map.c_str());
  }
  const LoadedMap map = a.map.empty() ? build_map_from_scans(run, o) : load_map(a.map, o, 3);
  StagedOutputs staged;  // a failed write leaves no partial map
  if (map.dense) save_vdt_map(staged.file(a.out), *map.dense);
  if (map.sparse) save_sparse_vdt_map(staged.file(a.out), *map.sparse);
  staged.commit();
  const VdtField3& f = map.field3();
  std::printf("wrote %s: %d x %d x %d voxels of %.3f m, %.1f MB, built in %.2f s\n", a.out.c_str(),
              f.size().x(), f.size().y(), f.size().z(), f.resolution(),
              static_cast<double>(map.memory_bytes()) * 1e-6, map.seconds);
}

}  // namespace

void add_map3d_command(CLI::App& app) {
  auto args = std::make_shared<Map3dArgs>();
  CLI::App* cmd = app.add_subcommand(
      "map3d",
      "Build the VDT map of a point cloud (PCD, PLY, VTK, CSV/TXT/XYZ) or an OctoMap "
      "(.bt, .ot), or of a mapping run (--scans DIR --poses FILE), and save it as a .vdt file "
      "for localize3d");
  cmd->add_option("--map", args->map, "Point cloud or octree file");
  cmd->add_option("--scans", args->run.dir,
                  "A mapping run instead of --map: a folder of clouds (.pcd .ply .vtk .csv .txt "
                  ".xyz), merged in name order by their --poses");
  cmd->add_option("--poses", args->run.poses,
                  "--scans: each cloud's pose in the map frame, KITTI (a 3x4 matrix row by row, a "
                  "line per cloud in name order) or TUM (t x y z qx qy qz qw, matched to clouds "
                  "named by their stamp)");
  cmd->add_option("--every", args->run.selection.every,
                  "--scans: take every N-th cloud (0, N, 2N, ... counted from 0 in name order)")
      ->capture_default_str();
  cmd->add_flag(
      "--skip-odd", args->run.selection.skip_odd,
      "--scans: leave out clouds 1, 3, 5, ... (build from half a run, localize the rest)");
  cmd->add_flag("--skip-even", args->run.selection.skip_even,
                "--scans: leave out clouds 0, 2, 4, ...");
  cmd->add_option("--stamp-tolerance", args->run.stamp_tolerance,
                  "--scans with TUM poses: seconds a cloud's stamp may be from its pose's")
      ->capture_default_str();
  cmd->add_option("--lidar-pose", args->lidar_pose,
                  "--scans: the clouds' frame in the frame the poses give, x,y,z,roll,pitch,yaw "
                  "(metres, radians; default identity), e.g. KITTI's camera poses and Velodyne "
                  "clouds");
  cmd->add_option("--out", args->out,
                  "Output map file: .vdt (dense) or .svdt (sparse: bricks near the surfaces, "
                  "built without a dense grid, memory-mapped when loaded)")
      ->required();
  cmd->add_option("--resolution", args->options.resolution,
                  "Voxel edge, metres (clouds: default 0.1; octrees: default the tree's own, "
                  "otherwise a whole multiple of it)");
  cmd->add_option("--margin", args->options.margin, "Free border around the occupied space, metres")
      ->capture_default_str();
  cmd->add_option("--crop", args->crop,
                  "Keep only the cloud's points in the box xmin,ymin,zmin,xmax,ymax,zmax (metres)");
  cmd->add_flag("--thin-surfaces,!--no-thin-surfaces", args->options.thin_surfaces,
                "Clouds: thin each wall to the voxels its surface crosses (default), or keep every "
                "voxel with a point (a slab as thick as the points' scatter, in which a scan "
                "slides)");
  cmd->add_flag("--quiet", args->quiet, "Only the result line");
  add_threads_option(*cmd, args->threads);
  cmd->callback([args] { run_map3d(*args); });
}

}  // namespace vdtnav::tools
