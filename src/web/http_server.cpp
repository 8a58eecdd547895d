#include "ridge/web/http_server.h"

#include "ridge/core/error.h"

#include <httplib.h>
#include <pthread.h>
#include <sys/socket.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <ctime>
#include <thread>

namespace ridge::web {

namespace {

void checkRange(int value, int lo, int hi, const char* name)
{
    if (value < lo || value > hi)
        throw Error(std::string("http ") + name + " " + std::to_string(value) + " outside [" +
                    std::to_string(lo) + ", " + std::to_string(hi) + "]");
}

WebRequest toWebRequest(const httplib::Request& req)
{
    WebRequest r;
    // HEAD is answered as GET; the library sends the headers and no body.
    r.method = req.method == "HEAD" ? "GET" : req.method;
    r.path = req.path;
    // The query as the library parsed it, in a canonical order ("format=webp&v=..."); only
    // the parameters TileService reads (tile_service.h) matter.
    for (const auto& [key, value] : req.params)
        r.query += (r.query.empty() ? "" : "&") + key + "=" + value;
    r.accept = req.get_header_value("Accept");
    r.accept_encoding = req.get_header_value("Accept-Encoding");
    r.if_none_match = req.get_header_value("If-None-Match");
    return r;
}

} // namespace

void HttpServerOptions::validate() const
{
    if (bind.empty() || bind.size() > 255)
        throw Error("http bind address '" + bind.substr(0, 64) + "' is empty or too long");
    checkRange(port, 0, 65535, "port");
    checkRange(threads, 1, 1024, "threads");
    checkRange(read_timeout_s, 1, 3600, "read timeout");
    checkRange(write_timeout_s, 1, 3600, "write timeout");
    checkRange(keep_alive_s, 1, 3600, "keep-alive");
}

struct HttpServer::Impl {
    httplib::Server server;
    TileService& service;
    bool log;
    int listening = -1; // the listening socket, seen when the library sets its options
    Impl(TileService& s, bool l) : service(s), log(l) {}

    void answer(const httplib::Request& req, httplib::Response& res)
    {
        const WebResponse out = service.handle(toWebRequest(req));
        res.status = out.status;
        for (const auto& [name, value] : out.headers)
            res.set_header(name.c_str(), value);
        if (out.status == 304)
            return;
        // Content-Encoding of a tile is already set; the library compresses only text types,
        // which tiles are not.
        res.set_content(out.body, out.content_type.c_str());
        if (log)
            std::fprintf(stderr, "%s %s %d %zu\n", req.method.c_str(), req.path.c_str(), out.status,
                         out.body.size());
    }
};

HttpServer::HttpServer(TileService& service, const HttpServerOptions& options)
    : impl_(std::make_unique<Impl>(service, options.log))
{
    options.validate();
    // A client that disconnects mid-response must not kill the process.
    std::signal(SIGPIPE, SIG_IGN);
    httplib::Server& s = impl_->server;
    const int threads = options.threads;
    s.new_task_queue = [threads] { return new httplib::ThreadPool(size_t(threads)); };
    s.set_read_timeout(options.read_timeout_s, 0);
    s.set_write_timeout(options.write_timeout_s, 0);
    s.set_keep_alive_timeout(options.keep_alive_s);
    s.set_payload_max_length(0); // no request carries a body
    // SO_REUSEADDR alone (a restarted server rebinds past TIME_WAIT). The library's default,
    // SO_REUSEPORT, would let a second server bind a port in use and share its requests.
    Impl* impl = impl_.get();
    s.set_socket_options([impl](int sock) {
        int yes = 1;
        ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        impl->listening = sock;
    });
    const auto handler = [impl](const httplib::Request& req, httplib::Response& res) {
        impl->answer(req, res);
    };
    s.Get(".*", handler);
    // Other methods reach TileService, which answers 405.
    s.Post(".*", handler);
    s.Put(".*", handler);
    s.Delete(".*", handler);
    s.Patch(".*", handler);
    s.Options(".*", [](const httplib::Request&, httplib::Response& res) {
        // CORS preflight: any origin may GET with the headers Cesium and MapLibre send.
        res.status = 204;
        res.set_header("Access-Control-Allow-Origin", "*");
        res.set_header("Access-Control-Allow-Methods", "GET, HEAD, OPTIONS");
        res.set_header("Access-Control-Allow-Headers", "Accept, If-None-Match, Range");
        res.set_header("Access-Control-Max-Age", "86400");
    });
    s.set_exception_handler(
        [](const httplib::Request&, httplib::Response& res, std::exception_ptr) {
            res.status = 500;
            res.set_content("500 internal error\n", "text/plain; charset=utf-8");
        });
    if (options.port == 0) {
        port_ = s.bind_to_any_port(options.bind);
        if (port_ <= 0)
            throw Error("http: cannot bind " + options.bind + " on any port");
    } else {
        if (!s.bind_to_port(options.bind, options.port))
            throw Error("http: cannot bind " + options.bind + ":" + std::to_string(options.port) +
                        " (in use, or not an address of this machine)");
        port_ = options.port;
    }
    // The library listens with a backlog of 5 (compiled into Debian's build): 100 clients
    // connecting at once overflowed it, and their connections waited for SYN retries (1 s,
    // 3 s, ...) or failed. Listening again on the bound socket raises the backlog (Linux).
    if (impl->listening >= 0)
        ::listen(impl->listening, SOMAXCONN);
}

HttpServer::~HttpServer()
{
    stop();
}

void HttpServer::run()
{
    impl_->server.listen_after_bind();
}

void HttpServer::stop()
{
    impl_->server.stop();
}

int runUntilSignalled(HttpServer& server)
{
    sigset_t signals, previous;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, &previous);
    std::atomic<bool> done{false};
    std::atomic<int> caught{0};
    std::thread watcher([&] {
        const timespec tick{0, 100 * 1000 * 1000};
        while (!done.load()) {
            const int s = sigtimedwait(&signals, nullptr, &tick);
            if (s == SIGINT || s == SIGTERM)
                caught = s;
            // Stopping again each tick: a signal that came before run() started listening
            // would otherwise be lost (the library ignores stop() until it runs).
            if (caught.load())
                server.stop();
        }
    });
    server.run();
    done = true;
    watcher.join();
    pthread_sigmask(SIG_SETMASK, &previous, nullptr);
    return caught.load();
}

} // namespace ridge::web
