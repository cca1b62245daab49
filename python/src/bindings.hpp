#pragma once
// The Python module's shared pieces: what each binding file adds to the module, and the maps the
// localizers hold on to (a Python object keeps its map alive through these shared pointers).
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include <pybind11/pybind11.h>

#include "vdtnav/estimation/localizer_factory.hpp"
#include "vdtnav/map/map_knowledge.hpp"
#include "vdtnav/map/sparse_vdt_map.hpp"
#include "vdtnav/map/vdt_map.hpp"

namespace vdtnav::python {

namespace py = pybind11;

/// \brief A 2D map as the localizers take it: the occupancy grid (udt-*, pf, global search), its
/// VDT map, the ROS cells when the map has unknown space (lost detection's MapKnowledge).
struct Map2 {
  OccupancyGrid<2> occupancy;
  std::optional<Grid<std::int8_t, 2>> cells;
  std::unique_ptr<VdtMap2> vdt;
  MapKnowledge knowledge;
  std::string source;
};

/// \brief A 3D VDT map, dense or sparse.
struct Map3 {
  std::unique_ptr<VdtMap3> dense;
  std::unique_ptr<SparseVdtMap3> sparse;
  std::string source;
  [[nodiscard]] const VdtField3& field() const {
    return dense ? static_cast<const VdtField3&>(*dense) : *sparse;
  }
};

/// \brief A 2D localizer and what it holds on to (its map, its settings).
struct Localizer2 {
  std::unique_ptr<std::mutex> mutex = std::make_unique<std::mutex>();  ///< one call at a time
  std::shared_ptr<Map2> map;
  LocalizerSettings settings;
  std::unique_ptr<Localizer2D> localizer;
};

void bind_maps(py::module_& m);
void bind_localization2d(py::module_& m);
void bind_localization3d(py::module_& m);
void bind_readers(py::module_& m);
void bind_evaluation(py::module_& m);
void bind_timing(py::module_& m);
void bind_bags(py::module_& m);

}  // namespace vdtnav::python
