// artemis view as a user starts it: a port another viewer holds, and a host other machines reach.
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>
#include <string>

#include "cli/cli_run.hpp"
#include "support/test_support.hpp"

namespace artemis {
namespace {

// One triangle and a viewer folder with what the server requires.
struct ViewFiles {
  test::TempDir tmp;
  ViewFiles() {
    std::ofstream(tmp / "tri.ply") << "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                                      "property float z\nelement face 1\nproperty list uchar uint vertex_indices\n"
                                      "end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
    std::filesystem::create_directories(tmp / "assets/node_modules/three/build");
    std::ofstream(tmp / "assets/index.html") << "<html></html>";
    std::ofstream(tmp / "assets/node_modules/three/build/three.module.js") << "export {};";
  }
  [[nodiscard]] std::string view(const std::string& flags) const {
    return "view " + (tmp / "tri.ply").string() + " --assets " + (tmp / "assets").string() + " " + flags;
  }
};

TEST(CliView, APortInUseIsAnErrorNamingIt) {
  // A listener as httplib sets one up by default (SO_REUSEPORT), as an older viewer would hold it.
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(fd, 0);
  const int yes = 1;
  setsockopt(fd, SOL_SOCKET, SO_REUSEPORT, &yes, sizeof yes);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof addr;
  ASSERT_EQ(bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  ASSERT_EQ(listen(fd, 4), 0);
  ASSERT_EQ(getsockname(fd, reinterpret_cast<sockaddr*>(&addr), &length), 0);
  const int port = ntohs(addr.sin_port);
  const ViewFiles files;
  const auto r = test::runCli(files.view("--port " + std::to_string(port) + " --exit-after 0.2"));
  close(fd);
  EXPECT_EQ(r.exit_code, 1) << r.out;
  EXPECT_EQ(r.out.find("viewer: http"), std::string::npos) << r.out;
  EXPECT_NE(r.err.find("port " + std::to_string(port) +
                       " is in use (another artemis view?); pick another with --port (0: any free port)"),
            std::string::npos)
      << r.err;
}

TEST(CliView, AHostOtherMachinesReachIsPrintedAsBoundWithAWarning) {
  const ViewFiles files;
  const auto exposed = test::runCli(files.view("--host 0.0.0.0 --port 0 --exit-after 0.2"));
  ASSERT_EQ(exposed.exit_code, 0) << exposed.err;
  EXPECT_EQ(exposed.out.rfind("viewer: http://0.0.0.0:", 0), 0U) << exposed.out;
  EXPECT_NE(exposed.err.find("NOT PRIVATE: listening on http://0.0.0.0:"), std::string::npos) << exposed.err;
  EXPECT_NE(exposed.err.find("--host 127.0.0.1"), std::string::npos) << exposed.err;

  const auto local = test::runCli(files.view("--port 0 --exit-after 0.2"));
  ASSERT_EQ(local.exit_code, 0) << local.err;
  EXPECT_EQ(local.out.rfind("viewer: http://127.0.0.1:", 0), 0U) << local.out;
  EXPECT_EQ(local.err.find("NOT PRIVATE"), std::string::npos) << local.err;
}

}  // namespace
}  // namespace artemis
