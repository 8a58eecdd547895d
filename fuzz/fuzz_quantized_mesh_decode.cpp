// libFuzzer target: the quantized-mesh-1.0 tile decoder on arbitrary bytes.
// Property: decoding returns a tile or throws ridge::Error, never reads out of bounds; a tile
// that decodes re-encodes, and that decodes to the same tile.
#include "ridge/core/error.h"
#include "ridge/web/quantized_mesh.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    ridge::web::QuantizedMesh tile;
    try {
        tile = ridge::web::decodeQuantizedMesh({data, size});
    } catch (const ridge::Error&) {
        return 0;
    }
    const std::vector<uint8_t> again = ridge::web::encodeQuantizedMesh(tile);
    const ridge::web::QuantizedMesh back = ridge::web::decodeQuantizedMesh(again);
    if (back.u != tile.u || back.v != tile.v || back.height != tile.height ||
        back.triangles != tile.triangles || back.west != tile.west || back.north != tile.north ||
        back.metadata != tile.metadata || back.water_mask != tile.water_mask)
        __builtin_trap();
    return 0;
}
