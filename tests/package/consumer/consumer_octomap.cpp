// A user's program against the installed vdtnav::octomap: an OcTree and its .bt file to maps.
#include <vdtnav/octomap/octomap.hpp>

#include <cstdio>

int main(int argc, char** argv) {
  using namespace vdtnav;
  if (argc < 2) return 2;
  // Two occupied 0.1 m voxels 1 m apart along x.
  octomap::OcTree tree(0.1);
  tree.updateNode(octomap::point3d(0.05f, 0.05f, 0.05f), true);
  tree.updateNode(octomap::point3d(1.05f, 0.05f, 0.05f), true);
  if (!tree.writeBinaryConst(argv[1])) return 1;
  OctreeOccupancyOptions options;
  options.margin = 0.5;
  const VdtMap3 from_file = load_octree_map(argv[1], options);
  const VdtMap3 in_memory = vdt_map_from_octree(tree, options);
  // 0.3 m from the first voxel's centre: DT_v = (0.3, 0, 0).
  const Eigen::Vector3d p(0.35, 0.05, 0.05);
  const Eigen::Vector3d v = from_file.evaluate(p).value;
  const bool ok = (v - Eigen::Vector3d(0.3, 0, 0)).norm() < 1e-4 &&
                  (in_memory.evaluate(p).value - v).norm() == 0.0;
  std::printf("DT_v = (%g, %g, %g): %s\n", v.x(), v.y(), v.z(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
