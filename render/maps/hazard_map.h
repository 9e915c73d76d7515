// Maps people look at: a per-cell statistic of an ensemble over a hillshade
// of its DEM, with a legend, a scale bar, a north arrow and the release areas; and the runout
// and reach-angle distributions of the realisations. Both are drawn by gnuplot (pngcairo)
// through render/figures/gnuplot.h and written through an OutputFile (temporary name, renamed
// when complete).
#pragma once

#include <string>
#include <vector>

#include "render/maps/colour_map.h"
#include "render/output/output_file.h"
#include "sim/core/math.h"
#include "sim/shape/heightfield.h"

namespace vf {

// Classes instead of a colour scale: class k holds the values in [edges[k - 1], edges[k])
// (edges ascending; the first class reaches down to -infinity, the last up to +infinity), drawn
// in colours[k] and named labels[k] in the legend. edges.size() + 1 labels and colours.
struct MapClasses {
  std::vector<double> edges;
  std::vector<std::string> labels;
  std::vector<Rgb8> colours;
};

// The rock-fall intensity classes of Swiss hazard mapping, labelled "low", "medium" and "high"
// (the map's title should give the limits): low below 30 kJ, medium 30 to 300 kJ, high above
// 300 kJ of kinetic energy (the federal recommendations for mass movements,
// BRP/BWW/BUWAL 1997, as the cantons apply them).
MapClasses swissRockfallIntensity();

// Passing-height classes with the given limits (m, ascending, 1 to 5 of them), labelled
// "< a m", "a-b m", ..., "> z m", in purples from light to dark (ColorBrewer's Purples
// without its near-white: no colour a map's lines, barriers or release areas use). No standard
// fixes these limits the way the Swiss classes fix the energies; a barrier's height is a natural
// one.
MapClasses passingHeightClasses(const std::vector<double>& limits);

// One per-cell statistic to map.
struct MapLayer {
  std::string name;            // file stem, e.g. "energy_p95"
  std::string title;           // e.g. "Kinetic energy, 95th percentile"
  std::string units;           // e.g. "kJ"; empty for a dimensionless number
  std::vector<double> values;  // dem.nx * dem.ny, laid out as Heightfield::z (z[j * nx + i],
                               // j from the south); NaN = no value
  // Colours by log10 of the value between the smallest positive value and the largest (values
  // at or below that smallest take the bottom colour), with a logarithmic legend.
  bool logScale = false;
  MapClasses classes{};  // no edges: the continuous colour map
};

// Whether the ensemble's statistic `name` is mapped on a logarithmic scale: the reach
// probability, the passages and the kinetic energies span orders of magnitude between the
// track's core and its fringe, and on a linear scale every fringe cell is the darkest colour.
bool mappedOnLogScale(const std::string& name);

// Where a hazard map of a DEM lands in its PNG. Map coordinates are the DEM file's (easting,
// northing: world minus dem.shift) when the DEM has a CRS, else world x, y; metres.
struct MapFrame {
  int width = 0, height = 0;                      // PNG size, px
  int left = 0, top = 0;                          // the map area's top-left pixel corner
  int plotWidth = 0, plotHeight = 0;              // the map area, px (same scale along x and y)
  double xMin = 0, xMax = 0, yMin = 0, yMax = 0;  // map coordinates of its edges, m
  double shiftX = 0, shiftY = 0;                  // map coordinates = world - shift, m
  bool fileCoordinates = false;        // axes in the DEM file's coordinates (it has a CRS)
  int i0 = 0, j0 = 0, ni = 0, nj = 0;  // the samples shown (MapWindow, resolved)

