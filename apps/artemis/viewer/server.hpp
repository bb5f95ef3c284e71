#pragma once
// The viewer's HTTP server (cpp-httplib, kept inside server.cpp): the page and its scripts, three.js
// from the viewer's npm packages, the scene (GET /api/info, GET /api/blocks?since=V), queries
// (GET /api/query?q=...), and the run folder's outputs (GET /run/<file>). Nothing else: every file
// path is resolved under its root and refused when it would leave it, and requests, queries and
// URIs have a size cap. It binds to 127.0.0.1 unless told otherwise, and never shares its port
// (no SO_REUSEPORT). Requests whose path or query is not UTF-8 get 400; an exception in a handler
// gets 500 with a generic body (the text goes to the log, never to the client).

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
  std::string flag_prefix;        // messages name --<flag_prefix>port, --<flag_prefix>host
  std::filesystem::path assets;   // the viewer folder: index.html, app.js, style.css, node_modules/three
  std::filesystem::path run_dir;  // served under /run/ (empty: nothing)
  std::size_t max_query_bytes = 1000;
  // Connections. A worker thread serves one connection for as long as it is open, so a client that
  // connects and sends nothing, or half a request, holds a worker until one of these timeouts; the
  // others wait in line. With 32 workers, 20 such clients leave a page's requests a free worker.
  int worker_threads = 32;       // 1 to 256
  int read_timeout_s = 2;        // for each read of a started request (its head, a byte at a time)
  int keep_alive_timeout_s = 2;  // for a connection's first or next request to begin
  int keep_alive_requests = 10;  // requests on one connection before the server closes it
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
  // index.html or three.js (with the set-up command that installs it), the port is taken ("port
  // 8080 is in use (another artemis view?); pick another with --port"), the host is not this
  // machine's, a connection setting is out of range.
  Result<int> start();
  void stop();
  // The address it listens on, as bound (after start()): "http://127.0.0.1:8080/",
  // "http://0.0.0.0:8080/" (every interface), "http://[::1]:8080/".
  [[nodiscard]] std::string url() const;
  // Whether only this machine can connect (a loopback address); false for 0.0.0.0 and the like.
  [[nodiscard]] bool loopbackOnly() const;
  [[nodiscard]] const ServerParams& params() const;

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
