// massid._massid: the compiled part of the Python package `massid`
// (python/massid/__init__.py re-exports it; _massid.pyi has the types).
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "hints.hpp"
#include "massid/version.hpp"

PYBIND11_MODULE(_massid, m) {
  namespace py = pybind11;
  m.doc() =
      "massid: mass parameters of a mechanism on a force/torque sensor, from static wrenches "
      "and in motion (compiled part; use the package `massid`).";
  m.attr("__version__") = MASSID_VERSION;
  massid::python::register_errors(m);  // InputError, IdentifiabilityError, with hints
  massid::python::bind_model(m);
  massid::python::bind_predict(m);
  massid::python::bind_identify(m);
  massid::python::bind_design(m);
  massid::python::bind_motion(m);
  massid::python::bind_track(m);
}
