// Readable linear combinations of standard parameters.
#include <fmt/format.h>

#include <cmath>

#include "massid/core/base_parameters.hpp"
#include "massid/core/regressor.hpp"

namespace massid {

std::string format_expression(const Model& model, const std::vector<Term>& terms) {
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
