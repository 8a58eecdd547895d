#include "ridge/web/pmtiles.h"

#include "ridge/core/error.h"
#include "ridge/core/file_io.h"
#include "ridge/web/gzip.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <unordered_map>

namespace ridge::web {

namespace {

constexpr size_t kHeaderBytes = 127;
// The header and the root directory must lie in the first 16 KiB (spec v3): one request.
constexpr uint64_t kRootRegion = 16384;
constexpr size_t kMaxDirectoryBytes = size_t(64) << 20; // decompressed, when reading
constexpr int kMaxLeafDepth = 3;

struct Entry {
    uint64_t tile_id = 0;
    uint64_t offset = 0; // in the tile data (or, run_length 0, in the leaf directories)
    uint32_t length = 0;
    uint32_t run_length = 0; // 0: a leaf directory
};

void putU64(uint8_t* p, uint64_t v)
{
    for (int i = 0; i < 8; ++i)
        p[i] = uint8_t(v >> (8 * i));
}
uint64_t getU64(const uint8_t* p)
{
    uint64_t v = 0;
    for (int i = 0; i < 8; ++i)
        v |= uint64_t(p[i]) << (8 * i);
    return v;
}
void putI32(uint8_t* p, int32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = uint8_t(uint32_t(v) >> (8 * i));
}
int32_t getI32(const uint8_t* p)
{
    uint32_t v = 0;
    for (int i = 0; i < 4; ++i)
        v |= uint32_t(p[i]) << (8 * i);
    return int32_t(v);
}
int32_t e7(double degrees)
{
    return int32_t(std::lround(degrees * 1e7));
}

void putVarint(std::string& out, uint64_t v)
{
    while (v >= 0x80) {
        out.push_back(char(uint8_t(v) | 0x80));
        v >>= 7;
    }
    out.push_back(char(v));
}

std::string serialize(const std::vector<Entry>& entries)
{
    std::string out;
    putVarint(out, entries.size());
    uint64_t last = 0;
    for (const Entry& e : entries) {
        putVarint(out, e.tile_id - last);
        last = e.tile_id;
    }
    for (const Entry& e : entries)
        putVarint(out, e.run_length);
    for (const Entry& e : entries)
        putVarint(out, e.length);
    for (size_t i = 0; i < entries.size(); ++i) {
        // 0: right after the previous entry's bytes (the common case when clustered).
        const bool follows =
            i > 0 && entries[i].offset == entries[i - 1].offset + entries[i - 1].length;
        putVarint(out, follows ? 0 : entries[i].offset + 1);
    }
    return out;
}

// Reads varints from a directory, refusing truncation and overflow.
class VarintReader {
  public:
    VarintReader(const std::string& bytes, const std::string& what) : b_(bytes), what_(what) {}
    uint64_t next()
    {
        uint64_t v = 0;
        for (int shift = 0; shift < 64; shift += 7) {
            if (at_ >= b_.size())
                throw Error(what_ + ": directory truncated");
            const uint8_t byte = uint8_t(b_[at_++]);
            if (shift == 63 && byte > 1)
                throw Error(what_ + ": directory varint overflows 64 bits");
            v |= uint64_t(byte & 0x7f) << shift;
            if (!(byte & 0x80))
                return v;
        }
        throw Error(what_ + ": directory varint longer than 10 bytes");
    }
    bool done() const { return at_ == b_.size(); }

