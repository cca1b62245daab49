#pragma once
/// \file
/// \brief The AMCL-style particle filter baseline (SPEC capability 5): Monte Carlo localization
/// with the odometry motion model, the likelihood-field range finder model, the low-variance
/// sampler and optional KLD-sampling (Thrun, Burgard & Fox, Probabilistic Robotics, Tables 5.6,
/// 6.3, 4.4 and 8.4; defaults are those of ROS amcl).

#include <cstddef>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/localizer.hpp"
#include "vdtnav/map/grid.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav {

/// \brief Options of ParticleFilterLocalizer (names and defaults follow ROS amcl).
struct ParticleFilterOptions {
  int particles = 2000;    ///< particle count when `kld` is false
  int max_beams = 60;      ///< valid beams used per scan, evenly subsampled (amcl laser_max_beams)
  double alpha1 = 0.2;     ///< rotation noise from rotation (amcl odom_alpha1)
  double alpha2 = 0.2;     ///< rotation noise from translation (amcl odom_alpha2)
  double alpha3 = 0.2;     ///< translation noise from translation (amcl odom_alpha3)
  double alpha4 = 0.2;     ///< translation noise from rotation (amcl odom_alpha4)
  double z_hit = 0.95;     ///< weight of the Gaussian hit term, in [0, 1] (amcl laser_z_hit)
  double z_rand = 0.05;    ///< weight of the uniform random term, in [0, 1] (amcl laser_z_rand)
  double sigma_hit = 0.2;  ///< metres, std. dev. of the hit term (amcl)
  double max_likelihood_distance = 2.0;  ///< metres, field clamp (amcl laser_likelihood_max_dist)
  bool kld = false;                      ///< adapt the particle count by KLD-sampling
  int min_particles = 500;               ///< KLD lower bound (amcl min_particles)
  int max_particles = 5000;              ///< KLD upper bound and count after reset (amcl)
  double kld_err = 0.01;                 ///< KLD bound epsilon, in (0, 1) (amcl kld_err)
  double kld_z = 0.99;  ///< upper standard normal quantile z_{1-delta} (amcl kld_z, used as is)
  double update_min_d = 0.0;  ///< metres of odometry before the filter runs (0: every scan)
  double update_min_a = 0.0;  ///< radians of odometry before the filter runs (0: every scan)
  std::uint32_t seed = 1;     ///< seed of the filter's std::mt19937_64
};

/// \brief An odometry increment decomposed into rotation, translation, rotation (Table 5.6,
/// lines 2-4) with the standard deviation of each part's noise.
struct OdometryMotion {
  double rot1 = 0.0;   ///< rad, heading of the translation in the previous robot frame
  double trans = 0.0;  ///< m
  double rot2 = 0.0;   ///< rad, rotation after the translation
  double rot1_sd = 0.0;
  double trans_sd = 0.0;
  double rot2_sd = 0.0;
};

/// \brief Decomposes `delta` (the increment in the previous robot frame) for the odometry model.
///
/// rot1 = atan2(dy, dx), trans = |(dx, dy)|, rot2 = dyaw - rot1 exactly, so that the noise-free
/// model reproduces compose(pose, delta). The noise follows amcl's reading of Table 5.6 (the
/// alphas multiply variances):
///   rot1_sd^2  = alpha1 rot1'^2 + alpha2 trans^2
///   trans_sd^2 = alpha3 trans^2 + alpha4 rot1'^2 + alpha4 rot2'^2
///   rot2_sd^2  = alpha1 rot2'^2 + alpha2 trans^2
/// where rot' = min(|rot|, |rot - pi|) so that driving backwards is as certain as driving
/// forwards, and, as in amcl, rot1' = 0 and rot2' = dyaw' when trans < 1 cm (the heading of a
/// tiny translation is meaningless).
[[nodiscard]] OdometryMotion decompose_odometry(const Pose2& delta,
                                                const ParticleFilterOptions& options);

/// \brief sample_motion_model_odometry (Table 5.6, lines 5-10): one sample of the pose after
/// `motion` from `pose`.
[[nodiscard]] Pose2 sample_motion_model_odometry(const Pose2& pose, const OdometryMotion& motion,
                                                 std::mt19937_64& rng);

/// \brief low_variance_sampler (Table 4.4): `count` indices drawn from normalised `weights` with
/// one random offset, written to `indices` (resized; its capacity is reused).
///
/// Particle i is drawn floor(count w_i) or ceil(count w_i) times.
/// \param u uniform in [0, 1); the sampler's offset is r = u / count.
void low_variance_sampler(const std::vector<double>& weights, std::size_t count, double u,
                          std::vector<std::size_t>& indices);

/// \brief The KLD-sampling bound M_chi (Table 8.4, line 15; Fox 2003) for k occupied bins:
/// (k-1)/(2 err) (1 - 2/(9(k-1)) + sqrt(2/(9(k-1))) z)^3, rounded up; 1 for k <= 1.
[[nodiscard]] int kld_sample_count(int bins, double err, double z);

/// \brief The likelihood field of Table 6.3: for every map cell, the distance from its centre to
/// the nearest occupied cell centre, clamped to `max_distance`.
class LikelihoodField {
 public:
  LikelihoodField() = default;
  /// \throws ConfigError when the map has no cell or max_distance is not finite and > 0.
  LikelihoodField(const OccupancyGrid<2>& occupancy, double max_distance);

