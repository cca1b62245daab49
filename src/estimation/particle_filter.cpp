#include "vdtnav/estimation/particle_filter.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "vdtnav/core/error.hpp"
#include "vdtnav/map/vector_distance_transform.hpp"

namespace vdtnav {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
/// amcl: below 1 cm of translation, the heading of the translation (rot1) is meaningless.
constexpr double kMinTransForHeading = 0.01;
/// amcl's kd-tree cell for KLD-sampling: 0.5 m, 0.5 m, 10 degrees.
constexpr double kKldBinXy = 0.5;
constexpr double kKldBinYaw = 10.0 * kPi / 180.0;
/// Floor for a beam's log-likelihood (only reached when z_hit N(d) and z_rand / range_max both
/// vanish), so that log weights stay finite.
constexpr double kLogLikelihoodFloor = -1e6;

void check(bool ok, const std::string& what) {
  if (!ok) throw ConfigError("ParticleFilterOptions: " + what);
}

bool finite_nonnegative(double v) { return std::isfinite(v) && v >= 0.0; }
bool unit_interval(double v) { return v >= 0.0 && v <= 1.0; }

void validate(const ParticleFilterOptions& o) {
  check(o.particles >= 1, "particles must be >= 1, got " + std::to_string(o.particles));
  check(o.max_beams >= 1, "max_beams must be >= 1, got " + std::to_string(o.max_beams));
  check(finite_nonnegative(o.alpha1) && finite_nonnegative(o.alpha2) &&
            finite_nonnegative(o.alpha3) && finite_nonnegative(o.alpha4),
        "alpha1..alpha4 must be finite and >= 0");
  check(unit_interval(o.z_hit), "z_hit must be in [0, 1], got " + std::to_string(o.z_hit));
  check(unit_interval(o.z_rand), "z_rand must be in [0, 1], got " + std::to_string(o.z_rand));
  check(o.z_hit + o.z_rand > 0.0, "z_hit + z_rand must be > 0");
  check(std::isfinite(o.sigma_hit) && o.sigma_hit > 0.0,
        "sigma_hit must be finite and > 0, got " + std::to_string(o.sigma_hit));
  check(std::isfinite(o.max_likelihood_distance) && o.max_likelihood_distance > 0.0,
        "max_likelihood_distance must be finite and > 0, got " +
            std::to_string(o.max_likelihood_distance));
  check(o.min_particles >= 1, "min_particles must be >= 1, got " + std::to_string(o.min_particles));
  check(o.max_particles >= o.min_particles, "max_particles must be >= min_particles, got " +
                                                std::to_string(o.max_particles) + " < " +
                                                std::to_string(o.min_particles));
  check(o.kld_err > 0.0 && o.kld_err < 1.0,
        "kld_err must be in (0, 1), got " + std::to_string(o.kld_err));
  check(std::isfinite(o.kld_z) && o.kld_z > 0.0,
        "kld_z must be finite and > 0, got " + std::to_string(o.kld_z));
  check(finite_nonnegative(o.update_min_d) && finite_nonnegative(o.update_min_a),
        "update_min_d and update_min_a must be finite and >= 0");
}

/// log(exp(a) + exp(b)) without overflow or underflow.
double log_add_exp(double a, double b) {
  if (a < b) std::swap(a, b);
  if (b == -kInf) return a;
  return a + std::log1p(std::exp(b - a));
}

/// min(|a|, |a - pi|): amcl's noise magnitude of a rotation, driving backwards included.
double rotation_noise_magnitude(double a) {
  return std::min(std::abs(wrap_angle(a)), std::abs(wrap_angle(a - kPi)));
}

/// Table 5.6, lines 5-10, with the caller's normal distribution (no state beyond it).
Pose2 sample_odometry(const Pose2& pose, const OdometryMotion& m, std::mt19937_64& rng,
                      std::normal_distribution<double>& normal) {
  const double rot1 = m.rot1 - m.rot1_sd * normal(rng);     // line 5
  const double trans = m.trans - m.trans_sd * normal(rng);  // line 6
  const double rot2 = m.rot2 - m.rot2_sd * normal(rng);     // line 7
  const double heading = pose[2] + rot1;
  return {pose[0] + trans * std::cos(heading), pose[1] + trans * std::sin(heading),  // 8, 9
          wrap_angle(heading + rot2)};                                               // line 10
}

/// The key of a pose's KLD bin; 21 bits per axis.
std::int64_t kld_bin(const Pose2& p) {
  const auto b = [](double v, double size) {
    return static_cast<std::int64_t>(std::floor(v / size)) & 0x1FFFFF;
  };
  return (b(p[0], kKldBinXy) << 42) | (b(p[1], kKldBinXy) << 21) | b(p[2], kKldBinYaw);
}

}  // namespace

