#include "hints.hpp"

#include <sstream>

namespace massid::cli {
namespace {

// "off" and "on" of a flag that is present or absent.
std::string flag(const std::string& option, const std::string& value) {
  return value == "off" ? "without " + option : option;
}

std::string or_placeholder(const std::string& value, const std::string& placeholder) {
  return value.empty() ? placeholder : value;
}

}  // namespace

std::string spell(const Hint& hint) {
  const std::string& v = hint.value;
  switch (hint.setting) {
    case Hint::Setting::HoldJoints: {
      std::istringstream in(v);
      std::string held, out;
      while (in >> held) out += (out.empty() ? "--fixed " : " --fixed ") + held;
      return out.empty() ? "--fixed JOINT=VALUE" : out;
    }
    case Hint::Setting::Offset:
      return flag("--offset", v);
    case Hint::Setting::Checks:
      return "--no-checks skips the set-up checks";
    case Hint::Setting::Robust:
      return "--robust";
    case Hint::Setting::Drift:
      return v == "off" ? "without --drift" : "--drift " + or_placeholder(v, "linear");
    case Hint::Setting::Dynamic:
      return flag("--dynamic", v);
    case Hint::Setting::Cutoff:
      return "--cutoff " + (v.empty() || v == "higher" ? std::string("HZ") : v);
    case Hint::Setting::Delay:
      return "--delay " + or_placeholder(v, "S");
    case Hint::Setting::MinHeight:
      return "--min-height " + (v.empty() || v == "lower" ? std::string("H") : v);
    case Hint::Setting::Limits:
      return "--limits " + or_placeholder(v, "JOINT=LO:HI");
    case Hint::Setting::LevelGravity:
      return "--gravity";
    case Hint::Setting::TiltMax:
      return "--tilt-max";
    case Hint::Setting::Physical:
      return "--physical";
    case Hint::Setting::SensorLink:
      return "--sensor " + or_placeholder(v, "LINK");
    case Hint::Setting::Poses:
      return "--poses";
    case Hint::Setting::SigmaForce:
      return "--sigma-force";
    case Hint::Setting::SigmaMoment:
      return "--sigma-moment";
    case Hint::Setting::LevelPoses:
      return "--level-poses " + or_placeholder(v, "N");
    case Hint::Setting::Rest:
      return "--rest " + or_placeholder(v, "auto");
    case Hint::Setting::RootGravity:
      return "--root-gravity " + or_placeholder(v, "gx,gy,gz");
    case Hint::Setting::Columns:
      return "--columns " + or_placeholder(v, "ROLE=NAME");
  }
  return "";
}

std::string name(Hint::Setting setting) {
  switch (setting) {
    case Hint::Setting::HoldJoints:
      return "--fixed";
    case Hint::Setting::Checks:
      return "--no-checks";
    case Hint::Setting::Drift:
      return "--drift";
    case Hint::Setting::Cutoff:
      return "--cutoff";
    case Hint::Setting::Delay:
      return "--delay";
    case Hint::Setting::MinHeight:
      return "--min-height";
    case Hint::Setting::Limits:
      return "--limits";
    case Hint::Setting::SensorLink:
      return "--sensor";
    case Hint::Setting::LevelPoses:
      return "--level-poses";
    case Hint::Setting::Rest:
      return "--rest";
    case Hint::Setting::RootGravity:
      return "--root-gravity";
    case Hint::Setting::Columns:
      return "--columns";
    default:  // a flag, or an option spelled without a value
      return spell({setting, ""});
  }
}

SettingSpelling spelling() { return {&name, &spell}; }

std::string with_hints(const std::string& message, const std::vector<Hint>& hints) {
  return massid::with_hints(message, hints, &spell);
}

}  // namespace massid::cli
