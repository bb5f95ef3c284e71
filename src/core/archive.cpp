#include "artemis/core/archive.hpp"

namespace artemis {

namespace {

constexpr std::uint64_t kPrime = 0x100000001b3ull;
constexpr std::uint64_t kSeed = 0xcbf29ce484222325ull;

// One chunk's FNV-1a over 64-bit words, then its last bytes, continuing from `h`.
std::uint64_t hashChunk(std::uint64_t h, std::span<const std::byte> chunk) {
  std::size_t k = 0;
  for (; k + 8 <= chunk.size(); k += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, chunk.data() + k, 8);
    h = (h ^ word) * kPrime;
  }
  for (; k < chunk.size(); ++k) h = (h ^ static_cast<std::uint64_t>(chunk[k])) * kPrime;
  return h;
}

std::uint64_t finalMix(std::uint64_t h, std::uint64_t size) {
  h ^= size;
  h ^= h >> 33;
  return h * 0xff51afd7ed558ccdull;
}

}  // namespace

void ArchiveWriter::emit() {
  checksum_ = hashChunk(emitted_ == 0 ? kSeed : checksum_, buffer_);
  emitted_ += buffer_.size();
  sink_(buffer_);
  buffer_.clear();
}

std::uint64_t ArchiveWriter::checksum() const {
  if (sink_) return finalMix(emitted_ == 0 ? kSeed : checksum_, emitted_);
  return archiveChecksum(buffer_);
}

std::uint64_t archiveChecksum(std::span<const std::byte> bytes) {
  std::uint64_t h = kSeed;
  for (std::size_t at = 0; at < bytes.size(); at += ArchiveWriter::kChunk) {
    h = hashChunk(h, bytes.subspan(at, std::min(ArchiveWriter::kChunk, bytes.size() - at)));
  }
  return finalMix(h, bytes.size());
}

}  // namespace artemis
