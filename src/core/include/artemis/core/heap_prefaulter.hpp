#pragma once
// The heap's pages, provided ahead of the thread that maps (see prefault.hpp). A frame's new voxels
// and faces take their arrays from the main thread's heap, 4-16 MB a KITTI frame, each new 2 MB
// huge page zeroed by the kernel on its first write: on a 2-core virtual machine that was about 6 ms
// of the mapping thread's time a frame, while the other core often idled. A HeapPrefaulter keeps a
// thread that, when asked, provides the pages at the top of that heap, at idle priority (it takes a
// core only when no other thread wants it) and without anyone waiting for it: a page it has not
// reached yet is faulted in by its writer, as without it.

#include <condition_variable>
#include <cstddef>
#include <mutex>
#include <thread>

namespace artemis {

class HeapPrefaulter {
 public:
  // `bytes`: how far past the heap's last allocation to provide pages at each request.
  explicit HeapPrefaulter(std::size_t bytes);
  ~HeapPrefaulter();  // stops and joins the thread (after the range it is at, if any)
  HeapPrefaulter(const HeapPrefaulter&) = delete;
  HeapPrefaulter& operator=(const HeapPrefaulter&) = delete;

  // Asks for the room ahead to be provided; returns at once. Requests made while one is served
  // merge into one. Does nothing where the heap's top is unknown (not glibc).
  void request();

 private:
  void serve();

  std::size_t bytes_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool pending_ = false;
  bool stop_ = false;
  std::thread thread_;  // last: started once the rest is in place
};

}  // namespace artemis
