// PLY, binary (either endianness) and ASCII (meshes, clouds, exported runs): readPly. What it
// accepts must survive the round trip the header promises: writePly, then readPly again, gives the
// same elements, properties and values.
#include <cstring>
#include <string>
#include <variant>

#include "artemis/io/ply.hpp"
#include "fuzz_common.hpp"

namespace {

bool sameData(const artemis::io::PlyData& a, const artemis::io::PlyData& b, std::string* why) {
  if (a.elements.size() != b.elements.size()) return *why = "element count", false;
  for (std::size_t e = 0; e < a.elements.size(); ++e) {
    const auto& ea = a.elements[e];
    const auto& eb = b.elements[e];
    if (ea.name != eb.name || ea.count != eb.count || ea.properties.size() != eb.properties.size()) {
      return *why = "element '" + ea.name + "'", false;
    }
    for (std::size_t p = 0; p < ea.properties.size(); ++p) {
      const auto& pa = ea.properties[p];
      const auto& pb = eb.properties[p];
      if (pa.name != pb.name || pa.type != pb.type || pa.is_list != pb.is_list ||
          (pa.is_list && (pa.count_type != pb.count_type || pa.list_offsets != pb.list_offsets))) {
        return *why = "property '" + ea.name + "." + pa.name + "' (name, type or lists)", false;
      }
      // Values compare bit for bit (NaNs included) through their bytes.
      const bool same = std::visit(
          [&](const auto& va) {
            using V = std::decay_t<decltype(va)>;
            const auto* vb = std::get_if<V>(&pb.values);
            return vb != nullptr && va.size() == vb->size() &&
                   (va.empty() || std::memcmp(va.data(), vb->data(), va.size() * sizeof(va[0])) == 0);
          },
          pa.values);
      if (!same) return *why = "values of '" + ea.name + "." + pa.name + "'", false;
    }
  }
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int* /*argc*/, char*** /*argv*/) {
  artemis::fuzz::quietLogs();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace artemis;
  const auto path = fuzz::writeInput(data, size, "mesh.ply");
  auto ply = io::readPly(path);
  if (!ply) return artemis::fuzz::rejected(ply.status());
  // The accessors the mesh readers use.
  (void)ply->scalarAs<float>("vertex", "x");
  (void)ply->scalarAs<double>("vertex", "z");
  (void)ply->scalarAs<std::uint8_t>("vertex", "red");
  // Round trip.
  const auto copy = fuzz::scratchDir() / "copy.ply";
  if (Status s = io::writePly(copy, *ply); !s.isOk()) {
    fuzz::invariantBroken("writePly", "cannot write what readPly read: " + s.message());
  }
  auto again = io::readPly(copy);
  if (!again) fuzz::invariantBroken("readPly", "cannot read what writePly wrote: " + again.status().message());
  std::string why;
  if (!sameData(*ply, *again, &why)) fuzz::invariantBroken("PLY round trip", why + " differ");
  return 0;
}
