// cpp-httplib stays in this file: it pulls <resolv.h>, whose macros break code that follows.
#include "server.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <chrono>
#include <cstdlib>
#include <thread>

#include "artemis/core/log.hpp"

namespace artemis::viewer {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kMaxUriBytes = 2048;
constexpr std::size_t kMaxBodyBytes = 4096;

std::string contentType(const fs::path& file) {
  const std::string ext = file.extension().string();
  if (ext == ".html") return "text/html; charset=utf-8";
  if (ext == ".js" || ext == ".mjs") return "text/javascript; charset=utf-8";
  if (ext == ".css") return "text/css; charset=utf-8";
  if (ext == ".json") return "application/json";
  if (ext == ".png") return "image/png";
  if (ext == ".txt") return "text/plain; charset=utf-8";
  if (ext == ".glb") return "model/gltf-binary";
  return "application/octet-stream";
}

void sendError(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(nlohmann::json{{"error", message}}.dump(), "application/json");
}

bool readFile(const fs::path& path, std::string& out) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) return false;
  out.clear();
  char buf[1 << 16];
  std::size_t n = 0;
  while ((n = std::fread(buf, 1, sizeof buf, f)) > 0) out.append(buf, n);
  const bool ok = std::ferror(f) == 0;
  std::fclose(f);
  return ok;
}

}  // namespace

std::optional<fs::path> resolveUnder(const fs::path& root, std::string_view relative) {
  if (relative.empty() || relative.size() > kMaxUriBytes || relative.front() == '/') return std::nullopt;
  std::size_t start = 0;
  while (start <= relative.size()) {
    const std::size_t end = std::min(relative.find('/', start), relative.size());
    const std::string_view segment = relative.substr(start, end - start);
    if (segment.empty() || segment.front() == '.') return std::nullopt;  // "", ".", "..", hidden files
    for (const char c : segment) {
      if (c == '\\' || c == '\0' || static_cast<unsigned char>(c) < 0x20) return std::nullopt;
    }
    start = end + 1;
  }
  std::error_code ec;
  const fs::path base = fs::canonical(root, ec);
  if (ec) return std::nullopt;
  const fs::path file = fs::canonical(base / fs::path(std::string(relative)), ec);
  if (ec || !fs::is_regular_file(file, ec)) return std::nullopt;
  // Links may point anywhere: the resolved file must still lie under the root.
  auto b = base.begin();
  auto f = file.begin();
  for (; b != base.end(); ++b, ++f) {
    if (f == file.end() || *b != *f) return std::nullopt;
  }
  return file;
}

fs::path defaultAssetsDir() {
  if (const char* env = std::getenv("ARTEMIS_VIEWER_DIR"); env != nullptr && *env != '\0') return env;
  std::error_code ec;
#ifdef ARTEMIS_SOURCE_VIEWER_DIR
  if (fs::exists(fs::path(ARTEMIS_SOURCE_VIEWER_DIR) / "index.html", ec)) return ARTEMIS_SOURCE_VIEWER_DIR;
#endif
  const fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? fs::path("viewer") : exe.parent_path().parent_path() / "share" / "artemis" / "viewer";
}

struct Server::Impl {
  const Scene& scene;
  ServerParams params;
  QueryFn query;
  httplib::Server http;
  std::thread thread;
  int port = 0;

  void serveFile(const fs::path& root, std::string_view relative, httplib::Response& res) const {
    const auto file = resolveUnder(root, relative);
    std::string body;
    if (!file || !readFile(*file, body)) {
      sendError(res, 404, fmt::format("not found: {}", relative.substr(0, 200)));
      return;
    }
    res.set_header("Cache-Control", "no-cache");
    res.set_content(std::move(body), contentType(*file).c_str());
  }

