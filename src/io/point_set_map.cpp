#include "vdtnav/io/point_set_map.hpp"

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <string_view>

namespace vdtnav {
namespace {

constexpr double kMaxCells = 2147483648.0;  // 2^31, Grid's limit

std::string_view trim(std::string_view s) {
  const auto space = [](char c) { return c == ' ' || c == '\t' || c == '\r'; };
  while (!s.empty() && space(s.front())) s.remove_prefix(1);
  while (!s.empty() && space(s.back())) s.remove_suffix(1);
  return s;
}

bool parse_number(std::string_view s, double& v) {
  s = trim(s);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

}  // namespace

template <int Dim>
OccupancyGrid<Dim> occupancy_from_points(const std::vector<Eigen::Matrix<double, Dim, 1>>& points,
                                         double resolution, double margin, std::size_t* dropped) {
  using Vector = typename SpaceTraits<Dim>::Vector;
  using Index = typename SpaceTraits<Dim>::Index;
  VDTNAV_CHECK(std::isfinite(resolution) && resolution > 0.0,
               "occupancy_from_points: resolution must be finite and > 0");
  VDTNAV_CHECK(std::isfinite(margin) && margin >= 0.0,
               "occupancy_from_points: margin must be finite and >= 0");
  Vector lo = Vector::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  std::size_t bad = 0;
  for (const Vector& p : points) {
    if (!p.allFinite()) {
      ++bad;
      continue;
    }
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  if (dropped != nullptr) *dropped = bad;
  VDTNAV_CHECK(!points.empty(), "occupancy_from_points: the point set is empty");
  VDTNAV_CHECK(bad < points.size(), "occupancy_from_points: no point has finite coordinates");

  Vector origin;
  Index size;
  double cells = 1.0;
  for (int d = 0; d < Dim; ++d) {
    origin[d] = std::floor((lo[d] - margin) / resolution) * resolution;  // snapped down
    const double n = std::floor((hi[d] + margin - origin[d]) / resolution) + 1.0;
    cells *= n;
    VDTNAV_CHECK(n >= 1.0 && cells < kMaxCells,
                 "occupancy_from_points: the point set's extent / resolution gives 2^31 cells or "
                 "more; use a coarser resolution");
    size[d] = static_cast<int>(n);
  }
  OccupancyGrid<Dim> grid(size, GridFrame<Dim>(resolution, origin), 0);
  for (const Vector& p : points) {
    if (!p.allFinite()) continue;
    // Every point lies inside the grid; the clamp only absorbs rounding at the outer faces.
    const Index i = grid.cell_of(p).cwiseMax(Index::Zero()).cwiseMin(size - Index::Ones());
    grid(i) = 1;
  }
  return grid;
}

template <int Dim>
std::vector<Eigen::Matrix<double, Dim, 1>> read_point_set_csv(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw IoError(path + ": cannot open point set: " + std::strerror(errno));
  std::vector<Eigen::Matrix<double, Dim, 1>> points;
  std::string line;
  std::size_t line_no = 0;
  bool first = true;
  while (std::getline(in, line)) {
    ++line_no;
    std::string_view text = line;
    text = trim(text.substr(0, text.find('#')));
    if (text.empty()) continue;
    Eigen::Matrix<double, Dim, 1> p;
    int fields = 0, numbers = 0;
    for (std::size_t start = 0;; ++fields) {
      const std::size_t comma = text.find(',', start);
      double v = 0.0;
      if (parse_number(text.substr(start, comma - start), v)) {
        if (fields < Dim) p[fields] = v;
        ++numbers;
      }
      if (comma == std::string_view::npos) {
        ++fields;
        break;
      }
      start = comma + 1;
    }
    if (fields == Dim && numbers == Dim) {
      points.push_back(p);
    } else if (!(first && numbers == 0)) {  // a first line without numbers is a header
      throw FormatError(
          path, line_no,
          std::string("expected ") +
              (Dim == 2 ? "2 comma-separated numbers x,y" : "3 comma-separated numbers x,y,z") +
              ", got '" + std::string(text) + "'");
    }
    first = false;
  }
  if (in.bad()) throw IoError(path + ": read error");
  return points;
}

template OccupancyGrid<2> occupancy_from_points<2>(const std::vector<Eigen::Vector2d>&, double,
                                                   double, std::size_t*);
template OccupancyGrid<3> occupancy_from_points<3>(const std::vector<Eigen::Vector3d>&, double,
                                                   double, std::size_t*);
template std::vector<Eigen::Vector2d> read_point_set_csv<2>(const std::string&);
template std::vector<Eigen::Vector3d> read_point_set_csv<3>(const std::string&);

}  // namespace vdtnav
