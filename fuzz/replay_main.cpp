// A main for the fuzz targets in trees without libFuzzer (the GCC sanitizer tree, build-asan/): it
// feeds each given file, or each file of each given folder, to the target's LLVMFuzzerTestOneInput
// once, under the sanitizers of the tree. `make test` replays the seed corpus and every saved finding
// this way, so that a bug a finding stands for cannot come back unnoticed; fuzzing itself needs the
// clang tree (make fuzz).
//
//   fuzz_ply [--max-seconds=S] FILE_OR_FOLDER...
//
// An input slower than S seconds (default 2; libFuzzer's limit in the fuzz tree is 1 s) fails the
// replay, as does an argument that holds no input. Allocations over a limit are the sanitizer's to
// refuse (ASAN_OPTIONS=max_allocation_size_mb=1024, as libFuzzer's -malloc_limit_mb).
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);
extern "C" __attribute__((weak)) int LLVMFuzzerInitialize(int* argc, char*** argv);

namespace {

namespace fs = std::filesystem;

// The regular files an argument names: the file itself, or a folder's files in name order.
std::vector<fs::path> inputsOf(const fs::path& arg) {
  std::vector<fs::path> files;
  std::error_code ec;
  if (fs::is_directory(arg, ec)) {
    for (const auto& entry : fs::directory_iterator(arg, ec)) {
      if (entry.is_regular_file(ec)) files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());
  } else if (fs::is_regular_file(arg, ec)) {
    files.push_back(arg);
  }
  return files;
}

bool readAll(const fs::path& path, std::vector<std::uint8_t>& bytes) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return !in.bad();
}

}  // namespace

int main(int argc, char** argv) {
  if (LLVMFuzzerInitialize != nullptr) LLVMFuzzerInitialize(&argc, &argv);
  double max_seconds = 2.0;
  std::vector<fs::path> args;
  for (int i = 1; i < argc; ++i) {
    const std::string_view arg = argv[i];
    if (arg.starts_with("--max-seconds=")) {
      max_seconds = std::strtod(argv[i] + 14, nullptr);
    } else {
      args.emplace_back(arg);
    }
  }
  if (args.empty() || !(max_seconds > 0.0)) {
    std::fprintf(stderr, "usage: %s [--max-seconds=S] FILE_OR_FOLDER...\n", argv[0]);
    return 2;
  }
  int inputs = 0;
  double slowest = 0.0;
  std::string slowest_name;
  std::vector<std::uint8_t> bytes;
  for (const auto& arg : args) {
    const auto files = inputsOf(arg);
    if (files.empty()) {
      std::fprintf(stderr, "replay: %s holds no input file\n", arg.c_str());
      return 1;
    }
    for (const auto& file : files) {
      if (!readAll(file, bytes)) {
        std::fprintf(stderr, "replay: cannot read %s\n", file.c_str());
        return 1;
      }
      // An exact-size copy, as libFuzzer gives: a read past the input's end is ASan's to report.
      const auto input = std::make_unique<std::uint8_t[]>(bytes.size());
      std::copy(bytes.begin(), bytes.end(), input.get());
      const auto start = std::chrono::steady_clock::now();
      LLVMFuzzerTestOneInput(input.get(), bytes.size());
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ++inputs;
      if (seconds > slowest) {
        slowest = seconds;
        slowest_name = file.string();
      }
      if (seconds > max_seconds) {
        std::fprintf(stderr, "replay: %s took %.2f s, over the limit of %.2f s\n", file.c_str(), seconds, max_seconds);
        return 1;
      }
    }
  }
  std::printf("replayed %d inputs; slowest %.3f s (%s)\n", inputs, slowest, slowest_name.c_str());
  return 0;
}
