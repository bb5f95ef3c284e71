#pragma once
// CLIP's text tokenizer (Radford et al. 2021; OpenAI's simple_tokenizer.py): byte-level BPE over
// lower-cased text, for CLIP text encoders exported to ONNX. The merges file is the user's
// (bpe_simple_vocab_16e6.txt.gz for OpenAI's models, plain or gzipped), read as CLIP reads it:
// the first line is a version header (skipped, whatever it holds), then one merge "a b" a line, of which the first
// max_merges count (CLIP's 49152 - 256 - 2). Ids: the 256 byte symbols, the same with "</w>" (a word's end), one per
// merge, then <|startoftext|> and <|endoftext|>, the largest id.
//
// Text is cleaned as CLIP cleans it, less ftfy's repairs of broken Unicode: HTML's &amp; &lt;
// &gt; &quot; &#39; undone, runs of white space made one space, trimmed, lower-cased (ASCII
// letters; other characters as they are). It is then split as CLIP's pattern splits it: the two
// special tokens, the contractions 's 't 're 've 'm 'll 'd, runs of letters (every non-ASCII
// character counts as a letter), single digits, and runs of other characters.

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::semantics {

inline constexpr std::size_t kClipMerges = 49152 - 256 - 2;
inline constexpr std::size_t kClipContext = 77;

class ClipTokenizer {
 public:
  // Reads a merges file; an unreadable file, a gzip that does not inflate or a line that is not
  // two symbols is an error naming the file and line.
  static Result<ClipTokenizer> load(const std::filesystem::path& merges, std::size_t max_merges = kClipMerges);
  // The same from the file's text (its version line included).
  static Result<ClipTokenizer> parse(std::string_view text, const std::string& origin,
                                     std::size_t max_merges = kClipMerges);

  // The BPE ids of `text`, without the start and end tokens.
  [[nodiscard]] std::vector<std::int64_t> encode(std::string_view text) const;
  // CLIP's input: start token, encode(text), end token, cut to `context` (the end token kept last)
  // and padded with zeros.
  [[nodiscard]] std::vector<std::int64_t> tokens(std::string_view text, std::size_t context = kClipContext) const;

  [[nodiscard]] std::int64_t startToken() const { return start_; }
  [[nodiscard]] std::int64_t endToken() const { return end_; }
  [[nodiscard]] std::size_t vocabularySize() const { return static_cast<std::size_t>(end_) + 1; }

 private:
  ClipTokenizer() = default;
  // The BPE of one word (its bytes as CLIP's unicode symbols), as ids.
  void encodeWord(std::string_view word, std::vector<std::int64_t>& out) const;

  std::vector<std::string> byte_symbol_;  // byte -> its unicode stand-in, UTF-8
  std::unordered_map<std::string, std::int64_t> ids_;
  std::unordered_map<std::string, std::size_t> ranks_;  // "a b" -> merge rank
  std::int64_t start_ = 0;
  std::int64_t end_ = 0;
};

}  // namespace artemis::semantics
