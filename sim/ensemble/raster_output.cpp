// Rasters out through GDAL (see raster_output.h). An in-memory dataset on the DEM's grid is
// filled and handed to the GeoTIFF or ESRI ASCII driver's CreateCopy, so both formats come
// from the same pixels and georeference.
#include "sim/ensemble/raster_output.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>

#include <cmath>
#include <filesystem>
#include <mutex>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"

namespace vf {

void writeRaster(const std::string& path, RasterFormat format, const std::vector<double>& values,
                 int nx, int ny, const std::string& demPath, const std::string& crsWkt) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  gdal::QuietErrors errors;
  if (values.size() != static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny))
    throw InputError(path, "raster has the wrong number of values");
  gdal::Dataset dem;
  dem.h = GDALOpen(demPath.c_str(), GA_ReadOnly);
  if (!dem.h) throw InputError(demPath, "cannot read the DEM's georeference: " + errors.last());
  if (GDALGetRasterXSize(dem.h) != nx || GDALGetRasterYSize(dem.h) != ny)
    throw InputError(demPath, "DEM size differs from the statistics' grid");
  double gt[6];
  if (GDALGetGeoTransform(dem.h, gt) != CE_None)
    throw InputError(demPath, "DEM has no geotransform");

  gdal::Dataset mem;
  mem.h = GDALCreate(GDALGetDriverByName("MEM"), "", nx, ny, 1, GDT_Float64, nullptr);
  if (!mem.h) throw InputError(path, "cannot create the raster: " + errors.last());
  GDALSetGeoTransform(mem.h, gt);
  const bool hasCrs = !crsWkt.empty();
  if (hasCrs) GDALSetProjection(mem.h, crsWkt.c_str());
  GDALRasterBandH band = GDALGetRasterBand(mem.h, 1);
  GDALSetRasterNoDataValue(band, kRasterNoData);
  // Our rows run from the south, GDAL's from the north.
  std::vector<double> row(static_cast<std::size_t>(nx));
  for (int line = 0; line < ny; ++line) {
    const std::size_t j = static_cast<std::size_t>(ny - 1 - line);
    for (int i = 0; i < nx; ++i) {
      const double v = values[j * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
      row[static_cast<std::size_t>(i)] = std::isnan(v) ? kRasterNoData : v;
    }
    if (GDALRasterIO(band, GF_Write, 0, line, nx, 1, row.data(), nx, 1, GDT_Float64, 0, 0) !=
        CE_None)
      throw InputError(path, "cannot fill the raster: " + errors.last());
  }
  const bool tiff = format == RasterFormat::kGeoTiff;
  GDALDriverH driver = GDALGetDriverByName(tiff ? "GTiff" : "AAIGrid");
  // GeoTIFF: compressed losslessly; ESRI ASCII: 10 significant digits.
  const char* tiffOptions[] = {"COMPRESS=DEFLATE", nullptr};
  const char* asciiOptions[] = {"SIGNIFICANT_DIGITS=10", nullptr};
  gdal::Dataset out;
  out.h = GDALCreateCopy(driver, path.c_str(), mem.h, FALSE,
                         const_cast<char**>(tiff ? tiffOptions : asciiOptions), nullptr, nullptr);
  if (!out.h) throw InputError(path, "cannot write the raster: " + errors.last());
  GDALClose(out.h);
  out.h = nullptr;
  if (CPLGetLastErrorType() >= CE_Failure)
    throw InputError(path, "cannot write the raster: " + errors.last());
  if (!tiff && hasCrs) {
    std::filesystem::path prj(path);
    prj.replace_extension(".prj");
    std::error_code ec;
    std::filesystem::remove(prj, ec);
  }
}

}  // namespace vf
