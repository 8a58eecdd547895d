// libFuzzer target: what a sharded build's steps read from other processes — a plan
// (loadPlan) and a shard file (ShardFileReader) — on arbitrary bytes. Property: each is
// accepted or refused with ridge::Error, and every section a file that opened lists is read
// or refused the same way: never a read out of bounds or an allocation past the file.
#include "memory_file.h"

#include "ridge/archive/shard_file.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/shard.h"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    static const ridge::fuzz::MemoryFile file;
    file.write(data, size);
    try {
        const ridge::ShardPlan plan = ridge::loadPlan(file.path());
        (void)plan.geometry();
    } catch (const ridge::Error&) {
    }
    try {
        const ridge::archive::ShardFileReader reader(file.path());
        using ridge::archive::shardTag;
        for (const uint32_t t : {shardTag("INFO"), shardTag("ROOT"), shardTag("RFLG"),
                                 shardTag("OBSV"), shardTag("CODC"), shardTag("PRNT"),
                                 shardTag("RECS"), shardTag("BLOB"), shardTag("TABL")}) {
            try {
                (void)reader.read(t, 1 << 20);
                uint8_t byte;
                reader.readAt(t, reader.sectionSize(t) / 2, &byte, 1);
            } catch (const ridge::Error&) {
            }
        }
    } catch (const ridge::Error&) {
    }
    return 0;
}
