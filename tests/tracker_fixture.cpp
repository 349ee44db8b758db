// Writes the tracked logs of tracker_support.hpp as CSV files for the tests of
// the Tracker's doors (tests/c_api/test_c_tracker.c, tests/python/
// test_tracker.py), which feed the same rows to `massid compensate --track`,
// the C interface and Python and compare the columns bit for bit:
//
//   massid_tracker_fixture DIR
//
// DIR/wrist_free.csv, DIR/wrist_tracked.csv: the sensor on wrist_3_link, the
//   arm's joints (all above the sensor) with _vel and _acc, fx..mz; free
//   (no object, no offsets, no contact) to identify from, tracked with an
//   object grasped and put down, drifting offsets and a contact;
// DIR/base_free.csv, DIR/base_tracked.csv: the same with the sensor under the
//   arm's base (joints below it) and gx,gy,gz added.
// Numbers are written as massid writes them (shortest round trip), so that
// every reader gets the same doubles.
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "tracker_support.hpp"

namespace {

using namespace massid::tracker_test;

// tracker_csv, with gx,gy,gz after t when `gravity`.
std::string tracker_fixture_csv(const TrackerLog& log, bool gravity) {
  const std::string csv = tracker_csv(log, massid::load_urdf(massid::test::kUrLikeUrdf));
  if (!gravity) return csv;
  std::string out;
  std::size_t at = 0;
  for (int i = -1; at < csv.size(); ++i) {
    const std::size_t end = csv.find('\n', at), comma = csv.find(',', at);
    out += csv.substr(at, comma - at);
    out += i < 0 ? std::string(",gx,gy,gz")
                 : fmt::format(",{},{},{}", log.samples.gravity(i, 0), log.samples.gravity(i, 1),
                               log.samples.gravity(i, 2));
    out += csv.substr(comma, end + 1 - comma);
    at = end + 1;
  }
  return out;
}

bool tracker_fixture_write(const std::string& path, const std::string& text) {
  std::ofstream out(path);
  out << text;
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s DIR\n", argv[0]);
    return 2;
  }
  const std::string dir = argv[1];
  bool ok = true;
  for (const bool wrist : {true, false}) {
    const std::string name = wrist ? "wrist" : "base";
    ok = ok && tracker_fixture_write(dir + "/" + name + "_free.csv",
                                     tracker_fixture_csv(tracker_log(wrist, 11, false), !wrist));
    ok = ok && tracker_fixture_write(dir + "/" + name + "_tracked.csv",
                                     tracker_fixture_csv(tracker_log(wrist, 12), !wrist));
  }
  if (!ok) std::fprintf(stderr, "cannot write the tracked logs in %s\n", dir.c_str());
  return ok ? 0 : 1;
}
