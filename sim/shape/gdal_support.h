// GDAL helpers shared by the files that talk to GDAL (sim/shape/dem_import.cpp reads DEMs,
// sim/shape/drape_import.cpp drapes textures on them, sim/shape/geo_location.cpp places them on
// the Earth, sim/shape/crs.cpp reads a scene's CRS, sim/shape/dem_grid_raster.cpp resamples
// rasters onto a DEM's grid, sim/shape/vector_import.cpp reads vector files,
// sim/ensemble/raster_output.cpp writes rasters). A private header: it includes GDAL, so no
// voxfall header may include it; only those .cpp files do.
#pragma once

#include <cpl_error.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "sim/shape/heightfield.h"

namespace vf::gdal {

// An open dataset, closed when it goes out of scope.
struct Dataset {
  GDALDatasetH h = nullptr;
  Dataset() = default;
  Dataset(const Dataset&) = delete;
  Dataset& operator=(const Dataset&) = delete;
  ~Dataset() {
    if (h) GDALClose(h);
  }
};

// GDAL reports problems through a per-thread error state and, by default, prints them to
// stderr. While one of these lives, the messages are collected instead, so the one InputError
// can carry the last of them.
class QuietErrors {
 public:
  QuietErrors() {
    CPLErrorReset();
    CPLPushErrorHandler(CPLQuietErrorHandler);
  }
  ~QuietErrors() { CPLPopErrorHandler(); }
  QuietErrors(const QuietErrors&) = delete;
  QuietErrors& operator=(const QuietErrors&) = delete;
  std::string last() const {
    const char* m = CPLGetLastErrorMsg();
    return m && *m ? std::string(m) : std::string("GDAL gave no reason");
  }
};

// A spatial reference, destroyed when it goes out of scope.
struct SrsDeleter {
  void operator()(OGRSpatialReferenceH h) const { OSRDestroySpatialReference(h); }
};
using Srs = std::unique_ptr<std::remove_pointer_t<OGRSpatialReferenceH>, SrsDeleter>;

// The DEM raster's extent in the DEM file's coordinates: the outer edges of its cells.
struct Extent {
  double x0, y0, x1, y1;
};
inline Extent demExtent(const Heightfield& h) {
  const Vec3 lo = worldToDem(h, Vec3(h.x0, h.y0, 0));
  return Extent{lo.x() - h.cell / 2, lo.y() - h.cell / 2, lo.x() + (h.nx - 0.5) * h.cell,
                lo.y() + (h.ny - 0.5) * h.cell};
}

// Runs a GDAL utility (gdal_translate or gdalwarp) with these arguments into an in-memory
// dataset (null when GDAL refuses the arguments or fails).
template <class Options, class Make, class Run, class Free>
GDALDatasetH runUtility(std::vector<std::string> args, Make make, Run run, Free free) {
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  Options* options = make(argv.data(), nullptr);
  if (!options) return nullptr;
  int usageError = 0;
  GDALDatasetH out = run(options, &usageError);
  free(options);
  return out;
}

}  // namespace vf::gdal
