#pragma once
// Private helpers of the PLY reader and writer: mapping between PlyType and C++ types.

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>

#include "artemis/io/ply.hpp"

namespace artemis::io::detail {

// The PlyType of a C++ value type; only the 8 PLY types compile.
template <typename T>
constexpr PlyType plyTypeOf() {
  static_assert(std::is_same_v<T, std::int8_t> || std::is_same_v<T, std::uint8_t> || std::is_same_v<T, std::int16_t> ||
                    std::is_same_v<T, std::uint16_t> || std::is_same_v<T, std::int32_t> ||
                    std::is_same_v<T, std::uint32_t> || std::is_same_v<T, float> || std::is_same_v<T, double>,
                "not a PLY value type");
  if (std::is_same_v<T, std::int8_t>) return PlyType::kInt8;
  if (std::is_same_v<T, std::uint8_t>) return PlyType::kUInt8;
  if (std::is_same_v<T, std::int16_t>) return PlyType::kInt16;
  if (std::is_same_v<T, std::uint16_t>) return PlyType::kUInt16;
  if (std::is_same_v<T, std::int32_t>) return PlyType::kInt32;
  if (std::is_same_v<T, std::uint32_t>) return PlyType::kUInt32;
  if (std::is_same_v<T, float>) return PlyType::kFloat32;
  return PlyType::kFloat64;
}

// Calls f(T{}) where T is the C++ type of `type`: one switch, then typed code.
template <typename F>
decltype(auto) visitPlyType(PlyType type, F&& f) {
  switch (type) {
    case PlyType::kInt8: return std::forward<F>(f)(std::int8_t{});
    case PlyType::kUInt8: return std::forward<F>(f)(std::uint8_t{});
    case PlyType::kInt16: return std::forward<F>(f)(std::int16_t{});
    case PlyType::kUInt16: return std::forward<F>(f)(std::uint16_t{});
    case PlyType::kInt32: return std::forward<F>(f)(std::int32_t{});
    case PlyType::kUInt32: return std::forward<F>(f)(std::uint32_t{});
    case PlyType::kFloat32: return std::forward<F>(f)(float{});
    case PlyType::kFloat64: break;
  }
  return std::forward<F>(f)(double{});
}

// The variant alternatives of PlyColumn are in PlyType order.
inline std::size_t columnIndex(PlyType type) {
  return static_cast<std::size_t>(type);
}

inline PlyColumn makeColumn(PlyType type) {
  return visitPlyType(type, [](auto tag) { return PlyColumn(std::vector<decltype(tag)>{}); });
}

inline std::size_t columnSize(const PlyColumn& column) {
  return std::visit([](const auto& values) { return values.size(); }, column);
}

inline bool isIntegerType(PlyType type) {
  return type != PlyType::kFloat32 && type != PlyType::kFloat64;
}

}  // namespace artemis::io::detail

namespace artemis::io::detail {

// Fills the (empty, typed) columns of `data` from the ASCII body [begin, end); the body's first
// line is line `first_line` of `file`. Checks every count against the data; never reads past end.
Status readPlyAsciiBody(const char* begin, const char* end, std::size_t first_line, const std::string& file,
                        PlyData& data);

}  // namespace artemis::io::detail
