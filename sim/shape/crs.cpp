// CRS definitions through GDAL/OGR's spatial-reference C API (see crs.h).
#include "sim/shape/crs.h"

#include <cpl_conv.h>

#include <stdexcept>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"
#include "sim/shape/heightfield.h"

namespace vf {
namespace {

std::string authorityName(OGRSpatialReferenceH srs) {
  const char* name = OSRGetAuthorityName(srs, nullptr);
  const char* code = OSRGetAuthorityCode(srs, nullptr);
  return name && code ? std::string(name) + ":" + code : std::string();
}

bool tiedToEarth(OGRSpatialReferenceH srs) {
  return OSRIsProjected(srs) || OSRIsGeographic(srs) || OSRIsGeocentric(srs);
}

}  // namespace

CrsDefinition parseCrs(const std::string& definition) {
  gdal::QuietErrors errors;
  gdal::Srs srs(OSRNewSpatialReference(nullptr));
  if (!srs || OSRSetFromUserInput(srs.get(), definition.c_str()) != OGRERR_NONE)
    throw std::invalid_argument("GDAL does not recognise the coordinate reference system '" +
                                definition + "': " + errors.last());
  if (!tiedToEarth(srs.get()))
    throw std::invalid_argument("'" + definition +
                                "' is a local coordinate system, not tied to the Earth; give a "
                                "projected or geographic CRS (e.g. \"EPSG:31287\")");
  char* wkt = nullptr;
  if (OSRExportToWkt(srs.get(), &wkt) != OGRERR_NONE || !wkt)
    throw std::invalid_argument("cannot write '" + definition + "' as WKT: " + errors.last());
  CrsDefinition d{wkt, authorityName(srs.get())};
  CPLFree(wkt);
  return d;
}

void assignCrs(Heightfield& dem, const CrsDefinition& crs, const std::string& demPath) {
  if (!dem.crsWkt.empty()) {
    gdal::QuietErrors errors;
    gdal::Srs own(OSRNewSpatialReference(dem.crsWkt.c_str()));
    gdal::Srs given(OSRNewSpatialReference(crs.wkt.c_str()));
    if (own && given && tiedToEarth(own.get()) && !OSRIsSame(own.get(), given.get())) {
      const std::string ownName = dem.crsName.empty() ? "its own" : dem.crsName;
      throw InputError(demPath, "the DEM's file names the coordinate reference system " + ownName +
                                    ", and [ground] crs gives " +
                                    (crs.name.empty() ? "another" : crs.name) +
                                    "; remove 'crs' or give the file's own");
    }
  }
  dem.crsWkt = crs.wkt;
  dem.crsName = crs.name;
}

bool crsConflict(const std::string& wktA, const std::string& wktB) {
  if (wktA.empty() || wktB.empty()) return false;
  gdal::QuietErrors errors;
  gdal::Srs a(OSRNewSpatialReference(wktA.c_str())), b(OSRNewSpatialReference(wktB.c_str()));
  return a && b && tiedToEarth(a.get()) && tiedToEarth(b.get()) && !OSRIsSame(a.get(), b.get());
}

std::string crsLabel(const std::string& wkt) {
  gdal::QuietErrors errors;
  gdal::Srs srs(OSRNewSpatialReference(wkt.c_str()));
  if (!srs) return "a CRS without a name";
  const std::string authority = authorityName(srs.get());
  if (!authority.empty()) return authority;
  const char* name = OSRGetName(srs.get());
  return name && *name ? std::string(name) : "a CRS without a name";
}

}  // namespace vf
