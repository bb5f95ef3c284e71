#pragma once
// The semantics of `artemis run --query --segmenter`: the vocabulary, the grounded queries and the
// segmenter, which the run's SemanticRunParams point into.

#include <memory>
#include <string>

#include "artemis/core/status.hpp"
#include "artemis/datasets/dataset.hpp"
#include "artemis/semantics/active_brush.hpp"
#include "artemis/semantics/query_grounder.hpp"
#include "artemis/semantics/segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "run_flags.hpp"

namespace artemis::cli {

struct SemanticSetup {
  semantics::Vocabulary vocabulary;
  std::unique_ptr<semantics::QueryGrounder> grounder;
  std::unique_ptr<semantics::Segmenter> segmenter;
  semantics::ActiveBrush brush;
  std::string settings_json;
};

// Builds the vocabulary, grounds the queries and opens the segmenter. Nothing to do without a
// segmenter; a query without one, or a segmenter without a query, is an error.
Result<std::unique_ptr<SemanticSetup>> setUpSemantics(const RunFlags& f, const datasets::Dataset& dataset);

}  // namespace artemis::cli
