#include "artemis/semantics/clip_tokenizer.hpp"

#include <fmt/format.h>
#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <limits>
#include <sstream>

#include "artemis/io/read_file.hpp"

namespace artemis::semantics {

namespace {

constexpr std::string_view kStart = "<|startoftext|>";
constexpr std::string_view kEnd = "<|endoftext|>";
constexpr std::string_view kWordEnd = "</w>";
constexpr std::size_t kMaxInflatedBytes = std::size_t{64} << 20;

std::string utf8(std::uint32_t cp) {
  std::string out;
  if (cp < 0x80) {
    out.push_back(static_cast<char>(cp));
  } else if (cp < 0x800) {
    out.push_back(static_cast<char>(0xC0 | (cp >> 6)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  } else {
    out.push_back(static_cast<char>(0xE0 | (cp >> 12)));
    out.push_back(static_cast<char>(0x80 | ((cp >> 6) & 0x3F)));
    out.push_back(static_cast<char>(0x80 | (cp & 0x3F)));
  }
  return out;
}

// CLIP's bytes_to_unicode(): the bytes in its order (printable ones first) and their stand-ins.
std::vector<std::pair<int, std::uint32_t>> byteOrder() {
  std::vector<std::pair<int, std::uint32_t>> order;
  std::vector<bool> listed(256, false);
  for (const auto& [lo, hi] : {std::pair{0x21, 0x7E}, std::pair{0xA1, 0xAC}, std::pair{0xAE, 0xFF}}) {
    for (int b = lo; b <= hi; ++b) {
      order.emplace_back(b, static_cast<std::uint32_t>(b));
      listed[static_cast<std::size_t>(b)] = true;
    }
  }
  std::uint32_t n = 0;
  for (int b = 0; b < 256; ++b) {
    if (!listed[static_cast<std::size_t>(b)]) order.emplace_back(b, 256 + n++);
  }
  return order;
}

Result<std::string> inflateGzip(const std::vector<unsigned char>& bytes, const std::string& origin) {
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) return ioError(origin + ": zlib failed to start");
  z.next_in = const_cast<Bytef*>(bytes.data());
  z.avail_in = static_cast<uInt>(bytes.size());
  std::string out;
  char buffer[1 << 16];
  int rc = Z_OK;
  while (rc != Z_STREAM_END) {
    z.next_out = reinterpret_cast<Bytef*>(buffer);
    z.avail_out = sizeof buffer;
    rc = inflate(&z, Z_NO_FLUSH);
    if (rc != Z_OK && rc != Z_STREAM_END) break;
    out.append(buffer, sizeof buffer - z.avail_out);
    if (out.size() > kMaxInflatedBytes || (rc == Z_OK && z.avail_in == 0 && z.avail_out != 0)) break;
  }
  inflateEnd(&z);
  if (rc != Z_STREAM_END) return parseError(origin + ": a gzip file that does not inflate whole");
  return out;
}

// CLIP's text cleaning (less ftfy): HTML entities, white space, lower case.
std::string clean(std::string_view text) {
  std::string unescaped;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    for (const auto& [entity, c] :
         {std::pair{std::string_view("&amp;"), '&'}, std::pair{std::string_view("&lt;"), '<'},
          std::pair{std::string_view("&gt;"), '>'}, std::pair{std::string_view("&quot;"), '"'},
          std::pair{std::string_view("&#39;"), '\''}}) {
      if (text.substr(i, entity.size()) == entity) {
        unescaped.push_back(c);
        i += entity.size();
        replaced = true;
        break;
      }
    }
    if (!replaced) unescaped.push_back(text[i++]);
  }
  std::string out;
  bool space = false;
  for (const char c : unescaped) {
    const auto u = static_cast<unsigned char>(c);
    if (u == ' ' || u == '\t' || u == '\n' || u == '\r' || u == '\f' || u == '\v') {
      space = !out.empty();
      continue;
    }
    if (space) out.push_back(' ');
    space = false;
    out.push_back(u < 0x80 ? static_cast<char>(std::tolower(u)) : c);
  }
  return out;
}

bool isLetter(unsigned char c) {
  return std::isalpha(c) != 0 || c >= 0x80;
}
bool isDigit(unsigned char c) {
  return c >= '0' && c <= '9';
}
bool isSpace(unsigned char c) {
  return c == ' ';
}

// CLIP's split of cleaned text into words.
std::vector<std::string_view> split(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t i = 0;
  const auto at = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
  while (i < text.size()) {
    if (isSpace(at(i))) {
      ++i;
      continue;
    }
    std::size_t n = 0;
    for (const std::string_view special : {kStart, kEnd}) {
      if (text.substr(i, special.size()) == special) n = special.size();
    }
    if (n == 0 && text[i] == '\'') {
      for (const std::string_view c : {"'s", "'t", "'re", "'ve", "'m", "'ll", "'d"}) {
        if (text.substr(i, c.size()) == c) n = c.size();
      }
    }
    if (n == 0 && isLetter(at(i))) {
      while (i + n < text.size() && isLetter(at(i + n))) ++n;
    } else if (n == 0 && isDigit(at(i))) {
      n = 1;
    } else if (n == 0) {
      while (i + n < text.size() && !isLetter(at(i + n)) && !isDigit(at(i + n)) && !isSpace(at(i + n))) ++n;
    }
    words.push_back(text.substr(i, n));
    i += n;
  }
  return words;
}

}  // namespace

Result<ClipTokenizer> ClipTokenizer::load(const std::filesystem::path& merges, std::size_t max_merges) {
  auto bytes = io::readFileBytes(merges, io::limits::kTextTable);
  if (!bytes) return Status(bytes.status().code(), bytes.status().message() + " (the CLIP merges file)");
  const bool gzip = bytes->size() >= 2 && (*bytes)[0] == 0x1F && (*bytes)[1] == 0x8B;
  if (!gzip) return parse(std::string(bytes->begin(), bytes->end()), merges.string(), max_merges);
  auto text = inflateGzip(*bytes, merges.string());
  if (!text) return text.status();
  return parse(*text, merges.string(), max_merges);
}

Result<ClipTokenizer> ClipTokenizer::parse(std::string_view text, const std::string& origin, std::size_t max_merges) {
  ClipTokenizer t;
  const auto order = byteOrder();
  t.byte_symbol_.assign(256, {});
  std::vector<std::string> vocab;
  for (const auto& [byte, cp] : order) {
    t.byte_symbol_[static_cast<std::size_t>(byte)] = utf8(cp);
    vocab.push_back(utf8(cp));
  }
  for (std::size_t i = 0; i < 256; ++i) vocab.push_back(vocab[i] + std::string(kWordEnd));
  std::istringstream in{std::string(text)};
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line) && t.ranks_.size() < max_merges) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (number == 1) continue;  // the version line: CLIP drops the first line, whatever it holds
    if (line.empty()) continue;
    const std::size_t space = line.find(' ');
    if (space == std::string::npos || space == 0 || space + 1 == line.size() ||
        line.find(' ', space + 1) != std::string::npos) {
      return parseError(
          fmt::format("{} line {}: '{}' is not a merge (two symbols and one space)", origin, number, line));
    }
    if (t.ranks_.emplace(line, t.ranks_.size()).second) {
      vocab.push_back(line.substr(0, space) + line.substr(space + 1));
    }
  }
  t.start_ = static_cast<std::int64_t>(vocab.size());
  t.end_ = t.start_ + 1;
  for (std::size_t i = 0; i < vocab.size(); ++i) t.ids_.emplace(vocab[i], static_cast<std::int64_t>(i));
  return t;
}

