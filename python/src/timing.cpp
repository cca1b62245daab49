// vdtnav._timing: the same calls as the bindings make, timed in C++ on the same data, so that
// bench/python/overhead.py can report the cost of the Python layer in one run (issue 33).
#include <algorithm>
#include <chrono>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "vdtnav/estimation/localizer.hpp"

namespace vdtnav::python {
namespace {

using Clock = std::chrono::steady_clock;

/// The median of `repeats` timings of f(), seconds.
template <typename F>
double median_seconds(int repeats, F&& f) {
  std::vector<double> t;
  for (int i = 0; i < std::max(repeats, 1); ++i) {
    const auto t0 = Clock::now();
    f();
    t.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.size() / 2), t.end());
  return t[t.size() / 2];
}

/// A C++ program's batch lookup of the same points. fresh_output: what one call that returns
/// its results costs a C++ user — the points as Eigen vectors (converted when they are float32 or
/// not packed doubles: the API takes doubles), a new vector of samples, the lookup. Otherwise the
/// lookup alone into a vector reused from call to call, the points converted beforehand.
template <int Dim>
double lookup_seconds(const VdtField<Dim>& field, const py::array& points, bool jacobian,
                      int repeats, bool fresh_output) {
  using Vector = typename SpaceTraits<Dim>::Vector;
  const PointView<Dim> view(points, "points");
  const std::vector<Vector> converted = view.all();
  std::vector<VdtSample<Dim>> reused(converted.size());
  py::gil_scoped_release release;
  if (!fresh_output)
    return median_seconds(repeats, [&] {
      field.evaluate(converted.data(), converted.size(), reused.data(), jacobian);
    });
  return median_seconds(repeats, [&] {
    const Vector* p = view.template as_vectors<Vector>(0);
    std::vector<Vector> own;
    if (p == nullptr) {
      own = view.all();
      p = own.data();
    }
    std::vector<VdtSample<Dim>> out(view.size());
    field.evaluate(p, out.size(), out.data(), jacobian);
  });
}

}  // namespace

void bind_timing(py::module_& m) {
  py::module_ t = m.def_submodule(
      "_timing", "The bindings' calls timed in C++ (bench/python/overhead.py): median seconds.");
  t.def(
      "lookup2",
      [](const Map2& map, const py::array& points, bool jacobian, int repeats, bool fresh) {
        return lookup_seconds<2>(*map.vdt, points, jacobian, repeats, fresh);
      },
      py::arg("map"), py::arg("points"), py::arg("jacobian") = true, py::arg("repeats") = 20,
      py::arg("fresh_output") = true,
      "Median seconds of a C++ batch lookup of `points` on a 2D map: with fresh_output, one call "
      "as a C++ program makes it (points as Eigen vectors, converted when float32 or strided; a "
      "new vector of samples; the lookup); without, the lookup alone into a reused vector.");
  t.def(
      "lookup3",
      [](const Map3& map, const py::array& points, bool jacobian, int repeats, bool fresh) {
        return lookup_seconds<3>(map.field(), points, jacobian, repeats, fresh);
      },
      py::arg("map"), py::arg("points"), py::arg("jacobian") = true, py::arg("repeats") = 20,
      py::arg("fresh_output") = true, "lookup2 on a 3D map.");
  t.def(
      "update2",
      [](Localizer2& l, const py::object& pose, const py::object& covariance,
         const OdometryStep& odometry, const LaserScan& scan, int repeats) {
        const Pose2 p = to_pose2(pose, "pose");
        const Eigen::Matrix3d c = to_matrix(covariance, 3, 3, "covariance");
        py::gil_scoped_release release;
        return median_seconds(repeats, [&] {
          l.localizer->reset(p, c);
          const LocalizationResult r = l.localizer->update(odometry, scan);
          (void)r;
        });
      },
      py::arg("localizer"), py::arg("pose"), py::arg("covariance"), py::arg("odometry"),
      py::arg("scan"), py::arg("repeats") = 20,
      "reset(pose, covariance) then update(odometry, scan), timed in C++.");
}

}  // namespace vdtnav::python
