// parse_localizer_config (the settings file) on fuzzed text; a file it accepts is printed and
// must read back.
#include <string>

#include "fuzz_input.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/estimation/localizer_config.hpp"
#include "vdtnav/estimation/localizer_factory.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  vdtnav::LocalizerSettings s;
  try {
    s = vdtnav::parse_localizer_config(text, "fuzz.yaml", vdtnav::log_settings());
  } catch (const vdtnav::Error&) {
    return 0;
  }
  const std::string printed = vdtnav::localizer_settings_yaml(s, "");
  (void)vdtnav::parse_localizer_config(printed, "printed.yaml", vdtnav::log_settings());
  return 0;
}
