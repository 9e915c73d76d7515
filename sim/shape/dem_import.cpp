// DEM input through GDAL (rasters are written by sim/ensemble/raster_output.cpp). Any raster
// GDAL reads (GeoTIFF, ESRI ASCII grids with xllcorner or xllcenter, ...) becomes a Heightfield;
// the hand-written ESRI reader this replaces handled one format and no CRS.
#include <cpl_conv.h>
#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <mutex>
#include <new>
#include <string>
#include <string_view>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"
#include "sim/shape/heightfield.h"

namespace vf {
namespace {

// GDAL 3.6's ESRI ASCII driver is lenient where a scene must not be: it fills a short grid
// with zeros, reads a non-number as 0 and skips an unknown header key (a typo `xlcorner`
// silently moves the grid). So an ASCII grid is checked first: known header keys, then exactly
// ncols x nrows numbers. GDAL still does the reading; this only refuses what it would guess.
void checkEsriAsciiGrid(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  int line = 1, tokenLine = 1;  // line of the last token read: where errors point
  auto next = [&](std::string_view& token) {
    while (pos < text.size() && std::isspace(static_cast<unsigned char>(text[pos])))
      line += text[pos++] == '\n';
    if (pos >= text.size()) return false;
    const std::size_t start = pos;
    tokenLine = line;
    while (pos < text.size() && !std::isspace(static_cast<unsigned char>(text[pos]))) ++pos;
    token = std::string_view(text).substr(start, pos - start);
    return true;
  };
  auto number = [](std::string_view t, double& v) {
    if (!t.empty() && t[0] == '+') t.remove_prefix(1);
    const auto r = std::from_chars(t.data(), t.data() + t.size(), v);
    return r.ec == std::errc() && r.ptr == t.data() + t.size();
  };
  auto fail = [&](const std::string& what) {
    return InputError(sourceLocation(path, tokenLine), what);
  };
  double ncols = 0, nrows = 0, v = 0;
  std::string_view token;
  while (next(token) && !number(token, v)) {
    std::string key(token);
    std::transform(key.begin(), key.end(), key.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    static const char* const kKeys[] = {"ncols",     "nrows",     "xllcorner", "xllcenter",
                                        "yllcorner", "yllcenter", "cellsize",  "nodata_value"};
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys))
      throw fail("unknown header key '" + std::string(token) +
                 "' (expected ncols, nrows, xllcorner|xllcenter, yllcorner|yllcenter, cellsize, "
                 "NODATA_value)");
    std::string_view value;
    if (!next(value) || !number(value, v))
      throw fail("header key '" + std::string(token) + "' needs a number");
    if (key == "ncols" || key == "nrows") {
      // A count of samples: whole, positive, and no more than GDAL's int holds (the product
      // then fits the messages' long long; a fuzz input asks for 4e18 rows).
      if (!(v >= 1 && v <= 2147483647.0 && v == std::floor(v)))
        throw fail("header key '" + std::string(token) + "' must be a whole number from 1 to " +
                   "2147483647, got " + std::string(value));
      (key == "ncols" ? ncols : nrows) = v;
    }
  }
  const double count = ncols * nrows;
  double n = 0;
  for (bool more = !token.empty() && pos <= text.size(); more; more = next(token)) {
    if (!number(token, v)) throw fail("'" + std::string(token) + "' is not a number");
    if (++n > count)
      throw fail("grid has more values than ncols x nrows = " +
                 std::to_string(static_cast<long long>(count)));
  }
  if (n < count)
    throw fail("grid has " + std::to_string(static_cast<long long>(n)) +
               " values; the header promises " + std::to_string(static_cast<long long>(count)));
}

}  // namespace

