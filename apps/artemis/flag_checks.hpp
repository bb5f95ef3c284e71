#pragma once
// Range checks for numeric flags. CLI11's own (PositiveNumber, Range) let NaN through, and infinity
// through PositiveNumber: within() refuses both, and --help shows the range.

#include <CLI/CLI.hpp>

namespace artemis::cli {

// A finite number from `min` to `max`, both included.
CLI::Validator within(double min, double max);

}  // namespace artemis::cli
