// load_relations on fuzzed text, strict and skipping malformed lines.
#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/io/relations.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = vdtnav::fuzz::write(data, size, "run.relations");
  for (const bool skip : {false, true}) {
    vdtnav::RelationsOptions o;
    o.skip_malformed = skip;
    try {
      (void)vdtnav::load_relations(path, o);
    } catch (const vdtnav::Error&) {
    }
  }
  return 0;
}
