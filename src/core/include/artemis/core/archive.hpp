#pragma once
// A flat binary form of in-memory state, for checkpoints: values and arrays as their bytes
// (little-endian, this build's layout), with named section tags that the reader checks, so that a
// file from another layout or a truncated one fails with a message naming what was expected where,
// instead of reading garbage. Not a portable exchange format: a checkpoint is read back by the same
// build of ARTEMIS on the same kind of machine (its header says which; see pipeline/checkpoint).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <functional>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "artemis/core/image.hpp"
#include "artemis/core/point_cloud.hpp"
#include "artemis/core/transform.hpp"

namespace artemis {

// Types stored as their bytes: trivially copyable ones, and Eigen's fixed-size matrices of numbers
// (plain arrays of their scalar, though Eigen declares copy constructors).
template <typename T>
concept Bytewise = std::is_trivially_copyable_v<T> || requires {
  typename T::Scalar;
  requires T::SizeAtCompileTime >
  0;
  requires std::is_arithmetic_v<typename T::Scalar>;
  requires sizeof(T) == sizeof(typename T::Scalar) * static_cast<std::size_t>(T::SizeAtCompileTime);
};

// A checkpoint that does not read back: truncated, from another build, or not one at all.
class ArchiveError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Writes into memory (bytes()), or, given a sink, streams through a buffer of kChunk bytes that is
// handed to the sink whenever it is full (and by finish()): a checkpoint of hundreds of MB then
// needs neither that much memory nor the page faults of growing a buffer that large.
class ArchiveWriter {
 public:
  static constexpr std::size_t kChunk = std::size_t{1} << 20;
  using Sink = std::function<void(std::span<const std::byte>)>;

  ArchiveWriter() = default;
  explicit ArchiveWriter(Sink sink) : sink_(std::move(sink)) { buffer_.reserve(kChunk); }

  // A section's name, checked by ArchiveReader::section().
  void section(std::string_view name) { string(name); }

  template <Bytewise T>
  void value(const T& v) {
    raw(&v, sizeof(T));
  }
  template <Bytewise T>
  void array(const std::vector<T>& v) {
    value(static_cast<std::uint64_t>(v.size()));
    raw(v.data(), v.size() * sizeof(T));
  }
  void string(std::string_view s) {
    value(static_cast<std::uint64_t>(s.size()));
    raw(s.data(), s.size());
  }
  void isometry(const Isometry3d& T) { value(Eigen::Matrix4d(T.matrix())); }
  template <typename T>
  void image(const Image<T>& im) {
    value(std::int32_t{im.width()});
    value(std::int32_t{im.height()});
    value(std::int32_t{im.channels()});
    array(im.data());
  }
  void cloud(const PointCloud& c) {
    array(c.points);
    array(c.intensity);
    array(c.labels);
    array(c.time_s);
  }

  // With a sink: hands it what is still buffered.
  void finish() {
    if (sink_ && !buffer_.empty()) emit();
  }
  // Everything written so far (without a sink).
  [[nodiscard]] std::span<const std::byte> bytes() const { return buffer_; }
  // Bytes written so far, and their archiveChecksum() (with a sink: once finish()ed).
  [[nodiscard]] std::uint64_t size() const { return emitted_ + buffer_.size(); }
  [[nodiscard]] std::uint64_t checksum() const;

 private:
  void raw(const void* p, std::size_t n) {
    const auto* b = static_cast<const std::byte*>(p);
    if (!sink_) {
      if (n == 0) return;
      const std::size_t at = buffer_.size();
      buffer_.resize(at + n);  // grows geometrically
      std::memcpy(buffer_.data() + at, b, n);
      return;
    }
    while (n > 0) {
      const std::size_t take = std::min(n, kChunk - buffer_.size());
      buffer_.insert(buffer_.end(), b, b + take);
      b += take;
      n -= take;
      if (buffer_.size() == kChunk) emit();
    }
  }
  void emit();

