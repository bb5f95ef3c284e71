// PLY reading: header parsing and the binary body. The whole file is read into memory once and
// decoded column by column (all-scalar elements) or item by item (elements with lists), with every
// count checked against the bytes that remain before anything is allocated for it.

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <bit>
#include <charconv>
#include <cstring>
#include <limits>
#include <string_view>

#include "artemis/io/ply.hpp"
#include "artemis/io/read_file.hpp"
#include "ply_detail.hpp"

namespace artemis::io {

namespace {

enum class BodyFormat { kAscii, kLittleEndian, kBigEndian };

struct Header {
  PlyData data;
  BodyFormat body = BodyFormat::kLittleEndian;
  std::size_t body_offset = 0;  // first byte after the end_header line
  std::size_t lines = 0;        // header lines, end_header included
};

std::vector<std::string_view> splitWords(std::string_view line) {
  std::vector<std::string_view> words;
  std::size_t pos = 0;
  while (pos < line.size()) {
    const std::size_t start = line.find_first_not_of(" \t", pos);
    if (start == std::string_view::npos) break;
    const std::size_t stop = std::min(line.find_first_of(" \t", start), line.size());
    words.push_back(line.substr(start, stop - start));
    pos = stop;
  }
  return words;
}

class HeaderParser {
 public:
  HeaderParser(const std::string& file, Header& header) : file_(file), header_(header) {}

  // One header line (without its line ending); sets *done on end_header.
  Status parseLine(std::string_view line, std::size_t line_no, bool* done) {
    line_no_ = line_no;
    // A header is text: a control character (a carriage return inside a line, a NUL) is a broken
    // file, and a name or comment holding one could not be written back.
    for (const char c : line) {
      const auto byte = static_cast<unsigned char>(c);
      if ((byte < 0x20 && c != '\t') || byte == 0x7F) {
        return error(fmt::format("control character 0x{:02X} in the header", byte));
      }
    }
    const auto words = splitWords(line);
    if (words.empty()) return Status::ok();
    const std::string_view keyword = words[0];
    if (keyword == "comment") {
      const std::size_t start = line.find("comment") + 7;
      header_.data.comments.emplace_back(start < line.size() ? line.substr(start + 1) : std::string_view{});
      return Status::ok();
    }
    if (keyword == "obj_info") return Status::ok();
    if (keyword == "format") return parseFormat(words);
    if (keyword == "element") return parseElement(words);
    if (keyword == "property") return parseProperty(words);
    if (keyword == "end_header") {
      if (!has_format_) return error("end_header before any format line");
      *done = true;
      return Status::ok();
    }
    return error("unknown header keyword '" + std::string(keyword) + "'");
  }

 private:
  Status error(const std::string& problem) const {
    return parseError(file_ + " line " + std::to_string(line_no_) + ": " + problem);
  }

  Status parseFormat(const std::vector<std::string_view>& words) {
    if (words.size() != 3) return error("expected 'format <type> 1.0'");
    if (words[1] == "ascii") {
      header_.body = BodyFormat::kAscii;
    } else if (words[1] == "binary_little_endian") {
      header_.body = BodyFormat::kLittleEndian;
    } else if (words[1] == "binary_big_endian") {
      header_.body = BodyFormat::kBigEndian;
    } else {
      return error("unknown format '" + std::string(words[1]) + "'");
    }
    if (words[2] != "1.0") return error("unsupported PLY version '" + std::string(words[2]) + "'");
    header_.data.format = header_.body == BodyFormat::kAscii ? PlyFormat::kAscii : PlyFormat::kBinaryLittleEndian;
    has_format_ = true;
    return Status::ok();
  }

  Status parseElement(const std::vector<std::string_view>& words) {
    if (words.size() != 3) return error("expected 'element <name> <count>'");
    std::size_t count = 0;
    const char* last = words[2].data() + words[2].size();
    const auto [ptr, ec] = std::from_chars(words[2].data(), last, count);
    if (ec != std::errc{} || ptr != last) return error("bad element count '" + std::string(words[2]) + "'");
    header_.data.elements.push_back(PlyElement{std::string(words[1]), count, {}});
    return Status::ok();
  }

  Result<PlyType> typeNamed(std::string_view name) const {
    auto type = plyTypeFromName(std::string(name));
    if (!type) return error("unknown property type '" + std::string(name) + "'");
    return *type;
  }

  Status parseProperty(const std::vector<std::string_view>& words) {
    if (header_.data.elements.empty()) return error("property before any element");
    PlyProperty property;
    if (words.size() >= 2 && words[1] == "list") {
      if (words.size() != 5) return error("expected 'property list <count type> <value type> <name>'");
      auto count_type = typeNamed(words[2]);
      if (!count_type) return count_type.status();
      if (!detail::isIntegerType(*count_type)) {
        return error("list count type '" + std::string(words[2]) + "' is not an integer type");
      }
      auto type = typeNamed(words[3]);
      if (!type) return type.status();
      property.is_list = true;
      property.count_type = *count_type;
      property.type = *type;
      property.list_offsets.push_back(0);
    } else {
      if (words.size() != 3) return error("expected 'property <type> <name>'");
      auto type = typeNamed(words[1]);
      if (!type) return type.status();
      property.type = *type;
    }
    property.name = std::string(words.back());
    property.values = detail::makeColumn(property.type);
    header_.data.elements.back().properties.push_back(std::move(property));
    return Status::ok();
  }

