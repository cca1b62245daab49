// Evaluation in Python: the relation metric (Kümmerle et al. 2009), the relation NEES, the NEES
// of a pose and the ANEES with its chi-square interval (nees.hpp).
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "numpy_points.hpp"
#include "vdtnav/eval/nees.hpp"
#include "vdtnav/eval/relation_metric.hpp"
#include "vdtnav/eval/relation_nees.hpp"

namespace vdtnav::python {
namespace {

eval::Trajectory2 trajectory(const py::object& times, const py::object& poses) {
  const std::vector<double> t = to_doubles(times, "times");
  const Eigen::MatrixXd p = to_matrix(poses, static_cast<py::ssize_t>(t.size()), 3, "poses");
  eval::Trajectory2 out;
  for (std::size_t i = 0; i < t.size(); ++i)
    out.push_back({t[i], p.row(static_cast<Eigen::Index>(i)).transpose()});
  return out;
}

std::vector<eval::Relation> relations(const py::object& rel) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(rel);
  if (!a || a.ndim() != 2 || a.shape(1) != 5)
    throw py::value_error("relations: expected an N x 5 array (t1, t2, x, y, yaw)");
  std::vector<eval::Relation> out;
  for (py::ssize_t i = 0; i < a.shape(0); ++i)
    out.push_back({a.at(i, 0), a.at(i, 1), Pose2(a.at(i, 2), a.at(i, 3), a.at(i, 4))});
  return out;
}

}  // namespace

