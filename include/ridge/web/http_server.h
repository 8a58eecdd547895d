#pragma once
// TileService on HTTP/1.1 through cpp-httplib (Debian's libcpp-httplib): sockets, parsing,
// keep-alive, timeouts and a bounded pool of worker threads are the library's; what is
// answered is TileService's.
//
// Hostile clients: a request line or header past 8 KiB is refused by the library (414/400),
// bodies are refused (ridge takes none), a client that sends or reads too slowly is cut off
// after the read/write timeout, and one that disconnects mid-response only ends its own
// connection (SIGPIPE is ignored process-wide while a server exists, so a write to a closed
// socket returns an error instead of killing the process).
#include "ridge/web/tile_service.h"

#include <memory>
#include <string>

namespace ridge::web {

struct HttpServerOptions {
    std::string bind = "127.0.0.1"; // an address, or "0.0.0.0" for every interface
    int port = 8080;                // 0: any free port (port() says which)
    int threads = 16;               // connections served at once, [1, 1024]
    int read_timeout_s = 5;         // [1, 3600]
    int write_timeout_s = 5;        // [1, 3600]
    int keep_alive_s = 2;           // idle time a kept-alive connection holds a thread, [1, 3600]
    bool log = false;               // one line a request on stderr
    // Throws ridge::Error naming the field out of range.
    void validate() const;
};

class HttpServer {
  public:
    // Binds the address and port. Throws ridge::Error naming them when it cannot.
    HttpServer(TileService& service, const HttpServerOptions& options);
    ~HttpServer();
    HttpServer(const HttpServer&) = delete;
    HttpServer& operator=(const HttpServer&) = delete;

    int port() const { return port_; }
    // Serves until stop(); returns at once when stopped before.
    void run();
    // Ends run() (thread-safe; connections in progress are closed).
    void stop();

  private:
    struct Impl;
    std::unique_ptr<Impl> impl_;
    int port_ = 0;
};

// server.run() until SIGINT or SIGTERM arrives (or server.stop() is called elsewhere), then
// stops it; returns the signal's number, or 0 when stopped otherwise. The two signals are
// blocked in the calling thread (and the server's threads, which it starts) and taken by
// sigwait in a watcher thread: no work happens in a signal handler.
int runUntilSignalled(HttpServer& server);

} // namespace ridge::web
