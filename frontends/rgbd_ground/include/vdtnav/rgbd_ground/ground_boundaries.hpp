#pragma once
/// \file
/// \brief Boundaries between ground surfaces (pavement, grass, gravel) in an RGB-D frame, as
/// robot-frame points with a covariance each: the observations of the VDT EKF in thesis 3.4.5
/// (eqs. 3.23-3.24, corrected per SPEC). The thesis detected the boundaries with HED, a neural
/// network whose weights are not available here; this front end finds them without one:
///
/// 1. the ground plane is fitted to the depth (ground_plane.hpp), and the camera's roll, pitch and
///    height over the ground are taken from it rather than from the nominal extrinsics;
/// 2. edges of the colour image's chroma (the a* and b* channels of CIE L*a*b* after a Gaussian
///    blur; Canny on each): grass, pavement and gravel differ in hue, whereas a shadow or a change
///    of light mostly changes the lightness L*, which is left out by default;
/// 3. an edge pixel is kept when its depth point and the depth points around it (8 directions at
///    the image distance that `clearance` metres span at that depth) lie within the prune
///    distance of the plane: edges on or next to anything standing on the ground (benches,
///    people, posts) are pruned;
/// 4. kept pixels are back-projected with their depth, p_c = z (x_n, y_n, 1) with (x_n, y_n) the
///    undistorted ray, and moved to the robot frame; the (x, y) of the point is the observation.
///
/// Covariance of a point: pixel noise sigma_pixel on (u, v) and the sensor's depth noise
/// sigma_z(z) (depth_noise.hpp), through the Jacobian of (x, y)_robot in (u, v, z):
///   J = R_rc[0:2, :] [ z dn/duv | (x_n, y_n, 1)^T ],  Sigma = J diag(s_px^2, s_px^2, s_z^2) J^T,
/// with dn/duv the inverse of the lens model's d pixel / d normalized. The points also share the
/// error of the fitted ground plane that levels the extrinsics: its tilt delta moves them all
/// alike (BoundaryPoint::tilt_jacobian, GroundBoundaries::tilt_covariance from the fit's
/// covariance, ground_plane.hpp), and observations() hands it to the estimators as the set's
/// shared error (observation_set.hpp), as the UAV camera does with its attitude error.
///
/// The aperture problem: a point of an edge says where the edge is, not where along the edge the
/// point lies (which pixels Canny keeps is arbitrary). Each point's tangent is the principal axis
/// of the kept points within `aperture_radius` around it, and its straightness the coherence
/// c = (l1 - l2) / (l1 + l2) of their scatter's eigenvalues (1 on a straight edge, 0 at a corner).
/// The observations carry Sigma + (c aperture_sigma)^2 t t^T: along a straight edge the point only
/// tells its distance across it. (Adding the term to the disparity's covariance along the edge
/// instead, after the map, calibrates worse: ANEES 6.8 against 3.3 over 600 frames of
/// examples/pmd_rgbd, since a staircase map's boundary also moves across as one slides along it.)
/// Without this, a boundary drawn in a grid map (a staircase of cells) ripples along its length,
/// and every point's ripple enters the filter as independent information along the edge: on a
/// straight path the along-track covariance then collapses to a few centimetres while the error
/// grows to 20 cm (examples/pmd_rgbd, seed 1, before this term).

#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vdtnav/camera/camera_model.hpp"
#include "vdtnav/rgbd_ground/depth_noise.hpp"
#include "vdtnav/rgbd_ground/ground_plane.hpp"
#include "vdtnav/rgbd_ground/rgbd_frame.hpp"
#include "vdtnav/sensor/laser_scan.hpp"

