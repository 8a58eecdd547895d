// libFuzzer target: the PMTiles v3 reader (ridge's check of `ridge tiles` output) on arbitrary
// files. Property: opening returns an archive or throws ridge::Error, and any tile asked of
// an archive that opened is returned, absent, or refused with ridge::Error — never a read out
// of bounds, a hang in the leaf directories or an allocation past the file.
#include "memory_file.h"

#include "ridge/core/error.h"
#include "ridge/web/pmtiles.h"

#include <cstddef>
#include <cstdint>
#include <optional>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const ridge::fuzz::MemoryFile file;
    file.write(data, size);
    std::optional<ridge::web::PmtilesReader> reader;
    try {
        reader.emplace(file.path());
    } catch (const ridge::Error&) {
        return 0;
    }
    // Tiles at every zoom of the header, and ones it does not list.
    const int last = reader->header().max_zoom;
    for (int z = 0; z <= last + 1 && z <= ridge::web::kPmtilesMaxZoom; ++z)
        for (const int64_t x : {int64_t(0), (int64_t(1) << z) - 1})
            try {
                (void)reader->tile({z, x, 0});
            } catch (const ridge::Error&) {
            }
    return 0;
}
