#include "checked_file.hpp"

#include <fmt/format.h>

#include <string>

#include "artemis/io/read_file.hpp"

namespace artemis::mapping::detail {

Result<CheckedFile> readCheckedFile(const std::filesystem::path& path, std::string_view magic, std::uint32_t version,
                                    std::string_view what) {
  auto bytes = io::readFileBytes(path, io::limits::kCheckpoint);
  if (!bytes) return bytes.status();
  CheckedFile f{std::move(*bytes), 0};
  const std::span<const std::byte> all(reinterpret_cast<const std::byte*>(f.bytes.data()), f.bytes.size());
  ArchiveReader in(all, path.string());
  try {
    if (in.string(64) != magic) return parseError(fmt::format("{}: not an ARTEMIS {}", path.string(), what));
    if (const auto found = in.value<std::uint32_t>(); found != version) {
      return invalidArgument(
          fmt::format("{}: a {} of format {}; this version of artemis reads {}", path.string(), what, found, version));
    }
    const auto size = in.value<std::uint64_t>();
    const auto sum = in.value<std::uint64_t>();
    const std::span<const std::byte> body = all.subspan(in.position());
    if (body.size() != size || archiveChecksum(body) != sum) {
      return parseError(
          fmt::format("{}: the {} is damaged (its size or checksum does not match)", path.string(), what));
    }
    f.body = in.position();
  } catch (const ArchiveError& e) {
    return parseError(e.what());
  }
  return f;
}

void writeCheckedHeader(ArchiveWriter& head, std::string_view magic, std::uint32_t version, const ArchiveWriter& body) {
  head.string(magic);
  head.value(version);
  head.value(body.size());
  head.value(archiveChecksum(body.bytes()));
}

}  // namespace artemis::mapping::detail
