// Where an ensemble's rocks start: the scene's release sources ([ensemble.release]) placed on
// the DEM, and the draw of one realisation's release point among them.
//
// A source is an area, a line, a list of points, a raster of source cells, or a vector file
// whose features (polygons, lines, points) are its parts. A realisation draws a source by the
// sources' weights, then a part of it (a file's feature, by its `weight_field` or else by its
// size: area, length, or one per point), then a point inside the part. A choice among one
// option draws no number, so a scene with one plain source draws exactly what it always did.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "sim/scene/scene.h"

namespace vf {

struct Heightfield;
class Prng;

class ReleaseSources {
 public:
  // Places `specs` (DEM coordinates) on `dem` (world coordinates: the DEM's plus [ground]
  // offset). Throws InputError naming the source's key or file when a vertex lies off the DEM
  // or over NODATA, a source raster is not on the DEM's grid or has no source cell, or a file
  // cannot be read, has no usable feature, mixes geometry kinds without `weight_field`, or
  // gives a feature a weight that is not > 0. `demPath` names the DEM in messages.
  ReleaseSources(const std::vector<ReleaseSpec>& specs, std::shared_ptr<const Heightfield> dem,
                 const std::string& demPath);

  // Realisation's release point, world x, y, from its own generator seeded by `seed`; the
  // index of the source it came from in `source` when given.
  Point2 draw(std::uint64_t seed, int* source = nullptr) const;

  // The sources as world x, y outlines for maps: each area ring (closed by the map), each
  // segment of a line (two points), each point (a list of one), each source cell's square.
  std::vector<std::vector<Point2>> outlines() const;

 private:
  enum class Form { kArea, kLine, kPoint, kCell };
  struct Part {
    Form form = Form::kPoint;
    std::vector<std::vector<Point2>> rings;  // area: exterior then holes; line; points: one ring
    std::vector<std::int32_t> cells;         // cells: the source cells' indices on the DEM
    std::string key;                         // for messages
  };
  struct Source {
    std::vector<Part> parts;
    std::vector<double> partWeights;  // cumulative, one per part
  };

  Part inlinePart(const ReleaseSpec& s, const std::string& demPath) const;
  Part cellsPart(const ReleaseSpec& s) const;
  void addFileParts(const ReleaseSpec& s, const std::string& demPath, Source& source) const;
  static double holesArea(const Part& p);
  Point2 drawInPart(const Part& p, Prng& rng) const;

  std::shared_ptr<const Heightfield> dem_;
  std::vector<Source> sources_;
  std::vector<double> sourceWeights_;  // cumulative, one per source
};

}  // namespace vf
