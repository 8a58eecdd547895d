// The validity mask of format version 2 (docs/FORMAT.md, "Validity mask"): every field is
// checked when a blob is decoded, with a message naming the archive, the patch and the field,
// and masks ridge writes round-trip exactly.
#include "archive_bytes.h"
#include "test_support.h"

#include "ridge/archive/archive_reader.h"
#include "ridge/archive/validity_storage.h"
#include "ridge/core/error.h"
#include "ridge/pipeline/build.h"
#include "ridge/pipeline/verify.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <zstd.h>

#include <functional>

#include <algorithm>
#include <cstring>
#include <string>

using namespace ridge;
using archive::packValidity;
using archive::unpackValidity;

namespace {

constexpr int kN = 17, kC = 16;

// A mask with a nodata corner: samples x + y < 6 invalid, cells drawable where all four
// corners are valid (what the finest level stores).
PatchValidity cornerMask()
{
    PatchValidity v;
    v.kind = PatchValidity::Kind::Mixed;
    v.patch_size = kN;
    v.samples.resize(kN * kN);
    v.cells.resize(kC * kC);
    for (int j = 0; j < kN; ++j)
        for (int i = 0; i < kN; ++i)
            v.samples[j * kN + i] = i + j >= 6;
    for (int j = 0; j < kC; ++j)
        for (int i = 0; i < kC; ++i)
            v.cells[j * kC + i] = v.samples[j * kN + i] && v.samples[(j + 1) * kN + i + 1] &&
                                  v.samples[j * kN + i + 1] && v.samples[(j + 1) * kN + i];
    return v;
}

std::string problemOf(const std::vector<uint8_t>& bytes, bool corners_rule = true)
{
    PatchValidity out;
    size_t consumed = 0;
    return unpackValidity(bytes.data(), bytes.size(), kN, corners_rule, out, consumed);
}

// A kind-2 mask around a zstd frame of `raw`.
std::vector<uint8_t> bitmapMask(const std::vector<uint8_t>& raw)
{
    std::vector<uint8_t> frame(ZSTD_compressBound(raw.size()));
    frame.resize(ZSTD_compress(frame.data(), frame.size(), raw.data(), raw.size(), 3));
    std::vector<uint8_t> out(5 + frame.size());
    out[0] = 2;
    const uint32_t size = static_cast<uint32_t>(frame.size());
    std::memcpy(out.data() + 1, &size, 4);
    std::copy(frame.begin(), frame.end(), out.begin() + 5);
    return out;
}

// The raw bit planes of cornerMask().
std::vector<uint8_t> cornerBits()
{
    const PatchValidity v = cornerMask();
    std::vector<uint8_t> raw((kN * kN + kC * kC + 7) / 8, 0);
    size_t bit = 0;
    for (const auto* plane : {&v.samples, &v.cells})
        for (uint8_t b : *plane) {
            if (b)
                raw[bit / 8] |= uint8_t(1u << (bit % 8));
            ++bit;
        }
    return raw;
}

} // namespace

TEST(ValidityMask, RoundTripsAndUniformMasksTakeOneByte)
{
    const PatchValidity v = cornerMask();
    const std::vector<uint8_t> bytes = packValidity(v, kN);
    ASSERT_GT(bytes.size(), 5u);
    EXPECT_EQ(bytes[0], 2);
    PatchValidity back;
    size_t consumed = 0;
    ASSERT_EQ(unpackValidity(bytes.data(), bytes.size(), kN, true, back, consumed), "");
    EXPECT_EQ(consumed, bytes.size());
    EXPECT_EQ(back.samples, v.samples);
    EXPECT_EQ(back.cells, v.cells);
    EXPECT_EQ(bitmapMask(cornerBits()), bytes); // the documented layout, bit for bit

    PatchValidity all = v;
    std::fill(all.samples.begin(), all.samples.end(), 1);
    std::fill(all.cells.begin(), all.cells.end(), 1);
    EXPECT_EQ(packValidity(all, kN), std::vector<uint8_t>{0});
    PatchValidity none = v;
    std::fill(none.samples.begin(), none.samples.end(), 0);
    std::fill(none.cells.begin(), none.cells.end(), 0);
    EXPECT_EQ(packValidity(none, kN), std::vector<uint8_t>{1});
}

