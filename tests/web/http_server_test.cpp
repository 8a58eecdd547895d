// TileService on a real loopback socket through cpp-httplib, with a real HTTP client and raw
// sockets playing hostile clients: the server answers what it should and stays up.
#include "ridge/web/http_server.h"

#include "everest_web.h"
#include "ridge/core/error.h"
#include "ridge/core/sanitizer.h"
#include "ridge/web/gzip.h"

#include <gtest/gtest.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <fstream>
#include <thread>

using namespace ridge;
using namespace ridge::web;

namespace {

constexpr const char* kAccept = "application/vnd.quantized-mesh;extensions=octvertexnormals-"
                                "watermask-metadata,application/octet-stream;q=0.9";

// A server on a free loopback port, run on its own thread for the test's lifetime.
class LoopbackServer {
  public:
    LoopbackServer(const std::string& archive, HttpServerOptions http = {},
                   TileServiceOptions tiles = {})
        : service_({archive}, tiles), server_(service_, withFreePort(http))
    {
        thread_ = std::thread([this] { server_.run(); });
    }
    ~LoopbackServer()
    {
        server_.stop();
        thread_.join();
    }
    int port() const { return server_.port(); }
    TileService& service() { return service_; }
    std::string name() const { return service_.tilesets()[0]->name(); }
    httplib::Client client() const
    {
        httplib::Client c("127.0.0.1", port());
        c.set_connection_timeout(5);
        c.set_read_timeout(30);
        c.set_decompress(false);
        return c;
    }

  private:
    static HttpServerOptions withFreePort(HttpServerOptions o)
    {
        o.port = 0;
        return o;
    }
    TileService service_;
    HttpServer server_;
    std::thread thread_;
};

// A raw TCP connection to the server, for clients no library would be.
int connectTo(int port)
{
    const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(uint16_t(port));
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0) {
        ::close(fd);
        return -1;
    }
    return fd;
}

// Resident memory of this process, bytes (Linux).
size_t residentBytes()
{
    std::ifstream statm("/proc/self/statm");
    size_t pages = 0, resident = 0;
    statm >> pages >> resident;
    return resident * size_t(::sysconf(_SC_PAGESIZE));
}

using HttpServerTest = test::EverestArchiveSuite;

} // namespace

TEST_F(HttpServerTest, ServesLayerAndTilesWithHttpSemantics)
{
    LoopbackServer server(archive());
    httplib::Client c = server.client();
    const auto layer = c.Get(("/" + server.name() + "/layer.json").c_str());
    ASSERT_TRUE(layer);
    EXPECT_EQ(layer->status, 200);
    EXPECT_EQ(layer->get_header_value("Access-Control-Allow-Origin"), "*");
    EXPECT_EQ(nlohmann::json::parse(layer->body)["format"], "quantized-mesh-1.0");

    const TileKey k = GeographicTms::tileAt(11, 86.88, 27.9);
    const std::string path =
        "/" + server.name() + "/11/" + std::to_string(k.x) + "/" + std::to_string(k.y) + ".terrain";
    const httplib::Headers asks = {{"Accept", kAccept}, {"Accept-Encoding", "gzip"}};
    const auto tile = c.Get(path.c_str(), asks);
    ASSERT_TRUE(tile);
    ASSERT_EQ(tile->status, 200);
    EXPECT_EQ(tile->get_header_value("Content-Encoding"), "gzip");
    const std::string raw = detail::gzipDecompress(tile->body, 1 << 26);
    const QuantizedMesh m =
        decodeQuantizedMesh(std::span(reinterpret_cast<const uint8_t*>(raw.data()), raw.size()));
    EXPECT_GT(m.vertexCount(), 3u);
    EXPECT_EQ(m.oct_normals.size(), 2 * m.vertexCount());

    httplib::Headers again = asks;
    again.emplace("If-None-Match", tile->get_header_value("ETag"));
    const auto revalidated = c.Get(path.c_str(), again);
    ASSERT_TRUE(revalidated);
    EXPECT_EQ(revalidated->status, 304);
    EXPECT_TRUE(revalidated->body.empty());

    const auto head = c.Head(path.c_str(), asks);
    ASSERT_TRUE(head);
    EXPECT_EQ(head->status, 200);
    EXPECT_EQ(head->get_header_value("Content-Length"), std::to_string(tile->body.size()));

    const auto preflight = c.Options(path.c_str());
    ASSERT_TRUE(preflight);
    EXPECT_EQ(preflight->status, 204);
    EXPECT_EQ(preflight->get_header_value("Access-Control-Allow-Methods"), "GET, HEAD, OPTIONS");

    const auto post = c.Post(path.c_str(), "", "text/plain");
    ASSERT_TRUE(post);
    EXPECT_EQ(post->status, 405);
    for (const std::string& bad :
         {std::string("/%2e%2e/%2e%2e/etc/passwd"), "/" + server.name() + "/1/a/0.terrain"}) {
        const auto r = c.Get(bad.c_str());
        ASSERT_TRUE(r) << bad;
        EXPECT_EQ(r->status, 400) << bad;
    }
    const auto absent = c.Get(("/" + server.name() + "/28/0/0.terrain").c_str());
    ASSERT_TRUE(absent);
    EXPECT_EQ(absent->status, 404);
}