  void routes() {
    http.set_payload_max_length(kMaxBodyBytes);
    http.set_read_timeout(5, 0);
    http.set_write_timeout(10, 0);
    http.set_default_headers({{"X-Content-Type-Options", "nosniff"}, {"Referrer-Policy", "no-referrer"}});
    http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
      if (req.target.size() > kMaxUriBytes) {
        sendError(res, 414, "request URI too long");
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    http.Get("/",
             [this](const httplib::Request&, httplib::Response& res) { serveFile(params.assets, "index.html", res); });
    http.Get(R"(/(app\.js|style\.css|index\.html))", [this](const httplib::Request& req, httplib::Response& res) {
      serveFile(params.assets, req.matches[1].str(), res);
    });
    // three.js: its build and its add-ons (controls), nothing else of node_modules.
    http.Get(R"(/vendor/three/((build|examples/jsm)/.+))", [this](const httplib::Request& req, httplib::Response& res) {
      serveFile(params.assets / "node_modules" / "three", req.matches[1].str(), res);
    });
    http.Get(R"(/run/(.+))", [this](const httplib::Request& req, httplib::Response& res) {
      if (params.run_dir.empty()) {
        sendError(res, 404, "no run folder");
        return;
      }
      serveFile(params.run_dir, req.matches[1].str(), res);
    });
    http.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(scene.infoJson().dump(), "application/json");
    });
    http.Get("/api/blocks", [this](const httplib::Request& req, httplib::Response& res) {
      std::uint32_t since = 0;
      if (req.has_param("since")) {
        const std::string s = req.get_param_value("since");
        char* end = nullptr;
        const unsigned long v = std::strtoul(s.c_str(), &end, 10);
        if (s.empty() || s.size() > 10 || end != s.c_str() + s.size() || v > 0xffffffffUL) {
          sendError(res, 400, "since: want a version number");
          return;
        }
        since = static_cast<std::uint32_t>(v);
      }
      res.set_header("Cache-Control", "no-store");
      res.set_content(scene.encodeSince(since), "application/octet-stream");
    });
    http.Get("/api/query", [this](const httplib::Request& req, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      const std::string q = req.has_param("q") ? req.get_param_value("q") : "";
      if (q.size() > params.max_query_bytes) {
        sendError(res, 413, fmt::format("query too long: {} bytes, at most {}", q.size(), params.max_query_bytes));
        return;
      }
      try {
        auto answer = query(q);
        if (!answer) {
          sendError(res, 400, answer.status().message());
          return;
        }
        res.set_content(answer->dump(), "application/json");
      } catch (const std::exception& e) {
        log::error("viewer: query '{}': {}", q.substr(0, 100), e.what());
        sendError(res, 500, "the query failed; see the server's log");
      }
    });
  }
};

Server::Server(const Scene& scene, ServerParams params, QueryFn query)
    : impl_(new Impl{scene, std::move(params), std::move(query), {}, {}, 0}) {}

Server::~Server() {
  stop();
}

Result<int> Server::start() {
  const fs::path& assets = impl_->params.assets;
  std::error_code ec;
  if (!fs::exists(assets / "index.html", ec)) {
    return notFound(
        fmt::format("{}: no index.html: the viewer's assets are not there (set ARTEMIS_VIEWER_DIR)", assets.string()));
  }
  if (!fs::exists(assets / "node_modules" / "three" / "build" / "three.module.js", ec)) {
    return notFound(fmt::format("{}: three.js is not installed; run scripts/install-deps.sh (npm ci --prefix {})",
                                (assets / "node_modules" / "three").string(), assets.string()));
  }
  impl_->routes();
  const ServerParams& p = impl_->params;
  if (p.port == 0) {
    impl_->port = impl_->http.bind_to_any_port(p.host);
  } else {
    impl_->port = impl_->http.bind_to_port(p.host, p.port) ? p.port : -1;
  }
  if (impl_->port <= 0) {
    return ioError(
        fmt::format("viewer: cannot listen on {}:{} (in use? try --port 0 for any free port)", p.host, p.port));
  }
  impl_->thread = std::thread([this] { impl_->http.listen_after_bind(); });
  // stop() only reaches a server that is listening: wait until it is (at most a second).
  for (int i = 0; i < 1000 && !impl_->http.is_running(); ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
  return impl_->port;
}

void Server::stop() {
  if (!impl_ || !impl_->thread.joinable()) return;
  impl_->http.stop();
  impl_->thread.join();
}

std::string Server::url() const {
  const std::string host = impl_->params.host == "0.0.0.0" ? "127.0.0.1" : impl_->params.host;
  return fmt::format("http://{}:{}/", host, impl_->port);
}

}  // namespace artemis::viewer
