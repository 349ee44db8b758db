#include "hints.hpp"

#include <sstream>

namespace massid::python {
namespace py = pybind11;
namespace {

std::string boolean(const std::string& value) { return value == "off" ? "False" : "True"; }

std::string or_placeholder(const std::string& value, const std::string& placeholder) {
  return value.empty() ? placeholder : value;
}

// The keyword of each setting (also the first member of an exception's hints).
const char* keyword(Hint::Setting s) {
  switch (s) {
    case Hint::Setting::HoldJoints:
      return "fixed";
    case Hint::Setting::Offset:
      return "offset";
    case Hint::Setting::Checks:
      return "checks";
    case Hint::Setting::Robust:
      return "robust";
    case Hint::Setting::Drift:
      return "drift";
    case Hint::Setting::Dynamic:
      return "dynamic";
    case Hint::Setting::Cutoff:
      return "cutoff";
    case Hint::Setting::Delay:
      return "delay";
    case Hint::Setting::MinHeight:
      return "min_height";
    case Hint::Setting::Limits:
      return "limits";
    case Hint::Setting::LevelGravity:
      return "level_gravity";
    case Hint::Setting::TiltMax:
      return "tilt_max_deg";
    case Hint::Setting::Physical:
      return "physical";
    case Hint::Setting::SensorLink:
      return "sensor";
    case Hint::Setting::Poses:
      return "poses";
    case Hint::Setting::SigmaForce:
      return "sigma_force";
    case Hint::Setting::SigmaMoment:
      return "sigma_moment";
    case Hint::Setting::LevelPoses:
      return "level_poses";
    case Hint::Setting::Rest:
      return "rest";
    case Hint::Setting::RootGravity:
      return "root_gravity";
    case Hint::Setting::Columns:
      return "columns";
  }
  return "";
}

}  // namespace

std::string spell(const Hint& hint) {
  const std::string& v = hint.value;
  const std::string k = keyword(hint.setting);
  switch (hint.setting) {
    case Hint::Setting::HoldJoints: {
      std::istringstream in(v);
      std::string held, out;
      while (in >> held) {
        const auto eq = held.find('=');
        out += (out.empty() ? "" : ", ") + ("'" + held.substr(0, eq) + "': ") +
               (eq == std::string::npos ? "VALUE" : held.substr(eq + 1));
      }
      return "fixed={" + or_placeholder(out, "'JOINT': VALUE") + "}";
    }
    case Hint::Setting::Offset:
    case Hint::Setting::Robust:
    case Hint::Setting::Dynamic:
    case Hint::Setting::Physical:
      return k + "=" + boolean(v);
    case Hint::Setting::Checks:
      return "checks=False skips the set-up checks";
    case Hint::Setting::Drift:
      return v == "off" ? "drift=None" : "drift='" + or_placeholder(v, "linear") + "'";
    case Hint::Setting::Delay:
      return v == "auto" ? "delay='auto'" : "delay=" + or_placeholder(v, "S");
    case Hint::Setting::MinHeight:
      return v == "none" ? "min_height=None"
                         : "min_height=" + (v.empty() || v == "lower" ? std::string("H") : v);
    case Hint::Setting::Cutoff:
      return "cutoff=" + (v.empty() || v == "higher" ? std::string("HZ") : v);
    case Hint::Setting::Limits: {
      const auto eq = v.find('='), colon = v.find(':');
      if (v.empty() || eq == std::string::npos || colon == std::string::npos)
        return "limits={'JOINT': (LO, HI)}";
      return "limits={'" + v.substr(0, eq) + "': (" + v.substr(eq + 1, colon - eq - 1) + ", " +
             v.substr(colon + 1) + ")}";
    }
    case Hint::Setting::SensorLink:
      return "sensor='" + or_placeholder(v, "LINK") + "'";
    case Hint::Setting::Rest:
      return "rest='" + or_placeholder(v, "auto") + "'";
    case Hint::Setting::RootGravity:
      return "root_gravity=" + (v.empty() ? std::string("[gx, gy, gz]") : "[" + v + "]");
    case Hint::Setting::Columns: {  // "fx=Fx,fy=Fy" -> columns={'fx': 'Fx', 'fy': 'Fy'}
      std::string out;
      std::istringstream in(v);
      std::string pair;
      while (std::getline(in, pair, ',')) {
        const auto eq = pair.find('=');
        out += (out.empty() ? "" : ", ") + ("'" + pair.substr(0, eq) + "': '") +
               (eq == std::string::npos ? "NAME" : pair.substr(eq + 1)) + "'";
      }
      return "columns={" + or_placeholder(out, "'ROLE': 'NAME'") + "}";
    }
    default:
      return v.empty() ? k : k + "=" + v;
  }
}

std::string name(Hint::Setting setting) { return keyword(setting); }

SettingSpelling spelling() { return {&name, &spell}; }

std::string with_hints(const std::string& message, const std::vector<Hint>& hints) {
  return massid::with_hints(message, hints, &spell);
}

void register_errors(py::module_& m) {
  // The CLI's errors, with its messages: exit code 2 and 3 there.
  static py::exception<InputError> input(m, "InputError", PyExc_ValueError);
  input.attr("__doc__") =
      "Bad input (the CLI's exit code 2): the message names file, line and column, or the "
      "argument; .hints are the settings to change, as (keyword, value) pairs.";
  static py::exception<IdentifiabilityError> identifiability(m, "IdentifiabilityError",
                                                             PyExc_ValueError);
  identifiability.attr("__doc__") =
      "The data cannot determine every base parameter (the CLI's exit code 3): the message "
      "names them and the poses that would; .hints are the settings to change.";
  py::register_exception_translator([](std::exception_ptr p) {
    const auto raise = [](const py::object& type, const Error& e) {
      py::list hints;
      for (const Hint& h : e.hints()) hints.append(py::make_tuple(keyword(h.setting), h.value));
      py::object value = type(with_hints(e.what(), e.hints()));
      value.attr("message") = std::string(e.what());
      value.attr("hints") = hints;
      PyErr_SetObject(type.ptr(), value.ptr());
    };
    try {
      if (p) std::rethrow_exception(p);
    } catch (const InputError& e) {
      raise(input, e);
    } catch (const IdentifiabilityError& e) {
      raise(identifiability, e);
    } catch (const ArgumentError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace massid::python