  const std::string& file_;
  Header& header_;
  std::size_t line_no_ = 0;
  bool has_format_ = false;
};

Result<Header> parseHeader(const std::vector<unsigned char>& bytes, const std::string& file) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  const auto line_at = [&text](std::size_t pos) {
    const std::size_t stop = text.find('\n', pos);
    std::string_view line = text.substr(pos, stop == std::string_view::npos ? text.size() - pos : stop - pos);
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    return std::pair{line, stop};
  };
  const auto [first, first_stop] = line_at(0);
  if (first != "ply" || first_stop == std::string_view::npos) {
    return parseError(file + ": not a PLY file (it does not start with a 'ply' line)");
  }
  Header header;
  HeaderParser parser(file, header);
  std::size_t pos = first_stop + 1;
  for (std::size_t line_no = 2;; ++line_no) {
    const auto [line, stop] = line_at(pos);
    if (stop == std::string_view::npos && line.empty()) return parseError(file + ": header has no end_header line");
    bool done = false;
    if (Status status = parser.parseLine(line, line_no, &done); !status.isOk()) return status;
    if (done) {
      header.body_offset = stop == std::string_view::npos ? text.size() : stop + 1;
      header.lines = line_no;
      return header;
    }
    if (stop == std::string_view::npos) return parseError(file + ": header has no end_header line");
    pos = stop + 1;
  }
}

template <typename T>
T loadValue(const unsigned char* source, bool swap) {
  std::array<unsigned char, sizeof(T)> raw{};
  std::memcpy(raw.data(), source, sizeof(T));
  if (swap) std::reverse(raw.begin(), raw.end());
  T value;
  std::memcpy(&value, raw.data(), sizeof(T));
  return value;
}

template <typename T>
void swapAll(std::vector<T>& values, std::size_t from) {
  if constexpr (sizeof(T) > 1) {
    for (std::size_t i = from; i < values.size(); ++i) {
      values[i] = loadValue<T>(reinterpret_cast<const unsigned char*>(&values[i]), true);
    }
  }
}

std::string bytesNeeded(std::size_t count, std::size_t row) {
  if (count > std::numeric_limits<std::size_t>::max() / row) {
    return std::to_string(count) + " x " + std::to_string(row);
  }
  return std::to_string(count * row);
}

class BinaryReader {
 public:
  BinaryReader(const unsigned char* begin, const unsigned char* end, bool swap, const std::string& file)
      : pos_(begin), end_(end), swap_(swap), file_(file) {}

  Status read(PlyElement& element) {
    std::size_t min_row = 0;
    bool has_list = false;
    for (const auto& property : element.properties) {
      min_row += plyTypeSize(property.is_list ? property.count_type : property.type);
      has_list = has_list || property.is_list;
    }
    if (min_row == 0 || element.count == 0) return Status::ok();
    const auto left = static_cast<std::size_t>(end_ - pos_);
    if (element.count > left / min_row) {
      return parseError(file_ + ": truncated: expected " + std::string(has_list ? "at least " : "") +
                        bytesNeeded(element.count, min_row) + " bytes of " + element.name + " data, found " +
                        std::to_string(left));
    }
    return has_list ? readItems(element) : readColumns(element, min_row);
  }

 private:
  // All scalar: a fixed row size, so each column is a strided gather over the whole block.
  Status readColumns(PlyElement& element, std::size_t row) {
    std::size_t offset = 0;
    for (auto& property : element.properties) {
      detail::visitPlyType(property.type, [&](auto tag) {
        using T = decltype(tag);
        std::vector<T> column(element.count);
        const unsigned char* source = pos_ + offset;
        if (row == sizeof(T)) {
          std::memcpy(column.data(), source, element.count * sizeof(T));
        } else {
          for (std::size_t i = 0; i < element.count; ++i) std::memcpy(&column[i], source + i * row, sizeof(T));
        }
        if (swap_) swapAll(column, 0);
        property.values = std::move(column);
      });
      offset += plyTypeSize(property.type);
    }
    pos_ += element.count * row;
    return Status::ok();
  }

  Status truncatedAt(const PlyElement& element, std::size_t item, const PlyProperty& property,
                     std::size_t needed) const {
    return parseError(file_ + ": truncated: " + element.name + " " + std::to_string(item) + " property '" +
                      property.name + "' needs " + std::to_string(needed) + " bytes, " + std::to_string(end_ - pos_) +
                      " left");
  }

