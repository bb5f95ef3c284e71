// cpp-httplib stays in this file: it pulls <resolv.h>, whose macros break code that follows.
#include "server.hpp"

#include <fmt/format.h>
#include <httplib.h>

#include <chrono>
#include <cstdlib>
#include <exception>
#include <thread>

#include "artemis/core/log.hpp"
#include "artemis/io/read_file.hpp"
#include "listen_address.hpp"
#include "utf8.hpp"

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

constexpr int kMaxWorkerThreads = 256;

// Bytes that are not UTF-8 (a folder's name in the title, a path echoed back) become U+FFFD
// instead of making dump() throw.
std::string dumpJson(const nlohmann::json& j) {
  return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

// {"error": message}, which the page shows.
void sendError(httplib::Response& res, int status, const std::string& message) {
  res.status = status;
  res.set_content(dumpJson({{"error", message}}), "application/json");
}

std::string whatOf(const std::exception_ptr& thrown) {
  try {
    if (thrown) std::rethrow_exception(thrown);
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
  return "an exception that is not a std::exception";
}

// A short answer that tells a client nothing of the server's insides.
void sendPlain(httplib::Response& res, int status, const char* text) {
  res.status = status;
  res.set_content(text, "text/plain; charset=utf-8");
}

// Whether the decoded path and every query parameter are UTF-8: the handlers echo them into JSON
// and hand them to the query grounder.
bool isUtf8Request(const httplib::Request& req) {
  if (!isValidUtf8(req.path)) return false;
  for (const auto& [key, value] : req.params) {
    if (!isValidUtf8(key) || !isValidUtf8(value)) return false;
  }
  return true;
}

// httplib's server, and the socket it listens on (to tell the address it bound).
class HttpServer final : public httplib::Server {
 public:
  [[nodiscard]] int listeningSocket() const { return svr_sock_; }
};

Status checkParams(const ServerParams& p) {
  const fs::path& assets = p.assets;
  std::error_code ec;
  if (!fs::exists(assets / "index.html", ec)) {
    return notFound(
        fmt::format("{}: no index.html: the viewer's assets are not there (set ARTEMIS_VIEWER_DIR)", assets.string()));
  }
  if (!fs::exists(assets / "node_modules" / "three" / "build" / "three.module.js", ec)) {
    return notFound(fmt::format("{}: three.js is not installed; run scripts/install-deps.sh (npm ci --prefix {})",
                                (assets / "node_modules" / "three").string(), assets.string()));
  }
  if (p.worker_threads < 1 || p.worker_threads > kMaxWorkerThreads || p.read_timeout_s < 1 ||
      p.keep_alive_timeout_s < 1 || p.keep_alive_requests < 1) {
    return invalidArgument(fmt::format(
        "viewer: worker_threads {} (want 1 to {}), read_timeout_s {}, keep_alive_timeout_s {}, keep_alive_requests {} "
        "(want 1 or more)",
        p.worker_threads, kMaxWorkerThreads, p.read_timeout_s, p.keep_alive_timeout_s, p.keep_alive_requests));
  }
  return Status::ok();
}

// A regular file only: a FIFO or device in the run folder would hold a worker forever.
bool readFile(const fs::path& path, std::string& out) {
  auto text = io::readTextFile(path, io::limits::kMesh);
  if (!text) {
    log::debug("viewer: {}", text.status().message());
    return false;
  }
  out = std::move(*text);
  return true;
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
  HttpServer http;
  std::thread thread;
  int port = 0;
  std::optional<ListenAddress> address;

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

  // Connections, sockets and what every request goes through before its route.
  void configure() {
    // Only SO_REUSEADDR (restart at once on a port whose old connections linger), not httplib's
    // default SO_REUSEPORT, with which a second viewer on the port would take half the requests.
    http.set_socket_options([](socket_t sock) {
      const int yes = 1;
      setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    });
    const auto workers = static_cast<std::size_t>(params.worker_threads);
    http.new_task_queue = [workers] { return new httplib::ThreadPool(workers); };
    http.set_read_timeout(params.read_timeout_s, 0);
    http.set_write_timeout(10, 0);
    http.set_keep_alive_timeout(params.keep_alive_timeout_s);
    http.set_keep_alive_max_count(static_cast<std::size_t>(params.keep_alive_requests));
    http.set_payload_max_length(kMaxBodyBytes);
    http.set_default_headers({{"X-Content-Type-Options", "nosniff"}, {"Referrer-Policy", "no-referrer"}});
    http.set_pre_routing_handler([](const httplib::Request& req, httplib::Response& res) {
      if (req.target.size() > kMaxUriBytes) {
        sendError(res, 414, "request URI too long");
        return httplib::Server::HandlerResponse::Handled;
      }
      if (!isUtf8Request(req)) {
        sendPlain(res, 400, "bad request: the path or query is not UTF-8\n");
        return httplib::Server::HandlerResponse::Handled;
      }
      return httplib::Server::HandlerResponse::Unhandled;
    });
    // Without it httplib answers 500 with the exception's text in a header.
    http.set_exception_handler(
        [](const httplib::Request& req, httplib::Response& res, const std::exception_ptr& thrown) {
          log::error("viewer: {}: {}", toValidUtf8(req.target.substr(0, 200)), toValidUtf8(whatOf(thrown)));
          sendError(res, 500, "internal error; see the viewer's log");
        });
  }

  void fileRoutes() {
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
  }

  void apiRoutes() {
    http.Get("/api/info", [this](const httplib::Request&, httplib::Response& res) {
      res.set_header("Cache-Control", "no-store");
      res.set_content(dumpJson(scene.infoJson()), "application/json");
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
    http.Get("/api/query", [this](const httplib::Request& req, httplib::Response& res) { answerQuery(req, res); });
  }

  void answerQuery(const httplib::Request& req, httplib::Response& res) const {
    res.set_header("Cache-Control", "no-store");
    const std::string q = req.has_param("q") ? req.get_param_value("q") : "";
    if (q.size() > params.max_query_bytes) {
      sendError(res, 413, fmt::format("query too long: {} bytes, at most {}", q.size(), params.max_query_bytes));
      return;
    }
    // An exception goes to the exception handler: a 500 whose text only the log sees.
    auto answer = query(q);
    if (!answer) {
      sendError(res, 400, answer.status().message());
      return;
    }
    res.set_content(dumpJson(*answer), "application/json");
  }
};

Server::Server(const Scene& scene, ServerParams params, QueryFn query)
    : impl_(new Impl{scene, std::move(params), std::move(query), {}, {}, 0, std::nullopt}) {}

Server::~Server() {
  stop();
}

Result<int> Server::start() {
  const ServerParams& p = impl_->params;
  if (Status checked = checkParams(p); !checked.isOk()) return checked;
  impl_->configure();
  impl_->fileRoutes();
  impl_->apiRoutes();
  if (p.port == 0) {
    impl_->port = impl_->http.bind_to_any_port(p.host);
  } else {
    impl_->port = impl_->http.bind_to_port(p.host, p.port) ? p.port : -1;
  }
  if (impl_->port <= 0) return ioError(bindFailure(p.host, p.port, p.flag_prefix));
  impl_->address = boundAddress(impl_->http.listeningSocket());
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
  if (impl_->address) return fmt::format("http://{}/", impl_->address->hostPort());
  return fmt::format("http://{}:{}/", impl_->params.host, impl_->port);
}

bool Server::loopbackOnly() const {
  return impl_->address && impl_->address->loopback;
}

const ServerParams& Server::params() const {
  return impl_->params;
}

}  // namespace artemis::viewer
