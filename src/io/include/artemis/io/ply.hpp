#pragma once
// PLY read and write: binary little-endian and ASCII, any elements, scalar and list properties
// of every PLY type, round-trip exact (values are stored in their declared type, never converted).
// Files we write open in Open3D, CloudCompare, MeshLab and Blender: vertex positions are
// float x, y, z; faces are element "face" with property "list uchar int vertex_indices".

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "artemis/core/status.hpp"

namespace artemis::io {

enum class PlyType { kInt8, kUInt8, kInt16, kUInt16, kInt32, kUInt32, kFloat32, kFloat64 };

// PLY type names: "char"/"int8", "uchar"/"uint8", ..., "float"/"float32", "double"/"float64".
// Writing uses the short classic names (char, uchar, short, ushort, int, uint, float, double).
const char* plyTypeName(PlyType type);
std::optional<PlyType> plyTypeFromName(const std::string& name);
std::size_t plyTypeSize(PlyType type);

// The values of one property over all items of an element, in its declared type.
using PlyColumn = std::variant<std::vector<std::int8_t>, std::vector<std::uint8_t>, std::vector<std::int16_t>,
                               std::vector<std::uint16_t>, std::vector<std::int32_t>, std::vector<std::uint32_t>,
                               std::vector<float>, std::vector<double>>;

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::kFloat32;  // value type (of the list items for a list)
  bool is_list = false;
  PlyType count_type = PlyType::kUInt8;     // list length type
  PlyColumn values;                         // scalar: one per item; list: all items' values concatenated
  std::vector<std::uint32_t> list_offsets;  // list only: item i spans [offsets[i], offsets[i+1]); size = count + 1
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;

  [[nodiscard]] const PlyProperty* find(const std::string& property) const;
  PlyProperty* find(const std::string& property);
};

enum class PlyFormat { kBinaryLittleEndian, kAscii };

struct PlyData {
  PlyFormat format = PlyFormat::kBinaryLittleEndian;  // as read; how write() writes
  std::vector<std::string> comments;
  std::vector<PlyElement> elements;

  [[nodiscard]] const PlyElement* find(const std::string& element) const;
  PlyElement* find(const std::string& element);

  // Adds (or replaces) a scalar property of `element`, creating the element with values.size() items
  // if it does not exist. Fails if the element exists with another count.
  template <typename T>
  Status setScalar(const std::string& element, const std::string& property, std::vector<T> values);

  // Adds (or replaces) a list property; `lists[i]` is item i's list.
  template <typename T>
  Status setList(const std::string& element, const std::string& property, PlyType count_type,
                 const std::vector<std::vector<T>>& lists);

  // Reads a scalar property as T (converted with static_cast from the stored type).
  // Error names the element and property when absent or when it is a list.
  template <typename T>
  Result<std::vector<T>> scalarAs(const std::string& element, const std::string& property) const;
};

// Errors name the file and the problem: missing file, bad header line (with its number),
// unsupported format (binary big endian is read too), truncated data, bad ASCII value.
Result<PlyData> readPly(const std::filesystem::path& path);

// Writes atomically (to a temporary file next to `path`, then renamed), so that a crash never
// leaves a half-written mesh. Checks that every property has `count` values (lists: count + 1 offsets).
Status writePly(const std::filesystem::path& path, const PlyData& data);
// The header writePly writes for `data` (its format, comments, elements' counts and properties;
// the values are not looked at): for writers that stream the body themselves.
std::string plyHeaderText(const PlyData& data);

// Convenience for the common cases: positions (float x y z), optional per-vertex normals
// (float nx ny nz), colours (uchar red green blue), and triangles (face / vertex_indices).
struct PlyMeshView {
  const std::vector<float>* xyz = nullptr;                // 3 per vertex
  const std::vector<float>* normals = nullptr;            // 3 per vertex, optional
  const std::vector<std::uint8_t>* rgb = nullptr;         // 3 per vertex, optional
  const std::vector<std::uint32_t>* triangles = nullptr;  // 3 per face, optional
};
PlyData makePlyMesh(const PlyMeshView& mesh);

}  // namespace artemis::io