TEST_F(HttpServerTest, HostileClientsDoNotStopTheServer)
{
    HttpServerOptions http;
    http.read_timeout_s = 1;
    http.write_timeout_s = 1;
    http.threads = 4;
    LoopbackServer server(archive(), http);
    const std::string path = "/" + server.name() + "/layer.json";
    const auto served = [&] {
        httplib::Client c = server.client();
        const auto r = c.Get(path.c_str());
        return r && r->status == 200;
    };

    // A slow client: half a request line, then nothing. The server cuts it off after its
    // read timeout (1 s) and answers others meanwhile.
    const int slow = connectTo(server.port());
    ASSERT_GE(slow, 0);
    ASSERT_EQ(::send(slow, "GET /", 5, MSG_NOSIGNAL), 5);
    EXPECT_TRUE(served());
    const auto start = std::chrono::steady_clock::now();
    char byte;
    timeval limit{10, 0};
    ::setsockopt(slow, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    const ssize_t got = ::recv(slow, &byte, 1, 0);
    const double waited =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LE(got, 0) << "the connection is closed, not answered";
    EXPECT_LT(waited, 5.0);
    ::close(slow);

    // Clients that disconnect mid-response (reset, nothing read) — many at once.
    for (int i = 0; i < 20; ++i) {
        const int fd = connectTo(server.port());
        ASSERT_GE(fd, 0);
        const std::string request = "GET /" + server.name() +
                                    "/0/1/0.terrain HTTP/1.1\r\nHost: x\r\nAccept: " + kAccept +
                                    "\r\n\r\n";
        ::send(fd, request.data(), request.size(), MSG_NOSIGNAL);
        linger reset{1, 0};
        ::setsockopt(fd, SOL_SOCKET, SO_LINGER, &reset, sizeof reset);
        ::close(fd);
    }
    EXPECT_TRUE(served());

    // Garbage, a request line past 8 KiB, a header past 8 KiB: refused, server up.
    httplib::Client c = server.client();
    const auto long_uri = c.Get(("/" + std::string(10000, 'a')).c_str());
    ASSERT_TRUE(long_uri);
    EXPECT_EQ(long_uri->status, 414);
    const auto long_header = c.Get(path.c_str(), {{"X-Junk", std::string(10000, 'b')}});
    EXPECT_TRUE(!long_header || long_header->status >= 400);
    const int junk = connectTo(server.port());
    ASSERT_GE(junk, 0);
    const std::string garbage = "HELLO THERE\r\n\r\n";
    ::send(junk, garbage.data(), garbage.size(), MSG_NOSIGNAL);
    char reply[64] = {};
    ::setsockopt(junk, SOL_SOCKET, SO_RCVTIMEO, &limit, sizeof limit);
    const ssize_t n = ::recv(junk, reply, sizeof reply - 1, 0);
    ::close(junk);
    EXPECT_TRUE(n <= 0 || std::string(reply).find(" 400 ") != std::string::npos) << reply;
    EXPECT_TRUE(served());
}

TEST_F(HttpServerTest, AHundredConcurrentRequestsInBoundedMemory)
{
    HttpServerOptions http;
    http.threads = 16;
    TileServiceOptions tiles;
    tiles.tile_cache_bytes = size_t(4) << 20;
    tiles.tileset.samplers = 2;
    LoopbackServer server(archive(), http, tiles);
    const int z = 11;
    const std::vector<TileRange> ranges = server.service().tilesets()[0]->available(z);
    ASSERT_EQ(ranges.size(), 1u);
    const size_t before = residentBytes();
    std::atomic<int> ok{0}, absent{0}, failed{0};
    std::vector<std::thread> clients;
    for (int i = 0; i < 100; ++i)
        clients.emplace_back([&, i] {
            // Nine tiles that exist and, one request in ten, one that does not.
            const TileRange& r = ranges[0];
            const int64_t x = r.x0 + i % 3, y = r.y0 + (i / 3) % 3;
            const std::string path = "/" + server.name() + "/" + std::to_string(z) + "/" +
                                     std::to_string(i % 10 == 9 ? x + 100 : x) + "/" +
                                     std::to_string(y) + ".terrain";
            httplib::Client c = server.client();
            const auto res = c.Get(path.c_str(), {{"Accept", kAccept}});
            if (!res)
                ++failed;
            else if (res->status == 200)
                ++ok;
            else if (res->status == 404)
                ++absent;
            else
                ++failed;
        });
    for (auto& t : clients)
        t.join();
    const size_t growth = residentBytes() - std::min(residentBytes(), before);
    std::printf("100 concurrent requests: %d tiles, %d absent, %d failed; resident memory "
                "grew %.1f MiB\n",
                ok.load(), absent.load(), failed.load(), double(growth) / (1 << 20));
    EXPECT_EQ(ok.load(), 90);
    EXPECT_EQ(absent.load(), 10);
    EXPECT_EQ(failed.load(), 0);
    // Bounded by the tile cache (4 MiB), two samplers' decoded patches and 16 threads'
    // stacks and buffers, not by the number of requests. (Under AddressSanitizer freed memory
    // stays resident in its quarantine, 256 MiB by default: the figure says nothing there.)
    if (!RIDGE_ADDRESS_SANITIZER) {
        EXPECT_LT(growth, size_t(96) << 20);
    }
    EXPECT_EQ(server.service().stats().tiles_made, 9u);
}

TEST_F(HttpServerTest, RefusesBadOptionsAndATakenPort)
{
    TileService service({archive()}, {});
    using Change = void (*)(HttpServerOptions&);
    for (const Change bad : std::vector<Change>{[](HttpServerOptions& o) { o.port = 70000; },
                                                [](HttpServerOptions& o) { o.threads = 0; },
                                                [](HttpServerOptions& o) { o.read_timeout_s = 0; },
                                                [](HttpServerOptions& o) { o.bind = ""; }}) {
        HttpServerOptions o;
        bad(o);
        EXPECT_THROW(HttpServer(service, o), ridge::Error);
    }
    HttpServerOptions first;
    first.port = 0;
    HttpServer taken(service, first);
    HttpServerOptions second;
    second.port = taken.port();
    try {
        HttpServer again(service, second);
        ADD_FAILURE() << "bound a port in use";
    } catch (const ridge::Error& e) {
        EXPECT_NE(std::string(e.what()).find(std::to_string(taken.port())), std::string::npos)
            << e.what();
    }
    HttpServerOptions nowhere;
    nowhere.bind = "203.0.113.7"; // TEST-NET-3: not an address of this machine
    EXPECT_THROW(HttpServer(service, nowhere), ridge::Error);
}
