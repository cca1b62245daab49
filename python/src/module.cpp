// The Python module vdtnav._vdtnav (imported by the package vdtnav, python/vdtnav/__init__.py):
// vdtnav's exceptions as Python exceptions carrying the same messages, then each binding file.
#include "bindings.hpp"
#include "vdtnav/core/error.hpp"
#include "vdtnav/core/parallel.hpp"

PYBIND11_MODULE(_vdtnav, m) {
  namespace py = pybind11;
  using namespace vdtnav::python;
  m.doc() =
      "vdtnav: robot localization on Vector Distance Transform maps (C++ core; see the package "
      "docstring).";
  // vdtnav.Error is a RuntimeError; IoError (a file that cannot be read or written), FormatError
  // (`file:line: what was expected`) and ConfigError (an option out of its domain) derive from it.
  static py::exception<vdtnav::Error> error(m, "Error", PyExc_RuntimeError);
  static py::exception<vdtnav::IoError> io_error(m, "IoError", error.ptr());
  static py::exception<vdtnav::FormatError> format_error(m, "FormatError", error.ptr());
  static py::exception<vdtnav::ConfigError> config_error(m, "ConfigError", error.ptr());
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const vdtnav::IoError& e) {
      io_error(e.what());
    } catch (const vdtnav::FormatError& e) {
      format_error(e.what());
    } catch (const vdtnav::ConfigError& e) {
      config_error(e.what());
    } catch (const vdtnav::Error& e) {
      error(e.what());
    }
  });
  // The pool of core/parallel.hpp (the CLI's --threads, the settings' threads:).
  m.def(
      "set_threads", [](int n) { vdtnav::set_threads(n); }, py::arg("n"),
      "Threads of the work that runs in parallel (map building, global search, 3D multi-start), "
      "process-wide; 0: the machine's cores (the default). Results are the same for any count.");
  m.def(
      "threads", [] { return vdtnav::threads(); },
      "The threads of the work that runs in parallel (set_threads()).");
  bind_maps(m);
  bind_localization2d(m);
  bind_localization3d(m);
  bind_readers(m);
  bind_evaluation(m);
  bind_bags(m);
  bind_timing(m);
}
