#pragma once
// The viewer's HTTP server (cpp-httplib, kept inside server.cpp): the page and its scripts, three.js
// from the viewer's npm packages, the scene (GET /api/info, GET /api/blocks?since=V), queries
// (GET /api/query?q=...), and the run folder's outputs (GET /run/<file>). Nothing else: every file
// path is resolved under its root and refused when it would leave it, and requests, queries and
// URIs have a size cap. It binds to 127.0.0.1 unless told otherwise.

#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "artemis/core/status.hpp"
#include "scene.hpp"

namespace artemis::viewer {

struct ServerParams {
  std::string host = "127.0.0.1";
  int port = 8080;                // 0: any free port
  std::filesystem::path assets;   // the viewer folder: index.html, app.js, style.css, node_modules/three
  std::filesystem::path run_dir;  // served under /run/ (empty: nothing)
  std::size_t max_query_bytes = 1000;
};

// Answers a query typed in the page: {"query", "matched": [{"id", "name", "rgb"}], "message", ...}.
// Errors (a malformed query) become HTTP 400 with {"error": message}.
using QueryFn = std::function<Result<nlohmann::json>(const std::string& query)>;

class Server {
 public:
  Server(const Scene& scene, ServerParams params, QueryFn query);
  ~Server();
  Server(const Server&) = delete;
  Server& operator=(const Server&) = delete;

  // Binds and serves on a thread of its own; returns the port. Errors: the assets folder lacks
  // index.html or three.js (with the set-up command that installs it), the port is taken.
  Result<int> start();
  void stop();
  [[nodiscard]] std::string url() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// The regular file that `relative` (a request path below a route, already URL-decoded) names
// under `root`, or nothing when it is empty, absolute, has a "..", ".", hidden or empty segment, a
// backslash or NUL, or resolves (through links) outside `root`.
std::optional<std::filesystem::path> resolveUnder(const std::filesystem::path& root, std::string_view relative);

// Where the viewer's assets are: $ARTEMIS_VIEWER_DIR, else the source tree's viewer/ folder (the
// build knows it), else <prefix>/share/artemis/viewer beside the installed program.
std::filesystem::path defaultAssetsDir();

}  // namespace artemis::viewer
