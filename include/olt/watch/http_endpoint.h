#pragma once
// A small HTTP/1.1 endpoint for the daemon's GET routes, served by cpp-httplib (kept out of this
// header). It binds to loopback unless given another host. Each connection has a thread of its own
// (up to a cap), so connections that send nothing cannot keep a health probe waiting: cpp-httplib's
// own pool gives each of its few threads to one connection until that connection's idle timeout.
#include <functional>
#include <map>
#include <memory>
#include <string>

namespace olt {

struct ListenAddress {
  std::string host = "127.0.0.1";
  int port = 0;  ///< 0: any free port (the endpoint tells which)
};

/// Parses `PORT`, `HOST:PORT` or `[IPV6]:PORT`; throws InputError naming `--listen` otherwise.
ListenAddress parse_listen_address(const std::string& text);

/// True for 127.0.0.0/8, ::1 and localhost.
bool is_loopback(const std::string& host);

struct HttpResponse {
  int status = 200;
  std::string content_type = "text/plain; charset=utf-8";
  std::string body;
};

/// GET routes by exact path; other paths get 404, other methods 405.
using HttpRoutes = std::map<std::string, std::function<HttpResponse()>>;

struct HttpLimits {
  int connections = 512;  ///< served at once; more wait for one of them to close
  int idle_seconds = 2;   ///< a connection that sends no request for this long is closed
};

class HttpEndpoint {
 public:
  /// Binds and starts serving; throws std::runtime_error when the address cannot be bound.
  HttpEndpoint(const ListenAddress& address, HttpRoutes routes, HttpLimits limits = {});
  ~HttpEndpoint();  ///< stops serving and joins the thread
  HttpEndpoint(const HttpEndpoint&) = delete;
  HttpEndpoint& operator=(const HttpEndpoint&) = delete;
  int port() const;  ///< the bound port (the chosen one when asked for 0)

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace olt
