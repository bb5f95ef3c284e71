#include "bag_structure.hpp"

#include <bzlib.h>
#include <roslz4/lz4s.h>
#include <sys/stat.h>
#include <time.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <span>
#include <string>
#include <tuple>
#include <vector>

namespace artemis::datasets::detail {

namespace fs = std::filesystem;

namespace {

enum Op : std::uint8_t {
  kMessageData = 0x02,
  kBagHeader = 0x03,
  kIndexData = 0x04,
  kChunk = 0x05,
  kChunkInfo = 0x06,
  kConnection = 0x07
};
constexpr std::uint64_t kMaxHeaderBytes = 1 << 20;    // record headers hold a few short fields
constexpr std::uint64_t kMaxChunkBytes = 1ULL << 28;  // 256 MiB: recorders close chunks near 768 KiB

using Bytes = std::vector<std::uint8_t>;
constexpr const char* kEndsInside = "the file ends inside this record";
using Fields = std::map<std::string, std::string, std::less<>>;

std::uint32_t u32At(std::span<const std::uint8_t> b, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, b.data() + at, sizeof v);
  return v;
}

// A record header's (or a connection header's) fields: a 4-byte length, then "name=value".
Result<Fields> parseFields(std::span<const std::uint8_t> bytes) {
  Fields fields;
  for (std::size_t at = 0; at < bytes.size();) {
    if (bytes.size() - at < 4) return parseError("a header field's length is cut off");
    const std::uint32_t n = u32At(bytes, at);
    at += 4;
    if (n > bytes.size() - at) return parseError("a header field of " + std::to_string(n) + " bytes runs past it");
    const std::string field(reinterpret_cast<const char*>(bytes.data() + at), n);
    at += n;
    const auto eq = field.find('=');
    if (eq == std::string::npos) return parseError("a header field without '='");
    fields[field.substr(0, eq)] = field.substr(eq + 1);
  }
  return fields;
}

// A field the library reads as a number: present, and exactly as wide.
template <typename T>
Result<T> number(const Fields& fields, const char* name) {
  const auto it = fields.find(name);
  if (it == fields.end()) return parseError(std::string("no \"") + name + "\" field");
  if (it->second.size() != sizeof(T)) {
    return parseError(std::string("field \"") + name + "\" of " + std::to_string(it->second.size()) + " bytes");
  }
  T v{};
  std::memcpy(&v, it->second.data(), sizeof v);
  return v;
}

struct Record {
  std::uint64_t offset = 0;
  std::uint8_t op = 0;
  Fields header;
  std::uint64_t data_offset = 0;
  std::uint32_t data_bytes = 0;
};

// A record at `at` of `bytes` (a whole chunk's records): its header and data fit.
Result<Record> recordIn(std::span<const std::uint8_t> bytes, std::size_t at) {
  Record r;
  r.offset = at;
  if (bytes.size() - at < 4) return parseError("a record's header length is cut off");
  const std::uint32_t header_bytes = u32At(bytes, at);
  if (header_bytes > bytes.size() - at - 4) return parseError("a record header runs past the chunk");
  auto header = parseFields(bytes.subspan(at + 4, header_bytes));
  if (!header) return header.status();
  r.header = std::move(header.value());
  const std::size_t data_at = at + 4 + header_bytes;
  if (bytes.size() - data_at < 4) return parseError("a record's data length is cut off");
  r.data_bytes = u32At(bytes, data_at);
  r.data_offset = data_at + 4;
  if (r.data_bytes > bytes.size() - r.data_offset) return parseError("a record's data runs past the chunk");
  auto op = number<std::uint8_t>(r.header, "op");
  if (!op) return op.status();
  r.op = *op;
  return r;
}

class BagWalk {
 public:
  BagWalk(const fs::path& bag, std::ifstream& in, std::uint64_t size, bool chunks)
      : bag_(bag), in_(in), size_(size), chunks_(chunks) {}

