// Vector files through OGR's C API (see vector_import.h).
#include "sim/shape/vector_import.h"

#include <ogr_api.h>

#include <filesystem>
#include <memory>
#include <type_traits>

#include "sim/core/error.h"
#include "sim/shape/gdal_support.h"

namespace vf {
namespace {

struct TransformDeleter {
  void operator()(OGRCoordinateTransformationH h) const { OCTDestroyCoordinateTransformation(h); }
};
using Transform =
    std::unique_ptr<std::remove_pointer_t<OGRCoordinateTransformationH>, TransformDeleter>;

struct FeatureDeleter {
  void operator()(OGRFeatureH h) const { OGR_F_Destroy(h); }
};
using Feature = std::unique_ptr<std::remove_pointer_t<OGRFeatureH>, FeatureDeleter>;

struct GeometryDeleter {
  void operator()(OGRGeometryH h) const { OGR_G_DestroyGeometry(h); }
};
using Geometry = std::unique_ptr<std::remove_pointer_t<OGRGeometryH>, GeometryDeleter>;

OGRLayerH openLayer(const gdal::Dataset& ds, const std::string& path, const std::string& layer) {
  if (!layer.empty()) {
    OGRLayerH l = GDALDatasetGetLayerByName(ds.h, layer.c_str());
    if (l == nullptr) throw InputError(path, "the file has no layer named '" + layer + "'");
    return l;
  }
  if (GDALDatasetGetLayerCount(ds.h) < 1) throw InputError(path, "the file holds no layer");
  return GDALDatasetGetLayer(ds.h, 0);
}

// A layer without a CRS, with a local one, or with a datum nobody named (GeoPackage writes
// "Undefined geographic SRS" for a layer saved without one) gives coordinates nothing can place:
// transforming them would put the shapes somewhere plausible and wrong.
bool placedOnEarth(OGRSpatialReferenceH srs) {
  if (srs == nullptr) return false;
  if (!(OSRIsProjected(srs) || OSRIsGeographic(srs) || OSRIsGeocentric(srs))) return false;
  const char* datum = OSRGetAttrValue(srs, "DATUM", 0);
  return datum != nullptr && std::string(datum) != "unknown";
}

// The file's CRS to the target's, both in easting-northing (x, y) order whatever the CRS's
// official axis order is: scene coordinates are always x east, y north.
Transform transformTo(OGRLayerH layer, const std::string& path, const std::string& targetWkt) {
  if (targetWkt.empty())
    throw InputError(path,
                     "the DEM has no coordinate reference system to place the file's shapes in; "
                     "give the DEM's with [ground] crs");
  OGRSpatialReferenceH own = OGR_L_GetSpatialRef(layer);
  if (!placedOnEarth(own))
    throw InputError(path,
                     "the file names no coordinate reference system; save it with one (e.g. the "
                     "DEM's)");
  gdal::Srs source(OSRClone(own));
  gdal::Srs target(OSRNewSpatialReference(targetWkt.c_str()));
  OSRSetAxisMappingStrategy(source.get(), OAMS_TRADITIONAL_GIS_ORDER);
  OSRSetAxisMappingStrategy(target.get(), OAMS_TRADITIONAL_GIS_ORDER);
  gdal::QuietErrors errors;
  Transform t(OCTNewCoordinateTransformation(source.get(), target.get()));
  if (!t)
    throw InputError(
        path,
        "cannot transform the file's coordinate reference system to the DEM's: " + errors.last());
  return t;
}

std::vector<std::array<double, 2>> ringPoints(OGRGeometryH g, bool closed) {
  std::vector<std::array<double, 2>> pts;
  const int n = OGR_G_GetPointCount(g);
  for (int i = 0; i < n; ++i) pts.push_back({OGR_G_GetX(g, i), OGR_G_GetY(g, i)});
  if (closed && pts.size() > 1 && pts.front() == pts.back()) pts.pop_back();
  return pts;
}

std::vector<std::pair<std::string, double>> numericFields(OGRFeatureH f) {
  std::vector<std::pair<std::string, double>> out;
  for (int i = 0; i < OGR_F_GetFieldCount(f); ++i) {
    OGRFieldDefnH d = OGR_F_GetFieldDefnRef(f, i);
    const OGRFieldType type = OGR_Fld_GetType(d);
    if (type != OFTInteger && type != OFTInteger64 && type != OFTReal) continue;
    if (!OGR_F_IsFieldSetAndNotNull(f, i)) continue;
    out.emplace_back(OGR_Fld_GetNameRef(d), OGR_F_GetFieldAsDouble(f, i));
  }
  return out;
}

// Appends the parts of one (transformed) geometry as features that share `base`'s attributes.
void appendParts(OGRGeometryH g, const VectorFeature& base, const std::string& path,
                 std::vector<VectorFeature>& out) {
  const std::string where = "feature " + std::to_string(base.id);
  if (OGR_G_IsEmpty(g)) throw InputError(path, where + " has an empty geometry");
  const OGRwkbGeometryType type = wkbFlatten(OGR_G_GetGeometryType(g));
  VectorFeature f = base;
  switch (type) {
    case wkbPoint:
      f.kind = VectorFeature::Kind::kPoint;
      f.rings.push_back({{OGR_G_GetX(g, 0), OGR_G_GetY(g, 0)}});
      out.push_back(std::move(f));
      return;
    case wkbLineString:
      f.kind = VectorFeature::Kind::kLine;
      f.rings.push_back(ringPoints(g, false));
      out.push_back(std::move(f));
      return;
    case wkbPolygon:
      f.kind = VectorFeature::Kind::kPolygon;
      for (int i = 0; i < OGR_G_GetGeometryCount(g); ++i)
        f.rings.push_back(ringPoints(OGR_G_GetGeometryRef(g, i), true));
      out.push_back(std::move(f));
      return;
    case wkbMultiPoint:
    case wkbMultiLineString:
    case wkbMultiPolygon:
    case wkbGeometryCollection:
      for (int i = 0; i < OGR_G_GetGeometryCount(g); ++i)
        appendParts(OGR_G_GetGeometryRef(g, i), base, path, out);
      return;
    default:
      throw InputError(path, where + " is a " + OGRGeometryTypeToName(type) +
                                 "; points, lines and polygons are read");
  }
}

}  // namespace

std::optional<double> VectorFeature::number(const std::string& field) const {
  for (const auto& [name, value] : numbers)
    if (name == field) return value;
  return std::nullopt;
}

std::vector<VectorFeature> readVectorFile(const std::string& path, const std::string& targetWkt,
                                          const std::string& layerName) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec) && !std::filesystem::is_directory(path, ec))
    throw InputError(path, "vector file not found");
  gdal::QuietErrors errors;
  GDALAllRegister();
  gdal::Dataset ds;
  ds.h = GDALOpenEx(path.c_str(), GDAL_OF_VECTOR | GDAL_OF_READONLY, nullptr, nullptr, nullptr);
  if (ds.h == nullptr)
    throw InputError(path, "GDAL/OGR cannot read this as a vector file: " + errors.last());
  OGRLayerH layer = openLayer(ds, path, layerName);
  const Transform transform = transformTo(layer, path, targetWkt);
  std::vector<VectorFeature> out;
  OGR_L_ResetReading(layer);
  while (Feature f{OGR_L_GetNextFeature(layer)}) {
    VectorFeature base;
    base.id = static_cast<long long>(OGR_F_GetFID(f.get()));
    base.numbers = numericFields(f.get());
    OGRGeometryH own = OGR_F_GetGeometryRef(f.get());
    if (own == nullptr)
      throw InputError(path, "feature " + std::to_string(base.id) + " has no geometry");
    Geometry g(OGR_G_Clone(own));
    if (OGR_G_Transform(g.get(), transform.get()) != OGRERR_NONE)
      throw InputError(path, "feature " + std::to_string(base.id) +
                                 " cannot be transformed to the DEM's coordinate reference system");
    appendParts(g.get(), base, path, out);
  }
  if (out.empty()) throw InputError(path, "the layer holds no features");
  return out;
}

}  // namespace vf