void bind_evaluation(py::module_& m) {
  py::class_<eval::RelationMetricResult>(m, "RelationMetric",
                                         "The relation metric over a set of relations.")
      .def_readonly("used", &eval::RelationMetricResult::used)
      .def_readonly("skipped", &eval::RelationMetricResult::skipped)
      .def_property_readonly(
          "translation_mean",
          [](const eval::RelationMetricResult& r) { return r.translation.mean; }, "metres")
      .def_property_readonly("translation_std",
                             [](const eval::RelationMetricResult& r) { return r.translation.std; })
      .def_property_readonly(
          "rotation_mean", [](const eval::RelationMetricResult& r) { return r.rotation.mean; },
          "radians")
      .def_property_readonly("rotation_std",
                             [](const eval::RelationMetricResult& r) { return r.rotation.std; })
      .def_property_readonly(
          "translation_squared_mean",
          [](const eval::RelationMetricResult& r) { return r.translation_squared.mean; },
          "mean of trans(e)^2, m^2 (the paper's translational part)")
      .def_property_readonly(
          "rotation_squared_mean",
          [](const eval::RelationMetricResult& r) { return r.rotation_squared.mean; },
          "mean of rot(e)^2, rad^2 (the paper's rotational part)")
      .def_readonly("skipped_no_stamp", &eval::RelationMetricResult::skipped_no_stamp)
      .def_readonly("skipped_outside", &eval::RelationMetricResult::skipped_outside)
      .def_readonly("skipped_in_gap", &eval::RelationMetricResult::skipped_in_gap)
      .def_property_readonly(
          "translation_errors",
          [](const eval::RelationMetricResult& r) {
            Eigen::VectorXd v(static_cast<Eigen::Index>(r.errors.size()));
            for (std::size_t i = 0; i < r.errors.size(); ++i)
              v[static_cast<Eigen::Index>(i)] = r.errors[i].outcome == eval::RelationOutcome::kUsed
                                                    ? r.errors[i].translation
                                                    : std::nan("");
            return to_array(v);
          },
          "per relation |e_xy| (NaN where skipped)")
      .def_property_readonly(
          "rotation_errors",
          [](const eval::RelationMetricResult& r) {
            Eigen::VectorXd v(static_cast<Eigen::Index>(r.errors.size()));
            for (std::size_t i = 0; i < r.errors.size(); ++i)
              v[static_cast<Eigen::Index>(i)] = r.errors[i].outcome == eval::RelationOutcome::kUsed
                                                    ? r.errors[i].rotation
                                                    : std::nan("");
            return to_array(v);
          },
          "per relation |e_yaw| (NaN where skipped)");

  m.def(
      "relation_metric",
      [](const py::object& times, const py::object& poses, const py::object& rel,
         double stamp_tolerance, bool interpolate, double max_gap) {
        eval::RelationMetricOptions o;
        o.stamp_tolerance = stamp_tolerance;
        o.interpolate = interpolate;
        o.max_gap = max_gap;
        return eval::relation_metric(trajectory(times, poses), relations(rel), o);
      },
      py::arg("times"), py::arg("poses"), py::arg("relations"), py::arg("stamp_tolerance") = 1e-6,
      py::arg("interpolate") = false, py::arg("max_gap") = 1.0,
      "The relation metric (Kümmerle et al. 2009) of a planar trajectory (times, N x 3 poses) on "
      "relations (N x 5, read_relations): mean and std of |e_xy| and |e_yaw|, e = between(delta*, "
      "delta). Ends matched to samples within stamp_tolerance seconds (or interpolated).");

  py::class_<eval::RelationNeesResult>(m, "RelationNees")
      .def_readonly("used", &eval::RelationNeesResult::used)
      .def_readonly("skipped_no_stamp", &eval::RelationNeesResult::skipped_no_stamp)
      .def_readonly("skipped_no_covariance", &eval::RelationNeesResult::skipped_no_covariance)
      .def_readonly("skipped_singular", &eval::RelationNeesResult::skipped_singular)
      .def_readonly("mean", &eval::RelationNeesResult::mean)
      .def_readonly("median", &eval::RelationNeesResult::median)
      .def_readonly("fraction_inside", &eval::RelationNeesResult::fraction_inside,
                    "fraction of the relations with NEES <= bound (chi^2_3 95 %: 7.81)")
      .def_property_readonly("values", [](const eval::RelationNeesResult& r) {
        return to_array(Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(
            r.values.data(), static_cast<Eigen::Index>(r.values.size()))));
      });

  m.def(
      "relation_nees",
      [](const py::object& times, const py::object& poses, const py::object& covariances,
         const py::object& rel, double stamp_tolerance, double bound) {
        const eval::Trajectory2 t = trajectory(times, poses);
        const auto c =
            py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(covariances);
        if (!c || c.ndim() != 3 || c.shape(0) != static_cast<py::ssize_t>(t.size()) ||
            c.shape(1) != 3 || c.shape(2) != 3)
          throw py::value_error("covariances: expected an N x 3 x 3 array, N = len(times)");
        std::vector<Eigen::Matrix3d> cov(t.size());
        for (std::size_t i = 0; i < t.size(); ++i)
          cov[i] = Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(c.data() + 9 * i);
        eval::RelationNeesOptions o;
        o.stamp_tolerance = stamp_tolerance;
        o.bound = bound;
        return eval::relation_nees(t, cov, relations(rel), o);
      },
      py::arg("times"), py::arg("poses"), py::arg("covariances"), py::arg("relations"),
      py::arg("stamp_tolerance") = 1e-6, py::arg("bound") = eval::kChi2Dof3P95,
      "The NEES of each relation under the covariance of the relative pose (both ends' "
      "covariances propagated through between(); relation_nees.hpp); covariances N x 3 x 3, NaN "
      "where the estimator gave none.");

  m.def(
      "nees",
      [](const py::object& estimate, const py::object& truth, const py::object& covariance,
         bool return_dof) -> py::object {
        const auto e = py::array_t<double, py::array::forcecast>::ensure(estimate);
        if (e && e.ndim() == 1) {
          const double v = eval::nees(to_pose2(estimate, "estimate"), to_pose2(truth, "truth"),
                                      to_matrix(covariance, 3, 3, "covariance"));
          return return_dof ? py::object(py::make_tuple(v, 3)) : py::object(py::float_(v));
        }
        int dof = 0;
        const double v = eval::nees(to_pose3(estimate, "estimate"), to_pose3(truth, "truth"),
                                    Matrix6d(to_matrix(covariance, 6, 6, "covariance")), &dof);
        return return_dof ? py::object(py::make_tuple(v, dof)) : py::object(py::float_(v));
      },
      py::arg("estimate"), py::arg("truth"), py::arg("covariance"), py::arg("return_dof") = false,
      "e^T P^-1 e of a pose estimate: planar (x, y, phi) with a 3 x 3 covariance, or 4 x 4 poses "
      "with the 6 x 6 covariance of the left perturbation (components whose rows are zero or NaN, "
      "held and not estimated, left out). NaN when P is not positive definite. return_dof: "
      "(nees, the chi-square's degrees of freedom).");

  py::class_<eval::ErrorStatistics>(m, "ErrorStatistics")
      .def_readonly("count", &eval::ErrorStatistics::count)
      .def_readonly("rmse", &eval::ErrorStatistics::rmse)
      .def_readonly("mean", &eval::ErrorStatistics::mean)
      .def_readonly("median", &eval::ErrorStatistics::median)
      .def_readonly("p99", &eval::ErrorStatistics::p99,
                    "99th percentile by nearest rank: the ceil(0.99 n)-th smallest value.")
      .def_readonly("std", &eval::ErrorStatistics::std)
      .def_readonly("min", &eval::ErrorStatistics::min)
      .def_readonly("max", &eval::ErrorStatistics::max);
  py::class_<eval::AteResult>(m, "Ate", "The absolute trajectory error (aligned and not).")
      .def_property_readonly("alignment",
                             [](const eval::AteResult& r) { return pose_array(r.alignment); })
      .def_readonly("translation", &eval::AteResult::translation)
      .def_readonly("rotation", &eval::AteResult::rotation)
      .def_readonly("unaligned_translation", &eval::AteResult::unaligned_translation)
      .def_readonly("unaligned_rotation", &eval::AteResult::unaligned_rotation);
  m.def(
      "absolute_trajectory_error",
      [](const py::object& times, const py::object& poses, const py::object& ref_times,
         const py::object& ref_poses, double max_time_difference) {
        eval::AteOptions o;
        o.max_time_difference = max_time_difference;
        return eval::absolute_trajectory_error(trajectory(times, poses),
                                               trajectory(ref_times, ref_poses), o);
      },
      py::arg("times"), py::arg("poses"), py::arg("ref_times"), py::arg("ref_poses"),
      py::arg("max_time_difference") = 0.01,
      "ATE of a planar trajectory against a reference (samples associated within "
      "max_time_difference seconds): statistics of the position and yaw errors, after the best "
      "rigid alignment and without it (trajectory_metrics.hpp).");
  py::class_<eval::RpeResult>(m, "Rpe", "The relative pose error.")
      .def_readonly("pairs", &eval::RpeResult::pairs)
      .def_readonly("translation", &eval::RpeResult::translation)
      .def_readonly("rotation", &eval::RpeResult::rotation);
  m.def(
      "relative_pose_error",
      [](const py::object& times, const py::object& poses, const py::object& ref_times,
         const py::object& ref_poses) {
        return eval::relative_pose_error(trajectory(times, poses),
                                         trajectory(ref_times, ref_poses));
      },
      py::arg("times"), py::arg("poses"), py::arg("ref_times"), py::arg("ref_poses"),
      "RPE over consecutive frames (trajectory_metrics.hpp's defaults).");

  py::class_<eval::AneesResult>(m, "Anees", "The average NEES of a run and its chi-square test.")
      .def_readonly("count", &eval::AneesResult::count)
      .def_readonly("failures", &eval::AneesResult::failures)
      .def_readonly("anees", &eval::AneesResult::anees)
      .def_property_readonly("interval",
                             [](const eval::AneesResult& r) {
                               return py::make_tuple(r.interval.lower, r.interval.upper);
                             })
      .def_readonly("consistent", &eval::AneesResult::consistent);

  m.def("anees", &eval::anees, py::arg("nees"), py::arg("dof"), py::arg("confidence") = 0.95,
        "ANEES of NEES values with `dof` degrees of freedom each and its two-sided interval "
        "[chi^2_{(1-c)/2}(n d) / n, chi^2_{(1+c)/2}(n d) / n].");
  m.def(
      "anees_interval",
      [](std::size_t n, int dof, double confidence) {
        const eval::ChiSquareInterval i = eval::anees_interval(n, dof, confidence);
        return py::make_tuple(i.lower, i.upper);
      },
      py::arg("n"), py::arg("dof"), py::arg("confidence") = 0.95,
      "The interval the mean of n NEES values of `dof` degrees of freedom lies in with "
      "probability `confidence` (Wilson-Hilferty).");
}

}  // namespace vdtnav::python
