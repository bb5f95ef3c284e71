#include "run_semantics.hpp"

#include <utility>

#include "artemis/core/log.hpp"
#include "segmenter_setup.hpp"

namespace artemis::cli {

Result<std::unique_ptr<SemanticSetup>> setUpSemantics(const RunFlags& f, const datasets::Dataset& dataset) {
  if (f.segmenter.empty()) {
    if (!f.queries.empty()) return invalidArgument("--query needs a segmenter: --segmenter dnn, onnx, sim or maskfile");
    return std::unique_ptr<SemanticSetup>();
  }
  if (f.queries.empty()) {
    return invalidArgument("--segmenter needs at least one --query (the classes to segment, e.g. --query \"cars\")");
  }
  auto setup = std::make_unique<SemanticSetup>();
  if (f.vocabulary.empty()) {
    setup->vocabulary = semantics::Vocabulary::semanticKitti();
  } else {
    auto v = semantics::Vocabulary::load(f.vocabulary);
    if (!v) return v.status();
    setup->vocabulary = std::move(*v);
  }
  semantics::AliasTable aliases = semantics::AliasTable::builtin();
  if (!f.aliases.empty()) {
    auto user = semantics::AliasTable::load(f.aliases);
    if (!user) return user.status();
    aliases = aliases.extendedWith(*user);
  }
  auto grounder = semantics::QueryGrounder::create(setup->vocabulary, aliases);
  if (!grounder) return grounder.status();
  setup->grounder = std::make_unique<semantics::QueryGrounder>(std::move(*grounder));
  const SegmenterChoice choice{f.segmenter, f.segmenter_noise, f.seed,         f.sim_gt,
                               f.masks,     f.model,           f.model_config, f.params.mapper.threads};
  auto open = openVocabulary(choice, setup->vocabulary);
  if (!open) return open.status();
  // Every query must name some class; terms it could not place are warned about, or, with an
  // open-vocabulary segmenter, become open classes of their own.
  bool opened = false;
  for (const std::string& q : f.queries) {
    auto g = setup->grounder->ground(q);
    if (!g) return g.status();
    std::vector<semantics::ClassId> classes = g->classes;
    for (const std::string& term : g->unmatched) {
      if (!*open) {
        log::warn("query '{}': no class matches '{}'", q, term);
        continue;
      }
      const semantics::SemanticClass* known = setup->vocabulary.findByName(term);
      auto id = known != nullptr ? Result<semantics::ClassId>(known->id) : setup->vocabulary.addOpenClass(term);
      if (!id) return id.status();
      if (known == nullptr) log::info("query '{}': '{}' is a new open class (id {})", q, term, *id);
      classes.push_back(*id);
      opened = true;
    }
    if (classes.empty()) return invalidArgument(semantics::describe(*g, setup->vocabulary));
    std::string names;
    for (const auto c : classes) names += (names.empty() ? "" : ", ") + std::string(setup->vocabulary.name(c));
    log::info("query '{}': {}", q, names);
    for (const auto& a : g->ambiguous) log::warn("query '{}': '{}' left out: {}", q, a.term, a.reason);
    setup->brush.add(q, classes);
  }
  if (opened) {  // later queries (the viewer's) find the open classes by name
    auto regrounded = semantics::QueryGrounder::create(setup->vocabulary, aliases);
    if (!regrounded) return regrounded.status();
    setup->grounder = std::make_unique<semantics::QueryGrounder>(std::move(*regrounded));
  }
  auto segmenter =
      makeSegmenter(choice, setup->vocabulary, setup->grounder.get(), dataset.root(), &setup->settings_json);
  if (!segmenter) return segmenter.status();
  setup->segmenter = std::move(*segmenter);
  return setup;
}

}  // namespace artemis::cli
