// Shared helpers of the library tests: the example robots and their plans.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/csv.hpp"
#include "massid/model.hpp"
#include "massid/samples.hpp"

namespace massid::test {

struct Example {
  std::string name;     // folder under examples/
  std::string urdf;     // path
  std::string plan;     // path
  int base_parameters;  // expected count without offsets
};

inline std::vector<Example> examples() {
  const std::string dir = MASSID_SOURCE_DIR "/examples/";
  return {
      {"puma260", dir + "puma260/puma260.urdf", dir + "puma260/plan.csv", 10},
      {"ur_like", dir + "ur_like/ur_like.urdf", dir + "ur_like/plan.csv", 16},
      {"branching", dir + "branching/branching.urdf", dir + "branching/plan.csv", 17},
      {"wrist_tool", dir + "wrist_tool/wrist_tool.urdf", dir + "wrist_tool/plan.csv", 4},
  };
}

inline Samples load_plan(const Model& model, const std::string& path) {
  return read_samples(model, read_csv(path), WrenchColumns::Optional);
}

}  // namespace massid::test
