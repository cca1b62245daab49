#include "uncertain_map_study.hpp"
namespace study { void intel_uncertain_map(const std::string&, const std::string&) {} }
