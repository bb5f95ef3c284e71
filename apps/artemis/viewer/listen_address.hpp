#pragma once
// Where the viewer listens, in words: the address its socket is bound to (for the URL it prints
// and the warning when other machines can reach it), and why listening on a port failed.

#include <optional>
#include <string>
#include <string_view>

namespace artemis::viewer {

struct ListenAddress {
  std::string ip;  // numeric, as bound: "127.0.0.1", "0.0.0.0" (every interface), "::1"
  int port = 0;
  bool loopback = false;  // only this machine can connect (127.0.0.0/8, ::1)
  bool ipv6 = false;

  // "127.0.0.1:8080", "[::1]:8080".
  [[nodiscard]] std::string hostPort() const;
};

// The local address of a bound socket (getsockname), or nothing when it has none.
std::optional<ListenAddress> boundAddress(int socket_fd);

// Why a listening socket on host:port cannot be had, found by binding one (SO_REUSEADDR, as the
// server does): "port 8080 is in use (another artemis view?); pick another with --port ...", a
// port that needs privileges, a host that is not an address of this machine. `flag_prefix` names
// the command line's options: "" for --port/--host, "viewer-" for --viewer-port/--viewer-host.
std::string bindFailure(const std::string& host, int port, std::string_view flag_prefix);

}  // namespace artemis::viewer