  Status run() {
    // The library reads the version line up to its newline and parses records after it: the
    // first record must start right after exactly this line.
    auto version = readBytes(0, std::min<std::uint64_t>(size_, 13));
    if (!version || version->size() != 13 || std::memcmp(version->data(), "#ROSBAG V2.0\n", 13) != 0) {
      return error(0, "the version line is not \"#ROSBAG V2.0\" and a newline");
    }
    std::vector<Record> records;
    for (std::uint64_t at = 13; at < size_;) {
      auto r = readRecord(at);
      if (!r && r.status().message() == kEndsInside) {
        return parseError(bag_.string() + ": the bag ends early, inside the record at byte " + std::to_string(at) +
                          " (a copy cut short, or a recording that was cut off: `rosbag reindex` repairs that)");
      }
      if (!r) return error(at, r.status().message());
      if (Status s = visit(*r, records.empty()); !s.isOk()) return error(at, s.message());
      at = r->data_offset + r->data_bytes;
      records.push_back(std::move(r.value()));
    }
    if (records.empty()) return error(13, "no bag header record");
    return checkIndex(records);
  }

 private:
  Status error(std::uint64_t at, const std::string& what) const {
    return parseError(bag_.string() + ": a damaged bag at byte " + std::to_string(at) + ": " + what);
  }

  Result<Bytes> readBytes(std::uint64_t at, std::uint64_t n) {
    Bytes out(n);
    in_.clear();
    in_.seekg(static_cast<std::streamoff>(at));
    in_.read(reinterpret_cast<char*>(out.data()), static_cast<std::streamsize>(n));
    if (!in_) return ioError("cannot read " + std::to_string(n) + " bytes");
    return out;
  }

  // A top-level record: its header read and parsed, its data's place (read as needed).
  Result<Record> readRecord(std::uint64_t at) {
    if (size_ - at < 4) return parseError(kEndsInside);
    auto length = readBytes(at, 4);
    if (!length) return length.status();
    const std::uint32_t header_bytes = u32At(*length, 0);
    if (header_bytes > kMaxHeaderBytes)
      return parseError("a record header of " + std::to_string(header_bytes) + " bytes");
    if (header_bytes + 8ULL > size_ - at) return parseError(kEndsInside);
    auto bytes = readBytes(at + 4, header_bytes + 4ULL);
    if (!bytes) return bytes.status();
    auto header = parseFields(std::span(*bytes).first(header_bytes));
    if (!header) return header.status();
    Record r;
    r.offset = at;
    r.header = std::move(header.value());
    r.data_bytes = u32At(*bytes, header_bytes);
    r.data_offset = at + 8 + header_bytes;
    if (r.data_bytes > size_ - r.data_offset) return parseError(kEndsInside);
    auto op = number<std::uint8_t>(r.header, "op");
    if (!op) return op.status();
    r.op = *op;
    return r;
  }

  Status visit(const Record& r, bool first) {
    if (first != (r.op == kBagHeader)) return parseError("the bag header record is not first, or not alone");
    switch (r.op) {
      case kBagHeader: return bagHeader(r);
      case kChunk: return chunk(r);
      case kIndexData: return indexData(r);
      case kConnection: return connection(r);
      case kChunkInfo: return chunkInfo(r);
      default: return parseError("a record of type " + std::to_string(r.op) + " where it cannot be");
    }
  }

  Status bagHeader(const Record& r) {
    auto index = number<std::uint64_t>(r.header, "index_pos");
    auto connections = number<std::uint32_t>(r.header, "conn_count");
    auto chunks = number<std::uint32_t>(r.header, "chunk_count");
    if (!index || !connections || !chunks) return parseError("bag header: a field missing or of the wrong width");
    // An encrypted bag's records are laid out otherwise: this check cannot vouch for them.
    if (const auto e = r.header.find("encryptor"); e != r.header.end() && e->second != "rosbag/NoEncryptor") {
      return parseError("an encrypted bag (\"" + e->second + "\"), which this reader does not take");
    }
    index_pos_ = *index;
    conn_count_ = *connections;
    chunk_count_ = *chunks;
    return Status::ok();
  }

