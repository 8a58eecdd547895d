#pragma once
// gdal_translate SRC DST ARGS through GDAL's own library (gdal_utils.h), for tests that make
// their inputs from the fixtures (a Float32 copy, a 3-band copy, a window) at run time.
#include <gdal.h>
#include <gdal_utils.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

namespace ridge::test {

inline void gdalTranslate(const std::string& src, const std::string& dst,
                          const std::vector<std::string>& args)
{
    GDALAllRegister();
    std::vector<char*> argv;
    for (const std::string& a : args)
        argv.push_back(const_cast<char*>(a.c_str()));
    argv.push_back(nullptr);
    GDALTranslateOptions* options = GDALTranslateOptionsNew(argv.data(), nullptr);
    ASSERT_NE(options, nullptr);
    GDALDatasetH in = GDALOpen(src.c_str(), GA_ReadOnly);
    ASSERT_NE(in, nullptr);
    int usage_error = 0;
    GDALDatasetH out = GDALTranslate(dst.c_str(), in, options, &usage_error);
    GDALTranslateOptionsFree(options);
    ASSERT_NE(out, nullptr);
    GDALClose(out);
    GDALClose(in);
}

} // namespace ridge::test
