#pragma once
// A client for the viewer's tests that writes requests byte for byte (no URL encoding, no
// checks), as a hostile or broken client would, and holds connections open without a request.

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstdint>
#include <string>

namespace artemis::test {

// A connected TCP socket, closed when the object dies.
class RawSocket {
 public:
  explicit RawSocket(int port) : fd_(socket(AF_INET, SOCK_STREAM, 0)) {
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_port = htons(static_cast<std::uint16_t>(port));
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    timeval timeout{10, 0};  // no test waits longer for an answer
    setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &timeout, sizeof timeout);
    if (connect(fd_, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
      close(fd_);
      fd_ = -1;
    }
  }
  ~RawSocket() {
    if (fd_ >= 0) close(fd_);
  }
  RawSocket(const RawSocket&) = delete;
  RawSocket& operator=(const RawSocket&) = delete;

  [[nodiscard]] bool connected() const { return fd_ >= 0; }
  bool send(const std::string& bytes) const {
    return fd_ >= 0 && ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) == static_cast<ssize_t>(bytes.size());
  }
  // Everything until the server closes the connection (or 10 s pass).
  [[nodiscard]] std::string receiveAll() const {
    std::string out;
    char buf[4096];
    ssize_t n = 0;
    while (fd_ >= 0 && (n = recv(fd_, buf, sizeof buf, 0)) > 0) out.append(buf, static_cast<std::size_t>(n));
    return out;
  }

 private:
  int fd_;
};

struct RawResponse {
  int status = 0;    // 0: no answer
  std::string head;  // status line and headers
  std::string body;
};

// GET `target` (sent as given) on a connection of its own, which it asks the server to close.
inline RawResponse rawGet(int port, const std::string& target) {
  RawSocket socket(port);
  RawResponse r;
  if (!socket.send("GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\nConnection: close\r\n\r\n")) return r;
  const std::string answer = socket.receiveAll();
  const std::size_t end = answer.find("\r\n\r\n");
  if (answer.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) return r;
  r.status = std::stoi(answer.substr(9, 3));
  r.head = answer.substr(0, end);
  r.body = answer.substr(end + 4);
  return r;
}

}  // namespace artemis::test