  // With lists the row size varies: walk item by item, checking each length against what is left.
  Status readItems(PlyElement& element) {
    for (auto& property : element.properties) {
      if (!property.is_list) {
        std::visit([&](auto& values) { values.reserve(element.count); }, property.values);
      } else {
        property.list_offsets.reserve(element.count + 1);
        // Most lists are triangles: reserve for three values each, within what the file can hold.
        const std::size_t fits = static_cast<std::size_t>(end_ - pos_) / plyTypeSize(property.type);
        const std::size_t guess = element.count <= fits / 3 ? element.count * 3 : fits;
        std::visit([guess](auto& values) { values.reserve(guess); }, property.values);
      }
    }
    for (std::size_t item = 0; item < element.count; ++item) {
      for (auto& property : element.properties) {
        Status status = property.is_list ? readList(element, item, property) : readScalar(element, item, property);
        if (!status.isOk()) return status;
      }
    }
    return Status::ok();
  }

  Status readScalar(const PlyElement& element, std::size_t item, PlyProperty& property) {
    const std::size_t size = plyTypeSize(property.type);
    if (static_cast<std::size_t>(end_ - pos_) < size) return truncatedAt(element, item, property, size);
    detail::visitPlyType(property.type, [&](auto tag) {
      using T = decltype(tag);
      std::get<std::vector<T>>(property.values).push_back(loadValue<T>(pos_, swap_));
    });
    pos_ += size;
    return Status::ok();
  }

  Status readList(const PlyElement& element, std::size_t item, PlyProperty& property) {
    const std::size_t count_size = plyTypeSize(property.count_type);
    if (static_cast<std::size_t>(end_ - pos_) < count_size) return truncatedAt(element, item, property, count_size);
    const std::int64_t length = detail::visitPlyType(property.count_type, [&](auto tag) -> std::int64_t {
      return static_cast<std::int64_t>(loadValue<decltype(tag)>(pos_, swap_));
    });
    if (length < 0) {
      return parseError(file_ + ": " + element.name + " " + std::to_string(item) + " property '" + property.name +
                        "': negative list length " + std::to_string(length));
    }
    pos_ += count_size;
    const auto n = static_cast<std::size_t>(length);
    const std::size_t size = plyTypeSize(property.type);
    if (static_cast<std::size_t>(end_ - pos_) / size < n) return truncatedAt(element, item, property, n * size);
    const std::size_t total = detail::columnSize(property.values) + n;
    if (total > std::numeric_limits<std::uint32_t>::max()) {
      return parseError(file_ + ": " + element.name + " property '" + property.name +
                        "': more than 2^32 - 1 list values in all");
    }
    detail::visitPlyType(property.type, [&](auto tag) {
      using T = decltype(tag);
      auto& values = std::get<std::vector<T>>(property.values);
      const std::size_t from = values.size();
      values.resize(from + n);
      if (n != 0) std::memcpy(values.data() + from, pos_, n * sizeof(T));
      if (swap_) swapAll(values, from);
    });
    pos_ += n * size;
    property.list_offsets.push_back(static_cast<std::uint32_t>(total));
    return Status::ok();
  }

  const unsigned char* pos_;
  const unsigned char* end_;
  bool swap_;
  const std::string& file_;
};

}  // namespace

Result<PlyData> readPly(const std::filesystem::path& path) {
  const std::string file = path.string();
  // The header first: a large file that is not a PLY (or whose header is broken) is refused after
  // reading its first bytes, not the whole file.
  constexpr std::size_t kHeaderBytes = std::size_t{1} << 20;
  auto head = readFileHead(path, limits::kMesh, kHeaderBytes);
  if (!head) return head.status();
  if (auto header = parseHeader(*head, file); !header) {
    const bool cut_short =
        head->size() == kHeaderBytes && header.status().message().find("no end_header") != std::string::npos;
    if (!cut_short) return header.status();
    return parseError(file + ": no end_header line in the first 1 MiB");
  }
  auto bytes = readFileBytes(path, limits::kMesh);
  if (!bytes) return bytes.status();
  auto header = parseHeader(*bytes, file);
  if (!header) return header.status();
  PlyData& data = header->data;
  const unsigned char* body = bytes->data() + header->body_offset;
  const unsigned char* end = bytes->data() + bytes->size();

  if (header->body == BodyFormat::kAscii) {
    Status status = detail::readPlyAsciiBody(reinterpret_cast<const char*>(body), reinterpret_cast<const char*>(end),
                                             header->lines + 1, file, data);
    if (!status.isOk()) return status;
    return std::move(data);
  }
  const bool file_little = header->body == BodyFormat::kLittleEndian;
  const bool swap = file_little != (std::endian::native == std::endian::little);
  BinaryReader reader(body, end, swap, file);
  for (auto& element : data.elements) {
    if (Status status = reader.read(element); !status.isOk()) return status;
  }
  return std::move(data);
}

}  // namespace artemis::io