  // The pixel (column, row from the top; fractional, pixel centres at .5) of world (x, y).
  double columnOf(double x) const { return left + (x - shiftX - xMin) / (xMax - xMin) * plotWidth; }
  double rowOf(double y) const { return top + (yMax - (y - shiftY)) / (yMax - yMin) * plotHeight; }
};

// The hillshade's grey where a map has no value: 255 (kHillshadeFloor + (1 - kHillshadeFloor)
// hillshade), so shadows stay mid-grey and never compete with the colour map's dark end.
inline constexpr double kHillshadeFloor = 0.4;

// The part of the grid a map shows: samples i0 .. i0 + ni - 1 (west to east) and j0 .. j0 + nj - 1
// (south to north); ni = 0 means the whole grid.
struct MapWindow {
  int i0 = 0, j0 = 0, ni = 0, nj = 0;
};

// The window an ensemble's maps show: the cells some realisation passed (passages > 0) and the
// release areas' points (world x, y), widened on every side by a margin of a tenth of the
// window's longer side and at least kMapMarginCells cells, within the grid. The whole grid when
// nothing was passed and there is no release area.
inline constexpr int kMapMarginCells = 10;
MapWindow affectedWindow(const Heightfield& dem, const std::vector<double>& passages,
                         const std::vector<std::vector<Vec2>>& releaseAreas);

// The window of the samples whose centres lie in [xMin, xMax] x [yMin, yMax], in the DEM
// file's coordinates (world minus dem.shift), m. Throws std::invalid_argument when the box is
// empty or holds no sample of the grid.
MapWindow extentWindow(const Heightfield& dem, double xMin, double yMin, double xMax, double yMax);

// The layout writeHazardMap uses for `window` of `dem`: the map's longer side is kMapLongSidePx
// pixels and covers the window's cells (each sample at the centre of its square), with room left
// for the axes, the title and the legend.
inline constexpr int kMapLongSidePx = 800;
MapFrame hazardMapFrame(const Heightfield& dem, const MapWindow& window = {});

// The values a map shows of one statistic (`name`, as kLayerNames of the ensemble) given its
// raster values and the passages per cell: a cell no realisation passed has no value, so it
// shows the hillshade and the reached area stands out; and on the deposits map a passed cell
// where no rock stopped has none either, so the few cells that hold deposits are not lost among
// the many a rock only crossed.
std::vector<double> mappedValues(const std::string& name, const std::vector<double>& values,
                                 const std::vector<double>& passages);

// A polyline drawn over a map, world (x, y) points, m: an evaluation line (blue, docs/rockfall.md),
// a barrier (black, thicker) or a piece of a forest stand's edge (green, thin).
struct MapPolyline {
  enum class Kind { kEvaluationLine, kBarrier, kForestEdge };
  std::vector<Vec2> points;
  Kind kind = Kind::kEvaluationLine;
};

// Writes a PNG map of `layer` over a hillshade of `dem` (hillshade.h: Horn's slope and aspect,
// sun at azimuth 315 deg, altitude 45 deg): each map pixel shows the largest value of the
// samples it covers (the sample under it when a pixel is smaller than a cell), in viridis
// (colour_map.h) scaled linearly from the layer's smallest to its largest value where the layer has
// a value (opaque, so the colour reads exactly against the legend), the hillshade in grey
// (kHillshadeFloor) where it has none, white where the DEM has no data. With a colour legend titled
// with `layer.title` and `layer.units`, a scale bar in metres of a round length (1, 2 or 5 times a
// power of ten, at most a quarter of the map's width), a north arrow, and the release areas
// outlined in red: each a polygon of world (x, y) points, m; one point is drawn as a marker, two as
// a line. `rules` as for every output (output_file.h). Throws InputError (naming the file) if
// values has the wrong size, the path cannot be written under `rules`, or gnuplot fails; a file
// already at pngPath is then left as it was, and no temporary file remains.
// `window` chooses the part of the grid shown (default: all of it); `polylines` are drawn over
// the map, each kind with one legend entry.
void writeHazardMap(const Heightfield& dem, const MapLayer& layer,
                    const std::vector<std::vector<Vec2>>& releaseAreas, const std::string& pngPath,
                    const OutputRules& rules = replaceOutputs(), const MapWindow& window = {},
                    const std::vector<MapPolyline>& polylines = {});

// Size of the runout plot's PNG, px.
inline constexpr int kRunoutPlotWidthPx = 1000, kRunoutPlotHeightPx = 450;

// Writes the runout (m) and reach-angle (deg) distributions of an ensemble's realisations as
// one PNG of two panels, each the empirical cumulative distribution (fraction of realisations
// at or below a value) with its median and 95th percentile (the smallest value whose cumulative
// fraction reaches 0.5 and 0.95) marked. Why a CDF and not a histogram: it needs no bin width
// (a histogram of a few hundred runs changes shape with it), shows every realisation, and the
// numbers a hazard assessment quotes (median runout, the runout exceeded by 5 % of the rocks)
// are read straight off it. Non-finite values are left out. Throws InputError if either list has
// no finite value, the path cannot be written, or gnuplot fails.
void writeRunoutPlot(const std::vector<double>& runoutsM, const std::vector<double>& reachAnglesDeg,
                     const std::string& pngPath, const OutputRules& rules = replaceOutputs());

}  // namespace vf
