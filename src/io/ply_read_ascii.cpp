// The ASCII PLY body: one item per line, values parsed with std::from_chars into the declared
// type. Counts are checked both ways: too few lines or values, and data left over, are errors.

#include <charconv>
#include <string_view>
#include <type_traits>

#include "ply_detail.hpp"

namespace artemis::io::detail {

namespace {

bool isSpace(char c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
}

// Next whitespace-separated word of `rest` (empty when none), consuming it.
std::string_view nextWord(std::string_view& rest) {
  std::size_t start = 0;
  while (start < rest.size() && isSpace(rest[start])) ++start;
  std::size_t stop = start;
  while (stop < rest.size() && !isSpace(rest[stop])) ++stop;
  const std::string_view word = rest.substr(start, stop - start);
  rest.remove_prefix(stop);
  return word;
}

// The whole word must be a value of T in range; a leading '+' is allowed.
template <typename T>
bool parseWord(std::string_view word, T& value) {
  const char* first = word.data();
  const char* last = word.data() + word.size();
  if (first != last && *first == '+') {
    ++first;
    if (first != last && (*first == '+' || *first == '-')) return false;
  }
  if (first == last) return false;
  std::from_chars_result result{};
  if constexpr (std::is_floating_point_v<T>) {
    result = std::from_chars(first, last, value, std::chars_format::general);
  } else {
    result = std::from_chars(first, last, value);
  }
  return result.ec == std::errc{} && result.ptr == last;
}

class AsciiReader {
 public:
  AsciiReader(const char* begin, const char* end, std::size_t first_line, const std::string& file)
      : pos_(begin), end_(end), next_line_no_(first_line), file_(file) {}

  Status read(PlyElement& element) {
    if (element.properties.empty()) return Status::ok();
    // Each item takes at least two bytes (a value and a line end): a bound on what to reserve.
    const std::size_t bound = static_cast<std::size_t>(end_ - pos_) / 2 + 1;
    const std::size_t reserve = element.count < bound ? element.count : bound;
    for (auto& property : element.properties) {
      if (property.is_list) {
        property.list_offsets.reserve(reserve + 1);
      } else {
        std::visit([reserve](auto& values) { values.reserve(reserve); }, property.values);
      }
    }
    for (std::size_t item = 0; item < element.count; ++item) {
      if (!nextLine()) {
        return parseError(file_ + ": truncated: expected " + std::to_string(element.count) + " " + element.name +
                          " lines, found " + std::to_string(item));
      }
      for (auto& property : element.properties) {
        Status status = property.is_list ? readList(element, item, property) : readScalar(element, item, property);
        if (!status.isOk()) return status;
      }
      if (!nextWord(line_).empty()) {
        return error(element, item,
                     "more values than its " + std::to_string(element.properties.size()) +
                         " properties (the header declares fewer?)");
      }
    }
    return Status::ok();
  }

  // Called after the last element: anything but blank lines is data the header does not declare.
  Status checkEnd(const PlyData& data) {
    if (!nextLine()) return Status::ok();
    const std::string last = data.elements.empty() ? std::string("none") : data.elements.back().name;
    return parseError(file_ + " line " + std::to_string(line_no_) +
                      ": data after the last element (the header declares fewer items than the file has; "
                      "last element: " +
                      last + ")");
  }

 private:
  // Moves to the next non-blank line; false at the end of the data.
  bool nextLine() {
    while (pos_ < end_) {
      const char* stop = pos_;
      while (stop < end_ && *stop != '\n') ++stop;
      line_ = std::string_view(pos_, static_cast<std::size_t>(stop - pos_));
      line_no_ = next_line_no_++;
      pos_ = stop < end_ ? stop + 1 : end_;
      std::string_view probe = line_;
      if (!nextWord(probe).empty()) return true;
    }
    return false;
  }

  Status error(const PlyElement& element, std::size_t item, const std::string& problem) const {
    return parseError(file_ + " line " + std::to_string(line_no_) + ": " + element.name + " " + std::to_string(item) +
                      ": " + problem);
  }

  template <typename T>
  Status parseValue(const PlyElement& element, std::size_t item, const PlyProperty& property, PlyType type, T& value) {
    const std::string_view word = nextWord(line_);
    if (word.empty()) return error(element, item, "too few values (missing '" + property.name + "')");
    if (!parseWord(word, value)) {
      return error(element, item,
                   std::string("bad ") + plyTypeName(type) + " value '" + std::string(word) + "' for property '" +
                       property.name + "'");
    }
    return Status::ok();
  }

  Status readScalar(const PlyElement& element, std::size_t item, PlyProperty& property) {
    return visitPlyType(property.type, [&](auto tag) {
      using T = decltype(tag);
      T value{};
      Status status = parseValue(element, item, property, property.type, value);
      if (status.isOk()) std::get<std::vector<T>>(property.values).push_back(value);
      return status;
    });
  }

  Status readList(const PlyElement& element, std::size_t item, PlyProperty& property) {
    std::uint32_t length = 0;
    Status status = visitPlyType(property.count_type, [&](auto tag) {
      using C = decltype(tag);
      C count{};
      Status parsed = parseValue(element, item, property, property.count_type, count);
      if (!parsed.isOk()) return parsed;
      // Count types are integers of at most 32 bits (checked in the header): only the sign can be wrong.
      if constexpr (std::is_signed_v<C>) {
        if (count < 0) return error(element, item, "negative list length for '" + property.name + "'");
      }
      // NOLINTNEXTLINE(bugprone-signed-char-misuse): a negative int8 count was rejected just above.
      length = static_cast<std::uint32_t>(count);
      return parsed;
    });
    if (!status.isOk()) return status;
    const std::size_t total = columnSize(property.values) + length;
    if (total > 0xFFFFFFFFu) return error(element, item, "more than 2^32 - 1 list values in all");
    status = visitPlyType(property.type, [&](auto tag) {
      using T = decltype(tag);
      auto& values = std::get<std::vector<T>>(property.values);
      for (std::uint32_t i = 0; i < length; ++i) {
        T value{};
        Status parsed = parseValue(element, item, property, property.type, value);
        if (!parsed.isOk()) return parsed;
        values.push_back(value);
      }
      return Status::ok();
    });
    if (!status.isOk()) return status;
    property.list_offsets.push_back(static_cast<std::uint32_t>(total));
    return Status::ok();
  }

  const char* pos_;
  const char* end_;
  std::size_t next_line_no_;
  std::size_t line_no_ = 0;
  std::string_view line_;
  const std::string& file_;
};

}  // namespace

Status readPlyAsciiBody(const char* begin, const char* end, std::size_t first_line, const std::string& file,
                        PlyData& data) {
  AsciiReader reader(begin, end, first_line, file);
  for (auto& element : data.elements) {
    if (Status status = reader.read(element); !status.isOk()) return status;
  }
  return reader.checkEnd(data);
}

}  // namespace artemis::io::detail
