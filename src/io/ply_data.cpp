#include <array>
#include <cmath>
#include <limits>
#include <type_traits>

#include "artemis/io/ply.hpp"
#include "ply_detail.hpp"

namespace artemis::io {

namespace {

struct TypeNames {
  PlyType type;
  const char* classic;  // what we write
  const char* sized;    // the other name readers must accept
};

constexpr std::array<TypeNames, 8> kTypeNames{{
    {PlyType::kInt8, "char", "int8"},
    {PlyType::kUInt8, "uchar", "uint8"},
    {PlyType::kInt16, "short", "int16"},
    {PlyType::kUInt16, "ushort", "uint16"},
    {PlyType::kInt32, "int", "int32"},
    {PlyType::kUInt32, "uint", "uint32"},
    {PlyType::kFloat32, "float", "float32"},
    {PlyType::kFloat64, "double", "float64"},
}};

template <typename Items>
auto* findByName(Items& items, const std::string& name) {
  for (auto& item : items) {
    if (item.name == name) return &item;
  }
  return static_cast<decltype(&items.front())>(nullptr);
}

// The property named `name` of `element`, appended when absent (a replaced one keeps its place).
PlyProperty& propertySlot(PlyElement& element, const std::string& name) {
  if (PlyProperty* existing = element.find(name)) {
    *existing = PlyProperty{};
    existing->name = name;
    return *existing;
  }
  element.properties.push_back(PlyProperty{});
  element.properties.back().name = name;
  return element.properties.back();
}

// The element named `name`, created with `count` items when absent; null when it has another count.
PlyElement* elementWithCount(PlyData& data, const std::string& name, std::size_t count) {
  if (PlyElement* element = data.find(name)) return element->count == count ? element : nullptr;
  data.elements.push_back(PlyElement{name, count, {}});
  return &data.elements.back();
}

Status countMismatch(const PlyData& data, const std::string& element, const std::string& property, std::size_t count) {
  return invalidArgument("ply element '" + element + "' has " + std::to_string(data.find(element)->count) +
                         " items, property '" + property + "' has " + std::to_string(count));
}

}  // namespace

const char* plyTypeName(PlyType type) {
  return kTypeNames[detail::columnIndex(type)].classic;
}

std::optional<PlyType> plyTypeFromName(const std::string& name) {
  for (const auto& entry : kTypeNames) {
    if (name == entry.classic || name == entry.sized) return entry.type;
  }
  return std::nullopt;
}

std::size_t plyTypeSize(PlyType type) {
  return detail::visitPlyType(type, [](auto tag) { return sizeof(tag); });
}

const PlyProperty* PlyElement::find(const std::string& property) const {
  return findByName(properties, property);
}
PlyProperty* PlyElement::find(const std::string& property) {
  return findByName(properties, property);
}
const PlyElement* PlyData::find(const std::string& element) const {
  return findByName(elements, element);
}
PlyElement* PlyData::find(const std::string& element) {
  return findByName(elements, element);
}

template <typename T>
Status PlyData::setScalar(const std::string& element, const std::string& property, std::vector<T> values) {
  PlyElement* target = elementWithCount(*this, element, values.size());
  if (target == nullptr) return countMismatch(*this, element, property, values.size());
  PlyProperty& slot = propertySlot(*target, property);
  slot.type = detail::plyTypeOf<T>();
  slot.values = std::move(values);
  return Status::ok();
}

template <typename T>
Status PlyData::setList(const std::string& element, const std::string& property, PlyType count_type,
                        const std::vector<std::vector<T>>& lists) {
  if (!detail::isIntegerType(count_type)) {
    return invalidArgument("ply list '" + property + "': count type " + plyTypeName(count_type) +
                           " is not an integer type");
  }
  std::size_t total = 0;
  for (const auto& list : lists) total += list.size();
  if (total > std::numeric_limits<std::uint32_t>::max()) {
    return invalidArgument("ply list '" + property + "': " + std::to_string(total) +
                           " values in all, more than 2^32 - 1");
  }
  PlyElement* target = elementWithCount(*this, element, lists.size());
  if (target == nullptr) return countMismatch(*this, element, property, lists.size());

  std::vector<T> values;
  values.reserve(total);
  std::vector<std::uint32_t> offsets;
  offsets.reserve(lists.size() + 1);
  offsets.push_back(0);
  for (const auto& list : lists) {
    values.insert(values.end(), list.begin(), list.end());
    offsets.push_back(static_cast<std::uint32_t>(values.size()));
  }
  PlyProperty& slot = propertySlot(*target, property);
  slot.type = detail::plyTypeOf<T>();
  slot.is_list = true;
  slot.count_type = count_type;
  slot.values = std::move(values);
  slot.list_offsets = std::move(offsets);
  return Status::ok();
}

// A floating-point value read as an integer saturates at the integer's range (NaN reads as 0):
// a plain cast of 300.0 to uint8 or 1e10 to int is undefined behaviour (found by fuzzing).
namespace {

template <typename T, typename S>
T convertValue(S value) {
  if constexpr (std::is_floating_point_v<S> && std::is_integral_v<T>) {
    if (std::isnan(value)) return T{0};
    if (value <= static_cast<S>(std::numeric_limits<T>::lowest())) return std::numeric_limits<T>::lowest();
    if (value >= static_cast<S>(std::numeric_limits<T>::max())) return std::numeric_limits<T>::max();
  }
  return static_cast<T>(value);
}

}  // namespace

template <typename T>
Result<std::vector<T>> PlyData::scalarAs(const std::string& element, const std::string& property) const {
  const PlyElement* source = find(element);
  if (source == nullptr) return notFound("ply: no element '" + element + "'");
  const PlyProperty* column = source->find(property);
  if (column == nullptr) return notFound("ply: element '" + element + "' has no property '" + property + "'");
  if (column->is_list) {
    return invalidArgument("ply: property '" + property + "' of element '" + element + "' is a list, not a scalar");
  }
  return std::visit(
      [](const auto& values) {
        std::vector<T> converted(values.size());
        // NOLINTNEXTLINE(bugprone-signed-char-misuse): int8 columns hold numbers; sign extension is intended.
        for (std::size_t i = 0; i < values.size(); ++i) converted[i] = convertValue<T>(values[i]);
        return converted;
      },
      column->values);
}

// NOLINTBEGIN(bugprone-macro-parentheses): T is a type used as a template argument; it cannot be parenthesised.
#define ARTEMIS_PLY_INSTANTIATE(T)                                                               \
  template Status PlyData::setScalar<T>(const std::string&, const std::string&, std::vector<T>); \
  template Status PlyData::setList<T>(const std::string&, const std::string&, PlyType,           \
                                      const std::vector<std::vector<T>>&);                       \
  template Result<std::vector<T>> PlyData::scalarAs<T>(const std::string&, const std::string&) const;
// NOLINTEND(bugprone-macro-parentheses)

ARTEMIS_PLY_INSTANTIATE(std::int8_t)
ARTEMIS_PLY_INSTANTIATE(std::uint8_t)
ARTEMIS_PLY_INSTANTIATE(std::int16_t)
ARTEMIS_PLY_INSTANTIATE(std::uint16_t)
ARTEMIS_PLY_INSTANTIATE(std::int32_t)
ARTEMIS_PLY_INSTANTIATE(std::uint32_t)
ARTEMIS_PLY_INSTANTIATE(float)
ARTEMIS_PLY_INSTANTIATE(double)
#undef ARTEMIS_PLY_INSTANTIATE

PlyData makePlyMesh(const PlyMeshView& mesh) {
  PlyData data;
  const std::size_t vertices = mesh.xyz != nullptr ? mesh.xyz->size() / 3 : 0;
  PlyElement vertex{"vertex", vertices, {}};
  // Columns are built directly rather than through setScalar: a normals or colour array of the
  // wrong length then shows up as a clear count error in writePly instead of vanishing here.
  auto add_triplet = [&vertex](const auto* interleaved, const char* const(&names)[3], PlyType type) {
    if (interleaved == nullptr) return;
    using T = typename std::decay_t<decltype(*interleaved)>::value_type;
    const std::size_t n = interleaved->size() / 3;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      std::vector<T> column(n);
      for (std::size_t i = 0; i < n; ++i) column[i] = (*interleaved)[3 * i + axis];
      vertex.properties.push_back(PlyProperty{names[axis], type, false, PlyType::kUInt8, std::move(column), {}});
    }
  };
  add_triplet(mesh.xyz, {"x", "y", "z"}, PlyType::kFloat32);
  add_triplet(mesh.normals, {"nx", "ny", "nz"}, PlyType::kFloat32);
  add_triplet(mesh.rgb, {"red", "green", "blue"}, PlyType::kUInt8);
  data.elements.push_back(std::move(vertex));

  if (mesh.triangles != nullptr) {
    const std::size_t faces = mesh.triangles->size() / 3;
    // int32 indices, as Open3D and MeshLab expect; the caller keeps indices below 2^31.
    std::vector<std::int32_t> indices(faces * 3);
    std::vector<std::uint32_t> offsets(faces + 1);
    for (std::size_t i = 0; i < faces * 3; ++i) indices[i] = static_cast<std::int32_t>((*mesh.triangles)[i]);
    for (std::size_t f = 0; f <= faces; ++f) offsets[f] = static_cast<std::uint32_t>(3 * f);
    PlyElement face{"face", faces, {}};
    face.properties.push_back(
        PlyProperty{"vertex_indices", PlyType::kInt32, true, PlyType::kUInt8, std::move(indices), std::move(offsets)});
    data.elements.push_back(std::move(face));
  }
  return data;
}

}  // namespace artemis::io