Heightfield loadDem(const std::string& path) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  gdal::QuietErrors errors;
  gdal::Dataset ds;
  // GDAL reads an ESRI ASCII grid with decimals as Float32 unless told otherwise: ask for
  // Float64 so heights keep every digit the file gives (the paper's cliff grid is exact to 1 mm
  // in double precision, and its trajectories are pinned bit for bit).
  const char* const asciiOptions[] = {"DATATYPE=Float64", nullptr};
  GDALDriverH driver = GDALIdentifyDriver(path.c_str(), nullptr);
  const bool ascii = driver && std::string(GDALGetDriverShortName(driver)) == "AAIGrid";
  if (ascii) checkEsriAsciiGrid(path);
  ds.h = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr,
                    ascii ? asciiOptions : nullptr, nullptr);
  if (!ds.h) throw InputError(path, "cannot read the terrain raster: " + errors.last());
  const int nx = GDALGetRasterXSize(ds.h), ny = GDALGetRasterYSize(ds.h);
  if (nx < 2 || ny < 2 || GDALGetRasterCount(ds.h) < 1)
    throw InputError(path, "terrain raster needs at least 2 x 2 samples and one band, got " +
                               std::to_string(nx) + " x " + std::to_string(ny));
  // The header's size is checked before anything is allocated: a broken or hostile header
  // (a 383-byte fuzz input that GDAL reads as 5.6e16 samples) must get a message,
  // not an allocation failure, and indices j * nx + i must fit in 32 bits (heightfield.h).
  const auto samples = static_cast<std::int64_t>(nx) * ny;
  if (samples > kMaxDemSamples)
    throw InputError(path, "terrain raster has " + std::to_string(nx) + " x " + std::to_string(ny) +
                               " samples, more than voxfall's limit of " +
                               std::to_string(kMaxDemSamples) +
                               "; crop or resample it (e.g. gdal_translate -projwin or -tr)");
  double gt[6];
  if (GDALGetGeoTransform(ds.h, gt) != CE_None)
    throw InputError(path, "terrain raster has no georeference (geotransform)");
  // North-up, square pixels: the Heightfield's grid is axis-aligned with one spacing.
  if (gt[2] != 0 || gt[4] != 0 || !(gt[1] > 0) || !(gt[5] < 0) ||
      std::abs(gt[1] + gt[5]) > 1e-9 * gt[1])
    throw InputError(path, "terrain raster must be north-up with square cells (geotransform " +
                               std::to_string(gt[1]) + ", " + std::to_string(gt[2]) + ", " +
                               std::to_string(gt[4]) + ", " + std::to_string(gt[5]) + ")");
  GDALRasterBandH band = GDALGetRasterBand(ds.h, 1);
  int hasNoData = 0;
  const double nodata = GDALGetRasterNoDataValue(band, &hasNoData);

  Heightfield h;
  h.nx = nx;
  h.ny = ny;
  h.cell = gt[1];
  h.x0 = gt[0] + 0.5 * gt[1];         // centre of the western column
  h.y0 = gt[3] + (ny - 0.5) * gt[5];  // centre of the southern row
  try {
    h.z.assign(static_cast<std::size_t>(nx) * ny, NAN);
  } catch (const std::bad_alloc&) {
    throw InputError(path, "not enough memory for the terrain raster's " + std::to_string(nx) +
                               " x " + std::to_string(ny) + " samples; crop or resample it");
  }
  // GDAL's rows run from the north; ours from the south: read with a negative line stride
  // into the last row first.
  double* last = h.z.data() + static_cast<std::size_t>(ny - 1) * nx;
  const GSpacing line = -static_cast<GSpacing>(sizeof(double)) * nx;
  if (GDALRasterIOEx(band, GF_Read, 0, 0, nx, ny, last, nx, ny, GDT_Float64, sizeof(double), line,
                     nullptr) != CE_None ||
      CPLGetLastErrorType() >= CE_Failure)
    throw InputError(path, "cannot read the terrain heights: " + errors.last());
  h.zMin = INFINITY;
  h.zMax = -INFINITY;
  for (double& v : h.z) {
    if ((hasNoData && v == nodata) || !std::isfinite(v)) v = NAN;
    if (!std::isnan(v)) h.zMin = std::min(h.zMin, v), h.zMax = std::max(h.zMax, v);
  }
  if (!std::isfinite(h.zMin))
    throw InputError(path, "terrain raster has no data (every value is NODATA)");
  if (const char* wkt = GDALGetProjectionRef(ds.h)) h.crsWkt = wkt;
  if (OGRSpatialReferenceH srs = GDALGetSpatialRef(ds.h)) {
    const char* name = OSRGetAuthorityName(srs, nullptr);
    const char* code = OSRGetAuthorityCode(srs, nullptr);
    if (name && code) h.crsName = std::string(name) + ":" + code;
  }
  return h;
}

}  // namespace vf