  // Decompressed and walked: connection and message records only, each fitting.
  Status chunk(const Record& r) {
    auto size = number<std::uint32_t>(r.header, "size");
    if (!size) return size.status();
    const auto c = r.header.find("compression");
    if (c == r.header.end()) return parseError("chunk: no compression field");
    if (*size > kMaxChunkBytes || r.data_bytes > kMaxChunkBytes) return parseError("a chunk over 256 MiB");
    chunk_offsets_.insert(r.offset);
    if (!chunks_) {  // the index alone: the chunk's records are read later, with its messages
      if (c->second != "none" && c->second != "bz2" && c->second != "lz4") {
        return parseError("chunk compression \"" + c->second + "\" (none, bz2 or lz4)");
      }
      if (c->second == "none" && *size != r.data_bytes) {
        return parseError("an uncompressed chunk whose size is not its data's");
      }
      return Status::ok();
    }
    auto data = readBytes(r.data_offset, r.data_bytes);
    if (!data) return data.status();
    auto records = decompress(c->second, std::move(data.value()), *size);
    if (!records) return records.status();
    message_offsets_.clear();
    for (std::size_t at = 0; at < records->size();) {
      auto inner = recordIn(*records, at);
      if (!inner) return parseError("in the chunk, at " + std::to_string(at) + ": " + inner.status().message());
      if (inner->op == kMessageData) {
        auto conn = number<std::uint32_t>(inner->header, "conn");
        if (!conn || !number<std::uint64_t>(inner->header, "time")) return parseError("a message record's fields");
        referenced_.insert(*conn);
        message_offsets_.insert(static_cast<std::uint32_t>(at));
      } else if (inner->op == kConnection) {
        if (Status s =
                connectionFields(inner->header, std::span(*records).subspan(inner->data_offset, inner->data_bytes));
            !s.isOk()) {
          return s;
        }
      } else {
        return parseError("a record of type " + std::to_string(inner->op) + " in a chunk");
      }
      at = inner->data_offset + inner->data_bytes;
    }
    return Status::ok();
  }

  static Result<Bytes> decompress(const std::string& compression, Bytes data, std::uint32_t size) {
    if (compression == "none") {
      if (data.size() != size) return parseError("an uncompressed chunk whose size is not its data's");
      return data;
    }
    Bytes out(size);
    unsigned int produced = size;
    bool ok = false;
    if (compression == "bz2") {
      ok = BZ2_bzBuffToBuffDecompress(reinterpret_cast<char*>(out.data()), &produced,
                                      reinterpret_cast<char*>(data.data()), static_cast<unsigned int>(data.size()), 0,
                                      0) == BZ_OK;
    } else if (compression == "lz4") {
      ok = roslz4_buffToBuffDecompress(reinterpret_cast<char*>(data.data()), static_cast<unsigned int>(data.size()),
                                       reinterpret_cast<char*>(out.data()), &produced) == ROSLZ4_OK;
    } else {
      return parseError("chunk compression \"" + compression + "\" (none, bz2 or lz4)");
    }
    if (!ok || produced != size) return parseError("a " + compression + " chunk that does not decompress to its size");
    return out;
  }

  Status connectionFields(const Fields& header, std::span<const std::uint8_t> data) {
    auto conn = number<std::uint32_t>(header, "conn");
    if (!conn || header.find("topic") == header.end()) return parseError("a connection record's fields");
    auto connection_header = parseFields(data);
    if (!connection_header) return parseError("a connection's header: " + connection_header.status().message());
    return Status::ok();
  }

  Status connection(const Record& r) {
    if (r.data_bytes > kMaxHeaderBytes * 16) return parseError("a connection header over 16 MiB");
    auto data = readBytes(r.data_offset, r.data_bytes);
    if (!data) return data.status();
    if (Status s = connectionFields(r.header, *data); !s.isOk()) return s;
    connections_.insert(*number<std::uint32_t>(r.header, "conn"));
    return Status::ok();
  }

  Status indexData(const Record& r) {
    auto version = number<std::uint32_t>(r.header, "ver");
    auto conn = number<std::uint32_t>(r.header, "conn");
    auto count = number<std::uint32_t>(r.header, "count");
    if (!version || !conn || !count || *version != 1) return parseError("an index record's fields");
    if (chunk_offsets_.empty()) return parseError("an index record before any chunk");
    if (static_cast<std::uint64_t>(*count) * 12 != r.data_bytes) return parseError("an index record's count");
    referenced_.insert(*conn);
    auto data = readBytes(r.data_offset, r.data_bytes);
    if (!data) return data.status();
    for (std::uint32_t k = 0; chunks_ && k < *count; ++k) {
      if (!message_offsets_.contains(u32At(*data, 12 * k + 8))) {
        return parseError("an index entry that points at no message of its chunk");
      }
    }
    return Status::ok();
  }