void ClipTokenizer::encodeWord(std::string_view word, std::vector<std::int64_t>& out) const {
  if (word == kStart || word == kEnd) {
    out.push_back(word == kStart ? start_ : end_);
    return;
  }
  std::vector<std::string> symbols;
  for (const char c : word) symbols.push_back(byte_symbol_[static_cast<unsigned char>(c)]);
  if (symbols.empty()) return;
  symbols.back() += kWordEnd;
  // CLIP's bpe(): merge the best-ranked adjacent pair, every occurrence left to right, until none ranks.
  while (symbols.size() > 1) {
    std::size_t best = std::numeric_limits<std::size_t>::max();
    std::string pair;
    for (std::size_t i = 0; i + 1 < symbols.size(); ++i) {
      const auto r = ranks_.find(symbols[i] + " " + symbols[i + 1]);
      if (r != ranks_.end() && r->second < best) {
        best = r->second;
        pair = r->first;
      }
    }
    if (best == std::numeric_limits<std::size_t>::max()) break;
    const std::string first = pair.substr(0, pair.find(' '));
    const std::string second = pair.substr(pair.find(' ') + 1);
    std::vector<std::string> merged;
    for (std::size_t i = 0; i < symbols.size();) {
      if (i + 1 < symbols.size() && symbols[i] == first && symbols[i + 1] == second) {
        merged.push_back(first + second);
        i += 2;
      } else {
        merged.push_back(symbols[i++]);
      }
    }
    symbols = std::move(merged);
  }
  for (const std::string& s : symbols) {
    const auto id = ids_.find(s);
    if (id != ids_.end()) out.push_back(id->second);
  }
}

std::vector<std::int64_t> ClipTokenizer::encode(std::string_view text) const {
  std::vector<std::int64_t> out;
  const std::string cleaned = clean(text);
  for (const std::string_view word : split(cleaned)) encodeWord(word, out);
  return out;
}

std::vector<std::int64_t> ClipTokenizer::tokens(std::string_view text, std::size_t context) const {
  std::vector<std::int64_t> out{start_};
  const std::vector<std::int64_t> body = encode(text);
  out.insert(out.end(), body.begin(), body.end());
  out.push_back(end_);
  if (context < 2) context = 2;
  if (out.size() > context) {
    out.resize(context);
    out.back() = end_;
  }
  out.resize(context, 0);
  return out;
}

}  // namespace artemis::semantics
