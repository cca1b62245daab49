#pragma once
/// \file
/// \brief Per-dimension facts in one place (like manif's LieGroupProperties).

#include <Eigen/Core>

namespace vdtnav {

/// \brief Fixed-size types and counts for a map/workspace of dimension Dim (2 or 3).
template <int Dim>
struct SpaceTraits {
  static_assert(Dim == 2 || Dim == 3, "vdtnav supports 2D and 3D workspaces");
  static constexpr int kDim = Dim;
  using Vector = Eigen::Matrix<double, Dim, 1>;
  using Matrix = Eigen::Matrix<double, Dim, Dim>;
  using Index = Eigen::Matrix<int, Dim, 1>;
};

/// \brief Degrees of freedom of a rigid pose in Dim dimensions: 3 for (x, y, yaw), 6 for SE(3).
template <int Dim>
struct PoseTraits {
  static_assert(Dim == 2 || Dim == 3, "vdtnav supports 2D and 3D poses");
  static constexpr int kDoF = Dim == 2 ? 3 : 6;
};

}  // namespace vdtnav
