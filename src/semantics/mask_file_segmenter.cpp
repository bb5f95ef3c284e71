#include "artemis/semantics/mask_file_segmenter.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <nlohmann/json.hpp>
#include <utility>
#include <vector>

#include "artemis/io/png.hpp"
#include "artemis/io/read_file.hpp"

namespace artemis::semantics {

namespace fs = std::filesystem;

MaskFileSegmenter::MaskFileSegmenter(fs::path dir, Vocabulary vocabulary, PhraseResolver resolver)
    : dir_(std::move(dir)), vocabulary_(std::move(vocabulary)), resolver_(std::move(resolver)) {}

Result<std::unique_ptr<MaskFileSegmenter>> MaskFileSegmenter::open(const fs::path& dir, const Vocabulary& vocabulary,
                                                                   PhraseResolver resolver) {
  if (!fs::is_directory(dir)) return notFound(fmt::format("{}: no such mask folder", dir.string()));
  return std::unique_ptr<MaskFileSegmenter>(new MaskFileSegmenter(dir, vocabulary, std::move(resolver)));
}

Result<SemanticObservation> MaskFileSegmenter::segment(const SegmentRequest& request,
                                                       std::span<const ClassId> prompts) {
  const fs::path png = dir_ / fmt::format("{:06d}.png", request.frame_index);
  const fs::path json = dir_ / fmt::format("{:06d}.json", request.frame_index);
  SemanticObservation obs;
  if (!fs::exists(png) || !fs::exists(json)) {
    obs.observed = false;
    obs.note = fmt::format("no mask file {}", (!fs::exists(png) ? png : json).string());
    return obs;
  }
  auto ids = io::readPng16(png);
  if (!ids) return ids.status();
  if (request.view != nullptr && request.view->hasImage() &&
      (ids->width() != request.view->image.width() || ids->height() != request.view->image.height())) {
    return invalidArgument(fmt::format("{}: {}x{} pixels, but the camera image is {}x{}", png.string(), ids->width(),
                                       ids->height(), request.view->image.width(), request.view->image.height()));
  }
  if (ids->channels() != 1) return invalidArgument(fmt::format("{}: expected a grey image of mask ids", png.string()));

  nlohmann::json j;
  {
    auto text = io::readTextFile(json, io::limits::kJson);
    if (!text) return text.status();
    try {
      j = nlohmann::json::parse(*text);
    } catch (const nlohmann::json::exception& e) {
      return parseError(fmt::format("{}: not valid JSON: {}", json.string(), e.what()));
    }
  }
  if (!j.is_object() || !j.contains("masks") || !j["masks"].is_array()) {
    return parseError(fmt::format("{}: expected an object with a \"masks\" array", json.string()));
  }
  // File id -> index into obs.masks + 1, or 0 for a mask of a class that was not prompted.
  std::vector<std::int32_t> remap(65536, -1);
  for (std::size_t k = 0; k < j["masks"].size(); ++k) {
    const auto& m = j["masks"][k];
    const std::string where = fmt::format("{}: mask #{}", json.string(), k);
    if (!m.is_object() || !m.contains("id") || !m["id"].is_number_integer()) {
      return parseError(where + ": needs an integer \"id\"");
    }
    const auto id = m["id"].get<std::int64_t>();
    if (id < 1 || id > 65535) return parseError(fmt::format("{}: id {} outside 1..65535", where, id));
    if (remap[static_cast<std::size_t>(id)] >= 0) return parseError(fmt::format("{}: id {} listed twice", where, id));
    if (!m.contains("score") || !m["score"].is_number()) return parseError(where + ": needs a number \"score\"");
    const double score = m["score"].get<double>();
    if (!(score >= 0.0 && score <= 1.0)) {
      return invalidArgument(fmt::format("{}: score {} outside [0, 1]", where, score));
    }
    ClassId cls = kNoClass;
    if (m.contains("class") && m["class"].is_string()) {
      const SemanticClass* c = vocabulary_.findByName(m["class"].get<std::string>());
      if (c == nullptr) {
        return invalidArgument(
            fmt::format("{}: unknown class '{}' (not in the vocabulary)", where, m["class"].get<std::string>()));
      }
      cls = c->id;
    } else if (m.contains("text") && m["text"].is_string()) {
      if (!resolver_) return invalidArgument(where + ": has a \"text\" but no query grounding is available");
      auto resolved = resolver_(m["text"].get<std::string>());
      if (!resolved) return invalidArgument(fmt::format("{}: {}", where, resolved.status().message()));
      cls = *resolved;
    } else {
      return parseError(where + ": needs a string \"class\" or \"text\"");
    }
    if (std::find(prompts.begin(), prompts.end(), cls) == prompts.end()) {
      remap[static_cast<std::size_t>(id)] = 0;
      continue;
    }
    obs.masks.push_back({cls, static_cast<float>(score)});
    remap[static_cast<std::size_t>(id)] = static_cast<std::int32_t>(obs.masks.size());
  }
  obs.observed = true;
  obs.mask_ids = std::move(*ids);
  // Renumber in place; an id the JSON does not list is an error.
  for (std::uint16_t& id : obs.mask_ids.data()) {
    if (id == 0) continue;
    const std::int32_t to = remap[id];
    if (to < 0) {
      return invalidArgument(fmt::format("{}: mask id {} is not listed in {}", png.string(), id, json.string()));
    }
    id = static_cast<std::uint16_t>(to);
  }
  return obs;
}

}  // namespace artemis::semantics
