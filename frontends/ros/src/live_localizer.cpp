// LiveLocalizer: scans wait for their odometry, then are localized as `vdtnav localize --bag`
// localizes them (live_localizer.hpp).

#include "vdtnav/ros/live_localizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>

#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/global_localization.hpp"
#include "vdtnav/io/log_odometry.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/map/vdt_map.hpp"
#include "vdtnav/ros/scan_sequence.hpp"

namespace vdtnav::ros {

namespace {

/// A scan whose odometry is still unknown when transforms this much newer than its stamp have
/// arrived will not get it (a gap in odom -> base, or a scan older than the first transform).
constexpr std::int64_t kOdometryWaitNs = 1'000'000'000;

}  // namespace

const char* to_string(LiveEstimate::Event e) {
  switch (e) {
    case LiveEstimate::Event::kLocalized:
      return "localized";
    case LiveEstimate::Event::kSkipped:
      return "skipped";
    case LiveEstimate::Event::kNoPose:
      return "no_pose";
    case LiveEstimate::Event::kNoOdometry:
      return "no_odometry";
    case LiveEstimate::Event::kNoTransform:
      return "no_transform";
  }
  return "?";
}

struct LiveLocalizer::MapState {
  OccupancyGrid<2> occupancy;
  std::unique_ptr<VdtMap2> vdt;
  MapKnowledge knowledge;
  std::unique_ptr<Localizer2D> localizer;
  std::unique_ptr<GlobalLocalizer> global;  // built at the first search on this map
};

LiveLocalizer::LiveLocalizer(RosMap map, const LocalizerSettings& settings,
                             LiveLocalizerOptions options)
    : map_(std::move(map)),
      settings_(settings),
      options_(std::move(options)),
      tf_(options_.tf_span) {
  build();
}

LiveLocalizer::~LiveLocalizer() = default;

void LiveLocalizer::build() {
  auto s = std::make_unique<MapState>();
  s->occupancy = occupancy(map_);
  s->vdt = std::make_unique<VdtMap2>(VdtMap2::build(s->occupancy));
  s->knowledge = MapKnowledge(map_.cells);
  s->localizer = make_localizer(options_.method, *s->vdt, s->occupancy, settings_, s->knowledge);
  state_ = std::move(s);
}

void LiveLocalizer::set_map(RosMap map) {
  map_ = std::move(map);
  build();
  tracking_ = false;
  if (has_last_pose_ && !pending_reset_) {
    const Eigen::Vector3d s = options_.init_sigma;
    pending_reset_.emplace(last_pose_, Eigen::Vector3d(s.cwiseProduct(s)).asDiagonal());
  }
}

void LiveLocalizer::set_pose(const Pose2& pose, const Eigen::Matrix3d& covariance) {
  if (!pose.allFinite() || !covariance.allFinite()) {
    throw ConfigError("LiveLocalizer::set_pose: the pose and its covariance must be finite");
  }
  pending_reset_.emplace(pose, covariance);
  global_pending_ = false;
}

void LiveLocalizer::start_global() {
  global_pending_ = true;
  pending_reset_.reset();
  tracking_ = false;
}

std::vector<LiveEstimate> LiveLocalizer::add_transforms(const TfMsg& tf, bool is_static) {
  tf_.add(tf, is_static);
  if (!is_static) {
    for (const TransformStampedMsg& t : tf.transforms) {
      newest_tf_ns_ = std::max(newest_tf_ns_, t.header.stamp_ns);
    }
  }
  return drain();
}

std::vector<LiveEstimate> LiveLocalizer::add_scan(const LaserScanMsg& scan) {
  // In stamp order (a scan delayed in transport goes before the newer ones waiting).
  const auto at =
      std::upper_bound(queue_.begin(), queue_.end(), scan.header.stamp_ns,
                       [](std::int64_t t, const LaserScanMsg& m) { return t < m.header.stamp_ns; });
  queue_.insert(at, scan);
  return drain();
}

std::vector<LiveEstimate> LiveLocalizer::drain() {
  std::vector<LiveEstimate> out;
  // The scans whose odometry is known now (and those that will not get it), oldest first.
  std::vector<std::pair<LaserScanMsg, Pose2>> ready;
  while (!queue_.empty()) {
    const std::int64_t t = queue_.front().header.stamp_ns;
    const std::optional<Pose2> odometry = odometry_at(t);
    const bool mounted = mount_for(queue_.front()).has_value();
    if (odometry && mounted) {
      ready.emplace_back(std::move(queue_.front()), *odometry);
      queue_.pop_front();
      continue;
    }
    const bool stale = newest_tf_ns_ != std::numeric_limits<std::int64_t>::min() &&
                       newest_tf_ns_ - t > kOdometryWaitNs;
    if (!stale && queue_.size() <= options_.max_queue) break;
    LiveEstimate e;
    e.event = mounted ? LiveEstimate::Event::kNoOdometry : LiveEstimate::Event::kNoTransform;
    e.stamp_ns = t;
    e.reason =
        "no transform " +
        (mounted ? options_.odom_frame + " -> " + options_.base_frame
                 : options_.base_frame + " -> " + strip_slash(queue_.front().header.frame_id) +
                       " (the scans' frame; or set laser_pose x,y,yaw)") +
        " at the scan's stamp (" +
        (stale ? "transforms 1 s newer arrived without it"
               : std::to_string(queue_.size()) + " scans waiting") +
        "; the frames: " + tf_.describe() + ")";
    out.push_back(std::move(e));
    queue_.pop_front();
  }
  for (std::size_t k = 0; k < ready.size(); ++k) {
    // A global search costs more than a scan period: only the newest scan is searched.
    if (global_pending_ && !pending_reset_ && k + 1 < ready.size()) {
      LiveEstimate e;
      e.event = LiveEstimate::Event::kNoPose;
      e.stamp_ns = ready[k].first.header.stamp_ns;
      e.odometry = ready[k].second;
      out.push_back(std::move(e));
      continue;
    }
    out.push_back(localize(ready[k].first, ready[k].second));
  }
  return out;
}

std::optional<Pose2> LiveLocalizer::odometry_at(std::int64_t t) const {
  const std::string& odom = options_.odom_frame;
  const std::string& base = options_.base_frame;
  if (tf_.can_lookup(odom, base, t)) return planar(tf_.lookup(odom, base, t));
  if (!(options_.odom_extrapolation > 0.0)) return std::nullopt;
  // A scan newer than the odometry: constant velocity over the last 0.1 s, carried to its stamp.
  const std::optional<std::int64_t> latest = tf_.latest_stamp(odom, base);
  const std::int64_t span = 100'000'000;
  if (!latest || *latest == 0 || t < *latest ||
      static_cast<double>(t - *latest) * 1e-9 > options_.odom_extrapolation ||
      !tf_.can_lookup(odom, base, *latest - span)) {
    return std::nullopt;
  }
  const Pose2 now = planar(tf_.lookup(odom, base, *latest));
  const Pose2 before = planar(tf_.lookup(odom, base, *latest - span));
  const double f = static_cast<double>(t - *latest) / static_cast<double>(span);
  return compose(now, f * between(before, now));
}

std::optional<Pose2> LiveLocalizer::mount_for(const LaserScanMsg& msg) {
  if (mount_) return mount_;
  const std::string frame = strip_slash(msg.header.frame_id);
  if (options_.laser_pose) {
    mount_ = *options_.laser_pose;
    mount_source_ = "laser_pose";
  } else if (frame == options_.base_frame) {
    mount_ = Pose2::Zero();
    mount_source_ = "the scans are in " + frame;
  } else if (tf_.can_lookup(options_.base_frame, frame, msg.header.stamp_ns)) {
    mount_ = planar(tf_.lookup(options_.base_frame, frame, msg.header.stamp_ns));
    mount_source_ = "TF " + options_.base_frame + " -> " + frame;
  }
  return mount_;
}

LiveEstimate LiveLocalizer::localize(const LaserScanMsg& msg, const Pose2& odometry) {
  const auto t0 = std::chrono::steady_clock::now();
  LiveEstimate e;
  e.stamp_ns = msg.header.stamp_ns;
  e.odometry = odometry;
  const std::optional<Pose2> mount = mount_for(msg);
  if (!mount) {  // drain() holds a scan back until its mounting is known
    e.event = LiveEstimate::Event::kNoTransform;
    e.reason = "no transform " + options_.base_frame + " -> " + strip_slash(msg.header.frame_id) +
               " (the scans' frame); set laser_pose x,y,yaw (the frames: " + tf_.describe() + ")";
    return e;
  }
  const LaserScan scan = to_laser_scan(msg, *mount, options_.sigma_range, options_.max_range);
  const double t = scan.time;
  Localizer2D& loc = *state_->localizer;
  OdometryStep step;  // the first scan of a track starts at the reset pose: no motion into it
  if (pending_reset_) {
    loc.reset(pending_reset_->first, pending_reset_->second);
    pending_reset_.reset();
    tracking_ = true;
  } else if (global_pending_) {
    // Built at the first search on this map (a new map, set_map(), starts without one).
    if (!state_->global) {
      GlobalLocalizationOptions o = settings_.global;
      o.optimizer = settings_.vdt_opt;
      state_->global =
          std::make_unique<GlobalLocalizer>(*state_->vdt, state_->occupancy, o, state_->knowledge);
    }
    const GlobalLocalizationResult g = state_->global->localize(scan_points(scan));
    if (g.result.status != LocalizationStatus::kConverged) {
      e.event = LiveEstimate::Event::kLocalized;
      e.result.status = LocalizationStatus::kRefused;
      e.result.explained = g.explained;
      e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return e;
    }
    const Eigen::Vector3d s = options_.init_sigma;
    loc.reset(g.result.pose,
              g.result.has_covariance
                  ? g.result.covariance
                  : Eigen::Matrix3d(Eigen::Vector3d(s.cwiseProduct(s)).asDiagonal()));
    global_pending_ = false;
    tracking_ = true;
  } else if (!tracking_) {
    e.event = LiveEstimate::Event::kNoPose;
    return e;
  } else {
    // amcl's rule: localize once the robot moved update_min_d or turned update_min_a.
    const Pose2 d = between(last_odometry_, odometry);
    if (!force_update_ && std::hypot(d[0], d[1]) < options_.update_min_d &&
        std::abs(d[2]) < options_.update_min_a) {
      e.event = LiveEstimate::Event::kSkipped;
      e.has_map_to_odom = map_to_odom_.has_value();
      if (map_to_odom_) e.map_to_odom = *map_to_odom_;
      return e;
    }
    // The step the CLI gives the same scan (odometry_steps(): from the previous scan to this).
    step = odometry_steps({last_time_, t}, {last_odometry_, odometry})[1];
  }
  e.result = loc.update(step, scan);
  e.event = LiveEstimate::Event::kLocalized;
  force_update_ = false;
  last_odometry_ = odometry;
  last_time_ = t;
  if (published_by_default(e.result.status)) {  // converged, or bridged across a gap
    last_pose_ = e.result.pose;
    has_last_pose_ = true;
    // REP 105: map -> odom = (map -> base) (+) (odom -> base)^-1.
    map_to_odom_ = compose(e.result.pose, between(odometry, Pose2::Zero()));
  }
  e.has_map_to_odom = map_to_odom_.has_value();
  if (map_to_odom_) e.map_to_odom = *map_to_odom_;
  e.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return e;
}

}  // namespace vdtnav::ros
