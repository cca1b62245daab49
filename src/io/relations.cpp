#include "vdtnav/io/relations.hpp"

#include <array>
#include <cmath>
#include <string_view>
#include <vector>

#include "text_fields.hpp"

namespace vdtnav {
namespace {

constexpr double kPlanarTolerance = 1e-9;
constexpr std::size_t kRelationFields = 8;
constexpr std::array<const char*, kRelationFields> kRelationNames = {"t1", "t2",   "x",     "y",
                                                                     "z",  "roll", "pitch", "yaw"};

/// \return an empty string and the relation, or what was expected.
std::string parse_relation_line(std::string_view line, Relation& rel) {
  std::vector<std::string_view> f;
  std::array<double, kRelationFields> v{};
  if (std::string error = io_text::parse_finite_fields(line, kRelationNames, f, v);
      !error.empty()) {
    return error;
  }
  for (std::size_t k = 4; k < 7; ++k) {
    if (std::abs(v[k]) > kPlanarTolerance) {
      return std::string(kRelationNames[k]) +
             ": expected 0 (a planar relation: z, roll and pitch 0 within 1e-9), got '" +
             std::string(f[k]) + "'";
    }
  }
  rel.t1 = v[0];
  rel.t2 = v[1];
  rel.delta = Pose2(v[2], v[3], v[7]);
  return {};
}

}  // namespace

RelationsFile load_relations(const std::string& path, const RelationsOptions& options) {
  RelationsFile file;
  io_text::read_data_lines(path, "relations", options.skip_malformed, parse_relation_line,
                           file.relations, file.malformed_lines);
  return file;
}

void save_relations(const std::string& path, const std::vector<Relation>& relations) {
  std::string out;
  for (std::size_t k = 0; k < relations.size(); ++k) {
    const Relation& r = relations[k];
    VDTNAV_CHECK(std::isfinite(r.t1) && std::isfinite(r.t2) && r.delta.allFinite(),
                 "save_relations: relation " + std::to_string(k) + " has a non-finite value");
    io_text::append_fixed(out, r.t1);
    out += ' ';
    io_text::append_fixed(out, r.t2);
    out += ' ';
    io_text::append_fixed(out, r.delta[0]);
    out += ' ';
    io_text::append_fixed(out, r.delta[1]);
    out += " 0 0 0 ";
    io_text::append_fixed(out, r.delta[2]);
    out += '\n';
  }
  io_text::write_text_file(path, out);
}

}  // namespace vdtnav
