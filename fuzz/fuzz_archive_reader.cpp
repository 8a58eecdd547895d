// libFuzzer target: opening and reading a whole .ridge archive from arbitrary bytes.
// Property: every failure is a ridge::Error (a clear message), never a crash, a hang, an
// out-of-bounds access or an unbounded allocation. Seed it with real archives
// (scripts/fuzz.sh builds some from tests/data).
#include "ridge/archive/archive_reader.h"
#include "ridge/core/error.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <unistd.h>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    // The reader works on files (pread); one scratch file per fuzzing process.
    static const std::string path = "/tmp/ridge-fuzz-" + std::to_string(::getpid()) + ".ridge";
    if (std::FILE* f = std::fopen(path.c_str(), "wb")) {
        std::fwrite(data, 1, size, f);
        std::fclose(f);
    } else {
        return 0;
    }
    try {
        const ridge::archive::ArchiveReader reader(path);
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
        }
    } catch (const ridge::Error&) {
    }
    return 0;
}