OdometryMotion decompose_odometry(const Pose2& delta, const ParticleFilterOptions& o) {
  OdometryMotion m;
  m.trans = std::hypot(delta[0], delta[1]);  // Table 5.6, line 3
  m.rot1 = std::atan2(delta[1], delta[0]);   // line 2 (atan2(0, 0) = 0)
  m.rot2 = wrap_angle(delta[2] - m.rot1);    // line 4
  const bool tiny = m.trans < kMinTransForHeading;
  const double r1 = tiny ? 0.0 : rotation_noise_magnitude(m.rot1);
  const double r2 = rotation_noise_magnitude(tiny ? delta[2] : m.rot2);
  const double t2 = m.trans * m.trans;
  m.rot1_sd = std::sqrt(o.alpha1 * r1 * r1 + o.alpha2 * t2);
  m.trans_sd = std::sqrt(o.alpha3 * t2 + o.alpha4 * r1 * r1 + o.alpha4 * r2 * r2);
  m.rot2_sd = std::sqrt(o.alpha1 * r2 * r2 + o.alpha2 * t2);
  return m;
}

Pose2 sample_motion_model_odometry(const Pose2& pose, const OdometryMotion& motion,
                                   std::mt19937_64& rng) {
  std::normal_distribution<double> normal;
  return sample_odometry(pose, motion, rng, normal);
}

void low_variance_sampler(const std::vector<double>& weights, std::size_t count, double u,
                          std::vector<std::size_t>& indices) {
  indices.resize(count);
  if (count == 0 || weights.empty()) return;
  const double step = 1.0 / static_cast<double>(count);
  const double r = u * step;  // Table 4.4, line 3: r ~ U[0, 1/M)
  double c = weights[0];      // line 4
  std::size_t i = 0;
  const std::size_t last = weights.size() - 1;
  for (std::size_t m = 0; m < count; ++m) {
    const double target = r + static_cast<double>(m) * step;  // line 6: U = r + (m - 1) / M
    while (target > c && i < last) c += weights[++i];         // lines 7-10
    indices[m] = i;                                           // line 11
  }
}

int kld_sample_count(int bins, double err, double z) {
  if (bins <= 1) return 1;
  const double k1 = bins - 1.0;
  const double a = 2.0 / (9.0 * k1);
  const double b = 1.0 - a + std::sqrt(a) * z;
  const double m = k1 / (2.0 * err) * b * b * b;  // Table 8.4, line 15
  return m >= static_cast<double>(std::numeric_limits<int>::max()) ? std::numeric_limits<int>::max()
                                                                   : static_cast<int>(std::ceil(m));
}

LikelihoodField::LikelihoodField(const OccupancyGrid<2>& occupancy, double max_distance)
    : max_distance_(max_distance) {
  VDTNAV_CHECK(occupancy.num_cells() > 0, "LikelihoodField: the map has no cell");
  VDTNAV_CHECK(std::isfinite(max_distance) && max_distance > 0.0,
               "LikelihoodField: max_distance must be finite and > 0");
  distances_ = unsigned_distance_transform(nearest_occupied_cells(occupancy));
  const auto clamp = static_cast<float>(max_distance);
  for (float& d : distances_.values()) d = std::min(d, clamp);  // +inf (empty map) -> clamp
}

double LikelihoodField::distance(const Eigen::Vector2d& p) const {
  const Eigen::Vector2i c = distances_.cell_of(p);
  return distances_.contains(c) ? static_cast<double>(distances_(c)) : max_distance_;
}

ParticleFilterLocalizer::ParticleFilterLocalizer(const OccupancyGrid<2>& map,
                                                 const ParticleFilterOptions& options)
    : options_(options), rng_(options.seed) {
  validate(options_);
  field_ = LikelihoodField(map, options_.max_likelihood_distance);
  log_likelihood_.resize(field_.distances().num_cells());
  const auto capacity =
      static_cast<std::size_t>(options_.kld ? options_.max_particles : options_.particles);
  for (auto* v : {&poses_, &scratch_poses_}) v->reserve(capacity);
  for (auto* v : {&weights_, &log_weights_}) v->reserve(capacity);
  indices_.reserve(capacity);
  bins_.reserve(capacity);
  beam_x_.reserve(static_cast<std::size_t>(options_.max_beams));
  beam_y_.reserve(static_cast<std::size_t>(options_.max_beams));
  reset(Pose2::Zero(), Eigen::Matrix3d::Zero());
}