  Status chunkInfo(const Record& r) {
    auto version = number<std::uint32_t>(r.header, "ver");
    auto chunk_pos = number<std::uint64_t>(r.header, "chunk_pos");
    auto count = number<std::uint32_t>(r.header, "count");
    if (!version || !chunk_pos || !count || *version != 1 || !number<std::uint64_t>(r.header, "start_time") ||
        !number<std::uint64_t>(r.header, "end_time")) {
      return parseError("a chunk info record's fields");
    }
    if (static_cast<std::uint64_t>(*count) * 8 != r.data_bytes) return parseError("a chunk info record's count");
    chunk_infos_.push_back(*chunk_pos);
    auto data = readBytes(r.data_offset, r.data_bytes);
    if (!data) return data.status();
    for (std::uint32_t k = 0; k < *count; ++k) referenced_.insert(u32At(*data, 8 * k));
    return Status::ok();
  }

  // The index section: conn_count connections then chunk_count chunk infos, from index_pos to the
  // end; chunk infos that point at chunks; no connection named that is not there.
  Status checkIndex(const std::vector<Record>& records) const {
    if (index_pos_ == 0) return Status::ok();  // unindexed: the library says so
    std::size_t k = 0;
    while (k < records.size() && records[k].offset < index_pos_) ++k;
    if (k == records.size() || records[k].offset != index_pos_) return error(index_pos_, "the index is at no record");
    const std::size_t expected = static_cast<std::size_t>(conn_count_) + chunk_count_;
    if (records.size() - k != expected) return error(index_pos_, "the index does not hold the records it counts");
    for (std::size_t i = 0; i < expected; ++i) {
      const std::uint8_t op = i < conn_count_ ? kConnection : kChunkInfo;
      if (records[k + i].op != op) return error(records[k + i].offset, "a record out of place in the index");
    }
    for (std::uint64_t pos : chunk_infos_) {
      if (!chunk_offsets_.contains(pos)) return error(index_pos_, "a chunk info that points at no chunk");
    }
    for (std::uint32_t conn : referenced_) {
      if (!connections_.contains(conn))
        return error(index_pos_, "connection " + std::to_string(conn) + " is named but not there");
    }
    return Status::ok();
  }

  const fs::path& bag_;
  std::ifstream& in_;
  std::uint64_t size_;
  bool chunks_;  // decompress and walk the chunks too
  std::uint64_t index_pos_ = 0;
  std::uint32_t conn_count_ = 0;
  std::uint32_t chunk_count_ = 0;
  std::set<std::uint64_t> chunk_offsets_;
  std::set<std::uint32_t> message_offsets_;  // of the last chunk
  std::set<std::uint32_t> connections_;
  std::set<std::uint32_t> referenced_;
  std::vector<std::uint64_t> chunk_infos_;
};

}  // namespace

Status checkBagStructure(const fs::path& bag, BagCheck depth) {
  // A file that passed is known by its inode, size and modification and change times (to the
  // nanosecond). One changed within the last 2 s is checked every time: a rewrite within the
  // clock's granularity could keep all four (git's "racy" rule).
  using Key = std::tuple<dev_t, ino_t, off_t, std::int64_t, std::int64_t, bool>;
  static std::mutex mutex;
  static std::set<Key> checked;
  struct stat st {};
  if (::stat(bag.c_str(), &st) != 0) return ioError(bag.string() + ": cannot read its size and times");
  const auto ns = [](const timespec& t) { return static_cast<std::int64_t>(t.tv_sec) * 1'000'000'000 + t.tv_nsec; };
  const bool chunks = depth == BagCheck::kChunks;
  const Key key{st.st_dev, st.st_ino, st.st_size, ns(st.st_mtim), ns(st.st_ctim), chunks};
  Key chunks_key = key;
  std::get<5>(chunks_key) = true;
  {
    const std::lock_guard lock(mutex);
    if (checked.contains(key) || checked.contains(chunks_key)) return Status::ok();  // chunks imply the index
  }
  std::ifstream in(bag, std::ios::binary);
  if (!in) return ioError(bag.string() + ": cannot open");
  if (Status s = BagWalk(bag, in, static_cast<std::uint64_t>(st.st_size), chunks).run(); !s.isOk()) return s;
  timespec now{};
  ::clock_gettime(CLOCK_REALTIME, &now);
  if (ns(now) - std::max(ns(st.st_mtim), ns(st.st_ctim)) < 2'000'000'000) return Status::ok();
  const std::lock_guard lock(mutex);
  if (checked.size() >= 4096) checked.clear();  // a long-lived process reading many bags
  checked.insert(key);
  return Status::ok();
}

}  // namespace artemis::datasets::detail
