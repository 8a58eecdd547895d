#include "ridge/io/dataset_files.h"

#include "gdal_support.h"

#include <cpl_string.h>

#include <algorithm>

namespace ridge::io {

std::vector<std::string> datasetFiles(const std::string& path)
{
    std::vector<std::string> files{path};
    detail::ensureGdalRegistered();
    // Swallows GDAL's messages: a dataset that cannot be opened is the ingest's to report.
    const detail::GdalErrorCapture capture;
    const detail::DatasetPtr ds(
        GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr));
    if (!ds)
        return files;
    const CPLStringList list(GDALGetFileList(ds.get()), TRUE);
    for (int k = 0; k < list.size(); ++k)
        if (std::find(files.begin(), files.end(), list[k]) == files.end())
            files.emplace_back(list[k]);
    return files;
}

} // namespace ridge::io
