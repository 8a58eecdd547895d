// `ridge query`, the geographic camera options and `ridge info`'s corners as a user runs them,
// against GDAL's own reads and gdalinfo's output.
#include "test_support.h"

#include <gdal.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <sstream>

using namespace ridge;

namespace {

std::string quoted(const std::string& path)
{
    std::string q = "'";
    q += path;
    q += "'";
    return q;
}

// stdout only (the CLI's stderr notes dropped), for JSON.
test::CommandResult runStdout(const std::string& args)
{
    return test::runShell("{ " + std::string(RIDGE_CLI_PATH) + " " + args + " 2>/dev/null; }");
}

std::vector<double> readSource(const std::string& path, int& width, int& height)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path.c_str(), GA_ReadOnly);
    EXPECT_NE(ds, nullptr);
    width = GDALGetRasterXSize(ds);
    height = GDALGetRasterYSize(ds);
    std::vector<double> v(size_t(width) * height);
    EXPECT_EQ(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, width, height, v.data(), width,
                           height, GDT_Float64, 0, 0),
              CE_None);
    GDALClose(ds);
    return v;
}

std::string buildArchive(const test::ScratchDir& dir, const std::string& source,
                         const std::string& name)
{
    const std::string arc = dir.path(name);
    const test::CommandResult r = test::runRidge("build " + quoted(test::dataPath(source)) +
                                                 " -o " + quoted(arc) + " -q --patch 33");
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return arc;
}

// The "Corner Coordinates:" block of a gdalinfo-style text output.
std::string cornerBlock(const std::string& text)
{
    const size_t start = text.find("Corner Coordinates:");
    if (start == std::string::npos)
        return {};
    size_t end = start;
    for (int line = 0; line < 6 && end != std::string::npos; ++line)
        end = text.find('\n', end + 1);
    return text.substr(start, end - start);
}

} // namespace

TEST(QueryCli, BatchFromStdinEchoesEachPointAndExitsOneForOffRasterPoints)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    int w = 0, h = 0;
    const std::vector<double> src = readSource(test::dataPath("everest_crop.tif"), w, h);
    // Pixel centres of a lossless archive: GDAL's values exactly.
    std::ostringstream input;
    for (int k = 0; k < 20; ++k)
        input << (k * 37 % w) + 0.5 << " " << (k * 23 % h) + 0.5 << "\n";
    const test::CommandResult ok = test::runShell("printf '" + input.str() + "' | " +
                                                  RIDGE_CLI_PATH + " query --pixel " + quoted(arc));
    ASSERT_EQ(ok.exit_code, 0) << ok.output;
    std::istringstream lines(ok.output);
    std::string line;
    int k = 0;
    for (; std::getline(lines, line) && k < 20; ++k) {
        const int c = k * 37 % w, r = k * 23 % h;
        double value = NAN;
        char echo[64];
        std::snprintf(echo, sizeof echo, "%d.5 %d.5: ", c, r);
        ASSERT_EQ(line.rfind(echo, 0), 0u) << "echo: " << line;
        ASSERT_EQ(std::sscanf(line.c_str() + std::strlen(echo), "%lf m", &value), 1) << line;
        EXPECT_EQ(value, src[size_t(r) * w + c]) << line;
    }
    EXPECT_EQ(k, 20);

    // An off-raster point and a malformed line: notes, every other point answered, exit 1.
    const test::CommandResult mixed =
        test::runShell("printf '10.5 10.5\\n-3 10\\nten 10\\n\\n20.5 20.5\\n' | " +
                       std::string(RIDGE_CLI_PATH) + " query --pixel " + quoted(arc));
    EXPECT_EQ(mixed.exit_code, 1) << mixed.output;
    EXPECT_NE(mixed.output.find("-3 10: off the raster"), std::string::npos) << mixed.output;
    EXPECT_NE(mixed.output.find("ten 10: error: expected two numbers"), std::string::npos)
        << mixed.output;
    EXPECT_NE(mixed.output.find("20.5 20.5: "), std::string::npos) << mixed.output;
    EXPECT_NE(mixed.output.find("2 point(s) without a height"), std::string::npos) << mixed.output;
}

