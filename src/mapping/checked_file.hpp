#pragma once
// Internal to the mapping module: the layout of the mapper's own files (tile files, tile state
// files): a magic string naming the kind, a format number, the body's size and checksum, then the
// body (an archive; see artemis/core/archive.hpp). A damaged, truncated or foreign file is refused
// with a message naming it.

#include <cstdint>
#include <filesystem>
#include <span>
#include <string_view>
#include <vector>

#include "artemis/core/archive.hpp"
#include "artemis/core/status.hpp"

namespace artemis::mapping::detail {

struct CheckedFile {
  std::vector<unsigned char> bytes;
  std::size_t body = 0;  // where the body starts
  [[nodiscard]] std::span<const std::byte> bodyBytes() const {
    return std::span<const std::byte>(reinterpret_cast<const std::byte*>(bytes.data()), bytes.size()).subspan(body);
  }
};

// Reads `path` and checks its header; `what` names the kind in errors ("tile file").
Result<CheckedFile> readCheckedFile(const std::filesystem::path& path, std::string_view magic, std::uint32_t version,
                                    std::string_view what);
// The header of a file whose body is `body`.
void writeCheckedHeader(ArchiveWriter& head, std::string_view magic, std::uint32_t version, const ArchiveWriter& body);

}  // namespace artemis::mapping::detail
