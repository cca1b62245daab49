#include "numpy_points.hpp"

#include <cstring>

namespace vdtnav::python {

template <int Dim>
PointView<Dim>::PointView(const py::array& a, const char* what) {
  const bool f64 = a.dtype().kind() == 'f' && a.itemsize() == 8;
  const bool f32 = a.dtype().kind() == 'f' && a.itemsize() == 4;
  if (!f64 && !f32)
    throw py::value_error(std::string(what) + ": expected a float32 or float64 array, got dtype " +
                          std::string(py::str(a.dtype())));
  if (a.ndim() != 2 || a.shape(1) != Dim) {
    std::string shape = "(";
    for (py::ssize_t i = 0; i < a.ndim(); ++i)
      shape += (i ? ", " : "") + std::to_string(a.shape(i));
    throw py::value_error(std::string(what) + ": expected an N x " + std::to_string(Dim) +
                          " array, got shape " + shape + (a.ndim() == 1 ? ",)" : ")"));
  }
  if (a.dtype().byteorder() == '>')
    throw py::value_error(std::string(what) + ": expected native byte order");
  data_ = static_cast<const char*>(a.data());
  n_ = static_cast<std::size_t>(a.shape(0));
  row_stride_ = a.strides(0);
  col_stride_ = a.strides(1);
  is_float32_ = f32;
}

template <int Dim>
void PointView<Dim>::read(std::size_t first, std::size_t count, Vector* out) const {
  const char* row = data_ + static_cast<py::ssize_t>(first) * row_stride_;
  for (std::size_t k = 0; k < count; ++k, row += row_stride_) {
    for (int d = 0; d < Dim; ++d) {
      const char* e = row + d * col_stride_;
      if (is_float32_) {
        float f;
        std::memcpy(&f, e, sizeof f);
        out[k][d] = f;
      } else {
        std::memcpy(&out[k][d], e, sizeof(double));
      }
    }
  }
}

template <int Dim>
std::vector<typename PointView<Dim>::Vector> PointView<Dim>::all() const {
  std::vector<Vector> v(n_);
  if (n_ > 0) read(0, n_, v.data());
  return v;
}

template class PointView<2>;
template class PointView<3>;

namespace {
py::array_t<double> as_doubles(const py::handle& h, const char* what) {
  try {
    return py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(h);
  } catch (const py::error_already_set&) {
    throw py::value_error(std::string(what) + ": expected numbers");
  }
}
std::string shape_of(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t i = 0; i < a.ndim(); ++i) s += (i ? ", " : "") + std::to_string(a.shape(i));
  return s + (a.ndim() == 1 ? ",)" : ")");
}
}  // namespace

Eigen::VectorXd to_vector(const py::handle& h, py::ssize_t n, const char* what) {
  const py::array_t<double> a = as_doubles(h, what);
  if (!a || a.ndim() != 1 || a.shape(0) != n)
    throw py::value_error(std::string(what) + ": expected " + std::to_string(n) +
                          " numbers, got shape " + (a ? shape_of(a) : std::string("?")));
  return Eigen::Map<const Eigen::VectorXd>(a.data(), n);
}

Eigen::MatrixXd to_matrix(const py::handle& h, py::ssize_t rows, py::ssize_t cols,
                          const char* what) {
  const py::array_t<double> a = as_doubles(h, what);
  if (!a || a.ndim() != 2 || a.shape(0) != rows || a.shape(1) != cols)
    throw py::value_error(std::string(what) + ": expected a " + std::to_string(rows) + " x " +
                          std::to_string(cols) + " array, got shape " +
                          (a ? shape_of(a) : std::string("?")));
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      a.data(), rows, cols);
}

Pose2 to_pose2(const py::handle& h, const char* what) { return to_vector(h, 3, what); }

Pose3 to_pose3(const py::handle& h, const char* what) {
  const Eigen::MatrixXd m = to_matrix(h, 4, 4, what);
  Pose3 p = Pose3::Identity();
  p.matrix() = m;
  return p;
}

std::vector<double> to_doubles(const py::handle& h, const char* what) {
  const py::array_t<double> a = as_doubles(h, what);
  if (!a || a.ndim() != 1)
    throw py::value_error(std::string(what) + ": expected a 1-D array, got shape " +
                          (a ? shape_of(a) : std::string("?")));
  return std::vector<double>(a.data(), a.data() + a.shape(0));
}

py::array_t<double> to_array(const Eigen::MatrixXd& m) {
  py::array_t<double> a({static_cast<py::ssize_t>(m.rows()), static_cast<py::ssize_t>(m.cols())});
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
      a.mutable_data(), m.rows(), m.cols()) = m;
  return a;
}

py::array_t<double> to_array(const Eigen::VectorXd& v) {
  py::array_t<double> a(static_cast<py::ssize_t>(v.size()));
  Eigen::Map<Eigen::VectorXd>(a.mutable_data(), v.size()) = v;
  return a;
}

py::array_t<double> pose_array(const Pose2& p) { return to_array(Eigen::VectorXd(p)); }
py::array_t<double> pose_array(const Pose3& p) { return to_array(Eigen::MatrixXd(p.matrix())); }

}  // namespace vdtnav::python
