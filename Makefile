# Convenience targets around CMake. Everything also works with plain
#   cmake -S . -B <dir> -G Ninja && cmake --build <dir>
.PHONY: build run bench test test-release test-asan install-check lint format clean

JOBS ?= 2
GENERATOR := $(shell command -v ninja >/dev/null 2>&1 && echo "-G Ninja")

# Release tree in build/, the CLI at build/bin/artemis.
build:
	cmake -S . -B build $(GENERATOR) -DCMAKE_BUILD_TYPE=Release
	cmake --build build -j $(JOBS)

# The main job on the built-in default: simulate the demo street (30 frames, KITTI layout), then
# read it back as a user would.
run: build
	build/bin/artemis sim --preset demo --out out/demo --force
	build/bin/artemis dataset info out/demo

# Benchmarks (Release build): they print per-stage figures.
bench: build
	build/bench/sim_bench

# Every test, twice: a Release build with warnings as errors, then an ASan/UBSan build.
test: test-release test-asan

test-release:
	cmake -S . -B build-ci $(GENERATOR) -DCMAKE_BUILD_TYPE=Release -DARTEMIS_WERROR=ON
	cmake --build build-ci -j $(JOBS)
	ctest --test-dir build-ci --output-on-failure -j $(JOBS)

test-asan:
	cmake -S . -B build-asan $(GENERATOR) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DARTEMIS_WERROR=ON -DARTEMIS_SANITIZE=ON
	cmake --build build-asan -j $(JOBS)
	ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
	  ctest --test-dir build-asan --output-on-failure -j $(JOBS)

lint: build
	cmake --build build --target lint

format:
	cmake -S . -B build $(GENERATOR) >/dev/null && cmake --build build --target format

clean:
	rm -rf build build-ci build-asan
