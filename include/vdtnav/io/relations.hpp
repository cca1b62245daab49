#pragma once
/// \file
/// \brief Relation files of the SLAM benchmark of Kümmerle et al., "On measuring the accuracy of
/// SLAM algorithms", Autonomous Robots 27(4), 2009: one relation `t1 t2 x y z roll pitch yaw` a
/// line, the manually verified pose of the robot at t2 expressed in its frame at t1.

#include <cstddef>
#include <string>
#include <vector>

#include "vdtnav/core/error.hpp"
#include "vdtnav/core/pose2.hpp"
#include "vdtnav/eval/relation_metric.hpp"

namespace vdtnav {

/// \brief One planar relation: the robot's pose at t2 in its frame at t1 (the type the relation
/// metric of eval/relation_metric.hpp scores).
using Relation = eval::Relation;

/// \brief How a relation file is read.
struct RelationsOptions {
  /// false: a malformed line throws FormatError. true: it is skipped and its line number
  /// recorded in RelationsFile::malformed_lines.
  bool skip_malformed = false;
};

/// \brief The content of a relation file.
struct RelationsFile {
  std::vector<Relation> relations;           ///< in file order
  std::vector<std::size_t> malformed_lines;  ///< 1-based lines skipped with skip_malformed
};

/// \brief Loads a relation file.
///
/// Blank lines and lines starting with `#` are ignored. A line is malformed unless it has exactly
/// 8 finite numbers with z, roll and pitch 0 within 1e-9 (the benchmark is planar; a 3D relation
/// cannot be represented by a Pose2). yaw is stored as written (not wrapped).
/// \throws IoError when the file cannot be read.
/// \throws FormatError (`file:line: what was expected`) for the first malformed line unless
///         options.skip_malformed.
[[nodiscard]] RelationsFile load_relations(const std::string& path,
                                           const RelationsOptions& options = {});

/// \brief Writes relations one a line, `t1 t2 x y 0 0 0 yaw`, every number in the shortest
/// fixed-point form that reads back as the same double, so load_relations() returns them
/// bit for bit.
/// \throws ConfigError when a value is not finite.
/// \throws IoError when the file cannot be written.
void save_relations(const std::string& path, const std::vector<Relation>& relations);

}  // namespace vdtnav
