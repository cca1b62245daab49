#include "vdtnav/camera_sim/runway_scene.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vdtnav/core/error.hpp"

namespace vdtnav::uav_camera {
namespace {

// Grey levels of the scene (luma of what a camera sees there): dark asphalt, mid green grass,
// white paint. The asphalt/grass step is a strong edge, so it is part of the marking map.
constexpr double kAsphalt = 72.0;
constexpr double kGrass = 104.0;
constexpr double kPaint = 218.0;
constexpr double kAsphaltFineSigma = 5.0;  // per texture pixel
constexpr double kGrassFineSigma = 6.0;
constexpr double kPaintFineSigma = 3.0;
constexpr double kStainAmplitude = 9.0;  // low-frequency value noise on the asphalt
constexpr double kStainScale = 3.0;      // metres between its lattice nodes
constexpr double kGrassAmplitude = 10.0;
constexpr double kGrassScale = 1.5;
constexpr double kCrackDepth = 14.0;  // cracks are this much darker than the asphalt

// One piece of the road centre: a straight segment or a circular arc, with the arc length at its
// start along the whole closed centreline (for the dashes).
struct RoadPiece {
  bool arc = false;
  Eigen::Vector2d start = Eigen::Vector2d::Zero();       // line: start point
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // line: unit direction
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();      // arc: centre
  double radius = 0.0;                                   // arc
  double start_angle = 0.0;                              // arc: polar angle of the start
  double turn = 1.0;  // arc: +1 counter-clockwise (centre on the left), -1 clockwise
  double length = 0.0;
  double s0 = 0.0;  // arc length of the start along the centreline

  // Local coordinates of p: s along the piece and the signed lateral offset d (left positive).
  // Returns false when p is not beside this piece or farther than max_offset from it.
  bool local(const Eigen::Vector2d& p, double max_offset, double* s, double* d) const {
    if (!arc) {
      const Eigen::Vector2d q = p - start;
      *s = q.dot(direction);
      *d = direction.x() * q.y() - direction.y() * q.x();
      return *s >= 0.0 && *s <= length && std::abs(*d) <= max_offset;
    }
    const Eigen::Vector2d q = p - centre;
    const double rho = q.norm();
    if (std::abs(radius - rho) > max_offset) return false;
    double delta = turn * (std::atan2(q.y(), q.x()) - start_angle);
    delta -= 2.0 * kPi * std::floor(delta / (2.0 * kPi));  // [0, 2 pi)
    *s = delta * radius;
    *d = turn * (radius - rho);  // left of a CCW arc is toward the centre
    return *s <= length;
  }

  Eigen::Vector2d point(double s) const {
    if (!arc) return start + s * direction;
    const double a = start_angle + turn * s / radius;
    return centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a));
  }
};

// The analytic figure of eight: two loops of radius R centred at (+-c, 0), joined by two straight
// legs tangent to both, which cross at the origin at angles +-alpha, sin(alpha) = R / c. Driven
// as: leg from the origin up-right, the right loop clockwise, the other leg through the origin,
// the left loop counter-clockwise, back to the origin.
struct FigureEight {
  std::vector<RoadPiece> pieces;
  double total_length = 0.0;

