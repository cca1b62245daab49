#include "raw_cloud.hpp"

#include <pcl/io/pcd_io.h>
#include <pcl/io/ply_io.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <exception>
#include <fstream>
#include <string_view>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/point_time_fields.hpp"

namespace vdtnav::detail {
namespace {

/// Opens and reads the first byte, so that a missing, unreadable or directory path is an IoError
/// with errno's reason rather than a parser complaint.
void check_readable(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open point cloud: " + std::strerror(errno));
  in.peek();
  if (in.bad()) throw IoError(path + ": cannot read point cloud: " + std::strerror(errno));
}

/// Splits a text line on commas, semicolons, spaces and tabs ('\r' included).
void split_fields(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  const auto sep = [](char c) {
    return c == ',' || c == ';' || c == ' ' || c == '\t' || c == '\r';
  };
  std::size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && sep(line[i])) ++i;
    const std::size_t start = i;
    while (i < line.size() && !sep(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

/// Parses a whole field as a double (nan and inf accepted, a leading '+' too).
bool parse_double(std::string_view s, double& v) {
  if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

/// A cloud of float64 fields `names` holding `values` (names.size() numbers per point).
pcl::PCLPointCloud2 float64_cloud(const std::vector<std::string>& names,
                                  const std::vector<double>& values) {
  pcl::PCLPointCloud2 cloud;
  for (std::size_t c = 0; c < names.size(); ++c) {
    pcl::PCLPointField f;
    f.name = names[c];
    f.offset = static_cast<std::uint32_t>(c * sizeof(double));
    f.datatype = pcl::PCLPointField::FLOAT64;
    f.count = 1;
    cloud.fields.push_back(f);
  }
  cloud.height = 1;
  cloud.width = static_cast<std::uint32_t>(values.size() / names.size());
  cloud.point_step = static_cast<std::uint32_t>(names.size() * sizeof(double));
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.is_dense = false;
  cloud.data.resize(values.size() * sizeof(double));
  if (!values.empty()) std::memcpy(cloud.data.data(), values.data(), cloud.data.size());
  return cloud;
}

pcl::PCLPointCloud2 xyz_cloud(const std::vector<double>& xyz) {
  return float64_cloud({"x", "y", "z"}, xyz);
}

/// Text points, one per line: x y z first (or the columns a header names x, y, z), separated by
/// commas, semicolons or blanks; '#' lines and blank lines skipped. A header may also name a
/// per-point time column (core/point_time_fields.hpp), kept as a float64 field of that name.
pcl::PCLPointCloud2 read_text_cloud(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open point cloud: " + std::strerror(errno));
  std::vector<double> values;
  std::vector<std::string_view> fields;
  std::string line;
  std::size_t line_no = 0;
  bool first = true;
  int column[4] = {0, 1, 2, -1};  // x, y, z, the time (-1: none)
  std::string time_name;
  int needed = 3;
  while (std::getline(in, line)) {
    ++line_no;
    const std::size_t start = line.find_first_not_of(" \t\r");
    if (start == std::string::npos || line[start] == '#') continue;
    split_fields(line, fields);
    const int count = column[3] >= 0 ? 4 : 3;
    double v[4];
    bool numbers = fields.size() >= static_cast<std::size_t>(needed);
    for (int c = 0; c < count && numbers; ++c)
      numbers = parse_double(fields[static_cast<std::size_t>(column[c])], v[c]);
    if (!numbers && first) {  // a header: find the columns named x, y, z (and a time)
      first = false;
      bool named = true;
      needed = 0;
      for (int c = 0; c < 3; ++c) {
        const std::string_view name = c == 0 ? "x" : c == 1 ? "y" : "z";
        const auto it = std::find(fields.begin(), fields.end(), name);
        named = named && it != fields.end();
        column[c] = named ? static_cast<int>(it - fields.begin()) : c;
        needed = std::max(needed, column[c] + 1);
      }
      if (!named) {
        throw FormatError(path, line_no,
                          "expected a header naming the columns x, y and z, or three numbers "
                          "x y z (separated by commas or blanks)");
      }
      for (const PointTimeField& tf : kPointTimeFields) {
        const auto it = std::find(fields.begin(), fields.end(), std::string_view(tf.name));
        if (it == fields.end()) continue;
        column[3] = static_cast<int>(it - fields.begin());
        needed = std::max(needed, column[3] + 1);
        time_name = tf.name;
        break;
      }
      continue;
    }
    first = false;
    if (!numbers) {
      throw FormatError(path, line_no,
                        "expected the numbers x y z" + (count == 4 ? " " + time_name : "") +
                            " in columns " + std::to_string(column[0] + 1) + ", " +
                            std::to_string(column[1] + 1) + ", " + std::to_string(column[2] + 1) +
                            (count == 4 ? ", " + std::to_string(column[3] + 1) : "") +
                            " (separated by commas or blanks)");
    }
    values.insert(values.end(), v, v + count);
  }
  if (in.bad()) throw IoError(path + ": cannot read point cloud: " + std::strerror(errno));
  if (values.empty()) throw FormatError(path, 0, "the cloud has no points");
  if (time_name.empty()) return xyz_cloud(values);
  return float64_cloud({"x", "y", "z", time_name}, values);
}

/// A legacy ASCII VTK file's POINTS section (any DATASET; cells and attributes ignored).
pcl::PCLPointCloud2 read_vtk_cloud(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path + ": cannot open point cloud: " + std::strerror(errno));
  std::string line;
  std::size_t line_no = 0;
  const auto next = [&]() -> bool {
    if (!std::getline(in, line)) return false;
    ++line_no;
    return true;
  };
  if (!next() || line.rfind("# vtk DataFile", 0) != 0)
    throw FormatError(path, 1, "expected a legacy VTK header '# vtk DataFile Version ...'");
  next();  // title
  if (!next() || line.rfind("ASCII", 0) != 0) {
    throw FormatError(path, line_no,
                      "expected 'ASCII' (binary legacy VTK files are not supported)");
  }
  std::vector<std::string_view> fields;
  while (next()) {
    split_fields(line, fields);
    if (fields.empty() || fields[0] != "POINTS") continue;
    double n = 0.0;
    if (fields.size() < 3 || !parse_double(fields[1], n) || !(n >= 1.0 && n < 1e9) ||
        n != static_cast<double>(static_cast<std::size_t>(n))) {
      throw FormatError(path, line_no, "expected 'POINTS <count> <float|double>'");
    }
    const std::size_t count = static_cast<std::size_t>(n);
    std::vector<double> xyz;
    // Grown as the coordinates come: a header may declare far more points than the file holds
    // (fuzzing: "POINTS 908204548" in a 140-byte file asked for 22 GB up front).
    xyz.reserve(std::min<std::size_t>(3 * count, std::size_t{3} << 20));
    while (xyz.size() < 3 * count && next()) {
      split_fields(line, fields);
      for (std::string_view f : fields) {
        double v = 0.0;
        if (!parse_double(f, v) || xyz.size() == 3 * count) {
          throw FormatError(path, line_no,
                            "expected " + std::to_string(3 * count) +
                                " coordinates after POINTS, got '" + std::string(f) + "'");
        }
        xyz.push_back(v);
      }
    }
    if (xyz.size() < 3 * count) {
      throw FormatError(path, line_no,
                        "the file ends after " + std::to_string(xyz.size()) + " of the " +
                            std::to_string(3 * count) + " coordinates POINTS declares");
    }
    return xyz_cloud(xyz);
  }
  throw FormatError(path, line_no, "expected a POINTS section");
}

pcl::PCLPointCloud2 read_pcd_or_ply(const std::string& path, const std::string& ext,
                                    Eigen::Vector3d* origin) {
  pcl::PCLPointCloud2 cloud;
  int rc = 0;
  try {
    if (ext == ".pcd") {
      pcl::PCDReader reader;
      // PCL 1.13's PCDReader::read dereferences an empty field list when the header has no
      // fields or no points (a garbage or empty file: segfault, PCL issue #5854), so the header is
      // checked first and such files never reach read().
      Eigen::Vector4f o;
      Eigen::Quaternionf orientation;
      int version = 0, data_type = 0;
      unsigned int data_index = 0;
      rc = reader.readHeader(path, cloud, o, orientation, version, data_type, data_index);
      if (rc < 0) {
        throw FormatError(path, 0,
                          "not a valid PCD file (no PCD header: PCL's reader failed with code " +
                              std::to_string(rc) + ")");
      }
      if (cloud.fields.empty())
        throw FormatError(path, 0, "not a valid PCD file: its header declares no FIELDS");
      if (static_cast<std::size_t>(cloud.width) * cloud.height == 0)
        throw FormatError(path, 0, "the cloud has no points");
      cloud = pcl::PCLPointCloud2();
      rc = reader.read(path, cloud, o, orientation, version);
      *origin = o.head<3>().cast<double>();
      if (!origin->allFinite())
        throw FormatError(path, 0, "the VIEWPOINT is not finite; expected the sensor's position");
    } else {
      pcl::PLYReader reader;
      rc = reader.read(path, cloud);
    }
  } catch (const Error&) {
    throw;
  } catch (const std::exception& e) {  // PCL throws pcl::IOException on some malformed files
    throw FormatError(
        path, 0,
        std::string("not a valid ") + (ext == ".pcd" ? "PCD" : "PLY") + " file: " + e.what());
  }
  if (rc < 0) {
    throw FormatError(path, 0,
                      std::string("not a valid ") + (ext == ".pcd" ? "PCD" : "PLY") +
                          " file (PCL's reader failed with code " + std::to_string(rc) + ")");
  }
  return cloud;
}

}  // namespace

RawCloud read_raw_cloud(const std::string& path) {
  const std::string ext = lower_extension(path);
  const bool text = ext == ".csv" || ext == ".txt" || ext == ".xyz";
  if (ext != ".pcd" && ext != ".ply" && ext != ".vtk" && !text) {
    throw FormatError(path, 0,
                      "unknown point cloud format '" + ext +
                          "'; expected a .pcd, .ply, .vtk (legacy ASCII) or text (.csv, .txt, "
                          ".xyz) file");
  }
  check_readable(path);
  RawCloud raw;
  if (text) {
    raw.cloud = read_text_cloud(path);
  } else if (ext == ".vtk") {
    raw.cloud = read_vtk_cloud(path);
  } else {
    raw.cloud = read_pcd_or_ply(path, ext, &raw.origin);
  }
  return raw;
}

Coordinate::Coordinate(const pcl::PCLPointCloud2& cloud, const char* name,
                       const std::string& path) {
  const auto it = std::find_if(cloud.fields.begin(), cloud.fields.end(),
                               [&](const pcl::PCLPointField& f) { return f.name == name; });
  if (it == cloud.fields.end()) {
    throw FormatError(
        path, 0,
        std::string("the cloud has no '") + name + "' field; expected x, y, z coordinates");
  }
  offset_ = it->offset;
  if (it->datatype == pcl::PCLPointField::FLOAT32) {
    is_double_ = false;
  } else if (it->datatype == pcl::PCLPointField::FLOAT64) {
    is_double_ = true;
  } else {
    throw FormatError(path, 0,
                      std::string("field '") + name + "' has PCL datatype " +
                          std::to_string(static_cast<int>(it->datatype)) +
                          "; expected float32 or float64 coordinates");
  }
  if (offset_ + (is_double_ ? sizeof(double) : sizeof(float)) > cloud.point_step)
    throw FormatError(path, 0, std::string("field '") + name + "' lies outside the point");
}

double Coordinate::operator()(const std::uint8_t* point) const {
  if (is_double_) {
    double v;
    std::memcpy(&v, point + offset_, sizeof v);
    return v;
  }
  float v;
  std::memcpy(&v, point + offset_, sizeof v);
  return static_cast<double>(v);
}

PointAccessor::PointAccessor(const pcl::PCLPointCloud2& cloud, const std::string& path)
    : x_(cloud, "x", path),
      y_(cloud, "y", path),
      z_(cloud, "z", path),
      data_(cloud.data.data()),
      width_(cloud.width),
      height_(cloud.height),
      point_step_(cloud.point_step),
      row_step_(cloud.row_step) {
  if (width_ * height_ > 0 &&
      (row_step_ < width_ * point_step_ || cloud.data.size() < height_ * row_step_)) {
    throw FormatError(path, 0, "the cloud's data is shorter than width x height points");
  }
}

}  // namespace vdtnav::detail
