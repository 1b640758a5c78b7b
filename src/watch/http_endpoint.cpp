#include "olt/watch/http_endpoint.h"

#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <chrono>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <thread>

#include "olt/core/error.h"
#include "olt/core/fs.h"

namespace olt {

ListenAddress parse_listen_address(const std::string& text) {
  ListenAddress address;
  std::string port = text;
  if (!text.empty() && text.front() == '[') {
    const auto close = text.find("]:");
    if (close == std::string::npos) throw InputError("--listen", "expected [IPV6]:PORT, got '" + text + "'");
    address.host = text.substr(1, close - 1);
    port = text.substr(close + 2);
  } else if (const auto colon = text.rfind(':'); colon != std::string::npos) {
    address.host = text.substr(0, colon);
    port = text.substr(colon + 1);
  }
  const bool digits = !port.empty() && port.size() <= 5 && port.find_first_not_of("0123456789") == std::string::npos;
  if (address.host.empty() || !digits || std::stoi(port) > 65535)
    throw InputError("--listen", "expected PORT, HOST:PORT or [IPV6]:PORT with a port in 0..65535, got '" + text + "'");
  address.port = std::stoi(port);
  return address;
}

bool is_loopback(const std::string& host) { return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0; }

namespace {

// cpp-httplib's task queue with a thread per connection, at most `cap` at once; connections beyond
// the cap wait, in order, for one to close (within the idle timeout). shutdown() waits for all.
class ThreadPerConnection : public httplib::TaskQueue {
 public:
  explicit ThreadPerConnection(size_t cap) : cap_(cap) {}

  void enqueue(std::function<void()> serve) override {
    std::lock_guard<std::mutex> lock(mutex_);
    waiting_.push_back(std::move(serve));
    start_waiting();
  }

  void shutdown() override {
    std::unique_lock<std::mutex> lock(mutex_);
    all_done_.wait(lock, [this] { return running_ == 0 && waiting_.empty(); });
  }

 private:
  // Called with the mutex held.
  void start_waiting() {
    while (running_ < cap_ && !waiting_.empty()) {
      ++running_;
      std::thread([this, serve = std::move(waiting_.front())] {
        serve();
        std::lock_guard<std::mutex> lock(mutex_);
        --running_;
        start_waiting();
        if (running_ == 0 && waiting_.empty()) all_done_.notify_all();
      }).detach();
      waiting_.pop_front();
    }
  }

  const size_t cap_;
  std::mutex mutex_;
  std::condition_variable all_done_;
  std::deque<std::function<void()>> waiting_;
  size_t running_ = 0;
};

// cpp-httplib 0.11 listens with a backlog of 5: in a burst of connections the others' handshakes are
// dropped and retried a second later. Linux lets a listening socket's backlog be set again: this
// finds the process's socket listening on `port` and gives it the system's maximum.
void widen_backlog(int port) {
  std::error_code error;
  for (const auto& entry : fs::directory_iterator("/proc/self/fd", error)) {
    int fd = -1;
    try {
      fd = std::stoi(entry.path().filename().string());
    } catch (const std::exception&) {
      continue;
    }
    int listening = 0;
    socklen_t size = sizeof listening;
    sockaddr_storage address{};
    socklen_t address_size = sizeof address;
    if (::getsockopt(fd, SOL_SOCKET, SO_ACCEPTCONN, &listening, &size) != 0 || !listening ||
        ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &address_size) != 0)
      continue;
    const int bound = address.ss_family == AF_INET6 ? ntohs(reinterpret_cast<sockaddr_in6*>(&address)->sin6_port)
                                                    : ntohs(reinterpret_cast<sockaddr_in*>(&address)->sin_port);
    if (bound == port) ::listen(fd, SOMAXCONN);
  }
}

}  // namespace

struct HttpEndpoint::Impl {
  httplib::Server server;
  std::thread thread;
  int port = 0;
};

HttpEndpoint::HttpEndpoint(const ListenAddress& address, HttpRoutes routes, HttpLimits limits)
    : impl_(std::make_unique<Impl>()) {
  const auto cap = static_cast<size_t>(std::max(1, limits.connections));
  impl_->server.new_task_queue = [cap] { return new ThreadPerConnection(cap); };
  impl_->server.set_keep_alive_timeout(limits.idle_seconds);
  impl_->server.set_read_timeout(limits.idle_seconds, 0);
  impl_->server.set_write_timeout(limits.idle_seconds, 0);
  auto shared = std::make_shared<HttpRoutes>(std::move(routes));
  impl_->server.Get(".*", [shared](const httplib::Request& request, httplib::Response& response) {
    const auto route = shared->find(request.path);
    if (route == shared->end()) {
      response.status = 404;
      response.set_content("not found; try /healthz, /status or /metrics\n", "text/plain; charset=utf-8");
      return;
    }
    const HttpResponse r = route->second();
    response.status = r.status;
    response.set_content(r.body, r.content_type.c_str());
  });
  const auto not_allowed = [](const httplib::Request&, httplib::Response& response) {
    response.status = 405;
    response.set_header("Allow", "GET");
    response.set_content("only GET\n", "text/plain; charset=utf-8");
  };
  impl_->server.Post(".*", not_allowed);
  impl_->server.Put(".*", not_allowed);
  impl_->server.Delete(".*", not_allowed);
  impl_->server.Patch(".*", not_allowed);
  impl_->port = address.port == 0 ? impl_->server.bind_to_any_port(address.host)
                                  : (impl_->server.bind_to_port(address.host, address.port) ? address.port : -1);
  if (impl_->port < 0)
    throw std::runtime_error("cannot listen on " + address.host + ":" + std::to_string(address.port) +
                             " (address in use, or not an address of this machine)");
  widen_backlog(impl_->port);
  impl_->thread = std::thread([this] { impl_->server.listen_after_bind(); });
  // Ready when the constructor returns; and stop() before the loop starts would be lost.
  for (int i = 0; i < 2000 && !impl_->server.is_running(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
}

HttpEndpoint::~HttpEndpoint() {
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

int HttpEndpoint::port() const { return impl_->port; }

}  // namespace olt
