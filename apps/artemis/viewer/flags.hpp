#pragma once
// The viewer's command-line settings, shared by `artemis view` and `artemis run --viewer`.

#include <CLI/CLI.hpp>
#include <string>

#include "server.hpp"

namespace artemis::cli {

struct ViewerFlags {
  std::string host = "127.0.0.1";
  int port = 8080;
  std::string assets;  // empty: viewer::defaultAssetsDir()
  double block_m = 3.2;
  std::string flag_prefix;  // set by addViewerFlags: "" (view) or "viewer-" (run)

  [[nodiscard]] viewer::ServerParams serverParams() const {
    viewer::ServerParams p;
    p.host = host;
    p.port = port;
    p.flag_prefix = flag_prefix;
    p.assets = assets.empty() ? viewer::defaultAssetsDir() : std::filesystem::path(assets);
    return p;
  }
};

// Adds --<prefix>host, --<prefix>port, --<prefix>assets (and --block-size for view).
inline void addViewerFlags(CLI::App& cmd, ViewerFlags& flags, const std::string& prefix) {
  flags.flag_prefix = prefix;
  cmd.add_option("--" + prefix + "port", flags.port, "Viewer: TCP port (0: any free port)")
      ->capture_default_str()
      ->check(CLI::Range(0, 65535));
  cmd.add_option("--" + prefix + "host", flags.host,
                 "Viewer: address to listen on; other than 127.0.0.1 (0.0.0.0: every interface) serves the map, "
                 "without a password, to every machine that can reach this one")
      ->capture_default_str();
  cmd.add_option(
      "--" + prefix + "assets", flags.assets,
      "Viewer: folder of its page and three.js (default: $ARTEMIS_VIEWER_DIR, else the source tree's viewer/)");
  if (prefix.empty()) {
    cmd.add_option("--block-size", flags.block_m, "Viewer: edge of the mesh blocks sent to the page (m)")
        ->capture_default_str()
        ->check(CLI::Range(0.5, 1000.0));
  }
}

}  // namespace artemis::cli