  Sink sink_;
  std::vector<std::byte> buffer_;
  std::uint64_t emitted_ = 0;
  std::uint64_t checksum_ = 0;  // of the chunks emitted
};

// A checksum of `bytes` that catches a damaged or truncated file (not an attacker), at memory
// speed: FNV-1a over 64-bit words, chunk by chunk of ArchiveWriter::kChunk, with a final mix.
std::uint64_t archiveChecksum(std::span<const std::byte> bytes);

class ArchiveReader {
 public:
  // `source` names the bytes in errors (the file's path).
  ArchiveReader(std::span<const std::byte> bytes, std::string source) : bytes_(bytes), source_(std::move(source)) {}

  // Throws unless the next thing is section `name`.
  void section(std::string_view name) {
    const std::size_t at = at_;
    if (const std::string got = string(64); got != name) {
      fail("expected section '" + std::string(name) + "' at byte " + std::to_string(at) + ", found '" + got + "'");
    }
  }

  template <Bytewise T>
  T value() {
    T v;
    raw(&v, sizeof(T));
    return v;
  }
  template <Bytewise T>
  void value(T& v) {
    v = value<T>();
  }
  template <Bytewise T>
  void array(std::vector<T>& v) {
    const auto n = value<std::uint64_t>();
    if (n > remaining() / (sizeof(T) == 0 ? 1 : sizeof(T)))
      fail("an array of " + std::to_string(n) + " runs past the end");
    v.resize(static_cast<std::size_t>(n));
    raw(v.data(), v.size() * sizeof(T));
  }
  std::string string(std::size_t max_size = std::size_t{1} << 30) {
    const auto n = value<std::uint64_t>();
    if (n > max_size || n > remaining()) fail("a string of " + std::to_string(n) + " bytes runs past the end");
    std::string s(static_cast<std::size_t>(n), '\0');
    raw(s.data(), s.size());
    return s;
  }
  Isometry3d isometry() {
    Isometry3d T;
    T.matrix() = value<Eigen::Matrix4d>();
    return T;
  }
  template <typename T>
  Image<T> image() {
    const auto w = value<std::int32_t>();
    const auto h = value<std::int32_t>();
    const auto c = value<std::int32_t>();
    if (w == 0 && h == 0 && c == 0) {  // a default-made (empty) image
      std::vector<T> none;
      array(none);
      if (!none.empty()) fail("an empty image with pixels");
      return {};
    }
    if (w < 0 || h < 0 || c < 1 || c > 4) {
      fail("an image of " + std::to_string(w) + "x" + std::to_string(h) + "x" + std::to_string(c));
    }
    std::vector<T> data;
    array(data);
    if (data.size() != static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * static_cast<std::size_t>(c)) {
      fail("an image's pixels do not match its size");
    }
    Image<T> im(w, h, c);
    im.data() = std::move(data);
    return im;
  }
  PointCloud cloud() {
    PointCloud c;
    array(c.points);
    array(c.intensity);
    array(c.labels);
    array(c.time_s);
    return c;
  }

  [[nodiscard]] bool atEnd() const { return at_ == bytes_.size(); }
  [[nodiscard]] std::size_t position() const { return at_; }
  [[nodiscard]] std::size_t remaining() const { return bytes_.size() - at_; }
  [[nodiscard]] const std::string& source() const { return source_; }
  [[noreturn]] void fail(const std::string& what) const { throw ArchiveError(source_ + ": " + what); }

 private:
  void raw(void* p, std::size_t n) {
    if (n > remaining()) fail("ends early (truncated at byte " + std::to_string(bytes_.size()) + ")");
    if (n > 0) std::memcpy(p, bytes_.data() + at_, n);
    at_ += n;
  }
  std::span<const std::byte> bytes_;
  std::string source_;
  std::size_t at_ = 0;
};

}  // namespace artemis
