#!/usr/bin/env bash
# Installs the Debian 12 packages ARTEMIS builds, tests and runs with.
# Idempotent: packages already present are left alone; safe to run again.
# Usage: scripts/install-deps.sh            (as root, or with sudo available)
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config ccache git
  clang-format clang-tidy
  # fuzzing (make fuzz, make fuzz-smoke): clang with libFuzzer and the sanitizer runtimes
  clang libclang-rt-dev
  # core dependencies (DESIGN.md)
  libeigen3-dev libtbb-dev libcgal-dev libembree-dev libnanoflann-dev
  libstb-dev libpng-dev libdeflate-dev zlib1g-dev libtinygltf-dev libcli11-dev libspdlog-dev libfmt-dev
  nlohmann-json3-dev libcpp-httplib-dev wordnet-dev wordnet-base
  # the dense segmenter: OpenCV's dnn and imgproc modules only (not the full libopencv-dev)
  libopencv-dnn-dev libopencv-imgproc-dev
  # ROS 1 bags without ROS: Debian's rosbag_storage library (bz2 and lz4 chunks), and the message
  # packages' generated C++ types for writing bags that any ROS tool reads
  librosbag-storage-dev libsensor-msgs-dev libnav-msgs-dev libtf2-msgs-dev libgeometry-msgs-dev
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
  # interoperability checks (tests load our files with Open3D, and write ROS bags with Debian's
  # own rosbag Python package)
  python3 python3-numpy python3-open3d
  # the ONNX segmenter's tests write their small models with Debian's onnx package
  python3-onnx
  # build/bench/memory_bench plots memory over the frames (OUT/memory.png)
  python3-matplotlib
  python3-rosbag python3-sensor-msgs python3-geometry-msgs python3-nav-msgs python3-tf2-msgs
  # the browser viewer: Node.js installs three.js and the test tools from npm; the browser tests
  # drive Debian's Chromium
  nodejs chromium
)
# Debian packages npm apart from Node.js; other Node.js builds bring their own.
command -v npm >/dev/null 2>&1 || packages+=(npm)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

# The viewer's npm packages (three.js, and playwright-core and gltf-validator for the tests), as
# pinned in viewer/package-lock.json, into viewer/node_modules; skipped when they are current.
install_npm() {
  local viewer
  viewer="$(cd "$(dirname "$0")/.." && pwd)/viewer"
  if [ -f "$viewer/node_modules/.package-lock.json" ] &&
     [ "$viewer/node_modules/.package-lock.json" -nt "$viewer/package-lock.json" ]; then
    echo "install-deps: viewer npm packages present"
    return 0
  fi
  echo "install-deps: installing the viewer's npm packages"
  npm ci --prefix "$viewer" --no-audit --no-fund --ignore-scripts
}

# ONNX Runtime for `--segmenter onnx`, which loads it at run time (dlopen; ARTEMIS never links it):
# the C API headers and the x86-64 Linux library of ORT 1.29 (MIT), as npm's
# com.github.asus4.onnxruntime ships them, unpacked into third_party/onnxruntime/{include,lib};
# skipped when that version is present. The package (150 MB, every platform) is checked against
# its registry checksum; only the headers, the library and the licence are kept (30 MB).
install_onnxruntime() {
  local root dest version=0.4.9 sha1=3659f34012db8208ffb7f67d704204cb08792fed tmp tgz headers
  root="$(cd "$(dirname "$0")/.." && pwd)"
  dest="$root/third_party/onnxruntime"
  if [ -f "$dest/VERSION" ] && [ "$(cat "$dest/VERSION")" = "$version" ]; then
    echo "install-deps: ONNX Runtime headers and library present"
    return 0
  fi
  if [ "$(uname -m)" != x86_64 ]; then
    echo "install-deps: ONNX Runtime skipped: the package ships an x86-64 Linux library only" >&2
    return 0
  fi
  echo "install-deps: fetching ONNX Runtime (npm com.github.asus4.onnxruntime@$version)"
  tmp="$(mktemp -d)"
  (cd "$tmp" && npm pack --silent "com.github.asus4.onnxruntime@$version" >/dev/null)
  tgz="$tmp/com.github.asus4.onnxruntime-$version.tgz"
  echo "$sha1  $tgz" | sha1sum -c --quiet -
  headers='package/Plugins/iOS~/onnxruntime.xcframework/ios-arm64_x86_64-simulator/onnxruntime.framework/Headers'
  tar xzf "$tgz" -C "$tmp" package/Plugins/Linux/x64/libonnxruntime.so package/LICENSE package/ThirdPartyNotices.txt \
    "$headers"
  rm -rf "$dest"
  mkdir -p "$dest/include" "$dest/lib"
  cp "$tmp/$headers"/*.h "$dest/include/"
  cp "$tmp/package/Plugins/Linux/x64/libonnxruntime.so" "$dest/lib/"
  cp "$tmp/package/LICENSE" "$tmp/package/ThirdPartyNotices.txt" "$dest/"
  echo "$version" >"$dest/VERSION"
  rm -rf "$tmp"
}

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  install_npm
  install_onnxruntime
  exit 0
fi

sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then
  command -v sudo >/dev/null || { echo "install-deps: need root or sudo to install: ${missing[*]}" >&2; exit 1; }
  sudo_cmd=(sudo)
fi

echo "install-deps: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}"
install_npm
install_onnxruntime
echo "install-deps: done"
