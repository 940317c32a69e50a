#include "common/http_server.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "absl/strings/str_cat.h"

namespace juggle {

HttpServer::~HttpServer() { Stop(); }

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(int port, bool all_interfaces,
                                                              Handler handler) {
  std::unique_ptr<HttpServer> server(new HttpServer());
  server->handler_ = std::move(handler);
  server->fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
  if (server->fd_ < 0) return absl::InternalError("http: socket() failed");
  const int one = 1;
  ::setsockopt(server->fd_, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(all_interfaces ? INADDR_ANY : INADDR_LOOPBACK);
  addr.sin_port = htons(port);
  if (::bind(server->fd_, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0 ||
      ::listen(server->fd_, 16) != 0) {
    const std::string err = std::strerror(errno);
    ::close(server->fd_);
    server->fd_ = -1;
    return absl::UnavailableError(absl::StrCat("http: cannot listen on port ", port, ": ", err));
  }
  socklen_t len = sizeof(addr);
  ::getsockname(server->fd_, reinterpret_cast<sockaddr*>(&addr), &len);
  server->port_ = ntohs(addr.sin_port);
  server->thread_ = std::thread(&HttpServer::Serve, server.get());
  return server;
}

void HttpServer::Stop() {
  if (stop_.exchange(true)) return;
  if (thread_.joinable()) thread_.join();
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void HttpServer::Serve() {
  while (!stop_) {
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, 200) <= 0) continue;
    const int client = ::accept(fd_, nullptr, nullptr);
    if (client < 0) continue;
    timeval tv{2, 0};
    ::setsockopt(client, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
    char buf[2048];
    const ssize_t n = ::recv(client, buf, sizeof(buf) - 1, 0);
    HttpResponse response;
    if (n <= 0) {
      ::close(client);
      continue;
    }
    buf[n] = '\0';
    const std::string request(buf);
    if (request.rfind("GET ", 0) != 0) {
      response = {405, "text/plain", "only GET\n"};
    } else {
      const size_t end = request.find(' ', 4);
      response = handler_(request.substr(4, end == std::string::npos ? std::string::npos : end - 4));
    }
    const std::string head = absl::StrCat("HTTP/1.0 ", response.status,
                                          response.status == 200 ? " OK" : " Error",
                                          "\r\nContent-Type: ", response.content_type,
                                          "\r\nContent-Length: ", response.body.size(),
                                          "\r\nConnection: close\r\n\r\n");
    const std::string all = head + response.body;
    size_t sent = 0;
    while (sent < all.size()) {
      const ssize_t k = ::send(client, all.data() + sent, all.size() - sent, MSG_NOSIGNAL);
      if (k <= 0) break;
      sent += k;
    }
    ::close(client);
  }
}

absl::StatusOr<std::string> HttpGet(int port, const std::string& path) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return absl::InternalError("http: socket() failed");
  timeval tv{5, 0};  // never hang on a server that accepts but does not answer
  ::setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof(tv));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(port);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof(addr)) != 0) {
    ::close(fd);
    return absl::UnavailableError(absl::StrCat("cannot connect to 127.0.0.1:", port));
  }
  const std::string req = absl::StrCat("GET ", path, " HTTP/1.0\r\n\r\n");
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  std::string response;
  char buf[4096];
  ssize_t n;
  while ((n = ::recv(fd, buf, sizeof(buf), 0)) > 0) response.append(buf, n);
  ::close(fd);
  const size_t body = response.find("\r\n\r\n");
  if (body == std::string::npos) return absl::DataLossError("malformed HTTP response");
  return response.substr(body + 4);
}

}  // namespace juggle
