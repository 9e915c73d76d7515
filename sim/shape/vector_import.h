// Vector files (GeoPackage, Shapefile, GeoJSON, anything OGR reads) as plain plan geometry in
// the DEM's coordinate reference system: release areas, barriers, evaluation lines and trees
// drawn in a GIS come in through here. GDAL/OGR stays behind vector_import.cpp.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace vf {

struct VectorFeature {
  enum class Kind { kPoint, kLine, kPolygon };
  Kind kind = Kind::kPoint;
  // x, y in the target CRS. A point: one ring of one vertex; a line: one ring, its vertices in
  // order; a polygon: the exterior ring first, then its holes, each without the closing vertex.
  std::vector<std::vector<std::array<double, 2>>> rings;
  // The feature's numeric attributes (integer and real fields that are set), by field name.
  std::vector<std::pair<std::string, double>> numbers;
  long long id = 0;  // OGR's feature id, for messages ("feature 7")

  std::optional<double> number(const std::string& field) const;
};

// Every feature of the file's first layer, or of layer `layer` when it is not empty, in the file's
// order, transformed into the CRS whose WKT is `targetWkt`. A multi-geometry (MultiPolygon, ...)
// becomes one feature per part, each with the feature's attributes. Throws InputError naming
// `path` when the file is missing or unreadable, has no such layer, names no CRS, when the target
// CRS is empty (a DEM without one), when a geometry cannot be transformed, or when a geometry is
// empty or of a type without points, lines or areas.
std::vector<VectorFeature> readVectorFile(const std::string& path, const std::string& targetWkt,
                                          const std::string& layer = "");

}  // namespace vf