void ParticleFilterLocalizer::reset(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  VDTNAV_CHECK(pose.allFinite(), "ParticleFilterLocalizer::reset: pose must be finite");
  VDTNAV_CHECK(covariance.allFinite(), "ParticleFilterLocalizer::reset: covariance must be finite");
  const Eigen::Matrix3d cov = 0.5 * (covariance + covariance.transpose());
  // A factor L with L L^T = cov: Cholesky when positive definite, otherwise V sqrt(max(D, 0)).
  Eigen::Matrix3d factor;
  const Eigen::LLT<Eigen::Matrix3d> llt(cov);
  if (llt.info() == Eigen::Success) {
    factor = llt.matrixL();
  } else {
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(cov);
    factor = eig.eigenvectors() * eig.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal();
  }
  const int n = options_.kld ? options_.max_particles : options_.particles;  // amcl: max after init
  poses_.resize(static_cast<std::size_t>(n));
  std::normal_distribution<double> normal;
  for (Pose2& p : poses_) {
    const Eigen::Vector3d z(normal(rng_), normal(rng_), normal(rng_));
    p = pose + factor * z;
    p[2] = wrap_angle(p[2]);
  }
  weights_.assign(poses_.size(), 1.0 / n);
  log_weights_.assign(poses_.size(), -std::log(static_cast<double>(n)));
  estimate_ = pose;
  estimate_[2] = wrap_angle(estimate_[2]);
  covariance_ = cov;
  accumulated_.setZero();
  force_update_ = true;
  neff_ = n;
  resampled_ = false;
}

void ParticleFilterLocalizer::tabulate_log_likelihood(double range_max) {
  if (table_valid_ && range_max == table_range_max_) return;
  const double s = options_.sigma_hit;
  // log z_hit N(d; 0, s^2) = log z_hit - log(sqrt(2 pi) s) - d^2 / (2 s^2)
  const double log_hit =
      options_.z_hit > 0.0 ? std::log(options_.z_hit) - std::log(std::sqrt(2.0 * kPi) * s) : -kInf;
  const double log_rand = options_.z_rand > 0.0 && std::isfinite(range_max) && range_max > 0.0
                              ? std::log(options_.z_rand / range_max)
                              : -kInf;
  const double inv_two_var = 1.0 / (2.0 * s * s);
  const auto log_p = [&](double d) {  // Table 6.3, line 9 (the z_max term is not used: amcl)
    const double v = log_add_exp(log_hit - d * d * inv_two_var, log_rand);
    return static_cast<float>(v > kLogLikelihoodFloor ? v : kLogLikelihoodFloor);
  };
  const float* d = field_.distances().data();
  for (std::size_t i = 0; i < log_likelihood_.size(); ++i) log_likelihood_[i] = log_p(d[i]);
  log_likelihood_outside_ = log_p(field_.max_distance());
  table_range_max_ = range_max;
  table_valid_ = true;
}

void ParticleFilterLocalizer::estimate(Pose2& mean, Eigen::Matrix3d& covariance) const {
  double sx = 0.0, sy = 0.0, sc = 0.0, ss = 0.0;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    const double w = weights_[i];
    sx += w * poses_[i][0];
    sy += w * poses_[i][1];
    sc += w * std::cos(poses_[i][2]);
    ss += w * std::sin(poses_[i][2]);
  }
  mean = Pose2(sx, sy, std::atan2(ss, sc));  // circular mean of yaw
  covariance.setZero();
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    const Eigen::Vector3d e = pose_error(poses_[i], mean);
    covariance.noalias() += weights_[i] * e * e.transpose();
  }
}

void ParticleFilterLocalizer::resample() {
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::size_t count = poses_.size();
  if (options_.kld) {
    // KLD-sampling (Table 8.4): k = occupied bins among max_particles draws; M = M_chi(k).
    const auto m_max = static_cast<std::size_t>(options_.max_particles);
    low_variance_sampler(weights_, m_max, uniform(rng_), indices_);
    bins_.resize(m_max);
    for (std::size_t m = 0; m < m_max; ++m) bins_[m] = kld_bin(poses_[indices_[m]]);
    std::sort(bins_.begin(), bins_.end());
    const auto k = static_cast<int>(std::unique(bins_.begin(), bins_.end()) - bins_.begin());
    const int m_chi = kld_sample_count(k, options_.kld_err, options_.kld_z);
    count =
        static_cast<std::size_t>(std::clamp(m_chi, options_.min_particles, options_.max_particles));
  }
  if (!options_.kld || count != indices_.size())
    low_variance_sampler(weights_, count, uniform(rng_), indices_);
  scratch_poses_.resize(count);
  for (std::size_t m = 0; m < count; ++m) scratch_poses_[m] = poses_[indices_[m]];
  poses_.swap(scratch_poses_);
  weights_.assign(count, 1.0 / static_cast<double>(count));
  log_weights_.assign(count, -std::log(static_cast<double>(count)));
}

