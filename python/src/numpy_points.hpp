#pragma once
// numpy arrays in and out of the bindings: N x Dim point arrays read in place (float32 or
// float64, any strides: no copy of the input is made), poses and matrices converted with their
// shapes checked (a ValueError naming the argument and the shape expected).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/core/pose3.hpp"

namespace vdtnav::python {

namespace py = pybind11;

/// \brief An N x Dim array of points read where it lies: float32 or float64, C- or
/// Fortran-ordered or strided (a slice, a transposed view). \throws ValueError (py::value_error)
/// for another dtype, another number of dimensions or columns.
template <int Dim>
class PointView {
 public:
  using Vector = Eigen::Matrix<double, Dim, 1>;
  PointView(const py::array& a, const char* what);
  [[nodiscard]] std::size_t size() const noexcept { return n_; }
  /// \brief Points [first, first + count) as doubles into out.
  void read(std::size_t first, std::size_t count, Vector* out) const;
  /// \return the points from `first` on as Eigen vectors in place (no conversion) when the array
  /// holds them so: float64, each row Dim packed doubles, rows Dim doubles apart, the data
  /// aligned as Eigen's fixed-size vectors require; nullptr otherwise (read() converts).
  template <typename V>
  [[nodiscard]] const V* as_vectors(std::size_t first) const noexcept {
    if (is_float32_ || col_stride_ != sizeof(double) ||
        row_stride_ != static_cast<py::ssize_t>(sizeof(V)) || sizeof(V) != Dim * sizeof(double) ||
        reinterpret_cast<std::uintptr_t>(data_) % alignof(V) != 0)
      return nullptr;
    return reinterpret_cast<const V*>(data_) + first;
  }
  /// \return all points (a copy: for the APIs that take a std::vector).
  [[nodiscard]] std::vector<Vector> all() const;
  /// \return the address of the first element (the no-copy test compares it with numpy's).
  [[nodiscard]] const void* data() const noexcept { return data_; }

 private:
  const char* data_ = nullptr;
  std::size_t n_ = 0;
  py::ssize_t row_stride_ = 0, col_stride_ = 0;
  bool is_float32_ = false;
};

/// \brief An array-like as a fixed-size vector / matrix. \throws ValueError naming `what`.
[[nodiscard]] Eigen::VectorXd to_vector(const py::handle& h, py::ssize_t n, const char* what);
[[nodiscard]] Eigen::MatrixXd to_matrix(const py::handle& h, py::ssize_t rows, py::ssize_t cols,
                                        const char* what);
[[nodiscard]] Pose2 to_pose2(const py::handle& h, const char* what);
[[nodiscard]] Pose3 to_pose3(const py::handle& h, const char* what);  ///< a 4 x 4 matrix
/// \brief A 1-D float64 array of any length (a copy in a std::vector).
[[nodiscard]] std::vector<double> to_doubles(const py::handle& h, const char* what);

[[nodiscard]] py::array_t<double> to_array(const Eigen::MatrixXd& m);  ///< rows x cols
[[nodiscard]] py::array_t<double> to_array(const Eigen::VectorXd& v);  ///< 1-D
[[nodiscard]] py::array_t<double> pose_array(const Pose2& p);          ///< (x, y, phi)
[[nodiscard]] py::array_t<double> pose_array(const Pose3& p);          ///< 4 x 4

}  // namespace vdtnav::python
