// A coordinate reference system a scene gives its DEM ([ground] crs), for grids whose file
// names none (an ESRI ASCII grid without its .prj). The DEM then carries it into every output
// that is georeferenced: rasters and their .prj files, GeoJSON, glTF extras, hazard maps, the
// drape's reprojection and the sun's place on the Earth.
#pragma once

#include <string>

namespace vf {

struct Heightfield;

struct CrsDefinition {
  std::string wkt;   // as GDAL exports it
  std::string name;  // "AUTHORITY:CODE" when the CRS has one, else empty
};

// Any definition GDAL's OSRSetFromUserInput accepts ("EPSG:31287", WKT, a PROJ string).
// Throws std::invalid_argument with GDAL's reason when it accepts none, or when the CRS is
// local (not tied to the Earth), which would georeference nothing.
CrsDefinition parseCrs(const std::string& definition);

// Gives `dem` the CRS. A DEM without a CRS, or with only a local engineering one (what GDAL
// reads from a grid without a .prj), takes it; a DEM whose file names another CRS refuses it
// with an InputError naming the file and both systems. The same CRS is accepted.
void assignCrs(Heightfield& dem, const CrsDefinition& crs, const std::string& demPath);

// Whether two CRS (WKT, as GDAL exports them) conflict: both tied to the Earth and not the same
// system. An empty or local one (a grid without a .prj) conflicts with nothing.
bool crsConflict(const std::string& wktA, const std::string& wktB);
// A CRS's "AUTHORITY:CODE", else its name in the WKT, else "a CRS without a name".
std::string crsLabel(const std::string& wkt);

}  // namespace vf
