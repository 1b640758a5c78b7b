#include "olt/watch/http_endpoint.h"

#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <vector>

using namespace olt;

namespace {

// A loopback TCP connection to `port` that sends nothing; -1 when it cannot connect.
int idle_connection(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) return fd;
  if (fd >= 0) ::close(fd);
  return -1;
}

// True while the server has not closed the connection (nothing to read, no end of stream).
bool still_open(int fd) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, 0) == 0;
}

}  // namespace

TEST_CASE("http endpoint: 200 connections that send nothing do not keep /healthz waiting") {
  // Idle connections are closed only after a minute here, so an answer while all of them are still
  // open shows /healthz did not wait for any of them (with cpp-httplib's pool of a few threads it
  // waits for 200 / threads idle timeouts).
  HttpEndpoint endpoint({"127.0.0.1", 0},
                        {{"/healthz",
                          [] {
                            return HttpResponse{200, "text/plain", "ok\n"};
                          }}},
                        HttpLimits{512, 60});
  std::vector<int> idle;
  for (int i = 0; i < 200; ++i) idle.push_back(idle_connection(endpoint.port()));
  for (int fd : idle) REQUIRE(fd >= 0);

  httplib::Client client("127.0.0.1", endpoint.port());
  client.set_read_timeout(30, 0);
  const auto response = client.Get("/healthz");
  REQUIRE(response);
  CHECK(response->status == 200);
  CHECK(response->body == "ok\n");
  int open = 0;
  for (int fd : idle) open += still_open(fd) ? 1 : 0;
  CHECK(open == 200);
  for (int fd : idle) ::close(fd);
}

TEST_CASE("http endpoint: beyond the connection cap a request waits for an idle connection to time out") {
  HttpEndpoint endpoint({"127.0.0.1", 0},
                        {{"/healthz",
                          [] {
                            return HttpResponse{200, "text/plain", "ok\n"};
                          }}},
                        HttpLimits{2, 1});
  const int a = idle_connection(endpoint.port()), b = idle_connection(endpoint.port());
  REQUIRE(a >= 0);
  REQUIRE(b >= 0);
  httplib::Client client("127.0.0.1", endpoint.port());
  client.set_read_timeout(30, 0);
  const auto response = client.Get("/healthz");
  REQUIRE(response);
  CHECK(response->body == "ok\n");
  // It was served in a slot one of the two freed when it was closed for idling.
  CHECK((!still_open(a) || !still_open(b)));
  ::close(a);
  ::close(b);
}
