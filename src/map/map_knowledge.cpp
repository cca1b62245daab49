#include "vdtnav/map/map_knowledge.hpp"

namespace vdtnav {

MapKnowledge::MapKnowledge(const Grid<std::int8_t, 2>& cells)
    : has_grid_(true), known_(cells.size(), cells.frame(), 0) {
  std::size_t n = 0;
  for (std::size_t k = 0; k < cells.num_cells(); ++k) {
    known_[k] = cells[k] >= 0 ? 1 : 0;
    n += known_[k];
  }
  known_fraction_ = static_cast<double>(n) / static_cast<double>(cells.num_cells());
}

}  // namespace vdtnav
