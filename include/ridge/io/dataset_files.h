#pragma once
// The files GDAL reads for a dataset, so that outputs can be refused when they would replace
// any of them (ridge::refuseOutputOverInput): an ENVI .bil has its .hdr, a GeoTIFF may have
// a .aux.xml, .ovr or .msk, a world file, and so on.
#include <string>
#include <vector>

namespace ridge::io {

// `path` first, then every other file GDALGetFileList lists for the dataset opened read-only
// as a raster. Just {path} when GDAL cannot open it (the ingest that follows reports why).
// Never throws for a bad dataset; costs one GDAL open (headers only, no samples read).
// Thread-safe as GDAL's open is.
std::vector<std::string> datasetFiles(const std::string& path);

} // namespace ridge::io