TEST(ValidityMask, EveryFieldIsCheckedAndNamed)
{
    const std::vector<uint8_t> good = bitmapMask(cornerBits());
    ASSERT_EQ(problemOf(good), "");
    EXPECT_NE(problemOf({}).find("validity mask missing"), std::string::npos);
    EXPECT_NE(problemOf({3}).find("validity kind is 3"), std::string::npos);
    EXPECT_NE(problemOf({255}).find("validity kind is 255"), std::string::npos);
    EXPECT_NE(problemOf({2, 1, 0}).find("frame_size missing"), std::string::npos);

    std::vector<uint8_t> bad = good;
    bad[1] += 1; // frame_size past what the blob holds
    EXPECT_NE(problemOf(bad).find("validity frame_size"), std::string::npos) << problemOf(bad);
    bad = good;
    bad.push_back(0); // a trailing byte inside frame_size
    bad[1] += 1;
    EXPECT_NE(problemOf(bad).find("not exactly one zstd frame"), std::string::npos)
        << problemOf(bad);
    bad = good;
    bad[1] -= 1; // a frame cut short
    EXPECT_NE(problemOf(bad), "");

    // Content of the wrong size, one byte short and one too many.
    std::vector<uint8_t> raw = cornerBits();
    raw.pop_back();
    EXPECT_NE(problemOf(bitmapMask(raw)).find("content size is"), std::string::npos);
    raw = cornerBits();
    raw.push_back(0);
    EXPECT_NE(problemOf(bitmapMask(raw)).find("content size is"), std::string::npos);

    // Padding bits past the last cell bit: (17² + 16²) = 545 bits, 7 padding bits.
    raw = cornerBits();
    raw.back() |= 0x80;
    EXPECT_NE(problemOf(bitmapMask(raw)).find("non-zero bit past its last"), std::string::npos);

    // Uniform bitmaps have a one-byte encoding; the bitmap form of them is not canonical.
    raw.assign(raw.size(), 0);
    EXPECT_NE(problemOf(bitmapMask(raw)).find("must be stored as kind 1"), std::string::npos);
    raw.assign(raw.size(), 0xff);
    raw.back() = 0x01; // bit 544 is the last
    EXPECT_NE(problemOf(bitmapMask(raw)).find("must be stored as kind 0"), std::string::npos);

    // A drawable cell with an invalid corner.
    PatchValidity v = cornerMask();
    v.cells[0] = 1;
    const std::vector<uint8_t> drawn = packValidity(v, kN);
    EXPECT_NE(problemOf(drawn).find("cell (0, 0) is drawable but a corner"), std::string::npos);
    EXPECT_EQ(problemOf(drawn, false), ""); // Neville's coarse levels have no such rule
}

