// The viewer's HTTP server as clients meet it: one server to a port, requests that are not UTF-8,
// exceptions that stay out of the answer, clients that hold connections without a request, and
// the address it reports.
#include <fmt/format.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <thread>
#include <vector>

#include "raw_http.hpp"
#include "support/test_support.hpp"
#include "viewer/scene.hpp"
#include "viewer/server.hpp"
#include "viewer/session.hpp"

namespace artemis::viewer {
namespace {

namespace fs = std::filesystem;
using test::rawGet;
using test::RawResponse;
using test::RawSocket;

// A viewer folder with what start() requires, and a run folder with one file.
struct Folders {
  test::TempDir tmp;
  Folders() {
    fs::create_directories(tmp / "assets/node_modules/three/build");
    fs::create_directories(tmp / "run");
    std::ofstream(tmp / "assets/index.html") << "<html></html>";
    std::ofstream(tmp / "assets/node_modules/three/build/three.module.js") << "export {};";
    std::ofstream(tmp / "run/timing.json") << "{}";
  }
  [[nodiscard]] ServerParams params() const {
    ServerParams p;
    p.port = 0;
    p.assets = tmp / "assets";
    p.run_dir = tmp / "run";
    return p;
  }
};

// Echoes the query; "throw" throws an exception whose text must stay in the server.
Result<nlohmann::json> echoQuery(const std::string& q) {
  if (q == "throw") throw std::runtime_error("secret internals at /etc/shadow");
  return nlohmann::json{{"query", q}, {"matched", nlohmann::json::array()}};
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

double secondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// A FIFO or a link to a device among the run's files would hold a worker forever: not found.
TEST(ViewerServer, ARunFileThatIsNotARegularFileIsNotServed) {
  const Folders folders;
  ASSERT_EQ(::mkfifo((folders.tmp / "run/mesh.ply").c_str(), 0600), 0);
  fs::create_symlink("/dev/zero", folders.tmp / "run/trajectory.txt");
  const Scene scene;
  Server server(scene, folders.params(), echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(rawGet(*port, "/run/mesh.ply").status, 404);
  EXPECT_EQ(rawGet(*port, "/run/trajectory.txt").status, 404);
  EXPECT_EQ(rawGet(*port, "/run/timing.json").status, 200);
  EXPECT_LT(secondsSince(start), 2.0);
}

TEST(ViewerServer, ASecondServerOnTheSamePortIsRefused) {
  const Folders folders;
  const Scene scene;
  Server first(scene, folders.params(), echoQuery);
  const auto port = first.start();
  ASSERT_TRUE(port) << port.status().message();
  ServerParams same = folders.params();
  same.port = *port;
  Server second(scene, same, echoQuery);
  const auto refused = second.start();
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.status().message(), fmt::format("viewer: port {} is in use (another artemis view?); pick another "
                                                    "with --port (0: any free port)",
                                                    *port));
  // `artemis run --viewer` names its own flag.
  same.flag_prefix = "viewer-";
  Server third(scene, same, echoQuery);
  const auto refused_run = third.start();
  ASSERT_FALSE(refused_run);
  EXPECT_NE(refused_run.status().message().find("--viewer-port"), std::string::npos);
  // The first server still answers every request.
  for (int i = 0; i < 4; ++i) EXPECT_EQ(rawGet(*port, "/api/info").status, 200);
}

// httplib's default, SO_REUSEPORT, lets two programs that both set it share a port: one that set
// it holds the port here, and the viewer must not join it.
TEST(ViewerServer, APortSharedWithSoReusePortIsRefused) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  const int yes = 1;
  ASSERT_EQ(setsockopt(fd, SOL_SOCKET, SO_REUSEPORT, &yes, sizeof yes), 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof addr;
  ASSERT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(listen(fd, 4), 0);
  ASSERT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length), 0);
  const int port = ntohs(addr.sin_port);
  const Folders folders;
  const Scene scene;
  ServerParams params = folders.params();
  params.port = port;
  Server server(scene, params, echoQuery);
  const auto refused = server.start();
  close(fd);
  ASSERT_FALSE(refused);
  EXPECT_NE(refused.status().message().find(fmt::format("port {} is in use", port)), std::string::npos)
      << refused.status().message();
}

TEST(ViewerServer, RequestsThatAreNotUtf8AreBadRequestsWithoutInternals) {
  const Folders folders;
  const Scene scene;
  Server server(scene, folders.params(), echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  for (const char* target :
       {"/api/query?q=%FF%FE", "/%C3%28", "/run/%C3%28", "/run/%FF", "/api/blocks?since=%FF", "/api/query?%FF=cars",
        "/api/query?q=%ED%A0%80" /* a surrogate */, "/api/query?q=%C0%AF" /* overlong '/' */}) {
    const RawResponse r = rawGet(*port, target);
    EXPECT_EQ(r.status, 400) << target << "\n" << r.head;
    EXPECT_EQ(r.body, "bad request: the path or query is not UTF-8\n") << target;
    const std::string head = lower(r.head);
    for (const char* leak : {"exception", "what", "json"}) EXPECT_EQ(head.find(leak), std::string::npos) << target;
  }
  // Well-formed UTF-8 goes through, and comes back as it was sent.
  const RawResponse ok = rawGet(*port, "/api/query?q=%C3%A9t%C3%A9%20%F0%9F%9A%97");
  ASSERT_EQ(ok.status, 200) << ok.head;
  EXPECT_EQ(nlohmann::json::parse(ok.body)["query"], "\xC3\xA9t\xC3\xA9 \xF0\x9F\x9A\x97");
}

TEST(ViewerServer, AnExceptionIsA500ThatKeepsItsTextInTheServer) {
  const Folders folders;
  const Scene scene;
  Server server(scene, folders.params(), echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  const RawResponse r = rawGet(*port, "/api/query?q=throw");
  EXPECT_EQ(r.status, 500);
  EXPECT_EQ(nlohmann::json::parse(r.body), (nlohmann::json{{"error", "internal error; see the viewer's log"}}));
  EXPECT_EQ((r.head + r.body).find("secret"), std::string::npos) << r.head;
  EXPECT_EQ(lower(r.head).find("exception"), std::string::npos) << r.head;
}

// A folder's name need not be UTF-8 on Linux; the page's title then shows U+FFFD for its bytes.
TEST(ViewerServer, InfoWithATitleThatIsNotUtf8IsServed) {
  const Folders folders;
  Scene scene;
  scene.setInfo("title", std::string("caf\xE9"));
  Server server(scene, folders.params(), echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  const RawResponse r = rawGet(*port, "/api/info");
  ASSERT_EQ(r.status, 200) << r.head;
  EXPECT_EQ(nlohmann::json::parse(r.body)["title"], "caf\xEF\xBF\xBD");
}

// 20 clients that connect and send nothing, or half a request line, must not hold up a page.
TEST(ViewerServer, IdleConnectionsDoNotStallARequest) {
  const Folders folders;
  const Scene scene;
  Server server(scene, folders.params(), echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  std::vector<std::unique_ptr<RawSocket>> idle;
  for (int i = 0; i < 20; ++i) {
    idle.push_back(std::make_unique<RawSocket>(*port));
    ASSERT_TRUE(idle.back()->connected());
    if (i % 2 == 1) {
      ASSERT_TRUE(idle.back()->send("GET /api/in"));
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // every idle one has reached a worker
  const auto start = std::chrono::steady_clock::now();
  const RawResponse r = rawGet(*port, "/api/info");
  const double elapsed_s = secondsSince(start);
  EXPECT_EQ(r.status, 200);
  EXPECT_LT(elapsed_s, 3.0);
}

// More idle clients than workers: each holds its worker for one timeout at most, so a request
// behind 2 workers' worth of them waits about 2 timeouts (1 s each), not httplib's 5 s each.
TEST(ViewerServer, IdleConnectionsBeyondTheWorkersAreDroppedAfterTheirTimeout) {
  const Folders folders;
  const Scene scene;
  ServerParams params = folders.params();
  params.worker_threads = 2;
  params.read_timeout_s = 1;
  params.keep_alive_timeout_s = 1;
  Server server(scene, params, echoQuery);
  const auto port = server.start();
  ASSERT_TRUE(port) << port.status().message();
  std::vector<std::unique_ptr<RawSocket>> idle;
  for (int i = 0; i < 4; ++i) {
    idle.push_back(std::make_unique<RawSocket>(*port));
    ASSERT_TRUE(idle.back()->connected());
    if (i % 2 == 1) {
      ASSERT_TRUE(idle.back()->send("GET /api/info HTTP/1.1\r\nHost: x"));
    }
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const auto start = std::chrono::steady_clock::now();
  const RawResponse r = rawGet(*port, "/api/info");
  const double elapsed_s = secondsSince(start);
  EXPECT_EQ(r.status, 200);
  EXPECT_GT(elapsed_s, 0.7);  // the idle ones did hold both workers
  EXPECT_LT(elapsed_s, 3.5);
}

TEST(ViewerServer, OutOfRangeConnectionSettingsAreRefused) {
  const Folders folders;
  const Scene scene;
  for (const int workers : {0, 257}) {
    ServerParams params = folders.params();
    params.worker_threads = workers;
    Server server(scene, params, echoQuery);
    const auto refused = server.start();
    ASSERT_FALSE(refused);
    EXPECT_NE(refused.status().message().find(fmt::format("worker_threads {} (want 1 to 256)", workers)),
              std::string::npos)
        << refused.status().message();
  }
}

TEST(ViewerServer, ReportsTheAddressItBoundAndWarnsWhenOthersCanReachIt) {
  const Folders folders;
  const Scene scene;
  Server local(scene, folders.params(), echoQuery);
  const auto local_port = local.start();
  ASSERT_TRUE(local_port) << local_port.status().message();
  EXPECT_EQ(local.url(), fmt::format("http://127.0.0.1:{}/", *local_port));
  EXPECT_TRUE(local.loopbackOnly());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  announce(local, "test");
  EXPECT_EQ(testing::internal::GetCapturedStdout(), fmt::format("viewer: http://127.0.0.1:{}/ (test)\n", *local_port));
  EXPECT_EQ(testing::internal::GetCapturedStderr(), "");

  ServerParams everywhere = folders.params();
  everywhere.host = "0.0.0.0";
  everywhere.flag_prefix = "viewer-";
  Server exposed(scene, everywhere, echoQuery);
  const auto port = exposed.start();
  ASSERT_TRUE(port) << port.status().message();
  EXPECT_EQ(exposed.url(), fmt::format("http://0.0.0.0:{}/", *port));
  EXPECT_FALSE(exposed.loopbackOnly());
  testing::internal::CaptureStdout();
  testing::internal::CaptureStderr();
  announce(exposed, "live");
  const std::string out = testing::internal::GetCapturedStdout();
  const std::string err = testing::internal::GetCapturedStderr();
  exposed.stop();
  EXPECT_EQ(out, fmt::format("viewer: http://0.0.0.0:{}/ (live)\n", *port));
  EXPECT_NE(err.find(fmt::format("NOT PRIVATE: listening on http://0.0.0.0:{}/", *port)), std::string::npos) << err;
  EXPECT_NE(err.find("no password"), std::string::npos) << err;
  EXPECT_NE(err.find("--viewer-host 127.0.0.1"), std::string::npos) << err;
}

TEST(ViewerServer, AHostThatIsNotThisMachineIsRefusedByName) {
  const Folders folders;
  const Scene scene;
  ServerParams params = folders.params();
  params.host = "192.0.2.1";  // TEST-NET-1: no machine has it
  Server server(scene, params, echoQuery);
  const auto refused = server.start();
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.status().message(),
            "viewer: cannot listen on 192.0.2.1: not an address of this machine; pick another with --host");
}

}  // namespace
}  // namespace artemis::viewer
