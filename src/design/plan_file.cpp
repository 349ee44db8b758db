#include <numbers>

#include "massid/design/design.hpp"
#include "massid/io/csv.hpp"

namespace massid {

void write_plan(const std::string& path, const Model& model, const std::vector<PlanPose>& plan) {
  // A wrist: the arm's joints first, and no tilt columns (gravity follows
  // from the arm; gx,gy,gz are what it gives).
  const bool wrist = !plan.empty() && plan.front().q_upstream.size() > 0;
  std::vector<std::string> header;
  if (wrist)
    for (const Joint& j : model.upstream_joints) header.push_back(j.name);
  for (const Joint& j : model.joints) header.push_back(j.name);
  for (const auto& [name, value] : model.held) header.push_back(name);
  header.insert(header.end(), {"gx", "gy", "gz"});
  if (!wrist) header.insert(header.end(), {"tilt_x_deg", "tilt_y_deg"});
  std::vector<std::vector<std::string>> rows;
  const double deg = 180.0 / std::numbers::pi;
  for (const PlanPose& p : plan) {
    std::vector<std::string> row;
    for (Eigen::Index j = 0; wrist && j < p.q_upstream.size(); ++j)
      row.push_back(format_number(p.q_upstream[j]));
    for (int j = 0; j < model.num_joints(); ++j) row.push_back(format_number(p.q[j]));
    for (const auto& [name, value] : model.held) row.push_back(format_number(value));
    for (int k = 0; k < 3; ++k) row.push_back(format_number(p.gravity[k]));
    if (!wrist) {
      row.push_back(format_number(p.tilt.x * deg));
      row.push_back(format_number(p.tilt.y * deg));
    }
    rows.push_back(std::move(row));
  }
  write_csv(path, header, rows);
}

}  // namespace massid