TEST(QueryCli, LonLatCrsAndJsonAgreeWithTheSource)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    int w = 0, h = 0;
    const std::vector<double> src = readSource(test::dataPath("everest_crop.tif"), w, h);
    // 86.925 E, 27.988 N: column 210, row 14.4 (pixel 210.5, line 14.9): bilinear between
    // rows 14 and 15; nearest (the default, as gdallocationinfo) the sample of pixel 210, 14.
    const double bilinear = 0.6 * src[14 * size_t(w) + 210] + 0.4 * src[15 * size_t(w) + 210];
    const double nearest = src[14 * size_t(w) + 210];
    for (const std::string& flags : {std::string("--lonlat"), std::string("")})
        for (const std::string& mode :
             {std::string(""), std::string("-r nearest"), std::string("--resampling bilinear")}) {
            const test::CommandResult r = runStdout("query " + flags + " " + mode + " --json " +
                                                    quoted(arc) + " 86.925 27.988");
            ASSERT_EQ(r.exit_code, 0) << r.output;
            const nlohmann::json j = nlohmann::json::parse(r.output);
            ASSERT_EQ(j["points"].size(), 1u);
            const nlohmann::json& p = j["points"][0];
            const bool is_bilinear = mode.find("bilinear") != std::string::npos;
            EXPECT_EQ(j["resampling"].get<std::string>(), is_bilinear ? "bilinear" : "nearest");
            EXPECT_TRUE(p["on_raster"].get<bool>());
            EXPECT_NEAR(p["height"].get<double>(), is_bilinear ? bilinear : nearest, 1e-6)
                << r.output;
            EXPECT_NEAR(p["pixel"][0].get<double>(), 210.5, 1e-6);
            EXPECT_NEAR(p["pixel"][1].get<double>(), 14.9, 1e-6);
        }
    const test::CommandResult cubic = test::runRidge("query -r cubic " + quoted(arc) + " 1 1");
    EXPECT_EQ(cubic.exit_code, 2) << cubic.output; // a usage error, named
    EXPECT_NE(cubic.output.find("cubic"), std::string::npos) << cubic.output;
    const test::CommandResult off = runStdout("query --lonlat --json " + quoted(arc) + " 80 27.9");
    EXPECT_EQ(off.exit_code, 1);
    const nlohmann::json j = nlohmann::json::parse(off.output);
    EXPECT_FALSE(j["points"][0]["on_raster"].get<bool>());
    EXPECT_TRUE(j["points"][0]["height"].is_null());
    EXPECT_EQ(j["failed"].get<int>(), 1);
    // A coarser level's surface, and a level that does not exist.
    const test::CommandResult coarse =
        runStdout("query --json --level 1 " + quoted(arc) + " 86.925 27.988");
    ASSERT_EQ(coarse.exit_code, 0) << coarse.output;
    EXPECT_EQ(nlohmann::json::parse(coarse.output)["points"][0]["level"].get<int>(), 1);
    const test::CommandResult deep = test::runRidge("query --level 9 " + quoted(arc) + " 1 1");
    EXPECT_EQ(deep.exit_code, 1);
    EXPECT_NE(deep.output.find("level"), std::string::npos) << deep.output;
    const test::CommandResult half = test::runRidge("query " + quoted(arc) + " 86.9");
    EXPECT_NE(half.exit_code, 0);
    EXPECT_NE(half.output.find("both X and Y"), std::string::npos) << half.output;
}

TEST(InfoCli, CornersAreGdalinfos)
{
    test::ScratchDir dir;
    for (const std::string source : {"everest_crop.tif", "everest_utm45.tif"}) {
        const std::string arc = buildArchive(dir, source, source + ".ridge");
        const test::CommandResult gdal =
            test::runShell("gdalinfo " + quoted(test::dataPath(source)));
        if (gdal.exit_code != 0)
            GTEST_SKIP() << "gdalinfo is not installed";
        const test::CommandResult ours = test::runRidge("info " + quoted(arc));
        ASSERT_EQ(ours.exit_code, 0) << ours.output;
        const std::string expected = cornerBlock(gdal.output);
        ASSERT_FALSE(expected.empty());
        EXPECT_EQ(cornerBlock(ours.output), expected) << ours.output;

        const nlohmann::json gj = nlohmann::json::parse(
            test::runShell("gdalinfo -json " + quoted(test::dataPath(source))).output);
        const nlohmann::json rj =
            nlohmann::json::parse(runStdout("info --json " + quoted(arc)).output);
        const auto& ring = gj["wgs84Extent"]["coordinates"][0]; // UL, LL, LR, UR
        const char* keys[] = {"upperLeft", "lowerLeft", "lowerRight", "upperRight"};
        for (int k = 0; k < 4; ++k) {
            for (int axis = 0; axis < 2; ++axis) {
                EXPECT_NEAR(rj["cornerCoordinates"][keys[k]][axis].get<double>(),
                            gj["cornerCoordinates"][keys[k]][axis].get<double>(), 1e-3)
                    << source << " " << keys[k];
                // gdalinfo rounds the WGS 84 extent to 7 decimals.
                EXPECT_NEAR(rj["cornerLonLat"][keys[k]][axis].get<double>(),
                            ring[k][axis].get<double>(), 6e-8)
                    << source << " " << keys[k];
            }
        }
    }
}

