#include "flag_checks.hpp"

#include <fmt/format.h>

#include <cmath>

namespace artemis::cli {

CLI::Validator within(double min, double max) {
  const std::string range = fmt::format("{} to {}", min, max);
  return CLI::Validator(
      [min, max, range](std::string& text) -> std::string {
        double value = 0.0;
        if (!CLI::detail::lexical_cast(text, value)) return fmt::format("'{}' is not a number", text);
        if (!std::isfinite(value) || value < min || value > max) {
          return fmt::format("{} is outside the valid range, {}", text, range);
        }
        return {};
      },
      range);
}

}  // namespace artemis::cli
