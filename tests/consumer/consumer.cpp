// Outside massid's tree: loads a URDF and a params file through the installed
// package, predicts the gravity wrench at every row of a measurement file and
// compares it with the wrench the file holds. Exit 0 when the largest
// difference is below 1e-9 of the measured range (the file is noise-free).
//
//   consumer ROBOT.urdf PARAMS.json MEASUREMENTS.csv
#include <cstdio>
#include <exception>
#include <massid/core/model.hpp>
#include <massid/core/samples.hpp>
#include <massid/io/csv.hpp>
#include <massid/io/read_samples.hpp>
#include <massid/live/identified_model.hpp>
#include <massid/version.hpp>
int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: consumer ROBOT.urdf PARAMS.json MEASUREMENTS.csv\n");
    return 2;
  }
  try {
    // The identified model every door of massid uses: the URDF loaded as the
    // params file says, its base parameters, values, offset and predictor.
    const massid::IdentifiedModel identified = massid::IdentifiedModel::load(argv[1], argv[2]);
    massid::IdentifiedModelData data(identified);
    const massid::Model& model = identified.model();
    const massid::Samples samples =
        massid::read_samples(model, massid::read_csv(argv[3]), massid::WrenchColumns::Required);
    double worst = 0.0, range = 0.0;
    for (int i = 0; i < samples.size(); ++i) {
      const Eigen::VectorXd q = samples.q.row(i).transpose();
      const Eigen::Vector3d g = samples.gravity.row(i).transpose();
      const massid::Wrench w = identified.sensor_reading(identified.predict_gravity(data, q, g));
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