TEST(RenderCli, AGeographicCameraIsPlacedThroughProj)
{
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    const test::CommandResult r = runStdout(
        "render " + quoted(arc) + " -o " + quoted(dir.path("g.png")) +
        " --size 64x36 --json --camera-lonlat 86.925,27.988,9500 --heading 200 --pitch -20");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    // Column 210 of 3" pixels ≈ 82.03 m apart, row 14.4 of ≈ 92.35 m rows from the north.
    const nlohmann::json info =
        nlohmann::json::parse(runStdout("info --json " + quoted(arc)).output);
    const double sx = info["spacing_x"].get<double>(), sy = info["spacing_y"].get<double>();
    EXPECT_NEAR(j["camera"][0].get<double>(), 210.0 * sx, 1e-3);
    EXPECT_NEAR(j["camera"][1].get<double>(), (202.0 - 14.4) * sy, 1e-3);
    EXPECT_EQ(j["camera"][2].get<double>(), 9500.0);
    EXPECT_NEAR(j["heading_deg"].get<double>(), -160.0, 1e-9);
    EXPECT_NEAR(j["pitch_deg"].get<double>(), -20.0, 1e-9);
    // Both forms of one thing, or a lon/lat camera without a CRS, are refused by name.
    const test::CommandResult both =
        test::runRidge("render " + quoted(arc) + " -o " + quoted(dir.path("b.png")) +
                       " --camera 1,2,3 --camera-lonlat 86.9,27.9,9000");
    EXPECT_NE(both.exit_code, 0);
    EXPECT_NE(both.output.find("--camera-lonlat"), std::string::npos) << both.output;
}

TEST(QueryCli, NegativeCoordinatesArePositionalNumbersNotFlags)
{
    test::ScratchDir dir;
    const test::CommandResult build =
        test::runRidge("build " + quoted(test::dataPath("rainier_voids.tif")) + " -o " +
                       quoted(dir.path("r.ridge")) + " -q --patch 33");
    ASSERT_EQ(build.exit_code, 0) << build.output;
    const test::CommandResult r =
        runStdout("query --lonlat --json " + quoted(dir.path("r.ridge")) + " -121.5 46.7");
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const nlohmann::json j = nlohmann::json::parse(r.output);
    EXPECT_EQ(j["points"][0]["input"].get<std::string>(), "-121.5 46.7");
    EXPECT_TRUE(j["points"][0]["on_raster"].get<bool>());
    EXPECT_GT(j["points"][0]["height"].get<double>(), 347.0); // the crop's range: 347..1994 m
    EXPECT_LT(j["points"][0]["height"].get<double>(), 1994.0);
}

