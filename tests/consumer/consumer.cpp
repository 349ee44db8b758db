// Outside massid's tree: loads a URDF and a params file through the installed
// package, predicts the gravity wrench at every row of a measurement file and
// compares it with the wrench the file holds. Exit 0 when the largest
// difference is below 1e-9 of the measured range (the file is noise-free).
//
//   consumer ROBOT.urdf PARAMS.json MEASUREMENTS.csv
#include <cstdio>
#include <exception>
#include <massid/core/model.hpp>
#include <massid/core/predictor.hpp>
#include <massid/core/samples.hpp>
#include <massid/io/csv.hpp>
#include <massid/io/params_file.hpp>
#include <massid/version.hpp>

#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer ROBOT.urdf PARAMS.json MEASUREMENTS.csv\n");
    return 2;
  }
  try {
    const massid::ParamsFile params = massid::read_params(argv[2]);
    const massid::Model model =
        massid::hold_joints(massid::load_urdf(argv[1], params.sensor_link), params.held);
    const massid::Predictor predictor = massid::compile_predictor(model, params);
    massid::PredictorData data(predictor);
    const massid::Samples samples =
        massid::read_samples(model, massid::read_csv(argv[3]), massid::WrenchColumns::Required);
    double worst = 0.0, range = 0.0;
    for (int i = 0; i < samples.size(); ++i) {
      const massid::Wrench w = massid::predict(predictor, data, samples.q.row(i).transpose(),
                                               samples.gravity.row(i).transpose());
      worst = std::max(worst, (w - samples.wrench.row(i).transpose()).cwiseAbs().maxCoeff());
      range = std::max(range, samples.wrench.row(i).cwiseAbs().maxCoeff());
    }
    std::printf("massid %s: %d samples, largest difference %.3g (range %.3g)\n", MASSID_VERSION,
                samples.size(), worst, range);
    return samples.size() > 0 && worst <= 1e-9 * range ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "consumer: %s\n", e.what());
    return 2;
  }
}
