#pragma once
/// \file
/// \brief `Grid<T, Dim>`: a dense regular grid of values with a world frame.

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/traits.hpp"

namespace vdtnav {

/// \brief Placement of a regular grid in the world: resolution, origin and (optionally) yaw.
///
/// `origin` is the world position of the *lower corner* of cell 0 (ROS map_server convention).
/// Cell centres lie at `origin + R (i + 1/2) resolution`. The grid may be rotated about the world
/// z axis by `yaw` around `origin` (ROS map_server's origin yaw); `axis_aligned()` is the fast
/// path.
template <int Dim>
class GridFrame {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Matrix = typename SpaceTraits<Dim>::Matrix;
  using Index = typename SpaceTraits<Dim>::Index;

  GridFrame() = default;
  GridFrame(double resolution, const Vector& origin, double yaw = 0.0)
      : resolution_(resolution), inv_resolution_(1.0 / resolution), origin_(origin), yaw_(yaw) {
    VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0.0,
                 "grid resolution must be finite and > 0");
    VDTNAV_CHECK(origin.allFinite() && std::isfinite(yaw), "grid origin and yaw must be finite");
    rotation_.setIdentity();
    if (yaw != 0.0) {
      const double c = std::cos(yaw), s = std::sin(yaw);
      rotation_(0, 0) = c;
      rotation_(0, 1) = -s;
      rotation_(1, 0) = s;
      rotation_(1, 1) = c;
    }
  }

  [[nodiscard]] double resolution() const noexcept { return resolution_; }
  /// \return 1 / resolution (queries multiply: a division costs more than the rest of a lookup).
  [[nodiscard]] double inv_resolution() const noexcept { return inv_resolution_; }
  [[nodiscard]] const Vector& origin() const noexcept { return origin_; }
  [[nodiscard]] double yaw() const noexcept { return yaw_; }
  /// \return R, the rotation from grid axes to world axes.
  [[nodiscard]] const Matrix& rotation() const noexcept { return rotation_; }
  [[nodiscard]] bool axis_aligned() const noexcept { return yaw_ == 0.0; }

  /// \return the continuous index u of world point p: cell centres sit at integer u.
  [[nodiscard]] Vector continuous_index(const Vector& p) const {
    const Vector local =
        axis_aligned() ? Vector(p - origin_) : Vector(rotation_.transpose() * (p - origin_));
    return local * inv_resolution_ - Vector::Constant(0.5);
  }
  /// \return the world position of continuous index u (inverse of continuous_index).
  [[nodiscard]] Vector world_point(const Vector& u) const {
    const Vector local = (u + Vector::Constant(0.5)) * resolution_;
    return axis_aligned() ? Vector(origin_ + local) : Vector(origin_ + rotation_ * local);
  }
  /// \return the centre of cell i in world coordinates.
  [[nodiscard]] Vector cell_center(const Index& i) const {
    return world_point(i.template cast<double>());
  }
  /// \return the index of the cell containing p (may lie outside the grid).
  [[nodiscard]] Index cell_of(const Vector& p) const {
    const Vector u = continuous_index(p) + Vector::Constant(0.5);
    Index i;
    for (int d = 0; d < Dim; ++d) i[d] = static_cast<int>(std::floor(u[d]));
    return i;
  }

 private:
  double resolution_ = 1.0;
  double inv_resolution_ = 1.0;
  Vector origin_ = Vector::Zero();
  double yaw_ = 0.0;
  Matrix rotation_ = Matrix::Identity();
};

/// \brief A dense Dim-dimensional grid of T, x fastest (linear = x + nx (y + ny z)).
template <typename T, int Dim>
class Grid {
 public:
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Index = typename SpaceTraits<Dim>::Index;

  Grid() : size_(Index::Zero()) {}
  /// \param size cells per axis (each >= 1); the total must fit in int32.
  Grid(const Index& size, const GridFrame<Dim>& frame, const T& fill = T{})
      : size_(size), frame_(frame) {
    std::int64_t n = 1;
    for (int d = 0; d < Dim; ++d) {
      VDTNAV_CHECK(size[d] >= 1, "grid size must be >= 1 along every axis");
      n *= size[d];
    }
    VDTNAV_CHECK(n < (std::int64_t{1} << 31), "grid has more than 2^31 cells");
    values_.assign(static_cast<std::size_t>(n), fill);
  }

  [[nodiscard]] const Index& size() const noexcept { return size_; }
  [[nodiscard]] std::size_t num_cells() const noexcept { return values_.size(); }
  [[nodiscard]] const GridFrame<Dim>& frame() const noexcept { return frame_; }
  [[nodiscard]] double resolution() const noexcept { return frame_.resolution(); }

  [[nodiscard]] bool contains(const Index& i) const noexcept {
    return (i.array() >= 0).all() && (i.array() < size_.array()).all();
  }
  [[nodiscard]] std::ptrdiff_t linear_index(const Index& i) const noexcept {
    std::ptrdiff_t l = i[Dim - 1];
    for (int d = Dim - 2; d >= 0; --d) l = l * size_[d] + i[d];
    return l;
  }
  [[nodiscard]] Index index_of(std::ptrdiff_t linear) const noexcept {
    Index i;
    for (int d = 0; d < Dim; ++d) {
      i[d] = static_cast<int>(linear % size_[d]);
      linear /= size_[d];
    }
    return i;
  }

  [[nodiscard]] T& operator()(const Index& i) {
    return values_[static_cast<std::size_t>(linear_index(i))];
  }
  [[nodiscard]] const T& operator()(const Index& i) const {
    return values_[static_cast<std::size_t>(linear_index(i))];
  }
  [[nodiscard]] T& operator[](std::size_t linear) { return values_[linear]; }
  [[nodiscard]] const T& operator[](std::size_t linear) const { return values_[linear]; }
  [[nodiscard]] T* data() noexcept { return values_.data(); }
  [[nodiscard]] const T* data() const noexcept { return values_.data(); }
  [[nodiscard]] std::vector<T>& values() noexcept { return values_; }
  [[nodiscard]] const std::vector<T>& values() const noexcept { return values_; }

  /// \return the centre of cell i in world coordinates.
  [[nodiscard]] Vector cell_center(const Index& i) const { return frame_.cell_center(i); }
  /// \return the cell containing world point p (may be outside; check with contains()).
  [[nodiscard]] Index cell_of(const Vector& p) const { return frame_.cell_of(p); }
  /// \return the world extent of the grid along its own axes.
  [[nodiscard]] Vector extent() const { return size_.template cast<double>() * resolution(); }

 private:
  Index size_;
  GridFrame<Dim> frame_;
  std::vector<T> values_;
};

template <typename T>
using Grid2 = Grid<T, 2>;
template <typename T>
using Grid3 = Grid<T, 3>;

/// Occupancy for the distance transforms: non-zero means occupied.
template <int Dim>
using OccupancyGrid = Grid<std::uint8_t, Dim>;

}  // namespace vdtnav
