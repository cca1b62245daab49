#pragma once
// Internal: thinning a voxelized cloud to its surfaces (PointCloudOccupancyOptions::thin).
//
// A map drawn from scans holds each wall as a slab: the range noise and the map builder's pose
// error scatter the points a few centimetres either side of the surface, and every voxel with a
// point is occupied. The VDT is zero inside the slab, so a scan matched on it slides freely
// across its thickness (on a simulated CATEC mapping drive, 3 cm range noise and 2 cm / 2 mrad of
// pose error give slabs of 2-3 voxels of 0.1 m and pose errors of +-0.12 m). The surface is
// where the points are densest: around each occupied voxel v, the points of its 3 x 3 x 3
// neighbourhood have mean m and covariance C (eigenvalues l0 <= l1 <= l2, normal n the
// eigenvector of l0). Where they lie on a plane (l0 <= kPlanarity l1, and l0 <= 0.2 res^2, a
// scatter under 0.45 voxel: two faces of a wall a voxel or more apart, or a wall exported as two
// layers of voxel centres, sqrt(l0) = res / 2, are not one plane) v is kept only if that plane
// crosses it, |n . (c_v - m)| <= res / 2 |n|_1 (the plane-box overlap test); elsewhere (edges,
// corners, clutter, too few points) v is kept.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "vdtnav/map/grid.hpp"

namespace vdtnav::detail {

/// A neighbourhood is a plane when its smallest spread is at most this fraction of the next.
inline constexpr double kPlanarity = 0.25;
/// Fewer points than this in a neighbourhood: no plane is fitted (the voxel is kept).
inline constexpr double kMinPlanePoints = 6.0;

/// The first and second moments of the points of one voxel, about the lattice origin.
struct VoxelMoments {
  double n = 0.0;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();

  void add(const Eigen::Vector3d& p) {
    n += 1.0;
    sum += p;
    outer += p * p.transpose();
  }
  void add(const VoxelMoments& o) {
    n += o.n;
    sum += o.sum;
    outer += o.outer;
  }
};

/// \param occupied the occupied voxels (each once).
/// \param n, point_at the points (non-finite ones skipped), as voxelize_points takes them.
/// \param voxel_of  voxel_of(p) -> Eigen::Vector3i, the voxel of a finite point.
/// \return for each voxel of `occupied`, in order, whether it stays occupied.
template <typename PointAt, typename VoxelOf>
std::vector<bool> surface_voxels(const std::vector<Eigen::Vector3i>& occupied,
                                 const GridFrame<3>& frame, std::size_t n, const PointAt& point_at,
                                 const VoxelOf& voxel_of) {
  const auto key = [](const Eigen::Vector3i& v) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v.x())) << 42) ^
           (static_cast<std::uint64_t>(static_cast<std::uint32_t>(v.y())) << 21) ^
           static_cast<std::uint64_t>(static_cast<std::uint32_t>(v.z()));
  };
  std::unordered_map<std::uint64_t, VoxelMoments> moments;
  moments.reserve(occupied.size());
  const Eigen::Vector3d origin = frame.origin();
  for (std::size_t k = 0; k < n; ++k) {
    const Eigen::Vector3d p = point_at(k);
    if (!p.allFinite()) continue;
    moments[key(voxel_of(p))].add(p - origin);
  }
  const double res = frame.resolution();
  std::vector<bool> keep(occupied.size(), true);
  for (std::size_t i = 0; i < occupied.size(); ++i) {
    VoxelMoments nb;
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const auto it = moments.find(key(occupied[i] + Eigen::Vector3i(dx, dy, dz)));
          if (it != moments.end()) nb.add(it->second);
        }
    if (nb.n < kMinPlanePoints) continue;
    const Eigen::Vector3d mean = nb.sum / nb.n;
    const Eigen::Matrix3d cov = nb.outer / nb.n - mean * mean.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    const Eigen::Vector3d l = eig.eigenvalues();  // ascending
    if (!(l[1] > 0.0 && l[0] <= kPlanarity * l[1] && l[0] <= 0.2 * res * res)) continue;
    const Eigen::Vector3d normal = eig.eigenvectors().col(0);
    const Eigen::Vector3d centre = frame.cell_center(occupied[i]) - origin;
    keep[i] = std::abs(normal.dot(centre - mean)) <= 0.5 * res * normal.lpNorm<1>() + 1e-12;
  }
  return keep;
}

}  // namespace vdtnav::detail
