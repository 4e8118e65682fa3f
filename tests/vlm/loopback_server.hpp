// A scripted HTTP/1.1 server on 127.0.0.1 for the vlm.query tests: it answers the n-th request
// with the n-th canned response (the last one repeats), one connection per request, and keeps
// every request body it received. A `hang` response is never answered: the server holds the
// connection until the client gives up and closes it (a stuck server, without timing). The
// faults of issue 16: `reset` aborts the connection (RST) instead of answering, `stream_bytes`
// sends that many bytes of body (with no Content-Length unless `declare_length`) until the client
// stops reading, and `echo_headers` answers with the request's headers as the body (a proxy that
// echoes the Authorization header back). A `respond` function answers from the request body
// instead (the embeddings stand-in, tests/text: one vector per input, whatever the inputs are).
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <functional>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace gslift::test {

struct CannedResponse {
  int status = 200;
  std::string body;
  bool hang = false;   // never answer; wait until the client closes the connection
  bool reset = false;  // close with SO_LINGER 0: the client sees "connection reset by peer"
  size_t stream_bytes = 0;
  bool declare_length = false;  // with stream_bytes: send Content-Length: stream_bytes first
  bool echo_headers = false;
  std::function<std::string(const std::string& body)> respond =
      nullptr;  // the body, from the request's
};

class LoopbackServer {
 public:
  explicit LoopbackServer(std::vector<CannedResponse> script) : script_(std::move(script)) {
    listener_ = ::socket(AF_INET, SOCK_STREAM, 0);
    if (listener_ < 0) throw std::runtime_error("socket() failed");
    const int yes = 1;
    ::setsockopt(listener_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    addr.sin_port = 0;  // ephemeral
    if (::bind(listener_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
        ::listen(listener_, 16) != 0)
      throw std::runtime_error("bind/listen on 127.0.0.1 failed");
    socklen_t len = sizeof addr;
    ::getsockname(listener_, reinterpret_cast<sockaddr*>(&addr), &len);
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] { serve(); });
  }

  ~LoopbackServer() {
    stopping_ = true;
    ::shutdown(listener_, SHUT_RDWR);
    ::close(listener_);
    thread_.join();
  }

  std::string url() const { return base_url() + "/v1/chat/completions"; }
  std::string base_url() const { return "http://127.0.0.1:" + std::to_string(port_); }

  std::vector<std::string> bodies() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return bodies_;
  }
  // Each request's headers, request line first ("POST /v1/embeddings HTTP/1.1").
  std::vector<std::string> headers() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return headers_;
  }

 private:
  void serve() {
    size_t n = 0;
    while (!stopping_) {
      const int client = ::accept(listener_, nullptr, nullptr);
      if (client < 0) return;  // listener closed
      std::string headers;
      const std::string body = read_request(client, &headers);
      {
        std::lock_guard<std::mutex> lock(mutex_);
        bodies_.push_back(body);
        headers_.push_back(headers);
      }
      const CannedResponse& r = script_[std::min(n++, script_.size() - 1)];
      if (r.hang) {
        wait_for_close(client);
        ::close(client);
        continue;
      }
      if (r.reset) {
        const linger abort{1, 0};
        ::setsockopt(client, SOL_SOCKET, SO_LINGER, &abort, sizeof abort);
        ::close(client);
        continue;
      }
      if (r.stream_bytes > 0) {
        stream(client, r);
        ::close(client);
        continue;
      }
      const std::string text = r.respond ? r.respond(body) : r.echo_headers ? headers : r.body;
      const std::string reply = "HTTP/1.1 " + std::to_string(r.status) +
                                " Canned\r\nContent-Type: application/json\r\nContent-Length: " +
                                std::to_string(text.size()) + "\r\nConnection: close\r\n\r\n" +
                                text;
      // MSG_NOSIGNAL: the client may have given up (timeout) and closed its end.
      ::send(client, reply.data(), reply.size(), MSG_NOSIGNAL);
      ::close(client);
    }
  }

  // Blocks until the client closes its end (recv returns 0) or the connection fails.
  static void wait_for_close(int client) {
    char buffer[4096];
    while (::recv(client, buffer, sizeof buffer, 0) > 0) {
    }
  }

  // A 200 whose body is r.stream_bytes of 'x', sent until done or the client stops reading.
  static void stream(int client, const CannedResponse& r) {
    std::string head = "HTTP/1.1 200 Canned\r\nContent-Type: application/json\r\n";
    if (r.declare_length) head += "Content-Length: " + std::to_string(r.stream_bytes) + "\r\n";
    head += "Connection: close\r\n\r\n";
    if (::send(client, head.data(), head.size(), MSG_NOSIGNAL) < 0) return;
    const std::string block(1 << 16, 'x');
    for (size_t sent = 0; sent < r.stream_bytes;) {
      const ssize_t n =
          ::send(client, block.data(), std::min(block.size(), r.stream_bytes - sent), MSG_NOSIGNAL);
      if (n <= 0) return;  // the client closed the connection
      sent += static_cast<size_t>(n);
    }
  }

  // Headers up to the blank line (into *headers), then Content-Length bytes of body.
  static std::string read_request(int client, std::string* headers_out) {
    std::string data;
    char buffer[65536];
    size_t header_end = std::string::npos, length = 0;
    while (true) {
      const ssize_t got = ::recv(client, buffer, sizeof buffer, 0);
      if (got <= 0) break;
      data.append(buffer, static_cast<size_t>(got));
      if (header_end == std::string::npos) {
        header_end = data.find("\r\n\r\n");
        if (header_end == std::string::npos) continue;
        *headers_out = data.substr(0, header_end);
        std::string headers = *headers_out;
        for (auto& c : headers) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
        const size_t at = headers.find("content-length:");
        if (at != std::string::npos) length = std::stoul(headers.substr(at + 15));
      }
      if (data.size() >= header_end + 4 + length) break;
    }
    return header_end == std::string::npos ? std::string() : data.substr(header_end + 4);
  }

  std::vector<CannedResponse> script_;
  int listener_ = -1;
  int port_ = 0;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
  mutable std::mutex mutex_;
  std::vector<std::string> bodies_;
  std::vector<std::string> headers_;
};

}  // namespace gslift::test
