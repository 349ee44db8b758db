// Readable linear combinations of standard parameters.
#include <fmt/format.h>

#include <cmath>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/regressor.hpp"

namespace massid {

std::string format_expression(const Model& model, const std::vector<Term>& terms) {
  // One parameter of every link, each once with coefficient 1: said in words when long.
  if (model.num_links() > kAllLinksShortened) {
    std::vector<char> seen(static_cast<std::size_t>(model.num_links()), 0);
    int count = 0, param = -1;
    bool all = true;
    for (const Term& t : terms) {
      if (t.coef == 0.0) continue;
      if (param < 0) param = t.param;
      all = all && t.param == param && std::abs(t.coef - 1.0) <= 1e-12 &&
            !seen[static_cast<std::size_t>(t.link)];
      if (!all) break;
      seen[static_cast<std::size_t>(t.link)] = 1;
      ++count;
    }
    if (all && count == model.num_links())
      return fmt::format("{}(all {} links below {}, itself included)",
                         standard_parameter_kind(param), count, model.sensor_link());
  }
  std::string out;
  for (const Term& t : terms) {
    if (t.coef == 0.0) continue;
    const double a = std::abs(t.coef);
    const bool negative = t.coef < 0.0;
    if (out.empty())
      out += negative ? "-" : "";
    else
      out += negative ? " - " : " + ";
    if (std::abs(a - 1.0) > 1e-12) out += fmt::format("{:.6g} ", a);
    out += fmt::format("{}({})", standard_parameter_kind(t.param), model.links[t.link].name);
  }
  return out.empty() ? "0" : out;
}

}  // namespace massid
