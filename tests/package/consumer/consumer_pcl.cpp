// A user's program against the installed vdtnav::pcl: a PCD file and a pcl::PointCloud to maps.
#include <vdtnav/pcl/pcl.hpp>

#include <cstdio>
#include <fstream>

int main(int argc, char** argv) {
  using namespace vdtnav;
  if (argc < 2) return 2;
  // Two points 1 m apart along x, each at the centre of a 0.1 m voxel.
  std::ofstream(argv[1]) << "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
                            "COUNT 1 1 1\nWIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\n"
                            "DATA ascii\n0.05 0.05 0.05\n1.05 0.05 0.05\n";
  pcl::PointCloud<pcl::PointXYZ> cloud;
  cloud.push_back(pcl::PointXYZ(0.05f, 0.05f, 0.05f));
  cloud.push_back(pcl::PointXYZ(1.05f, 0.05f, 0.05f));
  PointCloudOccupancyOptions options;
  options.resolution = 0.1;
  options.margin = 0.5;
  const VdtMap3 from_file = load_point_cloud_map(argv[1], options);
  const VdtMap3 in_memory = vdt_map_from_point_cloud(cloud, options);
  // 0.3 m from the first point's voxel centre: DT_v = (0.3, 0, 0).
  const Eigen::Vector3d p(0.35, 0.05, 0.05);
  const Eigen::Vector3d v = from_file.evaluate(p).value;
  const bool ok = (v - Eigen::Vector3d(0.3, 0, 0)).norm() < 1e-4 &&
                  (in_memory.evaluate(p).value - v).norm() == 0.0;
  std::printf("DT_v = (%g, %g, %g): %s\n", v.x(), v.y(), v.z(), ok ? "ok" : "WRONG");
  return ok ? 0 : 1;
}
