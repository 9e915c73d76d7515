// Drape rasters through GDAL: gdalwarp (as a library call) for a georeferenced raster, one
// resampled read for one without a georeference. Both land in an in-memory dataset of the
// drape's size, read back bottom row first.
#include "sim/shape/drape_import.h"

#include <gdal.h>
#include <gdal_alg.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <mutex>
#include <string>
#include <vector>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"

namespace vf {
namespace {

using gdal::demExtent;
using gdal::Extent;
using gdal::runUtility;

// A size of about `w` x `h` texels, scaled down (keeping the shape) to kMaxDrapeSide.
std::array<int, 2> capped(double w, double h) {
  const double scale = std::min(1.0, kMaxDrapeSide / std::max(w, h));
  return {std::clamp(static_cast<int>(std::lround(w * scale)), 1, kMaxDrapeSide),
          std::clamp(static_cast<int>(std::lround(h * scale)), 1, kMaxDrapeSide)};
}

bool georeferenced(GDALDatasetH ds) {
  double gt[6];
  return GDALGetGeoTransform(ds, gt) == CE_None &&
         !(gt[0] == 0 && gt[1] == 1 && gt[2] == 0 && gt[3] == 0 && gt[4] == 0 && gt[5] == 1);
}

// The raster with a palette turned into red, green, blue bands (gdal_translate -expand rgb);
// otherwise null, and the source is used as it is.
GDALDatasetH expandPalette(GDALDatasetH src) {
  GDALRasterBandH band = GDALGetRasterBand(src, 1);
  if (GDALGetRasterColorInterpretation(band) != GCI_PaletteIndex) return nullptr;
  return runUtility<GDALTranslateOptions>(
      {"-of", "MEM", "-expand", "rgb"}, GDALTranslateOptionsNew,
      [&](GDALTranslateOptions* o, int* e) { return GDALTranslate("", src, o, e); },
      GDALTranslateOptionsFree);
}

// gdalwarp of a georeferenced raster onto the DEM's extent, in the DEM's CRS where both have
// one, with a coverage band; at the raster's own resolution there, capped.
GDALDatasetH warpOntoDem(GDALDatasetH src, const Heightfield& h) {
  const Extent e = demExtent(h);
  const std::string srcWkt = GDALGetProjectionRef(src) ? GDALGetProjectionRef(src) : "";
  const bool reproject = !srcWkt.empty() && !h.crsWkt.empty();
  // The raster's own texel size in the DEM's coordinates: what gdalwarp would choose.
  double texel = 0;
  if (reproject) {
    void* transformer = GDALCreateGenImgProjTransformer(src, srcWkt.c_str(), nullptr,
                                                        h.crsWkt.c_str(), FALSE, 0, 1);
    double gt[6];
    int w = 0, hh = 0;
    if (transformer &&
        GDALSuggestedWarpOutput(src, GDALGenImgProjTransform, transformer, gt, &w, &hh) == CE_None)
      texel = gt[1];
    if (transformer) GDALDestroyGenImgProjTransformer(transformer);
  } else {
    double gt[6];
    GDALGetGeoTransform(src, gt);
    texel = std::sqrt(std::abs(gt[1] * gt[5] - gt[2] * gt[4]));
  }
  if (!(texel > 0)) texel = h.cell;
  const auto [w, hh] = capped((e.x1 - e.x0) / texel, (e.y1 - e.y0) / texel);
  std::vector<std::string> args = {"-of",
                                   "MEM",
                                   "-r",
                                   "bilinear",
                                   "-dstalpha",
                                   "-te",
                                   std::to_string(e.x0),
                                   std::to_string(e.y0),
                                   std::to_string(e.x1),
                                   std::to_string(e.y1),
                                   "-ts",
                                   std::to_string(w),
                                   std::to_string(hh)};
  if (reproject) args.insert(args.end(), {"-t_srs", h.crsWkt});
  // std::to_string keeps 6 decimals: a millimetre, against metre-sized texels.
  return runUtility<GDALWarpAppOptions>(
      args, GDALWarpAppOptionsNew,
      [&](GDALWarpAppOptions* o, int* err) { return GDALWarp("", nullptr, 1, &src, o, err); },
      GDALWarpAppOptionsFree);
}

}  // namespace

DrapeImage loadDrape(const std::string& path, const Heightfield& h) {
  static std::once_flag registered;
  std::call_once(registered, [] { GDALAllRegister(); });
  gdal::QuietErrors errors;
  gdal::Dataset src;
  src.h = GDALOpenEx(path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (!src.h) throw InputError(path, "cannot read the texture raster: " + errors.last());
  if (GDALGetRasterCount(src.h) < 1) throw InputError(path, "texture raster has no band");
  gdal::Dataset expanded;
  expanded.h = expandPalette(src.h);
  GDALDatasetH input = expanded.h ? expanded.h : src.h;
  const int bands = GDALGetRasterCount(input);

  const Extent e = demExtent(h);
  DrapeImage image;
  const Vec3 lo = demToWorld(h, Vec3(e.x0, e.y0, 0)), hi = demToWorld(h, Vec3(e.x1, e.y1, 0));
  image.x0 = lo.x(), image.y0 = lo.y(), image.x1 = hi.x(), image.y1 = hi.y();

  gdal::Dataset warped;
  std::array<int, 4> read{};  // the bands that become red, green, blue, coverage (0: opaque)
  int w = 0, hh = 0;
  if (georeferenced(input)) {
    warped.h = warpOntoDem(input, h);
    if (!warped.h) throw InputError(path, "cannot place the texture on the DEM: " + errors.last());
    input = warped.h;
    const int n = GDALGetRasterCount(input);  // the source's bands, then the coverage band
    read = n - 1 >= 3 ? std::array<int, 4>{1, 2, 3, n} : std::array<int, 4>{1, 1, 1, n};
    w = GDALGetRasterXSize(input);
    hh = GDALGetRasterYSize(input);
  } else {
    read = bands >= 3 ? std::array<int, 4>{1, 2, 3, 0} : std::array<int, 4>{1, 1, 1, 0};
    const auto size = capped(GDALGetRasterXSize(input), GDALGetRasterYSize(input));
    w = size[0];
    hh = size[1];
  }
  image.width = w;
  image.height = hh;
  image.rgba.assign(static_cast<std::size_t>(w) * hh * 4, 255);
  // Rows from the south: start at the last row and step back by a row (as loadDem reads).
  GDALRasterIOExtraArg extra;
  INIT_RASTERIO_EXTRA_ARG(extra);
  extra.eResampleAlg = GRIORA_Bilinear;
  const GSpacing pixel = 4, line = -static_cast<GSpacing>(4) * w;
  for (int c = 0; c < 4; ++c) {
    if (read[static_cast<std::size_t>(c)] == 0) continue;
    GDALRasterBandH band = GDALGetRasterBand(input, read[static_cast<std::size_t>(c)]);
    std::uint8_t* last = image.rgba.data() + static_cast<std::size_t>(hh - 1) * w * 4 + c;
    if (GDALRasterIOEx(band, GF_Read, 0, 0, GDALGetRasterXSize(input), GDALGetRasterYSize(input),
                       last, w, hh, GDT_Byte, pixel, line, &extra) != CE_None)
      throw InputError(path, "cannot read the texture's pixels: " + errors.last());
  }
  return image;
}

}  // namespace vf
