#pragma once
// The keys of the settings file, once (private to the estimation component): each visit() names
// every key of one options struct with its unit and meaning, and the reader
// (localizer_config_reader.cpp) and the writer (localizer_config_writer.cpp) walk the same list,
// so the file and its documentation cannot disagree. A visitor V has number, number_or_nan,
// integer, size, uint32, flag, choice, section (a nested mapping) and sensor (a
// VdtSensorModelOptions: the writer prints only the keys that differ from the shared sensor:
// block). The 3D localizer's section is localizer_config_keys3d.hpp.

#include <cstdint>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "vdtnav/estimation/localizer_factory.hpp"

namespace vdtnav::config_keys {

template <typename E>
using Names = std::initializer_list<std::pair<const char*, E>>;

inline const Names<GateMode> kGateModes{
    {"components", GateMode::kComponents}, {"norm", GateMode::kNorm}, {"none", GateMode::kNone}};
inline const Names<ResidualMode> kResidualModes{{"interpolated", ResidualMode::kInterpolated},
                                                {"nearest_point", ResidualMode::kNearestPoint}};
inline const Names<DisparityCovariance> kDisparityCovariances{
    {"exact_rank_one", DisparityCovariance::kExactRankOne},
    {"diagonal", DisparityCovariance::kDiagonal}};
inline const Names<ScanSolver> kScanSolvers{{"ceres", ScanSolver::kCeres},
                                            {"dense", ScanSolver::kDense}};
inline const Names<TrustRegion> kTrustRegions{
    {"levenberg_marquardt", TrustRegion::kLevenbergMarquardt}, {"dogleg", TrustRegion::kDogleg}};
inline const Names<RobustLoss> kLosses{
    {"none", RobustLoss::kNone}, {"huber", RobustLoss::kHuber}, {"cauchy", RobustLoss::kCauchy}};
inline const Names<CovarianceMethod> kCovarianceMethods{
    {"implicit_function", CovarianceMethod::kImplicitFunction},
    {"gauss_newton", CovarianceMethod::kGaussNewton}};
inline const Names<BeamStrategy> kBeamStrategies{{"active-trace", BeamStrategy::kActiveTrace},
                                                 {"active-det", BeamStrategy::kActiveDet},
                                                 {"active-fisher", BeamStrategy::kActiveFisher},
                                                 {"passive-fixed", BeamStrategy::kPassiveFixed},
                                                 {"passive-rotate", BeamStrategy::kPassiveRotate}};
inline const Names<MotionModelKind> kMotionModels{
    {"velocity", MotionModelKind::kVelocity},
    {"odometry_increment", MotionModelKind::kOdometryIncrement}};

// ------------------------------------------------------------------ the keys, once
// Each visit() names every key of one options struct with its unit and meaning; the reader and
// the writer below walk the same list, so the file and its documentation cannot disagree.

template <typename V>
void visit(V& v, VdtSensorModelOptions& o) {
  v.choice("gate_mode", o.gate_mode, kGateModes,
           "gate (3.3): components = every |DT_c| < gate, norm = |DT_v| < gate, none");
  v.number("gate", o.gate, "m", "alpha of (3.3): readings farther than this from the map drop out");
  v.choice("residual", o.residual, kResidualModes,
           "interpolated = the C2 B-spline of DT_v, nearest_point = p - c(cell(p))");
  v.choice("covariance", o.covariance, kDisparityCovariances,
           "disparity covariance: exact_rank_one = sigma_r^2 j j^T + sigma_map^2 I, "
           "diagonal = the thesis's (2.13)");
  v.number("map_sigma", o.map_sigma, "m",
           "map-noise floor per component; < 0: resolution / sqrt(12) (cell quantisation)");
  v.number("map_correlation_length", o.map_correlation_length, "m",
           "readings within one square of this side share one map error; 0: independent");
  v.number("map_pose_sigma", o.map_pose_sigma, "m",
           "pose error of the map builder; < 0: resolution / 2; 0: an exact map");
}

template <typename V>
void visit(V& v, MotionNoise& o) {
  v.number("sigma_v", o.sigma_v, "m/s", "velocity model: translational velocity noise");
  v.number("sigma_w", o.sigma_w, "rad/s", "velocity model: rotational velocity noise");
  v.number("floor_xy_rate", o.floor_xy_rate, "m/s", "velocity model: position noise floor");
  v.number("floor_yaw_rate", o.floor_yaw_rate, "rad/s", "velocity model: heading noise floor");
  v.number("a_tt", o.a_tt, "m/m", "odometry increment: translation noise per metre travelled");
  v.number("a_tr", o.a_tr, "m/rad", "odometry increment: translation noise per radian turned");
  v.number("a_rr", o.a_rr, "rad/rad", "odometry increment: rotation noise per radian turned");
  v.number("a_rt", o.a_rt, "rad/m", "odometry increment: rotation noise per metre travelled");
  v.number("floor_t", o.floor_t, "m", "odometry increment: translation noise per step");
  v.number("floor_r", o.floor_r, "rad", "odometry increment: rotation noise per step");
}

template <typename V>
void visit(V& v, GuessSearchOptions& o) {
  v.flag("enabled", o.enabled, "window search and acceptance test (guess_search.hpp)");
  v.number("explained_distance", o.explained_distance, "m",
           "a reading with |d| below this is explained");
  v.number("search_below", o.search_below, "fraction",
           "search a window when the solution explains less than this");
  v.number("accept_fraction", o.accept_fraction, "fraction",
           "refuse a solution explaining less (prediction kept)");
  v.number("reentry_fraction", o.reentry_fraction, "fraction",
           "after refused updates: a solution outside the 99 % region must explain this");
  v.flag("check_every_jump", o.check_every_jump,
         "apply the re-entry test to every update (maps whose pattern repeats)");
  v.number("window_xy", o.window_xy, "m", "half-width of the window in x and y");
  v.number("window_yaw", o.window_yaw, "rad", "half-width of the window in yaw");
  v.integer("steps_xy", o.steps_xy, "count", "candidates per axis in x and y (odd)");
  v.integer("steps_yaw", o.steps_yaw, "count", "candidates in yaw (odd)");
  v.number("truncation", o.truncation, "m", "tau of the truncated VCD that scores candidates");
  v.size("max_beams", o.max_beams, "count", "readings scoring a candidate (0: all)");
  v.number("window_sigmas", o.window_sigmas, "sigma",
           "the window grows to this many standard deviations of the prediction");
  v.number("max_window_xy", o.max_window_xy, "m", "largest half-width in x and y");
  v.number("max_window_yaw", o.max_window_yaw, "rad", "largest half-width in yaw");
  v.section("odometry_noise", "vdt-opt: uncertainty growth while updates are refused",
            [&](V& s) { visit(s, o.odometry_noise); });
}

template <typename V>
void visit(V& v, LocalScanMapOptions& o) {
  v.flag("enabled", o.enabled, "match unexplained scans against the recent scans (gap bridging)");
  v.integer("scans", o.scans, "count", "recent scans in the local map");
  v.number("resolution", o.resolution, "m", "cell size of the local map");
  v.number("radius", o.radius, "m", "endpoints farther than this from the guess are left out");
  v.number("accept_fraction", o.accept_fraction, "fraction",
           "use a match explaining at least this fraction");
  v.number("uncertainty_growth", o.uncertainty_growth, "fraction",
           "a bridged step grows the uncertainty by this share of the odometry's");
}

template <typename V>
void visit(V& v, VdtOptimizerOptions& o) {
  v.sensor("sensor", "the VDT sensor model", o.sensor);
  v.choice("solver", o.solver, kScanSolvers,
           "dense = Levenberg-Marquardt on the fixed-size normal equations (Ceres's steps, "
           "faster), ceres = Ceres Solver");
  v.choice("trust_region", o.trust_region, kTrustRegions,
           "Ceres trust-region strategy (solver: ceres; dense is Levenberg-Marquardt)");
  v.flag("odometry_prior", o.odometry_prior,
         "vdt-opt, localize3d: the prediction as a prior of every solve (maximum a "
         "posteriori)");
  v.choice("loss", o.loss, kLosses, "robust loss on each reading's squared disparity");
  v.number("loss_scale", o.loss_scale, "m", "where the robust loss departs from quadratic");
  v.choice("covariance_method", o.covariance, kCovarianceMethods,
           "implicit_function = (3.4) with the full Hessian, gauss_newton = sandwich");
  v.integer("max_iterations", o.max_iterations, "count", "solver iterations per solve");
  v.number("function_tolerance", o.function_tolerance, "fraction",
           "solver ceres: a solve stops when a step changes the cost by less than this fraction");
  v.number("step_sigma", o.step_sigma, "sigma",
           "solver dense: converged (and stopped) when the Newton step is at most this many of "
           "the pose's standard deviations");
  v.flag("newton", o.newton,
         "solver dense: steps on Newton's curvature (the loss's and the field's); false: IRLS");
  v.number("newton_floor", o.newton_floor, "fraction",
           "solver dense: lowest curvature of a step relative to IRLS, reached while steps fall "
           "short (within one sigma of the minimum as low as keeps the step inside it, >= 1/64); "
           "< 0: 0.25 in 2D, 1/64 in 3D");
  v.integer("gate_rounds", o.gate_rounds, "count",
            "re-gate at the solution and solve again while the inliers change");
  v.integer("min_inliers", o.min_inliers, "count", "fewer usable readings: too few observations");
  v.integer("pyramid_levels", o.pyramid_levels, "count",
            "coarse-to-fine levels for poor guesses; < 0: 2 in 2D, 3 in 3D");
  v.number("coarse_threshold", o.coarse_threshold, "m",
           "median disparity above which the coarse levels run; < 0: 0.1 m in 2D, 0 in 3D");
  v.flag("variance_factor", o.variance_factor,
         "scale the covariance by the a posteriori variance factor when > 1");
  v.section("search", "window search and acceptance", [&](V& s) { visit(s, o.search); });
  v.section("bridge", "gap bridging by scan-to-scan matching", [&](V& s) { visit(s, o.bridge); });
}

template <typename V>
void visit(V& v, VdtEkfOptions& o) {
  v.sensor("sensor", "the VDT sensor model", o.sensor);
  v.choice("motion", o.motion, kMotionModels,
           "prediction: velocity (3.7)-(3.10) or odometry_increment");
  v.section("noise", "motion noise of the prediction", [&](V& s) { visit(s, o.noise); });
  v.integer("min_inliers", o.min_inliers, "count", "fewer usable readings: prediction only");
  v.integer("max_iterations", o.max_iterations, "count",
            "iterated-EKF relinearisations (1: classic EKF)");
  v.choice("loss", o.loss, kLosses,
           "robust loss on each reading's squared disparity (IRLS weights in the update)");
  v.number("loss_scale", o.loss_scale, "m", "where the robust loss departs from quadratic");
  v.section("search", "window search and acceptance", [&](V& s) { visit(s, o.search); });
  v.flag("optimizer_start", o.optimizer_start,
         "start the iterations at the optimizer's solution (settings: start)");
  v.section("start", "the optimizer that gives the start (keys of vdt-opt)",
            [&](V& s) { visit(s, o.start); });
  v.flag("schmidt_map_errors", o.schmidt_map_errors,
         "carry map errors shared per square from scan to scan (Schmidt-Kalman) instead of "
         "reporting the scan's map term on top");
  v.number("correction_gate", o.correction_gate, "chi2",
           "refuse an update whose correction is larger, as a Mahalanobis size under the prior, "
           "than this chi-square(3) value (11.34: its 99 % point); 0: off");
}

template <typename V>
void visit(V& v, UdtOptions& o) {
  v.number("gate", o.gate, "m", "readings with DT_u >= gate are dropped");
  v.number("map_sigma", o.map_sigma, "m", "EKF map-noise floor; < 0: resolution / sqrt(12)");
  v.integer("min_inliers", o.min_inliers, "count", "fewer usable readings: too few observations");
  v.integer("max_iterations", o.max_iterations, "count", "solver iterations (udt-opt)");
  v.choice("motion", o.motion, kMotionModels, "udt-ekf prediction model");
  v.section("noise", "udt-ekf motion noise", [&](V& s) { visit(s, o.noise); });
}

template <typename V>
void visit(V& v, ParticleFilterOptions& o) {
  v.integer("particles", o.particles, "count", "particles when kld is off");
  v.integer("max_beams", o.max_beams, "count", "readings used per scan (amcl laser_max_beams)");
  v.number("alpha1", o.alpha1, "-", "rotation noise from rotation (amcl odom_alpha1)");
  v.number("alpha2", o.alpha2, "-", "rotation noise from translation (amcl odom_alpha2)");
  v.number("alpha3", o.alpha3, "-", "translation noise from translation (amcl odom_alpha3)");
  v.number("alpha4", o.alpha4, "-", "translation noise from rotation (amcl odom_alpha4)");
  v.number("z_hit", o.z_hit, "-", "weight of the hit term (amcl laser_z_hit)");
  v.number("z_rand", o.z_rand, "-", "weight of the random term (amcl laser_z_rand)");
  v.number("sigma_hit", o.sigma_hit, "m", "std. dev. of the hit term (amcl laser_sigma_hit)");
  v.number("max_likelihood_distance", o.max_likelihood_distance, "m",
           "likelihood-field clamp (amcl laser_likelihood_max_dist)");
  v.flag("kld", o.kld, "adapt the particle count by KLD-sampling");
  v.integer("min_particles", o.min_particles, "count", "KLD lower bound");
  v.integer("max_particles", o.max_particles, "count", "KLD upper bound and count after reset");
  v.number("kld_err", o.kld_err, "-", "KLD bound epsilon, in (0, 1)");
  v.number("kld_z", o.kld_z, "-", "upper standard normal quantile z_{1-delta}");
  v.number("update_min_d", o.update_min_d, "m", "odometry travel before the filter runs");
  v.number("update_min_a", o.update_min_a, "rad", "odometry turn before the filter runs");
  v.uint32("seed", o.seed, "-", "random seed");
}

template <typename V>
void visit(V& v, RotatingBeamOptions& o) {
  v.number("rotation_range", o.rotation_range, "rad", "the beam turns within this, centred ahead");
  v.number("angular_velocity", o.angular_velocity, "rad/s", "how fast the beam turns");
  v.integer("segments", o.segments, "count", "n, the goal segments of the rotation range");
  v.number("lambda", o.lambda, "m^2 per segment", "weight of the motion in the cost (4.1)");
  v.number("range_min", o.range_min, "m", "closer readings are not used");
  v.number("range_max", o.range_max, "m", "further readings are not used");
  v.number("sigma_range", o.sigma_range, "m", "range noise of the hypothetical readings");
  v.number("hypothesis_resolution", o.hypothesis_resolution, "rad",
           "spacing of a segment's hypothetical readings");
  v.number("gate", o.gate, "sigma",
           "a reading this many sigma off the range ray cast from the prediction is not used; "
           "<= 0: no gate");
}

template <typename V>
void visit(V& v, ActiveBeamLocalizerOptions& o) {
  v.choice("strategy", o.strategy, kBeamStrategies,
           "active-trace (4.1), active-det, active-fisher, passive-fixed or passive-rotate");
  v.number("bearing_tolerance", o.bearing_tolerance, "rad",
           "a scan's reading nearest the beam's bearing is kept if within this");
  v.section("beam", "the rotating single-beam sensor (Table 4.3 by default)",
            [&](V& s) { visit(s, o.beam); });
  v.section("ekf",
            "the VDT EKF it updates (keys of vdt-ekf; sensor.map_sigma < 0: the map's measured "
            "wall roughness, map/surface_roughness.hpp)",
            [&](V& s) { visit(s, o.ekf); });
}

/// The keys global localization shares in 2D and 3D (GlobalLocalizationOptions,
/// GlobalLocalization3Options): the refinement of the distinct leaves and the decision
/// (global_decision.hpp).
template <typename V, typename Options>
void visit_global_decision(V& v, Options& o) {
  v.integer("candidates", o.candidates, "count", "distinct leaves refined by the optimizer");
  v.number("distinct_distance", o.distinct_distance, "m", "poses this far apart are distinct");
  v.number("distinct_angle", o.distinct_angle, "rad", "poses this much turned are distinct");
  v.number("alternative_margin", o.alternative_margin, "fraction of N tau^2",
           "alternatives scoring at most best + this are refined");
  v.number("explained_distance", o.explained_distance, "m",
           "a reading with a smaller disparity is explained");
  v.number("accept_fraction", o.accept_fraction, "fraction",
           "the refined best must explain this much of the scan");
  v.number("ambiguity_margin", o.ambiguity_margin, "fraction",
           "a distinct alternative explaining within this of the best: ambiguous, refused");
}

template <typename V>
void visit(V& v, GlobalLocalizationOptions& o) {
  v.number("truncation", o.truncation, "m", "tau: a reading farther from the map counts tau^2");
  v.integer("max_readings", o.max_readings, "count", "readings scored, evenly over the scan");
  v.number("angular_step", o.angular_step, "rad",
           "between headings; <= 0: resolution / the scan's 90th-percentile range");
  v.integer("levels", o.levels, "count", "coarsest box 2^levels cells; < 0: about 3.2 m");
  visit_global_decision(v, o);
}

template <typename V>
void visit(V& v, ScanAgreementOptions& o) {
  v.number("explained_distance", o.explained_distance, "m",
           "a reading with a smaller disparity is explained");
  v.number("margin", o.margin, "m",
           "a wall crossed within this of the endpoint or the sensor contradicts nothing; < 0: 2 "
           "explained_distance + one map cell");
  v.integer("max_readings", o.max_readings, "count", "readings weighed, evenly; 0: all");
}

template <typename V>
void visit(V& v, LostDetectionOptions& o) {
  v.integer("window", o.window, "scans", "W, scans whose agreement is pooled");
  v.number("lost_contradiction", o.lost_contradiction, "fraction",
           "lost when the map contradicts this share of the window's judged readings (through a "
           "wall, or ending in known free space)");
  v.number("found_contradiction", o.found_contradiction, "fraction",
           "found again when the window's contradiction falls to this");
  v.number("doubt_contradiction", o.doubt_contradiction, "fraction",
           "in doubt from this: search for a clearly better pose, not lost");
  v.number("doubt_rise", o.doubt_rise, "fraction",
           "also in doubt when the window is contradicted this much more than the track's "
           "baseline...");
  v.number("sigmas", o.sigmas, "std. dev.",
           "... or this many standard deviations of the track's windows, if more");
  v.number("scan_doubt_contradiction", o.scan_doubt_contradiction, "fraction",
           "also in doubt when the scan alone is contradicted this much (1: never)");
  v.integer("baseline_scans", o.baseline_scans, "windows",
            "the baseline's exponential mean spans this many windows");
  v.number("min_judged", o.min_judged, "fraction",
           "the window decides only when the map judges this share of its readings (the rest "
           "ends where the map knows nothing)");
}

template <typename V>
void visit(V& v, RecoveryOptions& o) {
  v.flag("detect", o.detect,
         "test a window of scans (vdt-opt, vdt-ekf) and report status lost when the map "
         "contradicts them");
  v.flag("recover", o.recover,
         "while lost or in doubt, search for the pose by global localization (section global:) "
         "and adopt a clearly better one; --recover / --no-recover");
  visit(v, o.lost);  // the window test's keys, those of localize3d's lost: section
  v.integer("min_readings", o.min_readings, "count",
            "scans with fewer readings do not enter the window (they say nothing either way)");
  v.integer("search_boxes", o.search_boxes, "boxes per update",
            "the anytime global search's budget in each update");
  v.flag("search_thread", o.search_thread,
         "run the search on a worker thread (a second core) instead of search_boxes per update: "
         "faster re-acquisition, not repeatable bit for bit");
  v.number("search_leaf", o.search_leaf, "m",
           "the search's leaf boxes (powers of two of the map's cell); headings to match");
  v.integer("verify_scans", o.verify_scans, "scans",
            "a candidate is tracked beside the track this long before it can be adopted");
  v.number("verify_margin", o.verify_margin, "fraction",
           "adopted only when explaining this much more than the track over those scans, and "
           "contradicted this much less where the map judges the track");
  v.number("doubt_margin", o.doubt_margin, "fraction of N tau^2",
           "in doubt, search only for poses scoring this much better than the track");
  v.section("agreement", "how a scan is weighed at a pose (explained, contradicted, unknown)",
            [&](V& s) { visit(s, o.agreement); });
}

}  // namespace vdtnav::config_keys