TEST(ValidityMask, CorruptMasksInAnArchiveAreRefusedNamingTheFileAndPatch)
{
    test::ScratchDir dir;
    const std::string path = dir.path("utm.ridge");
    BuildOptions o;
    o.patch_size = 17;
    buildArchive(test::dataPath("everest_utm44.tif"), path, o);
    const archive::ArchiveReader reader(path);
    // A patch with a bitmap and one with kind 0.
    PatchId mixed{-1, 0, 0}, whole{-1, 0, 0};
    for (int64_t i = 0; i < reader.geometry().patchCount(); ++i) {
        const PatchId p = reader.geometry().patchAt(i);
        const PatchValidity v = reader.readValidity(p);
        if (v.kind == PatchValidity::Kind::Mixed && mixed.level < 0)
            mixed = p;
        if (v.kind == PatchValidity::Kind::AllValid && p.level == reader.geometry().finestLevel())
            whole = p;
    }
    ASSERT_GE(mixed.level, 0);
    ASSERT_GE(whole.level, 0);
    const std::string crafted = dir.path("crafted.ridge");
    auto maskOffset = [&](PatchId p) {
        const archive::PatchRecord& r = reader.record(p);
        return static_cast<size_t>(r.offset + r.block_errors_size);
    };
    auto craft = [&](PatchId p, size_t delta, uint8_t value) {
        test::ArchiveBytes bytes(path);
        bytes.bytes()[maskOffset(p) + delta] = value;
        bytes.reseal(); // past the blob's CRC: only the mask's own checks stand
        bytes.save(crafted);
        const archive::ArchiveReader damaged(crafted);
        std::vector<uint16_t> codes(17 * 17);
        try {
            damaged.decodePatch(p, codes.data());
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    const std::string name = crafted + ": " + archive::ArchiveReader::patchName(mixed);
    std::string m = craft(mixed, 0, 9);
    EXPECT_EQ(m.rfind(name + ": validity kind is 9", 0), 0u) << m;
    m = craft(mixed, 1,
              uint8_t(reader.readBlob(mixed)[reader.record(mixed).block_errors_size + 1] + 1));
    EXPECT_EQ(m.rfind(name + ": validity frame", 0), 0u) << m;
    // Kind 0 in front of a bitmap: the bitmap's bytes become the sample flags (version 4) and
    // the payload, neither of which they are.
    m = craft(mixed, 0, 0);
    EXPECT_TRUE(m.rfind(name + ": sample flags", 0) == 0 ||
                m.rfind(name + ": cannot decode", 0) == 0)
        << m;

    // A mask that decodes but lies (kind 1 on a patch of data) is what verify --source sees.
    test::ArchiveBytes bytes(path);
    bytes.bytes()[maskOffset(whole)] = 1;
    bytes.reseal();
    bytes.save(crafted);
    VerifyOptions v;
    v.source = test::dataPath("everest_utm44.tif");
    const VerifyReport report = verifyArchive(crafted, v);
    ASSERT_FALSE(report.ok());
    // (Its parents' masks no longer follow from it either: verify says so too.)
    EXPECT_TRUE(std::any_of(report.problems.begin(), report.problems.end(),
                            [](const std::string& p) {
                                return p.find("kept as nodata where the source") !=
                                       std::string::npos;
                            }))
        << report.problems.front();
}

TEST(ValidityMask, TheMetadataCountsAndModeAreCheckedOnOpen)
{
    test::ScratchDir dir;
    const std::string path = dir.path("utm.ridge");
    BuildOptions o;
    o.patch_size = 33;
    buildArchive(test::dataPath("everest_utm44.tif"), path, o);
    const std::string crafted = dir.path("crafted.ridge");
    auto openWith = [&](const std::function<void(nlohmann::json&)>& change) {
        test::ArchiveBytes bytes(path);
        nlohmann::json j = nlohmann::json::parse(bytes.metadata());
        change(j);
        bytes.setMetadata(j.dump(2));
        bytes.reseal();
        bytes.save(crafted);
        try {
            const archive::ArchiveReader reader(crafted);
            return std::string();
        } catch (const Error& e) {
            return std::string(e.what());
        }
    };
    EXPECT_EQ(openWith([](nlohmann::json&) {}), "");
    const int64_t samples = 285 * 222;
    std::string m = openWith([](nlohmann::json& j) { j["source"]["fill_voids"] = "some"; });
    EXPECT_NE(m.find("source.fill_voids is \"some\""), std::string::npos) << m;
    m = openWith([&](nlohmann::json& j) { j["source"]["voids_kept"] = samples + 1; });
    EXPECT_NE(m.find("source.voids_kept is " + std::to_string(samples + 1)), std::string::npos)
        << m;
    m = openWith([](nlohmann::json& j) { j["source"]["fill_voids"] = "all"; });
    EXPECT_NE(m.find("must be 0"), std::string::npos) << m;
    m = openWith([](nlohmann::json& j) { j["source"].erase("voids_kept"); });
    EXPECT_NE(m.find("source.voids_kept is missing"), std::string::npos) << m;
    m = openWith([](nlohmann::json& j) { j["source"]["nodata"] = "x"; });
    EXPECT_NE(m.find("source.nodata is"), std::string::npos) << m;
    for (const std::string& message : {m})
        EXPECT_EQ(message.rfind(crafted + ": metadata: ", 0), 0u) << message;
}
