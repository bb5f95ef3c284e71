#pragma once
// The memory allocator's settings for a mapping process. A mapper touches fresh memory every frame:
// the map grows by megabytes, and per-frame buffers (rendered depth, solver arrays) of megabytes
// are made and freed. With glibc's defaults, buffers above 128 KiB to 32 MiB are mapped from the
// kernel and unmapped again on free, and the heap is trimmed back: each frame faults its buffers
// in anew, page by page. A page fault costs 0.1-0.3 us on bare metal but about 15 us in some
// virtual machines (measured here: 14.5 us a 4 KiB page), where a KITTI frame took 10-30 ms more
// for it (median).
//
// So `artemis run` and the benchmarks start with glibc malloc tunables (GLIBC_TUNABLES, read by
// glibc only at process start, hence a re-execution of the same program with the same arguments
// and process id; other commands are not worth a second start, which loads the program's
// libraries again: about 100 ms on a busy 2-core machine):
//   glibc.malloc.mmap_threshold=32 MiB  buffers up to 32 MiB come from the heap, not the kernel;
//   glibc.malloc.trim_threshold=4 GiB   freed memory stays in the heap for the next frame;
//   glibc.malloc.top_pad=64 MiB        ... on the other threads too. Threads but the main one
//                                     allocate from arenas made of 64 MiB heaps, and glibc unmaps
//                                     a heap (other than an arena's first) once frees leave it
//                                     empty, whatever the trim threshold, unless the pad to keep
//                                     is a heap's size: so the frame reader's scan and image and
//                                     the workers' buffers were faulted in afresh, zeroed page by
//                                     page (a 50-frame KITTI run with huge pages: 28,500 faults,
//                                     4,100 with it; with 4 KiB pages, 12 frames of the demo
//                                     street gave 47,600 faults with it or without);
//   glibc.malloc.hugetlb=1            transparent huge pages for the heap (one fault per 2 MiB
//                                     where the system allows them on request, "madvise"), only
//                                     where a 4 KiB page fault is slow (pageFaultMicros() at least
//                                     kSlowPageFaultUs): there the map's growth costs less in huge
//                                     pages. Where a fault is quick (1.6 us on one 2-core machine),
//                                     huge pages cost more than they save: a 2 MiB page took 0.2 to
//                                     4.4 ms to provide there, 512 small ones 0.8 ms, and a KITTI
//                                     frame took 5-8 ms more with them (median).
// With huge pages peak memory grows by about a tenth (whole huge pages). ARTEMIS_ALLOCATOR=system
// keeps glibc's defaults; GLIBC_TUNABLES that already set any of these are left as they are.

#include <optional>
#include <string>

namespace artemis {

// A 4 KiB page fault's cost above which the heap asks for huge pages (microseconds).
inline constexpr double kSlowPageFaultUs = 5.0;

// The GLIBC_TUNABLES value to run with, given the current one (null: unset), with or without huge
// pages, or nullopt when it already sets one of the four tunables (the user's choice stands).
std::optional<std::string> tunedGlibcTunables(const char* current, bool huge_pages);

// What a first write to a fresh 4 KiB page costs this process (microseconds; the least of a few
// tries over 256 pages of an anonymous mapping, without huge pages), or a negative value when it
// could not be measured.
double pageFaultMicros();

// Re-executes this program with the tunables above when it runs on glibc without them, unless
// ARTEMIS_ALLOCATOR=system or a sanitizer (which replaces malloc) is built in. Returns when it
// does not re-execute (also when the re-execution fails: the program then runs untuned).
void useTunedAllocator(char** argv);

// Whether this process runs with the tunables, and with huge pages (for logs and timing reports).
bool allocatorTuned();
bool allocatorHugePages();

}  // namespace artemis