  private:
    const std::string& b_;
    const std::string& what_;
    size_t at_ = 0;
};

std::vector<Entry> deserialize(const std::string& bytes, const std::string& what)
{
    VarintReader in(bytes, what);
    const uint64_t n = in.next();
    if (n > bytes.size()) // every entry takes at least four bytes
        throw Error(what + ": directory claims " + std::to_string(n) + " entries in " +
                    std::to_string(bytes.size()) + " bytes");
    std::vector<Entry> entries(n);
    uint64_t id = 0;
    for (uint64_t i = 0; i < n; ++i) {
        const uint64_t delta = in.next();
        if (i > 0 && delta == 0)
            throw Error(what + ": directory tile ids not increasing");
        if (delta > UINT64_MAX - id)
            throw Error(what + ": directory tile id overflows");
        id += delta;
        entries[i].tile_id = id;
    }
    for (Entry& e : entries) {
        const uint64_t run = in.next();
        if (run > UINT32_MAX)
            throw Error(what + ": directory run length too large");
        e.run_length = uint32_t(run);
    }
    for (Entry& e : entries) {
        const uint64_t length = in.next();
        if (length == 0 || length > UINT32_MAX)
            throw Error(what + ": directory entry of length " + std::to_string(length));
        e.length = uint32_t(length);
    }
    for (uint64_t i = 0; i < n; ++i) {
        const uint64_t v = in.next();
        if (v == 0) {
            if (i == 0)
                throw Error(what + ": directory's first offset is relative");
            entries[i].offset = entries[i - 1].offset + entries[i - 1].length;
        } else {
            entries[i].offset = v - 1;
        }
    }
    if (!in.done())
        throw Error(what + ": directory has trailing bytes");
    return entries;
}

// The entry holding `id`, or a leaf to search, or null (searching a sorted directory).
const Entry* findEntry(const std::vector<Entry>& entries, uint64_t id)
{
    auto it = std::upper_bound(entries.begin(), entries.end(), id,
                               [](uint64_t v, const Entry& e) { return v < e.tile_id; });
    if (it == entries.begin())
        return nullptr;
    --it;
    if (it->run_length == 0 || id - it->tile_id < it->run_length)
        return &*it;
    return nullptr;
}

} // namespace

uint64_t pmtilesTileId(TileKey k)
{
    if (k.z < 0 || k.z > kPmtilesMaxZoom)
        throw Error("PMTiles zoom " + std::to_string(k.z) + " outside [0, 26]");
    const int64_t n = int64_t(1) << k.z;
    if (k.x < 0 || k.y < 0 || k.x >= n || k.y >= n)
        throw Error("PMTiles tile " + std::to_string(k.z) + "/" + std::to_string(k.x) + "/" +
                    std::to_string(k.y) + " outside its zoom");
    const uint64_t before = ((uint64_t(1) << (2 * k.z)) - 1) / 3; // Σ 4^t, t < z
    uint64_t x = uint64_t(k.x), y = uint64_t(k.y), d = 0;
    for (uint64_t s = uint64_t(n) / 2; s > 0; s /= 2) {
        const uint64_t rx = (x & s) ? 1 : 0, ry = (y & s) ? 1 : 0;
        d += s * s * ((3 * rx) ^ ry);
        if (ry == 0) { // rotate the quadrant
            if (rx == 1) {
                x = s - 1 - x;
                y = s - 1 - y;
            }
            std::swap(x, y);
        }
    }
    return before + d;
}

TileKey pmtilesTileKey(uint64_t id)
{
    int z = 0;
    uint64_t before = 0;
    while (z <= kPmtilesMaxZoom && id >= before + (uint64_t(1) << (2 * z))) {
        before += uint64_t(1) << (2 * z);
        ++z;
    }
    if (z > kPmtilesMaxZoom)
        throw Error("PMTiles tile id " + std::to_string(id) + " past zoom 26");
    const uint64_t n = uint64_t(1) << z;
    uint64_t t = id - before, x = 0, y = 0;
    for (uint64_t s = 1; s < n; s *= 2) {
        const uint64_t rx = 1 & (t / 2), ry = 1 & (t ^ rx);
        if (ry == 0) {
            if (rx == 1) {
                x = s - 1 - x;
                y = s - 1 - y;
            }
            std::swap(x, y);
        }
        x += s * rx;
        y += s * ry;
        t /= 4;
    }
    return {z, int64_t(x), int64_t(y)};
}

struct PmtilesWriter::Impl {
    int fd;
    std::string path;
    std::vector<Entry> entries;
    // Distinct contents by hash: where each is stored (hash collisions compared byte by byte).
    std::unordered_multimap<uint64_t, std::pair<uint64_t, uint32_t>> stored;
    uint64_t contents = 0;
    bool finished = false;
};

PmtilesWriter::PmtilesWriter(int fd, std::string path) : impl_(std::make_unique<Impl>())
{
    impl_->fd = fd;
    impl_->path = std::move(path);
    // The root region is written last; zeros hold its place.
    const std::string zeros(kRootRegion, '\0');
    writeAllAt(fd, zeros.data(), zeros.size(), 0, impl_->path);
    end_ = kRootRegion;
}

PmtilesWriter::~PmtilesWriter() = default;

void PmtilesWriter::add(uint64_t tile_id, std::span<const uint8_t> bytes)
{
    Impl& m = *impl_;
    if (m.finished)
        throw Error(m.path + ": tile added after the archive was finished");
    if (!m.entries.empty() && tile_id <= m.entries.back().tile_id + m.entries.back().run_length - 1)
        throw Error(m.path + ": tile id " + std::to_string(tile_id) + " not above the last one");
    if (bytes.empty() || bytes.size() > UINT32_MAX)
        throw Error(m.path + ": tile of " + std::to_string(bytes.size()) + " bytes");
    const uint64_t hash = fnv1a64(bytes.data(), bytes.size());
    std::optional<std::pair<uint64_t, uint32_t>> found;
    auto [first, last] = m.stored.equal_range(hash);
    for (auto it = first; it != last && !found; ++it) {
        if (it->second.second != bytes.size())
            continue;
        std::vector<uint8_t> there(bytes.size());
        readAllAt(m.fd, there.data(), there.size(), kRootRegion + it->second.first, m.path);
        if (std::equal(there.begin(), there.end(), bytes.begin()))
            found = it->second;
    }
    if (!found) {
        const uint64_t offset = end_ - kRootRegion;
        writeAllAt(m.fd, bytes.data(), bytes.size(), end_, m.path);
        end_ += bytes.size();
        found = std::pair(offset, uint32_t(bytes.size()));
        m.stored.emplace(hash, *found);
        ++m.contents;
    }
    Entry* previous = m.entries.empty() ? nullptr : &m.entries.back();
    if (previous && previous->offset == found->first &&
        previous->tile_id + previous->run_length == tile_id && previous->run_length < UINT32_MAX)
        ++previous->run_length; // the same tile again, next in line
    else
        m.entries.push_back({tile_id, found->first, found->second, 1});
    ++addressed_;
}

void PmtilesWriter::finish(const PmtilesHeader& h, const std::string& metadata_json)
{
    Impl& m = *impl_;
    if (m.finished)
        throw Error(m.path + ": archive finished twice");
    m.finished = true;
    const uint64_t data_length = end_ - kRootRegion;
    const std::string metadata = detail::gzipCompress(metadata_json);
    const uint64_t metadata_offset = end_;
    writeAllAt(m.fd, metadata.data(), metadata.size(), end_, m.path);
    end_ += metadata.size();

    // The root directory, or leaves of more and more entries until the root fits.
    std::string root = detail::gzipCompress(serialize(m.entries));
    std::string leaves;
    for (size_t leaf_size = 4096; kHeaderBytes + root.size() > kRootRegion; leaf_size *= 2) {
        leaves.clear();
        std::vector<Entry> root_entries;
        for (size_t at = 0; at < m.entries.size(); at += leaf_size) {
            const std::vector<Entry> part(
                m.entries.begin() + std::ptrdiff_t(at),
                m.entries.begin() + std::ptrdiff_t(std::min(at + leaf_size, m.entries.size())));
            const std::string leaf = detail::gzipCompress(serialize(part));
            root_entries.push_back({part.front().tile_id, leaves.size(), uint32_t(leaf.size()), 0});
            leaves += leaf;
        }
        root = detail::gzipCompress(serialize(root_entries));
    }
    const uint64_t leaves_offset = end_;
    writeAllAt(m.fd, leaves.data(), leaves.size(), end_, m.path);
    end_ += leaves.size();

    uint8_t header[kHeaderBytes] = {};
    std::memcpy(header, "PMTiles", 7);
    header[7] = 3;
    const uint64_t fields[11] = {kHeaderBytes,  root.size(),      metadata_offset, metadata.size(),
                                 leaves_offset, leaves.size(),    kRootRegion,     data_length,
                                 addressed_,    m.entries.size(), m.contents};
    for (int i = 0; i < 11; ++i)
        putU64(header + 8 + 8 * i, fields[i]);
    header[96] = 1; // clustered: tile data in tile-id order
    header[97] = uint8_t(PmtilesCompression::Gzip);
    header[98] = uint8_t(h.tile_compression);
    header[99] = uint8_t(h.tile_type);
    header[100] = uint8_t(h.min_zoom);
    header[101] = uint8_t(h.max_zoom);
    putI32(header + 102, e7(h.bounds.west));
    putI32(header + 106, e7(h.bounds.south));
    putI32(header + 110, e7(h.bounds.east));
    putI32(header + 114, e7(h.bounds.north));
    header[118] = uint8_t(h.center_zoom);
    putI32(header + 119, e7(h.center_lon));
    putI32(header + 123, e7(h.center_lat));
    writeAllAt(m.fd, header, kHeaderBytes, 0, m.path);
    writeAllAt(m.fd, root.data(), root.size(), kHeaderBytes, m.path);
}

struct PmtilesReader::Impl {
    std::string path;
    int fd = -1;
    uint64_t size = 0;
    PmtilesHeader header;
    std::string metadata;
    uint64_t root_offset = 0, root_length = 0, leaves_offset = 0, leaves_length = 0,
             data_offset = 0, data_length = 0, addressed = 0, entries = 0, contents = 0;
    bool clustered = false;
    PmtilesCompression internal = PmtilesCompression::None;
    std::vector<Entry> root;

