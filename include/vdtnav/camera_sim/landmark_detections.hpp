#pragma once
/// \file
/// \brief A simulated landmark detector (the thesis's PMD framework ran YOLO on a forward
/// camera): bearings to the lamp posts of a ParkScene within the detector's field of view and
/// range, with bearing noise, missed detections and false positives. Like a class detector it
/// reports "a lamp post" (label 0), never which one: the filter associates (bearing_update.hpp).

#include <random>
#include <vector>

#include "vdtnav/camera_sim/park_scene.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/estimation/bearing_update.hpp"

namespace vdtnav::rgbd_ground {

/// \brief The detector.
struct DetectionOptions {
  double half_fov = 1.0;          ///< radians either side of the robot's x axis (forward)
  double max_range = 15.0;        ///< metres
  double sigma = 0.025;           ///< radians of bearing noise (~1.4 deg)
  double miss_probability = 0.2;  ///< of each visible lamp post
  double false_per_frame = 0.3;   ///< mean false positives per frame (Poisson), uniform in the FOV
};

/// \brief The detections of one frame from the true pose `robot`.
[[nodiscard]] std::vector<BearingDetection> detect_landmarks(const ParkScene& scene,
                                                             const Pose2& robot,
                                                             const DetectionOptions& options,
                                                             std::mt19937& rng);

/// \brief The lamp posts as landmarks of the bearing update (label 0).
[[nodiscard]] std::vector<Landmark2> park_landmarks(const ParkScene& scene);

}  // namespace vdtnav::rgbd_ground