LocalizationResult ParticleFilterLocalizer::update(const OdometryStep& odometry,
                                                   const ScanPoints& points) {
  LocalizationResult result;
  result.has_covariance = true;
  resampled_ = false;
  result.dropped = static_cast<int>(points.dropped_not_finite + points.dropped_out_of_range);

  // 1. amcl's update gate on the odometry accumulated since the filter last ran. Non-finite
  //    odometry is ignored (nothing can be predicted from it).
  if (odometry.delta.allFinite()) accumulated_ = compose(accumulated_, odometry.delta);
  const bool moved = std::hypot(accumulated_[0], accumulated_[1]) >= options_.update_min_d ||
                     std::abs(accumulated_[2]) >= options_.update_min_a;
  if (!moved && !force_update_) {
    result.status = LocalizationStatus::kTooFewObservations;
    result.pose = compose(estimate_, accumulated_);
    result.covariance = covariance_;
    return result;
  }
  force_update_ = false;

  // 2. Prediction (Table 5.6) with the accumulated increment.
  const OdometryMotion motion = decompose_odometry(accumulated_, options_);
  accumulated_.setZero();
  std::normal_distribution<double> normal;
  for (Pose2& p : poses_) p = sample_odometry(p, motion, rng_, normal);

  if (points.size() == 0) {
    result.status = LocalizationStatus::kTooFewObservations;
    estimate(estimate_, covariance_);
    result.pose = estimate_;
    result.covariance = covariance_;
    return result;
  }

  // 3. Correction (Table 6.3) in log space, with the endpoints in the grid's cell units.
  tabulate_log_likelihood(points.range_max);
  const std::size_t n_valid = points.size();
  const std::size_t n_beams = std::min(n_valid, static_cast<std::size_t>(options_.max_beams));
  const GridFrame<2>& frame = field_.distances().frame();
  const double inv_res = frame.inv_resolution();
  beam_x_.resize(n_beams);
  beam_y_.resize(n_beams);
  for (std::size_t k = 0; k < n_beams; ++k) {
    const std::size_t j = n_beams == 1 ? n_valid / 2 : k * (n_valid - 1) / (n_beams - 1);
    beam_x_[k] = points.points[j].x() * inv_res;
    beam_y_[k] = points.points[j].y() * inv_res;
  }
  const Eigen::Matrix2d rt = frame.rotation().transpose();
  const Eigen::Vector2d origin = frame.origin();
  const double nx = field_.distances().size()[0], ny = field_.distances().size()[1];
  const auto stride = static_cast<std::ptrdiff_t>(field_.distances().size()[0]);
  const float* table = log_likelihood_.data();
  const double outside = log_likelihood_outside_;
  double max_log_weight = -kInf;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    // The particle in grid-local cell units: endpoint u = t + R(yaw) b, cell = floor(u).
    const Eigen::Vector2d t = rt * (poses_[i].head<2>() - origin) * inv_res;
    const double yaw = poses_[i][2] - frame.yaw();
    const double c = std::cos(yaw), s = std::sin(yaw);
    double log_likelihood = 0.0;
    for (std::size_t k = 0; k < n_beams; ++k) {
      const double ux = t.x() + c * beam_x_[k] - s * beam_y_[k];
      const double uy = t.y() + s * beam_x_[k] + c * beam_y_[k];
      if (ux >= 0.0 && ux < nx && uy >= 0.0 && uy < ny) {  // false for NaN too
        const auto ix = static_cast<std::ptrdiff_t>(ux), iy = static_cast<std::ptrdiff_t>(uy);
        log_likelihood += table[iy * stride + ix];
      } else {
        log_likelihood += outside;
      }
    }
    log_weights_[i] += log_likelihood;
    if (log_weights_[i] > max_log_weight) max_log_weight = log_weights_[i];
  }
  // Normalisation by log-sum-exp; N_eff = 1 / sum w^2.
  double sum = 0.0;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    weights_[i] = std::exp(log_weights_[i] - max_log_weight);
    sum += weights_[i];
  }
  const double log_normaliser = max_log_weight + std::log(sum);
  const double inv_sum = 1.0 / sum;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < poses_.size(); ++i) {
    weights_[i] *= inv_sum;
    log_weights_[i] -= log_normaliser;
    sum_sq += weights_[i] * weights_[i];
  }
  neff_ = 1.0 / sum_sq;

  // 4. Estimate before resampling.
  estimate(estimate_, covariance_);

  // 5. Selective resampling.
  if (neff_ < 0.5 * static_cast<double>(poses_.size())) {
    resample();
    resampled_ = true;
  }

  result.status = LocalizationStatus::kConverged;
  result.pose = estimate_;
  result.covariance = covariance_;
  result.iterations = 1;
  result.final_cost = -log_normaliser;
  result.inliers = static_cast<int>(n_beams);
  return result;
}

}  // namespace vdtnav
