// libFuzzer target: the URDF loading path of the CLI. load_urdf (the entry
// point every command uses) on the input, with the root and with a child link
// as the sensor link, then what `massid model` does with the model: hold a
// joint still (--fixed), find the base parameters, print the report and the
// JSON, and compile a predictor from the URDF's own inertials.
#include <Eigen/Core>

#include "fuzz_support.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"

using namespace massid;

namespace {

// Larger trees are valid but make find_base_parameters (an SVD over all
// links) slow enough to look like a hang; the loader itself sees any size.
constexpr int kMaxLinksForAnalysis = 24;

void analyse(const Model& urdf_model) {
  if (urdf_model.num_links() > kMaxLinksForAnalysis) return;
  std::vector<std::pair<std::string, double>> held;
  if (urdf_model.num_joints() > 1) held.emplace_back(urdf_model.joints.back().name, 0.5);
  const Model model = hold_joints(urdf_model, held);
  for (const bool offset : {false, true}) {
    BaseParameterOptions options;
    options.offset = offset;
    const BaseParameters base = find_base_parameters(model, options);
    (void)model_report(model, base);
    (void)params_json(model, base, nullptr);
    // The predictor of the URDF's own inertials: base values = K * standard.
    Eigen::VectorXd values = Eigen::VectorXd::Zero(base.num_unknowns());
    values.head(base.num_mass()) = base.K * nominal_standard_parameters(model);
    const Predictor predictor = compile_predictor(model, base, values);
    PredictorData data(predictor);
    const Eigen::VectorXd q = Eigen::VectorXd::Constant(model.num_joints(), 0.3);
    (void)predict(predictor, data, q, Eigen::Vector3d(0.0, 0.0, -9.81));
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static fuzz::ScratchFile scratch(".urdf");
  const std::string& path = scratch.write(data, size);
  Model model;
  if (!fuzz::expect_clean("load_urdf", [&] { model = load_urdf(path); })) return 0;
  fuzz::expect_clean("model", [&] { analyse(model); });
  if (model.num_links() > 1) {
    fuzz::expect_clean("load_urdf --sensor",
                       [&] { analyse(load_urdf(path, model.links[1].name)); });
  }
  return 0;
}
