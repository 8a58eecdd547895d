#pragma once
// gzip (RFC 1952) through zlib: how quantized-mesh tiles travel (Content-Encoding: gzip).
#include <cstddef>
#include <string>
#include <string_view>

namespace ridge::web::detail {

// The gzip stream of `data` at zlib's default level.
std::string gzipCompress(std::string_view data);
// The data of a gzip stream; throws ridge::Error when it is not one or inflates past
// `max_bytes`.
std::string gzipDecompress(std::string_view gz, size_t max_bytes);

} // namespace ridge::web::detail
