#include "listen_address.hpp"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstring>

namespace artemis::viewer {

std::string ListenAddress::hostPort() const {
  return ipv6 ? fmt::format("[{}]:{}", ip, port) : fmt::format("{}:{}", ip, port);
}

std::optional<ListenAddress> boundAddress(int socket_fd) {
  sockaddr_storage storage{};
  socklen_t length = sizeof storage;
  if (socket_fd < 0 || getsockname(socket_fd, reinterpret_cast<sockaddr*>(&storage), &length) != 0) {
    return std::nullopt;
  }
  std::array<char, INET6_ADDRSTRLEN> text{};
  ListenAddress out;
  if (storage.ss_family == AF_INET) {
    const auto& v4 = reinterpret_cast<const sockaddr_in&>(storage);
    if (inet_ntop(AF_INET, &v4.sin_addr, text.data(), text.size()) == nullptr) return std::nullopt;
    out.port = ntohs(v4.sin_port);
    out.loopback = (ntohl(v4.sin_addr.s_addr) >> 24) == 127;
  } else if (storage.ss_family == AF_INET6) {
    const auto& v6 = reinterpret_cast<const sockaddr_in6&>(storage);
    if (inet_ntop(AF_INET6, &v6.sin6_addr, text.data(), text.size()) == nullptr) return std::nullopt;
    out.port = ntohs(v6.sin6_port);
    out.ipv6 = true;
    // ::1, or 127.x.y.z written as an IPv4-mapped address (::ffff:127.0.0.1).
    out.loopback = IN6_IS_ADDR_LOOPBACK(&v6.sin6_addr) != 0 ||
                   (IN6_IS_ADDR_V4MAPPED(&v6.sin6_addr) != 0 && v6.sin6_addr.s6_addr[12] == 127);
  } else {
    return std::nullopt;
  }
  out.ip = text.data();
  return out;
}

namespace {

// The errno of binding a socket as the server does to the first address `host` resolves to
// (0: it binds now), or nothing when `host` does not resolve.
std::optional<int> probeBind(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (getaddrinfo(host.c_str(), service.c_str(), &hints, &found) != 0 || found == nullptr) return std::nullopt;
  int error = EADDRNOTAVAIL;
  for (const addrinfo* a = found; a != nullptr; a = a->ai_next) {
    const int fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd < 0) continue;
    const int yes = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    error = bind(fd, a->ai_addr, a->ai_addrlen) == 0 ? 0 : errno;
    close(fd);
    if (error != EADDRNOTAVAIL) break;
  }
  freeaddrinfo(found);
  return error;
}

}  // namespace

std::string bindFailure(const std::string& host, int port, std::string_view flag_prefix) {
  const auto error = probeBind(host, port);
  if (!error)
    return fmt::format("viewer: cannot listen on {}: no such host; pick another with --{}host", host, flag_prefix);
  if (*error == EADDRNOTAVAIL) {
    return fmt::format("viewer: cannot listen on {}: not an address of this machine; pick another with --{}host", host,
                       flag_prefix);
  }
  if (*error == EADDRINUSE) {
    return fmt::format(
        "viewer: port {} is in use (another artemis view?); pick another with --{}port (0: any free port)", port,
        flag_prefix);
  }
  if (*error == EACCES) {
    return fmt::format("viewer: port {} needs privileges (ports below 1024); pick another with --{}port", port,
                       flag_prefix);
  }
  return fmt::format("viewer: cannot listen on {}:{}: {}; pick another port with --{}port", host, port,
                     *error == 0 ? "the port was taken, then freed" : std::strerror(*error), flag_prefix);
}

}  // namespace artemis::viewer