  FigureEight(double radius, double separation) {
    const double c = 0.5 * separation;
    const double alpha = std::asin(radius / c);
    const double leg = c * std::cos(alpha);  // origin to a tangent point
    const double sweep = kPi + 2.0 * alpha;  // angle each loop turns through
    const Eigen::Vector2d up(std::cos(alpha), std::sin(alpha));
    const Eigen::Vector2d up_left(-std::cos(alpha), std::sin(alpha));

    RoadPiece l1;
    l1.start = Eigen::Vector2d::Zero();
    l1.direction = up;
    l1.length = leg;
    RoadPiece a1;
    a1.arc = true;
    a1.centre = Eigen::Vector2d(c, 0.0);
    a1.radius = radius;
    a1.start_angle = 0.5 * kPi + alpha;
    a1.turn = -1.0;
    a1.length = sweep * radius;
    RoadPiece l2;
    l2.start = leg * Eigen::Vector2d(std::cos(alpha), -std::sin(alpha));
    l2.direction = up_left;
    l2.length = 2.0 * leg;
    RoadPiece a2;
    a2.arc = true;
    a2.centre = Eigen::Vector2d(-c, 0.0);
    a2.radius = radius;
    a2.start_angle = 0.5 * kPi - alpha;
    a2.turn = 1.0;
    a2.length = sweep * radius;
    RoadPiece l3;
    l3.start = -leg * up;
    l3.direction = up;
    l3.length = leg;
    pieces = {l1, a1, l2, a2, l3};
    for (RoadPiece& p : pieces) {
      p.s0 = total_length;
      total_length += p.length;
    }
  }

  Eigen::Vector2d point(double s) const {
    s -= total_length * std::floor(s / total_length);
    for (const RoadPiece& p : pieces) {
      if (s <= p.s0 + p.length) return p.point(s - p.s0);
    }
    return pieces.back().point(pieces.back().length);
  }
};

// Paint of the road, shared by the texture and the marking map so that both come from one
// geometry. `blur` is the width over which an edge ramps from 0 to 1: the texture pixel size for
// an area-sampled (antialiased) texture, ~0 for the point-sampled map.
struct RoadPaint {
  const FigureEight* eight;
  double half_lane;
  double half_line;
  double dash;
  double period;

  // Fraction of a pixel of width `blur` at p covered by paint.
  double coverage(const Eigen::Vector2d& p, double blur) const {
    const double inv = 1.0 / blur;
    double best = 0.0;
    for (const RoadPiece& piece : eight->pieces) {
      double s = 0.0, d = 0.0;
      if (!piece.local(p, half_lane + half_line + blur, &s, &d)) continue;  // far from the road
      // Edge lines at d = +-half_lane.
      const double edge = half_line - std::min(std::abs(d - half_lane), std::abs(d + half_lane));
      best = std::max(best, std::clamp(0.5 + edge * inv, 0.0, 1.0));
      // Dashed centre line: lateral coverage times (min) coverage along the dash pattern.
      const double lateral = std::clamp(0.5 + (half_line - std::abs(d)) * inv, 0.0, 1.0);
      if (lateral > 0.0) {
        const double m = std::fmod(piece.s0 + s, period);
        const double inside = m < dash ? std::min(m, dash - m) : -std::min(m - dash, period - m);
        best = std::max(best, std::min(lateral, std::clamp(0.5 + inside * inv, 0.0, 1.0)));
      }
      if (best >= 1.0) break;
    }
    return best;
  }
};

// Signed distance to the runway's border: positive inside the asphalt.
double runway_signed_distance(const Eigen::Vector2d& p, double half_length, double half_width) {
  const double ex = std::abs(p.x()) - half_length;
  const double ey = std::abs(p.y()) - half_width;
  if (ex <= 0.0 && ey <= 0.0) return -std::max(ex, ey);
  return -std::hypot(std::max(ex, 0.0), std::max(ey, 0.0));
}

