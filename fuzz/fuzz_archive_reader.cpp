// libFuzzer target: opening and reading a whole .ridge archive from arbitrary bytes.
// Property: every failure is a ridge::Error (a clear message), never a crash, a hang, an
// out-of-bounds access or an unbounded allocation. Seed it with real archives
// (scripts/fuzz.sh builds some from tests/data).
#include "memory_file.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"

#include <cstdint>
#include <string>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    // The reader works on files (pread): one memory file per fuzzing process.
    static const ridge::fuzz::MemoryFile file;
    file.write(data, size);
    try {
        const ridge::archive::ArchiveReader reader(file.path());
        const int n = reader.geometry().patchSize();
        if (reader.geometry().patchCount() > 4096 || n > 257)
            return 0; // valid but too big to be worth decoding in a fuzzing loop
        std::vector<uint16_t> codes(static_cast<size_t>(n) * n);
        std::vector<float> block_errors;
        for (int64_t i = 0; i < reader.geometry().patchCount(); ++i) {
            const ridge::PatchId p = reader.geometry().patchAt(i);
            try {
                reader.decodePatch(p, codes.data(), nullptr, &block_errors);
            } catch (const ridge::Error&) {
            }
            try { // the validity mask (format v2) on its own
                const ridge::PatchValidity v = reader.readValidity(p);
                if (v.kind == ridge::PatchValidity::Kind::Mixed &&
                    (v.samples.size() != size_t(n) * n ||
                     v.cells.size() != size_t(n - 1) * (n - 1)))
                    __builtin_trap();
            } catch (const ridge::Error&) {
            }
        }
    } catch (const ridge::Error&) {
    }
    return 0;
}
