// PLY writing: the data is checked first (so that a bad PlyData never reaches the disk), then
// streamed through a large buffer into an AtomicFile. ASCII values use std::to_chars, whose
// shortest representation reads back to the identical float or double.

#include <algorithm>
#include <bit>
#include <charconv>
#include <cstring>
#include <limits>

#include "artemis/io/ply.hpp"
#include "file_util.hpp"
#include "ply_detail.hpp"

namespace artemis::io {

namespace {

bool isName(const std::string& name) {
  return !name.empty() && name.find_first_of(" \t\r\n") == std::string::npos;
}

std::uint64_t maxCount(PlyType count_type) {
  return detail::visitPlyType(count_type, [](auto tag) -> std::uint64_t {
    using C = decltype(tag);
    if constexpr (std::is_integral_v<C>) return static_cast<std::uint64_t>(std::numeric_limits<C>::max());
    return 0;
  });
}

Status checkProperty(const std::string& file, const PlyElement& element, const PlyProperty& property) {
  const std::string where = file + ": " + element.name + " property '" + property.name + "'";
  if (!isName(property.name)) return invalidArgument(where + ": a name must be non-empty, without spaces");
  if (property.values.index() != detail::columnIndex(property.type)) {
    return invalidArgument(where + ": declared " + plyTypeName(property.type) + " but holds " +
                           plyTypeName(static_cast<PlyType>(property.values.index())) + " values");
  }
  const std::size_t values = detail::columnSize(property.values);
  if (!property.is_list) {
    if (values == element.count) return Status::ok();
    return invalidArgument(where + ": " + std::to_string(values) + " values for " + std::to_string(element.count) +
                           " items");
  }
  if (!detail::isIntegerType(property.count_type)) {
    return invalidArgument(where + ": list count type " + plyTypeName(property.count_type) + " is not an integer");
  }
  const auto& offsets = property.list_offsets;
  if (offsets.size() != element.count + 1) {
    return invalidArgument(where + ": " + std::to_string(offsets.size()) + " list offsets for " +
                           std::to_string(element.count) + " items (expected count + 1)");
  }
  if (offsets.front() != 0 || offsets.back() != values) {
    return invalidArgument(where + ": list offsets must run from 0 to the number of values (" + std::to_string(values) +
                           ")");
  }
  const std::uint64_t max_length = maxCount(property.count_type);
  for (std::size_t i = 0; i + 1 < offsets.size(); ++i) {
    if (offsets[i + 1] < offsets[i]) {
      return invalidArgument(where + ": list offsets decrease at item " + std::to_string(i));
    }
    if (offsets[i + 1] - offsets[i] > max_length) {
      return invalidArgument(where + ": item " + std::to_string(i) + " has " +
                             std::to_string(offsets[i + 1] - offsets[i]) + " values, more than a " +
                             plyTypeName(property.count_type) + " count can hold");
    }
  }
  return Status::ok();
}

Status checkData(const std::string& file, const PlyData& data) {
  for (const auto& comment : data.comments) {
    if (comment.find_first_of("\r\n") != std::string::npos) {
      return invalidArgument(file + ": a comment contains a line break");
    }
  }
  for (const auto& element : data.elements) {
    if (!isName(element.name)) {
      return invalidArgument(file + ": element name '" + element.name + "' must be non-empty, without spaces");
    }
    for (const auto& property : element.properties) {
      if (Status status = checkProperty(file, element, property); !status.isOk()) return status;
    }
  }
  return Status::ok();
}

// A property seen as raw bytes, so that the per-value loop needs no type dispatch.
struct RawColumn {
  const unsigned char* values = nullptr;
  std::size_t size = 0;  // bytes per value
  const PlyProperty* property = nullptr;
  char* (*format)(char*, const unsigned char*) = nullptr;  // ASCII text of one value
  char* (*format_count)(char*, std::uint32_t) = nullptr;   // ASCII list length
};

template <typename T>
char* formatValue(char* out, const unsigned char* source) {
  T value;
  std::memcpy(&value, source, sizeof(T));
  return std::to_chars(out, out + 32, value).ptr;
}

char* formatCount(char* out, std::uint32_t count) {
  return std::to_chars(out, out + 16, count).ptr;
}

RawColumn rawColumn(const PlyProperty& property) {
  RawColumn raw;
  raw.property = &property;
  raw.size = plyTypeSize(property.type);
  raw.values =
      std::visit([](const auto& v) { return reinterpret_cast<const unsigned char*>(v.data()); }, property.values);
  raw.format = detail::visitPlyType(property.type, [](auto tag) { return &formatValue<decltype(tag)>; });
  raw.format_count = &formatCount;
  return raw;
}

class BodyWriter {
 public:
  explicit BodyWriter(detail::AtomicFile& file) : file_(file) { buffer_.reserve(kFlushAt + 4096); }