namespace vdtnav::rgbd_ground {

/// \brief Options of the extraction.
struct GroundBoundaryOptions {
  DepthNoiseModel noise;
  GroundPlaneOptions plane;
  double blur_sigma = 1.5;  ///< pixels, Gaussian blur before the edges
  double canny_low = 12.0;  ///< hysteresis thresholds of Canny on a* and b* (8-bit units)
  double canny_high = 30.0;
  bool use_lightness = false;  ///< also the edges of L* (shadows and light changes then count)
  /// Metres: an edge is pruned when a point within the plane's prune distance is farther than this
  /// from the plane: max(prune_floor, 3 sigma_z(z)).
  double prune_floor = 0.04;
  double clearance = 0.10;        ///< metres around an edge that must be ground too (see above)
  double max_range = 6.0;         ///< metres of depth: farther edges are dropped
  int stride = 2;                 ///< keep every stride-th edge pixel (raster order)
  double aperture_radius = 0.15;  ///< metres: the neighbourhood of a point's tangent (see above)
  /// Metres of standard deviation along a straight edge in observations(); 0: off. Large, not
  /// infinite, so the covariance stays invertible; the map's own floor bounds what remains.
  double aperture_sigma = 10.0;
};

/// \brief One kept boundary point.
struct BoundaryPoint {
  Eigen::Vector2i pixel = Eigen::Vector2i::Zero();
  Eigen::Vector3d camera = Eigen::Vector3d::Zero();      ///< back-projected, camera frame
  Eigen::Vector2d robot = Eigen::Vector2d::Zero();       ///< on the ground, robot frame
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();  ///< pixel and depth noise
  /// d robot / d delta = [[0, v_z], [-v_z, 0]]: the point moves by delta x v with the levelled
  /// extrinsics' tilt error delta (GroundBoundaries::tilt_covariance), v = R' camera the ray to
  /// it in robot axes. On the ground v_z = -h (the camera's height), so every point of the frame
  /// moves by the same (-h delta_y, h delta_x): an error the whole frame shares.
  Eigen::Matrix2d tilt_jacobian = Eigen::Matrix2d::Zero();
  Eigen::Vector2d tangent = Eigen::Vector2d::UnitX();  ///< edge direction, robot frame
  double straightness = 0.0;  ///< coherence of the neighbourhood, [0, 1] (0: too few neighbours)
};

/// \brief Sets every point's tangent and straightness from the points within `radius` of it
/// (robot frame; fewer than 4 there: straightness 0). Called by GroundBoundaryExtractor::extract.
void estimate_edge_tangents(std::vector<BoundaryPoint>& points, double radius);

/// \brief What one frame gives.
struct GroundBoundaries {
  GroundPlane plane;
  /// Covariance of the levelled extrinsics' tilt (levelled_tilt_covariance()): an error every
  /// point of the frame shares, carried by observations() as the set's shared error.
  Eigen::Matrix2d tilt_covariance = Eigen::Matrix2d::Zero();
  std::vector<BoundaryPoint> points;
  std::vector<Eigen::Vector2i> pruned_pixels;  ///< edge pixels pruned as off the ground
  int edge_pixels = 0;                         ///< edge pixels with a depth within max_range
  int pruned = 0;
};

/// \brief The extraction for one camera and mounting.
class GroundBoundaryExtractor {
 public:
  /// \throws ConfigError for options out of their domain.
  GroundBoundaryExtractor(camera::PinholeCamera camera, Eigen::Isometry3d camera_to_robot,
                          GroundBoundaryOptions options = {});

  /// \throws ConfigError when the frame's size is not the camera's.
  [[nodiscard]] GroundBoundaries extract(const RgbdFrame& frame) const;

  /// \brief The kept points as observations of the VDT estimators: each with its covariance plus
  /// the aperture term (straightness aperture_sigma)^2 t t^T (see above).
  [[nodiscard]] ScanPoints observations(const GroundBoundaries& boundaries) const;

  /// \brief (x, y) in the robot frame of pixel (u, v) at z-depth z with `camera_to_robot`, and
  /// its Jacobian in (u, v, z) (2 x 3).
  [[nodiscard]] Eigen::Vector2d back_project(const Eigen::Vector2d& pixel, double z,
                                             const Eigen::Isometry3d& camera_to_robot,
                                             Eigen::Matrix<double, 2, 3>* jacobian) const;

  [[nodiscard]] const GroundBoundaryOptions& options() const noexcept { return options_; }

 private:
  camera::PinholeCamera camera_;
  Eigen::Isometry3d camera_to_robot_;
  GroundBoundaryOptions options_;
  std::vector<Eigen::Vector2f> rays_;  ///< undistorted (x_n, y_n) of every pixel, row-major
};

}  // namespace vdtnav::rgbd_ground