    ~Impl()
    {
        if (fd >= 0)
            ::close(fd);
    }
    std::string section(uint64_t offset, uint64_t length, const char* what) const
    {
        if (offset > size || length > size - offset)
            throw Error(path + ": " + what + " (" + std::to_string(length) + " bytes at " +
                        std::to_string(offset) + ") lies past the file's " + std::to_string(size) +
                        " bytes");
        std::string out(length, '\0');
        readAllAt(fd, out.data(), out.size(), offset, path);
        return out;
    }
    std::string inflate(const std::string& bytes) const
    {
        if (internal != PmtilesCompression::Gzip)
            return bytes;
        try {
            return detail::gzipDecompress(bytes, kMaxDirectoryBytes);
        } catch (const Error& e) {
            throw Error(path + ": " + e.what());
        }
    }
    std::vector<Entry> directory(uint64_t offset, uint64_t length, const char* what) const
    {
        std::vector<Entry> d = deserialize(inflate(section(offset, length, what)), path);
        for (const Entry& e : d) {
            const uint64_t limit = e.run_length == 0 ? leaves_length : data_length;
            if (e.offset > limit || e.length > limit - e.offset)
                throw Error(path + ": " + what + " entry for tile id " + std::to_string(e.tile_id) +
                            " points past its section");
        }
        return d;
    }
};

PmtilesReader::PmtilesReader(const std::string& path) : impl_(std::make_unique<Impl>())
{
    Impl& m = *impl_;
    m.path = path;
    m.fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
    if (m.fd < 0)
        throw Error(path + ": cannot open: " + std::strerror(errno));
    struct stat st {};
    if (::fstat(m.fd, &st) != 0 || !S_ISREG(st.st_mode))
        throw Error(path + ": not a regular file");
    m.size = uint64_t(st.st_size);
    if (m.size < kHeaderBytes)
        throw Error(path + ": " + std::to_string(m.size) + " bytes, shorter than a PMTiles header");
    uint8_t h[kHeaderBytes];
    readAllAt(m.fd, h, kHeaderBytes, 0, path);
    if (std::memcmp(h, "PMTiles", 7) != 0)
        throw Error(path + ": not a PMTiles archive (no magic)");
    if (h[7] != 3)
        throw Error(path + ": PMTiles version " + std::to_string(h[7]) + ", not 3");
    uint64_t f[11];
    for (int i = 0; i < 11; ++i)
        f[i] = getU64(h + 8 + 8 * i);
    m.root_offset = f[0];
    m.root_length = f[1];
    m.leaves_offset = f[4];
    m.leaves_length = f[5];
    m.data_offset = f[6];
    m.data_length = f[7];
    m.addressed = f[8];
    m.entries = f[9];
    m.contents = f[10];
    if (h[96] > 1)
        throw Error(path + ": clustered flag " + std::to_string(h[96]));
    m.clustered = h[96] == 1;
    if (h[97] != uint8_t(PmtilesCompression::None) && h[97] != uint8_t(PmtilesCompression::Gzip))
        throw Error(path + ": internal compression " + std::to_string(h[97]) +
                    " (ridge reads none and gzip)");
    m.internal = PmtilesCompression(h[97]);
    if (h[98] > 4 || h[99] > 5)
        throw Error(path + ": unknown tile compression or type");
    m.header.tile_compression = PmtilesCompression(h[98]);
    m.header.tile_type = PmtilesType(h[99]);
    m.header.min_zoom = h[100];
    m.header.max_zoom = h[101];
    if (m.header.min_zoom > m.header.max_zoom || m.header.max_zoom > kPmtilesMaxZoom)
        throw Error(path + ": zooms " + std::to_string(m.header.min_zoom) + " to " +
                    std::to_string(m.header.max_zoom));
    m.header.bounds = {getI32(h + 102) / 1e7, getI32(h + 106) / 1e7, getI32(h + 110) / 1e7,
                       getI32(h + 114) / 1e7};
    const GeoRect& b = m.header.bounds;
    if (!(b.west >= -180 && b.east <= 180 && b.south >= -90 && b.north <= 90 && b.west <= b.east &&
          b.south <= b.north))
        throw Error(path + ": bounds out of range");
    m.header.center_zoom = h[118];
    m.header.center_lon = getI32(h + 119) / 1e7;
    m.header.center_lat = getI32(h + 123) / 1e7;
    if (m.data_offset > m.size || m.data_length > m.size - m.data_offset)
        throw Error(path + ": tile data lies past the end of the file");
    if (m.leaves_offset > m.size || m.leaves_length > m.size - m.leaves_offset)
        throw Error(path + ": leaf directories lie past the end of the file");
    m.metadata = m.inflate(m.section(f[2], f[3], "metadata"));
    m.root = m.directory(m.root_offset, m.root_length, "root directory");
}

PmtilesReader::~PmtilesReader() = default;
const PmtilesHeader& PmtilesReader::header() const
{
    return impl_->header;
}
const std::string& PmtilesReader::metadata() const
{
    return impl_->metadata;
}
uint64_t PmtilesReader::addressedTiles() const
{
    return impl_->addressed;
}
uint64_t PmtilesReader::tileEntries() const
{
    return impl_->entries;
}
uint64_t PmtilesReader::tileContents() const
{
    return impl_->contents;
}
bool PmtilesReader::clustered() const
{
    return impl_->clustered;
}

std::optional<std::vector<uint8_t>> PmtilesReader::tile(TileKey k) const
{
    const Impl& m = *impl_;
    const uint64_t id = pmtilesTileId(k);
    std::vector<Entry> leaf;
    const std::vector<Entry>* directory = &m.root;
    for (int depth = 0; depth <= kMaxLeafDepth; ++depth) {
        const Entry* e = findEntry(*directory, id);
        if (!e)
            return std::nullopt;
        if (e->run_length > 0) {
            const std::string bytes = m.section(m.data_offset + e->offset, e->length, "tile");
            return std::vector<uint8_t>(bytes.begin(), bytes.end());
        }
        leaf = m.directory(m.leaves_offset + e->offset, e->length, "leaf directory");
        directory = &leaf;
    }
    throw Error(m.path + ": leaf directories nested deeper than " + std::to_string(kMaxLeafDepth));
}

} // namespace ridge::web
