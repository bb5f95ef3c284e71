// An external segmenter's mask list (<dir>/NNNNNN.json beside NNNNNN.png, mask_file_segmenter.hpp):
// the input is the JSON; the mask-id image beside it is a fixed 16-bit 6x4 PNG with ids 0..3 (PNG
// decoding has its own target). MaskFileSegmenter::segment with a few prompt sets and a phrase
// resolver that accepts the vocabulary's class names.
#include <vector>

#include "artemis/core/image.hpp"
#include "artemis/io/png.hpp"
#include "artemis/semantics/mask_file_segmenter.hpp"
#include "artemis/semantics/vocabulary.hpp"
#include "fuzz_common.hpp"

namespace {

namespace fs = std::filesystem;

const fs::path& maskDir() {
  static const fs::path dir = [] {
    const fs::path d = artemis::fuzz::scratchDir() / "masks";
    fs::create_directories(d);
    artemis::ImageU16 ids(6, 4, 1, 0);
    for (int v = 0; v < 4; ++v) {
      for (int u = 0; u < 6; ++u) ids.at(u, v) = static_cast<std::uint16_t>((u + v) % 4);
    }
    if (!artemis::io::writePng(d / "000000.png", ids).isOk()) std::abort();
    return d;
  }();
  return dir;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  (void)maskDir();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  using namespace artemis::semantics;
  fuzz::writeBytes(maskDir() / "000000.json", data, size);
  const Vocabulary& vocabulary = Vocabulary::semanticKitti();
  PhraseResolver resolver = [&vocabulary](const std::string& text) -> Result<ClassId> {
    const SemanticClass* c = vocabulary.findByName(text);
    if (c == nullptr) return invalidArgument("'" + text + "' names no class");
    return c->id;
  };
  auto segmenter = MaskFileSegmenter::open(maskDir(), vocabulary, resolver);
  if (!segmenter) fuzz::invariantBroken("MaskFileSegmenter::open", segmenter.status().message());
  std::vector<ClassId> all;
  for (const auto& c : vocabulary.classes()) all.push_back(c.id);
  for (const std::vector<ClassId>& prompts : {std::vector<ClassId>{}, std::vector<ClassId>{1, 9}, all}) {
    SegmentRequest request;
    request.frame_index = 0;
    auto obs = (*segmenter)->segment(request, prompts);
    if (!obs) {
      fuzz::rejected(obs.status());
      continue;
    }
    // What fusion relies on: ids within the list, classes among the prompts, scores in [0, 1].
    if (Status s = obs->validate(prompts); !s.isOk()) {
      fuzz::invariantBroken("MaskFileSegmenter::segment", "observation fails validate(): " + s.message());
    }
  }
  return 0;
}
