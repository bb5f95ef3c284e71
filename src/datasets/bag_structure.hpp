#pragma once
// A ROS 1 bag's structure, checked before Debian's rosbag_storage reads it. That library trusts
// the file: a record header whose field runs past its end, a chunk that claims gigabytes, an index
// entry that points into the middle of a record or names a connection that does not exist make it
// read past its buffers or allocate without bound (fuzzing found both within a minute). So every
// record the library will parse is walked here first, with every length checked against what
// holds it (format 2.0, http://wiki.ros.org/Bags/Format/2.0):
//
//   - top level, from byte 13 to the end: each record's header and data fit in the file; the bag
//     header record first; its index position is 0 (an unindexed bag, which the library reports)
//     or the offset of a record, from which follow conn_count connection records and chunk_count
//     chunk info records;
//   - record headers: every field fits, holds "name=value", and the fields the library reads as
//     numbers have their exact width; op is a known record type for its place;
//   - chunks: compression none, bz2 or lz4, at most 256 MiB uncompressed, decompressing to exactly
//     the size claimed; inside, only connection and message records, each fitting;
//   - index data after a chunk and chunk infos: counts that match their data; every connection
//     they name exists; every index entry points at the start of a message record of its chunk;
//     every chunk info points at a chunk.
//
// The library reads the index (the bag header, connections, chunk infos, each chunk's header and
// its index records) when it opens a bag, and a chunk's records only when it reads its messages:
// kIndex checks what opening reads (fast: it seeks over the chunks' data), kChunks everything
// (it decompresses every chunk once). A file that passed is remembered (inode, size, modification
// and change times) for the rest of the process, so that a run's several opens check it once;
// one changed in the last 2 s is checked each time.
// The version line must be exactly "#ROSBAG V2.0\n"; encrypted bags are refused.

#include <filesystem>

#include "artemis/core/status.hpp"

namespace artemis::datasets::detail {

enum class BagCheck { kIndex, kChunks };

// Ok, or an error naming the file, the byte offset and what is wrong there.
Status checkBagStructure(const std::filesystem::path& bag, BagCheck depth);

}  // namespace artemis::datasets::detail
