// fileIdentity / refuseOutputOverInput: the same file is recognised whatever path reaches it.
#include "ridge/core/error.h"
#include "ridge/core/file_identity.h"

#include "test_support.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

using namespace ridge;
namespace fs = std::filesystem;

namespace {

std::string writeFile(const test::ScratchDir& dir, const std::string& name, const std::string& text)
{
    const std::string path = dir.path(name);
    std::ofstream(path, std::ios::binary) << text;
    return path;
}

std::string refusal(const std::string& output, const std::vector<std::string>& inputs)
{
    try {
        refuseOutputOverInput(output, inputs);
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

} // namespace

TEST(FileIdentity, IsTheSameThroughDotSlashParentDirectorySymlinkAndHardLink)
{
    test::ScratchDir dir;
    const std::string a = writeFile(dir, "a.tif", "A");
    fs::create_directory(dir.path("sub"));
    fs::create_symlink(a, dir.path("link.tif"));
    fs::create_hard_link(a, dir.path("hard.tif"));
    const auto id = fileIdentity(a);
    ASSERT_TRUE(id);
    EXPECT_EQ(fileIdentity((dir.dir() / "." / "a.tif").string()), id);
    EXPECT_EQ(fileIdentity((dir.dir() / "sub" / ".." / "a.tif").string()), id);
    EXPECT_EQ(fileIdentity(dir.path("link.tif")), id);
    EXPECT_EQ(fileIdentity(dir.path("hard.tif")), id);
}

TEST(FileIdentity, DiffersBetweenFilesAndIsAbsentForMissingPathsAndDanglingLinks)
{
    test::ScratchDir dir;
    const std::string a = writeFile(dir, "a", "same bytes");
    const std::string b = writeFile(dir, "b", "same bytes");
    EXPECT_NE(fileIdentity(a), fileIdentity(b));
    EXPECT_FALSE(fileIdentity(dir.path("missing")));
    EXPECT_FALSE(fileIdentity(""));
    fs::create_symlink(dir.path("nowhere"), dir.path("dangling"));
    EXPECT_FALSE(fileIdentity(dir.path("dangling")));
}

TEST(RefuseOutputOverInput, NamesBothPathsWhenTheOutputIsAnInputByAnyPath)
{
    test::ScratchDir dir;
    const std::string in = writeFile(dir, "in.ridge", "archive");
    fs::create_symlink(in, dir.path("link.ridge"));
    fs::create_hard_link(in, dir.path("hard.ridge"));
    for (const std::string& out : {in, (dir.dir() / "." / "in.ridge").string(),
                                   dir.path("link.ridge"), dir.path("hard.ridge")}) {
        const std::string message = refusal(out, {dir.path("other"), in});
        EXPECT_NE(message.find(out + ":"), std::string::npos) << message;
        EXPECT_NE(message.find(in), std::string::npos) << message;
        EXPECT_NE(message.find("same file"), std::string::npos) << message;
    }
    // A relative output reaching the input from the working directory.
    const fs::path cwd = fs::current_path();
    fs::current_path(dir.dir());
    EXPECT_NE(refusal("./in.ridge", {in}), "");
    fs::current_path(cwd);
}

TEST(RefuseOutputOverInput, AcceptsNewOutputsOtherFilesAndDanglingSymlinks)
{
    test::ScratchDir dir;
    const std::string in = writeFile(dir, "in.ridge", "archive");
    const std::string other = writeFile(dir, "other.ridge", "archive");
    fs::create_symlink(dir.path("nowhere"), dir.path("dangling"));
    EXPECT_EQ(refusal(dir.path("new.ridge"), {in}), "");
    EXPECT_EQ(refusal(other, {in}), "");
    EXPECT_EQ(refusal(dir.path("dangling"), {in}), "");
    EXPECT_EQ(refusal(in, {}), "");
    EXPECT_EQ(refusal(in, {"/vsizip/x.zip/in.tif"}), "");
}