  Status writeBinary(const PlyElement& element) {
    const auto columns = rawColumns(element);
    for (std::size_t item = 0; item < element.count && status_.isOk(); ++item) {
      for (const auto& column : columns) {
        if (!column.property->is_list) {
          append(column.values + item * column.size, column.size);
          continue;
        }
        const auto& offsets = column.property->list_offsets;
        appendCount(column.property->count_type, offsets[item + 1] - offsets[item]);
        append(column.values + std::size_t{offsets[item]} * column.size,
               std::size_t{offsets[item + 1] - offsets[item]} * column.size, column.size);
      }
      if (buffer_.size() >= kFlushAt) flush();
    }
    return status_;
  }

  Status writeAscii(const PlyElement& element) {
    const auto columns = rawColumns(element);
    char text[64];
    for (std::size_t item = 0; item < element.count && status_.isOk(); ++item) {
      bool first = true;
      auto put = [&](char* stop) {
        if (!first) buffer_.push_back(' ');
        buffer_.append(text, static_cast<std::size_t>(stop - text));
        first = false;
      };
      for (const auto& column : columns) {
        std::size_t begin = item;
        std::size_t end = item + 1;
        if (column.property->is_list) {
          begin = column.property->list_offsets[item];
          end = column.property->list_offsets[item + 1];
          put(column.format_count(text, static_cast<std::uint32_t>(end - begin)));
        }
        for (std::size_t i = begin; i < end; ++i) put(column.format(text, column.values + i * column.size));
      }
      buffer_.push_back('\n');
      if (buffer_.size() >= kFlushAt) flush();
    }
    return status_;
  }

  Status finish() {
    flush();
    return status_;
  }

 private:
  static constexpr std::size_t kFlushAt = std::size_t{1} << 22;

  static std::vector<RawColumn> rawColumns(const PlyElement& element) {
    std::vector<RawColumn> columns;
    for (const auto& property : element.properties) columns.push_back(rawColumn(property));
    return columns;
  }

  // PLY binary is little-endian: values are copied as they are on a little-endian host, and
  // reversed value by value on a big-endian one.
  void append(const unsigned char* bytes, std::size_t total, std::size_t value_size = 0) {
    const std::size_t from = buffer_.size();
    buffer_.append(reinterpret_cast<const char*>(bytes), total);
    if constexpr (std::endian::native == std::endian::big) {
      const std::size_t size = value_size == 0 ? total : value_size;
      for (std::size_t i = from; size > 1 && i + size <= buffer_.size(); i += size) {
        std::reverse(buffer_.begin() + static_cast<std::ptrdiff_t>(i),
                     buffer_.begin() + static_cast<std::ptrdiff_t>(i + size));
      }
    }
  }

  void appendCount(PlyType count_type, std::uint32_t count) {
    detail::visitPlyType(count_type, [&](auto tag) {
      const auto value = static_cast<decltype(tag)>(count);  // fits: checked by checkProperty
      append(reinterpret_cast<const unsigned char*>(&value), sizeof(value));
    });
  }

  void flush() {
    if (status_.isOk() && !buffer_.empty()) status_ = file_.write(buffer_.data(), buffer_.size());
    buffer_.clear();
  }

  detail::AtomicFile& file_;
  std::string buffer_;
  Status status_;
};

}  // namespace

std::string plyHeaderText(const PlyData& data) {
  std::string text = "ply\nformat ";
  text += data.format == PlyFormat::kAscii ? "ascii" : "binary_little_endian";
  text += " 1.0\n";
  for (const auto& comment : data.comments) text += "comment " + comment + "\n";
  for (const auto& element : data.elements) {
    text += "element " + element.name + " " + std::to_string(element.count) + "\n";
    for (const auto& property : element.properties) {
      text += "property ";
      if (property.is_list) text += std::string("list ") + plyTypeName(property.count_type) + " ";
      text += std::string(plyTypeName(property.type)) + " " + property.name + "\n";
    }
  }
  text += "end_header\n";
  return text;
}

Status writePly(const std::filesystem::path& path, const PlyData& data) {
  const std::string file = path.string();
  if (Status status = checkData(file, data); !status.isOk()) return status;
  detail::AtomicFile out;
  if (Status status = out.open(path); !status.isOk()) return status;
  const std::string header = plyHeaderText(data);
  if (Status status = out.write(header.data(), header.size()); !status.isOk()) return status;
  BodyWriter body(out);
  for (const auto& element : data.elements) {
    Status status = data.format == PlyFormat::kAscii ? body.writeAscii(element) : body.writeBinary(element);
    if (!status.isOk()) return status;
  }
  if (Status status = body.finish(); !status.isOk()) return status;
  return out.commit();
}

}  // namespace artemis::io