TEST(QueryCli, NearestIsGdallocationinfoAtEveryPoint)
{
    // A lossless archive of an Int16 source; random CRS points and points exactly on pixel
    // edges and corners (where the answer hangs on the inverse geotransform's last bit), fed
    // to both tools on stdin: the same value at every point.
    test::ScratchDir dir;
    if (test::runShell("gdallocationinfo --version").exit_code != 0)
        GTEST_SKIP() << "gdallocationinfo is not installed";
    for (const std::string source : {"everest_crop.tif", "everest_utm45.tif"}) {
        const std::string arc = buildArchive(dir, source, source + ".ridge");
        GDALAllRegister();
        GDALDatasetH ds = GDALOpen(test::dataPath(source).c_str(), GA_ReadOnly);
        ASSERT_NE(ds, nullptr);
        double gt[6];
        GDALGetGeoTransform(ds, gt);
        const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
        GDALClose(ds);
        std::mt19937 rng(29);
        std::uniform_real_distribution<double> u(0.0, 1.0);
        std::string input;
        char line[96];
        int points = 0;
        auto add = [&](double p, double l) {
            std::snprintf(line, sizeof line, "%.17g %.17g\n", gt[0] + p * gt[1] + l * gt[2],
                          gt[3] + p * gt[4] + l * gt[5]);
            input += line;
            ++points;
        };
        for (int k = 0; k < 2000; ++k)
            add(u(rng) * w, u(rng) * h);
        for (int i = 0; i < w; i += 3)
            for (int j = 0; j < h; j += 11)
                add(i, j);
        const std::string points_file = dir.path(source + ".txt");
        {
            std::FILE* f = std::fopen(points_file.c_str(), "w");
            ASSERT_NE(f, nullptr);
            std::fputs(input.c_str(), f);
            std::fclose(f);
        }
        const test::CommandResult gdal =
            test::runShell("gdallocationinfo -valonly -geoloc " + quoted(test::dataPath(source)) +
                           " < " + quoted(points_file));
        ASSERT_EQ(gdal.exit_code, 0) << gdal.output;
        const test::CommandResult ours =
            runStdout("query " + quoted(arc) + " < " + quoted(points_file));
        ASSERT_EQ(ours.exit_code, 0) << ours.output.substr(0, 2000);
        std::istringstream gdal_lines(gdal.output), our_lines(ours.output), inputs(input);
        std::string g, o, in;
        int compared = 0;
        while (std::getline(inputs, in)) {
            ASSERT_TRUE(std::getline(gdal_lines, g) && std::getline(our_lines, o)) << in;
            ASSERT_EQ(o.rfind(in + ": ", 0), 0u) << o;
            double value = NAN;
            ASSERT_EQ(std::sscanf(o.c_str() + in.size() + 2, "%lf m", &value), 1) << o;
            ASSERT_EQ(value, std::stod(g))
                << source << ": " << in << " -> ridge " << o << ", gdallocationinfo " << g;
            ++compared;
        }
        EXPECT_EQ(compared, points) << source;
    }
}

TEST(QueryCli, StdinAnswersEachPointBeforeTheNextArrives)
{
    // Batching must not hold an answer back while the writer waits for it: one line in,
    // its answer out, then the next line (a pipe kept open, as a program would).
    test::ScratchDir dir;
    const std::string arc = buildArchive(dir, "everest_crop.tif", "e.ridge");
    int to_child[2], from_child[2];
    ASSERT_EQ(pipe(to_child), 0);
    ASSERT_EQ(pipe(from_child), 0);
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
        dup2(to_child[0], STDIN_FILENO);
        dup2(from_child[1], STDOUT_FILENO);
        close(to_child[1]);
        close(from_child[0]);
        execl(RIDGE_CLI_PATH, RIDGE_CLI_PATH, "query", "--pixel", arc.c_str(), (char*)nullptr);
        _exit(127);
    }
    close(to_child[0]);
    close(from_child[1]);
    // However the test ends: the input closed (the CLI then ends), the child reaped.
    struct Child {
        pid_t pid;
        int& in;
        int out;
        int status = -1;
        ~Child()
        {
            if (in >= 0)
                close(in);
            if (pid > 0)
                waitpid(pid, &status, 0);
            close(out);
        }
    };
    int input = to_child[1];
    Child child{pid, input, from_child[0]};
    std::string received;
    for (const char* point : {"10.5 20.5\n", "30.5 40.5\n", "50.5 60.5\n"}) {
        ASSERT_EQ(write(input, point, std::strlen(point)), ssize_t(std::strlen(point)));
        // Its answer within 20 s (the CLI's start and one decode), the input still open.
        const size_t lines = size_t(std::count(received.begin(), received.end(), '\n'));
        while (size_t(std::count(received.begin(), received.end(), '\n')) == lines) {
            pollfd fd{from_child[0], POLLIN, 0};
            ASSERT_GT(poll(&fd, 1, 20000), 0) << "no answer to " << point << " while waiting";
            char buffer[256];
            const ssize_t n = read(from_child[0], buffer, sizeof buffer);
            ASSERT_GT(n, 0);
            received.append(buffer, size_t(n));
        }
    }
    close(input);
    input = -1;
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    child.pid = 0;
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
    EXPECT_NE(received.find("30.5 40.5: "), std::string::npos) << received;
}
