// vdtnav map3d: builds the VDT map of a point cloud or an octree once and saves it (.vdt dense,
// .svdt sparse), so that `vdtnav localize3d --map MAP.vdt` loads it in a moment instead of
// building it every run.
#include <cstdio>

#include "common.hpp"
#include "exit_status.hpp"
#include "map3d.hpp"
#include "staged_output.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/sparse_vdt_map_file.hpp"
#include "vdtnav/io/vdt_map_file.hpp"

namespace vdtnav::tools {

namespace {

struct Map3dArgs {
  std::string map, out, crop;
  Map3dOptions options;
  int threads = -1;
};

void run_map3d(const Map3dArgs& a) {
  apply_threads(a.threads, 0);
  Map3dOptions o = a.options;
  if (!a.crop.empty()) o.crop = parse_crop(a.crop, "--crop");
  const auto ends_with = [&](const std::string& e) {
    return a.out.size() > e.size() && a.out.compare(a.out.size() - e.size(), e.size(), e) == 0;
  };
  o.sparse = ends_with(".svdt");
  if (!o.sparse && !ends_with(".vdt")) {
    throw UsageError("map3d: --out must name a .vdt (dense) or .svdt (sparse) file, got '" + a.out +
                     "'");
  }
  std::fprintf(stderr, "[map3d] building the %s VDT map of %s\n", o.sparse ? "sparse" : "dense",
               a.map.c_str());
  const Map3d map = load_map3d(a.map, o);
  StagedOutputs staged;  // a failed write leaves no partial map
  if (map.dense) save_vdt_map(staged.file(a.out), *map.dense);
  if (map.sparse) save_sparse_vdt_map(staged.file(a.out), *map.sparse);
  staged.commit();
  const VdtField3& f = map.field();
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
      "(.bt, .ot) and save it as a .vdt file for localize3d");
  cmd->add_option("--map", args->map, "Point cloud or octree file")->required();
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
  cmd->add_flag("--quiet", args->options.quiet, "Only the result line");
  add_threads_option(*cmd, args->threads);
  cmd->callback([args] { run_map3d(*args); });
}

}  // namespace vdtnav::tools