  /// \return distances in metres, one per map cell.
  [[nodiscard]] const Grid<float, 2>& distances() const noexcept { return distances_; }
  [[nodiscard]] double max_distance() const noexcept { return max_distance_; }
  /// \return the field at world point p (the value of its cell), max_distance() outside the map.
  [[nodiscard]] double distance(const Eigen::Vector2d& p) const;

 private:
  Grid<float, 2> distances_;
  double max_distance_ = 0.0;
};

/// \brief Monte Carlo localization as ROS amcl does it, the baseline the VDT methods are
/// compared with.
///
/// update():
///  1. amcl's update gate: odometry is accumulated and the filter runs only once it exceeds
///     update_min_d or update_min_a (both 0 by default: every scan; the first scan after reset
///     always runs). A gated scan returns the last estimate moved by the accumulated odometry,
///     status kTooFewObservations.
///  2. Prediction: every particle is moved by sample_motion_model_odometry.
///  3. Correction (likelihood_field_range_finder_model, Table 6.3, in log space): up to
///     max_beams valid beams, evenly spaced among the valid ones, each adding
///     log(z_hit N(d; 0, sigma_hit^2) + z_rand / range_max), with d the field at the endpoint
///     (max_likelihood_distance outside the map). The per-cell log-likelihood is tabulated once
///     per scan range_max. Log weights are normalised by log-sum-exp.
///  4. Estimate: weighted mean (circular mean for yaw) and weighted sample covariance
///     sum_i w_i (x_i - mean)(x_i - mean)^T with the yaw difference wrapped, taken before
///     resampling (resampling only adds Monte Carlo noise).
///  5. Selective resampling: low_variance_sampler when N_eff = 1 / sum w_i^2 < N/2 (Doucet;
///     Grisetti et al. 2007). amcl instead resamples every resample_interval-th update (2); the
///     N_eff rule resamples as often when the scan is informative (the likelihood of 60 beams is
///     peaked) and keeps the particle diversity when it is not (corridors, empty scans). Weights
///     of a set that is not resampled carry over to the next update.
///     With kld, the size of the new set is M_chi(k) clamped to [min_particles, max_particles],
///     k the number of occupied (0.5 m, 0.5 m, 10 deg) bins (amcl's kd-tree cell) among
///     max_particles low-variance draws; the set is then drawn with the low-variance sampler.
/// No valid beam: prediction only, status kTooFewObservations. Otherwise kConverged with
/// inliers = beams used, dropped = invalid readings, iterations = 1 and final_cost = the negative
/// log marginal likelihood of the scan, -log sum_i w_i p(z | x_i).
///
/// Buffers are sized at construction and reset; update() does not throw and allocates only the
/// scan's valid points (scan_points()).
class ParticleFilterLocalizer final : public Localizer2D {
 public:
  /// \brief Precomputes the likelihood field of `map` and starts at the origin, zero covariance.
  /// \throws ConfigError for options out of their domain or an empty map.
  explicit ParticleFilterLocalizer(const OccupancyGrid<2>& map,
                                   const ParticleFilterOptions& options = {});

  /// \brief Draws the particles from N(pose, covariance) (Cholesky factor; eigen-decomposition
  /// when covariance is only semi-definite, so a zero covariance puts every particle at pose).
  /// \throws ConfigError when pose or covariance is not finite.
  void reset(const Pose2& pose, const Eigen::Matrix3d& covariance) override;

  /// \brief Predicts with odometry.delta, corrects with the scan, resamples (see the class).
  using Localizer2D::update;
  [[nodiscard]] LocalizationResult update(const OdometryStep& odometry,
                                          const ScanPoints& observations) override;

  /// \return "pf".
  [[nodiscard]] std::string name() const override { return "pf"; }

  [[nodiscard]] const ParticleFilterOptions& options() const noexcept { return options_; }
  [[nodiscard]] const LikelihoodField& likelihood_field() const noexcept { return field_; }
  /// \return the particle poses (after the last update, resampled or not).
  [[nodiscard]] const std::vector<Pose2>& particles() const noexcept { return poses_; }
  /// \return the normalised particle weights, one per particle.
  [[nodiscard]] const std::vector<double>& weights() const noexcept { return weights_; }
  /// \return N_eff of the last correction (before resampling).
  [[nodiscard]] double effective_sample_size() const noexcept { return neff_; }
  /// \return whether the last update resampled.
  [[nodiscard]] bool resampled() const noexcept { return resampled_; }

 private:
  void tabulate_log_likelihood(double range_max);
  void estimate(Pose2& mean, Eigen::Matrix3d& covariance) const;
  void resample();

  ParticleFilterOptions options_;
  LikelihoodField field_;
  std::vector<float> log_likelihood_;  // per cell, for table_range_max_
  float log_likelihood_outside_ = 0.0F;
  double table_range_max_ = 0.0;
  bool table_valid_ = false;

  std::mt19937_64 rng_;
  std::vector<Pose2> poses_, scratch_poses_;
  std::vector<double> weights_, log_weights_;
  std::vector<std::size_t> indices_;
  std::vector<std::int64_t> bins_;
  std::vector<double> beam_x_, beam_y_;  // subsampled endpoints, robot frame, in cells

  Pose2 estimate_ = Pose2::Zero();
  Eigen::Matrix3d covariance_ = Eigen::Matrix3d::Zero();
  Pose2 accumulated_ = Pose2::Zero();  // odometry since the filter last ran
  bool force_update_ = true;
  double neff_ = 0.0;
  bool resampled_ = false;
};

}  // namespace vdtnav
