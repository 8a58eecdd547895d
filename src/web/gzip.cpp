#include "ridge/web/gzip.h"

#include "ridge/core/error.h"

#include <zlib.h>

#include <climits>

namespace ridge::web::detail {

namespace {

constexpr int kGzipWindow = 15 + 16; // zlib's window bits for a gzip wrapper

} // namespace

std::string gzipCompress(std::string_view data)
{
    z_stream z{};
    if (deflateInit2(&z, Z_DEFAULT_COMPRESSION, Z_DEFLATED, kGzipWindow, 8, Z_DEFAULT_STRATEGY) !=
        Z_OK)
        throw Error("gzip: zlib could not start");
    std::string out(deflateBound(&z, uLong(data.size())), '\0');
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(data.data()));
    z.avail_in = uInt(data.size());
    z.next_out = reinterpret_cast<Bytef*>(out.data());
    z.avail_out = uInt(out.size());
    const int rc = deflate(&z, Z_FINISH);
    const size_t size = z.total_out;
    deflateEnd(&z);
    if (rc != Z_STREAM_END)
        throw Error("gzip: zlib could not compress " + std::to_string(data.size()) + " bytes");
    out.resize(size);
    return out;
}

std::string gzipDecompress(std::string_view gz, size_t max_bytes)
{
    if (gz.size() > UINT_MAX)
        throw Error("gzip: stream too large");
    z_stream z{};
    if (inflateInit2(&z, kGzipWindow) != Z_OK)
        throw Error("gzip: zlib could not start");
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(gz.data()));
    z.avail_in = uInt(gz.size());
    std::string out;
    char chunk[16384];
    int rc = Z_OK;
    while (rc == Z_OK) {
        z.next_out = reinterpret_cast<Bytef*>(chunk);
        z.avail_out = sizeof chunk;
        rc = inflate(&z, Z_NO_FLUSH);
        out.append(chunk, sizeof chunk - z.avail_out);
        if (out.size() > max_bytes) {
            inflateEnd(&z);
            throw Error("gzip: stream inflates past " + std::to_string(max_bytes) + " bytes");
        }
        if (rc == Z_OK && z.avail_in == 0 && z.avail_out != 0)
            rc = Z_DATA_ERROR; // input ended before the stream did
    }
    inflateEnd(&z);
    if (rc != Z_STREAM_END || z.avail_in != 0)
        throw Error("gzip: not a whole gzip stream");
    return out;
}

} // namespace ridge::web::detail