// Small fast deterministic generator for per-pixel texture noise (splitmix64).
struct SplitMix {
  std::uint64_t state;
  std::uint64_t next() {
    std::uint64_t z = (state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  // Approximately standard normal: the sum of four uniforms (Irwin-Hall), variance 4/12.
  double normal() {
    const std::uint64_t r = next();
    double sum = 0.0;
    for (int k = 0; k < 4; ++k) sum += static_cast<double>((r >> (16 * k)) & 0xFFFF);
    return (sum / 65535.0 - 2.0) * std::sqrt(3.0);
  }
};

// Smooth value noise: uniform values in [-1, 1] on a square lattice, interpolated with
// smoothstep weights (C1), for stains and grass blotches.
class ValueNoise {
 public:
  ValueNoise(std::uint64_t seed, const Eigen::Vector2d& lower, const Eigen::Vector2d& upper,
             double spacing)
      : lower_(lower), inv_spacing_(1.0 / spacing) {
    nx_ = static_cast<int>(std::ceil((upper.x() - lower.x()) * inv_spacing_)) + 2;
    ny_ = static_cast<int>(std::ceil((upper.y() - lower.y()) * inv_spacing_)) + 2;
    SplitMix rng{seed};
    values_.resize(static_cast<std::size_t>(nx_) * ny_);
    for (double& v : values_) v = static_cast<double>(rng.next() >> 11) * 0x1.0p-52 - 1.0;
  }

  double operator()(const Eigen::Vector2d& p) const {
    const double u = (p.x() - lower_.x()) * inv_spacing_;
    const double v = (p.y() - lower_.y()) * inv_spacing_;
    const int i = std::clamp(static_cast<int>(std::floor(u)), 0, nx_ - 2);
    const int j = std::clamp(static_cast<int>(std::floor(v)), 0, ny_ - 2);
    const double fu = smooth(std::clamp(u - i, 0.0, 1.0));
    const double fv = smooth(std::clamp(v - j, 0.0, 1.0));
    const auto at = [&](int a, int b) { return values_[static_cast<std::size_t>(b) * nx_ + a]; };
    return (1 - fv) * ((1 - fu) * at(i, j) + fu * at(i + 1, j)) +
           fv * ((1 - fu) * at(i, j + 1) + fu * at(i + 1, j + 1));
  }

 private:
  static double smooth(double t) { return t * t * (3.0 - 2.0 * t); }
  Eigen::Vector2d lower_;
  double inv_spacing_;
  int nx_ = 0, ny_ = 0;
  std::vector<double> values_;
};

void validate(const RunwaySceneOptions& o) {
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  VDTNAV_CHECK(positive(o.resolution), "runway scene: resolution must be > 0");
  VDTNAV_CHECK(positive(o.map_resolution), "runway scene: map_resolution must be > 0");
  VDTNAV_CHECK(positive(o.runway_length) && positive(o.runway_width),
               "runway scene: runway_length and runway_width must be > 0");
  VDTNAV_CHECK(std::isfinite(o.grass_margin) && o.grass_margin >= 0.0,
               "runway scene: grass_margin must be >= 0");
  VDTNAV_CHECK(std::isfinite(o.map_margin) && o.map_margin >= 0.0,
               "runway scene: map_margin must be >= 0");
  VDTNAV_CHECK(positive(o.loop_radius), "runway scene: loop_radius must be > 0");
  VDTNAV_CHECK(std::isfinite(o.loop_separation) && o.loop_separation > 2.0 * o.loop_radius,
               "runway scene: loop_separation must exceed 2 loop_radius (the legs must cross)");
  VDTNAV_CHECK(positive(o.line_width) && positive(o.lane_width) && o.lane_width > o.line_width,
               "runway scene: need lane_width > line_width > 0");
  VDTNAV_CHECK(o.lane_width < o.loop_radius, "runway scene: lane_width must be < loop_radius");
  VDTNAV_CHECK(positive(o.dash_length) && std::isfinite(o.dash_gap) && o.dash_gap >= 0.0,
               "runway scene: dash_length must be > 0 and dash_gap >= 0");
  VDTNAV_CHECK(positive(o.border_width), "runway scene: border_width must be > 0");
  VDTNAV_CHECK(positive(o.centreline_spacing), "runway scene: centreline_spacing must be > 0");
  const double reach = 0.5 * o.lane_width + 0.5 * o.line_width + 0.25;  // keep off the border
  VDTNAV_CHECK(0.5 * o.loop_separation + o.loop_radius + reach <= 0.5 * o.runway_length &&
                   o.loop_radius + reach <= 0.5 * o.runway_width,
               "runway scene: the figure of eight does not fit on the runway");
  const double w = o.runway_length + 2.0 * o.grass_margin;
  const double h = o.runway_width + 2.0 * o.grass_margin;
  VDTNAV_CHECK(w / o.resolution * (h / o.resolution) < 2.0e9,
               "runway scene: texture too large (lower grass_margin or raise resolution)");
}

}  // namespace

double GroundTexture::sample(const Eigen::Vector2d& xy) const {
  if (image.empty() || !contains(xy)) return background;
  const double inv = 1.0 / resolution;
  const double cu = (xy.x() - origin.x()) * inv - 0.5;
  const double cv = static_cast<double>(image.rows) - 0.5 - (xy.y() - origin.y()) * inv;
  const int c0 = std::clamp(static_cast<int>(std::floor(cu)), 0, image.cols - 1);
  const int r0 = std::clamp(static_cast<int>(std::floor(cv)), 0, image.rows - 1);
  const int c1 = std::min(c0 + 1, image.cols - 1);
  const int r1 = std::min(r0 + 1, image.rows - 1);
  const double fu = std::clamp(cu - c0, 0.0, 1.0);
  const double fv = std::clamp(cv - r0, 0.0, 1.0);
  const auto grey = [&](int r, int c) -> double {
    if (image.channels() == 1) return image.at<std::uint8_t>(r, c);
    const cv::Vec3b& bgr = image.at<cv::Vec3b>(r, c);
    return 0.114 * bgr[0] + 0.587 * bgr[1] + 0.299 * bgr[2];  // BT.601 luma, as cv::cvtColor
  };
  return (1 - fv) * ((1 - fu) * grey(r0, c0) + fu * grey(r0, c1)) +
         fv * ((1 - fu) * grey(r1, c0) + fu * grey(r1, c1));
}

Eigen::Vector2d GroundTexture::pixel_center(int col, int row) const {
  return origin + resolution * Eigen::Vector2d(col + 0.5, image.rows - 1 - row + 0.5);
}

bool GroundTexture::contains(const Eigen::Vector2d& xy) const {
  const Eigen::Vector2d q = (xy - origin) / resolution;
  return q.x() >= 0.0 && q.y() >= 0.0 && q.x() < image.cols && q.y() < image.rows;
}

RunwayScene make_runway_scene(const RunwaySceneOptions& options) {
  validate(options);
  const double half_length = 0.5 * options.runway_length;
  const double half_width = 0.5 * options.runway_width;
  const FigureEight eight(options.loop_radius, options.loop_separation);
  const RoadPaint paint{&eight, 0.5 * options.lane_width, 0.5 * options.line_width,
                        options.dash_length, options.dash_length + options.dash_gap};

  RunwayScene scene;
  scene.runway = Eigen::AlignedBox2d(Eigen::Vector2d(-half_length, -half_width),
                                     Eigen::Vector2d(half_length, half_width));

  // Centreline: the analytic curve sampled at (about) the requested spacing.
  const auto n_centre = static_cast<std::size_t>(
      std::max(8.0, std::round(eight.total_length / options.centreline_spacing)));
  scene.centreline.reserve(n_centre);
  for (std::size_t k = 0; k < n_centre; ++k) {
    scene.centreline.push_back(
        eight.point(eight.total_length * static_cast<double>(k) / static_cast<double>(n_centre)));
  }

  // Texture: runway plus the grass margin, antialiased by evaluating coverage over one pixel.
  GroundTexture& tex = scene.texture;
  const double res = options.resolution;
  tex.resolution = res;
  tex.origin =
      Eigen::Vector2d(-half_length - options.grass_margin, -half_width - options.grass_margin);
  tex.background = kGrass;
  const int cols =
      static_cast<int>(std::ceil((options.runway_length + 2 * options.grass_margin) / res));
  const int rows =
      static_cast<int>(std::ceil((options.runway_width + 2 * options.grass_margin) / res));
  tex.image.create(rows, cols, CV_8UC1);
  const Eigen::Vector2d upper = tex.origin + res * Eigen::Vector2d(cols, rows);
  const ValueNoise stains(options.seed * 3 + 1, tex.origin, upper, kStainScale);
  const ValueNoise blotches(options.seed * 3 + 2, tex.origin, upper, kGrassScale);
  for (int r = 0; r < rows; ++r) {
    SplitMix rng{options.seed * 0x100000001B3ull + static_cast<std::uint64_t>(r)};
    auto* row = tex.image.ptr<std::uint8_t>(r);
    for (int c = 0; c < cols; ++c) {
      const Eigen::Vector2d p = tex.pixel_center(c, r);
      const double inside = runway_signed_distance(p, half_length, half_width);
      const double asphalt_fraction = std::clamp(0.5 + inside / res, 0.0, 1.0);
      double grass = 0.0;
      if (asphalt_fraction < 1.0) {
        grass = kGrass + kGrassAmplitude * blotches(p) + kGrassFineSigma * rng.normal();
      }
      double value = grass;
      if (asphalt_fraction > 0.0) {
        double asphalt = kAsphalt + kStainAmplitude * stains(p) + kAsphaltFineSigma * rng.normal();
        const double cover = inside > -res ? paint.coverage(p, res) : 0.0;
        if (cover > 0.0) {
          asphalt += cover * (kPaint + kPaintFineSigma * rng.normal() - asphalt);
        }
        value = asphalt_fraction * asphalt + (1.0 - asphalt_fraction) * grass;
      }
      row[c] = cv::saturate_cast<std::uint8_t>(value);
    }
  }

  // Cracks: thin random-walk polylines a little darker than the asphalt (low contrast).
  {
    std::mt19937_64 rng(options.seed * 7 + 5);
    std::uniform_real_distribution<double> ux(-half_length + 1.0, half_length - 1.0);
    std::uniform_real_distribution<double> uy(-half_width + 1.0, half_width - 1.0);
    std::uniform_real_distribution<double> heading(-kPi, kPi);
    std::normal_distribution<double> bend(0.0, 0.4);
    cv::Mat mask = cv::Mat::zeros(rows, cols, CV_8UC1);
    const auto n_cracks =
        static_cast<int>(options.runway_length * options.runway_width / 40.0);  // one per 40 m^2
    for (int k = 0; k < n_cracks; ++k) {
      Eigen::Vector2d p(ux(rng), uy(rng));
      double a = heading(rng);
      std::vector<cv::Point> polyline;
      for (int step = 0; step <= 12; ++step) {
        const double col = (p.x() - tex.origin.x()) / res - 0.5;
        const double row = rows - 0.5 - (p.y() - tex.origin.y()) / res;
        polyline.emplace_back(static_cast<int>(std::lround(col)),
                              static_cast<int>(std::lround(row)));
        a += bend(rng);
        p += 0.4 * Eigen::Vector2d(std::cos(a), std::sin(a));
        p.x() = std::clamp(p.x(), -half_length + 0.5, half_length - 0.5);
        p.y() = std::clamp(p.y(), -half_width + 0.5, half_width - 0.5);
      }
      cv::polylines(mask, polyline, false, cv::Scalar(255), 1, cv::LINE_AA);
    }
    for (int r = 0; r < rows; ++r) {
      auto* row = tex.image.ptr<std::uint8_t>(r);
      const auto* m = mask.ptr<std::uint8_t>(r);
      for (int c = 0; c < cols; ++c) {
        if (m[c] != 0)
          row[c] = cv::saturate_cast<std::uint8_t>(row[c] - kCrackDepth * m[c] / 255.0);
      }
    }
  }

  // Marking map: point-sampled from the same paint geometry, plus the runway border as a line.
  {
    const double mres = options.map_resolution;
    const Eigen::Vector2d morigin(-half_length - options.map_margin,
                                  -half_width - options.map_margin);
    const Eigen::Vector2i size(
        static_cast<int>(std::ceil((options.runway_length + 2 * options.map_margin) / mres)),
        static_cast<int>(std::ceil((options.runway_width + 2 * options.map_margin) / mres)));
    scene.markings = OccupancyGrid<2>(size, GridFrame<2>(mres, morigin), 0);
    const double point_blur = 1e-9 * mres;  // a step: the paint is there or not
    const double half_border = 0.5 * options.border_width;
    for (int j = 0; j < size.y(); ++j) {
      for (int i = 0; i < size.x(); ++i) {
        const Eigen::Vector2i idx(i, j);
        const Eigen::Vector2d p = scene.markings.cell_center(idx);
        const double inside = runway_signed_distance(p, half_length, half_width);
        const bool border = std::abs(inside) <= half_border;
        const bool painted = inside > 0.0 && paint.coverage(p, point_blur) >= 0.5;
        scene.markings(idx) = (border || painted) ? 1 : 0;
      }
    }
  }
  return scene;
}

void save_marking_map(const std::string& prefix, const RunwayScene& scene) {
  const OccupancyGrid<2>& grid = scene.markings;
  VDTNAV_CHECK(grid.num_cells() > 0, "save_marking_map: the scene has no marking map");
  VDTNAV_CHECK(grid.frame().axis_aligned(),
               "save_marking_map: the marking map must not be rotated");
  const int nx = grid.size().x(), ny = grid.size().y();
  // map_server convention: image row 0 is the top of the map, so cell (i, j) is pixel
  // (column i, row ny - 1 - j); black (0) = occupied, white (255) = free.
  cv::Mat image(ny, nx, CV_8UC1);
  for (int j = 0; j < ny; ++j) {
    auto* row = image.ptr<std::uint8_t>(ny - 1 - j);
    for (int i = 0; i < nx; ++i) row[i] = grid(Eigen::Vector2i(i, j)) != 0 ? 0 : 255;
  }
  const std::string png = prefix + ".png";
  const std::string yaml = prefix + ".yaml";
  bool written = false;
  try {
    written = cv::imwrite(png, image);
  } catch (const cv::Exception& e) {
    throw IoError("cannot write " + png + ": " + e.what());
  }
  if (!written) throw IoError("cannot write " + png);

  std::ofstream out(yaml);
  if (!out) throw IoError("cannot write " + yaml);
  out << std::setprecision(std::numeric_limits<double>::max_digits10);
  out << "image: " << std::filesystem::path(png).filename().string() << "\n"
      << "resolution: " << grid.resolution() << "\n"
      << "origin: [" << grid.frame().origin().x() << ", " << grid.frame().origin().y() << ", 0.0]\n"
      << "negate: 0\n"
      << "occupied_thresh: 0.65\n"
      << "free_thresh: 0.196\n";
  if (!out) throw IoError("cannot write " + yaml);
}

GroundTexture photograph_texture(const cv::Mat& photo, double resolution,
                                 const Eigen::Vector2d& origin) {
  VDTNAV_CHECK(!photo.empty(), "photograph_texture: the photo is empty");
  VDTNAV_CHECK(photo.type() == CV_8UC1 || photo.type() == CV_8UC3,
               "photograph_texture: the photo must be 8-bit grey or BGR");
  VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0.0,
               "photograph_texture: resolution must be > 0");
  VDTNAV_CHECK(origin.allFinite(), "photograph_texture: origin must be finite");
  GroundTexture texture;
  texture.image = photo;  // shares the pixels (cv::Mat reference counting)
  texture.resolution = resolution;
  texture.origin = origin;
  // Beyond the photo: its mean grey level, so that the photo's border is not a strong edge.
  const cv::Scalar m = cv::mean(photo);
  texture.background = photo.channels() == 1 ? m[0] : 0.114 * m[0] + 0.587 * m[1] + 0.299 * m[2];
  return texture;
}

}  // namespace vdtnav::uav_camera
