// libFuzzer target: the params-file reader (params_file.cpp), then what
// `predict` and `emulate` do with a file it accepts: bind it to each example
// robot (sensor link and held joints from the file), express its values in the
// robot's base parameters and compile a predictor from them.
#include <Eigen/Core>

#include "fuzz_support.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"

using namespace massid;

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::ScratchFile scratch(".json");
  const auto& robots = fuzz::example_robots();
  const std::string& path = scratch.write(data, size);
  ParamsFile params;
  if (!fuzz::expect_clean("read_params", [&] { params = read_params(path); })) return 0;
  for (const auto& robot : robots) {
    fuzz::expect_clean("predict with the params", [&] {
      const Model model = hold_joints(
          load_urdf_string(robot.urdf_text, params.sensor_link, robot.name + ".urdf"), params.held);
      const IdentifiedModel identified = IdentifiedModel::from_params(model, params);
      IdentifiedModelData scratch_data(identified);
      const Eigen::VectorXd q = Eigen::VectorXd::Constant(model.num_joints(), 0.3);
      const Wrench w =
          identified.predict_gravity(scratch_data, q, Eigen::Vector3d(0.0, 0.0, -9.81));
      (void)w;
    });
  }
  return 0;
}
