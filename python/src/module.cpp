// massid._massid: the compiled part of the Python package `massid`
// (python/massid/__init__.py re-exports it; _massid.pyi has the types).
#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "massid/errors.hpp"

#ifndef MASSID_VERSION
#define MASSID_VERSION "0.0.0"
#endif

PYBIND11_MODULE(_massid, m) {
  namespace py = pybind11;
  m.doc() =
      "massid: mass parameters of a mechanism on a force/torque sensor, from static wrenches "
      "and in motion (compiled part; use the package `massid`).";
  m.attr("__version__") = MASSID_VERSION;
  // The CLI's errors, with its messages: exit code 2 and 3 there.
  py::register_exception<massid::InputError>(m, "InputError", PyExc_ValueError).attr("__doc__") =
      "Bad input (the CLI's exit code 2): the message names file, line and column, or the "
      "argument.";
  py::register_exception<massid::IdentifiabilityError>(m, "IdentifiabilityError", PyExc_ValueError)
      .attr("__doc__") =
      "The data cannot determine every base parameter (the CLI's exit code 3): the message "
      "names them and the poses that would.";
  massid::python::bind_model(m);
  massid::python::bind_predict(m);
  massid::python::bind_identify(m);
  massid::python::bind_design(m);
  massid::python::bind_motion(m);
}
