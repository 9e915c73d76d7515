// A hazard map is one gnuplot plot: the map pixels (statistic in viridis over the hillshade)
// are composed here into one RGBA image of exactly the map area's size, so gnuplot draws it
// 1:1 and every map pixel is a colour this file chose; gnuplot adds what needs fonts and
// vectors (axes, title, colour box, scale bar, north arrow, release outlines). Its data files
// go to a scratch folder; the PNG goes through an OutputFile.
#include "render/maps/hazard_map.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

#include "render/figures/gnuplot.h"
#include "render/maps/colour_map.h"
#include "render/maps/hillshade.h"
#include "sim/core/error.h"

namespace vf {
namespace {

using fig::gnuplotString;

// Space around the map, px: tick labels and axis title on the left and below, the title above,
// the colour box and its label on the right. The colour box is at least kMinLegendPx tall.
constexpr int kLeftPx = 100, kRightPx = 200, kTopPx = 50, kBottomPx = 80, kMinLegendPx = 260;
// Release outlines: red, a colour neither viridis nor the grey hillshade contains.
constexpr const char* kReleaseColour = "#e41a1c";
// The forest's edge: a dark green that neither viridis nor the grey hillshade contains.
constexpr const char* kForestColour = "#1b7837";

// The largest 1, 2 or 5 times a power of ten not above `target` (> 0), m.
double roundLength(double target) {
  const double p = std::pow(10.0, std::floor(std::log10(target)));
  for (double m : {5.0, 2.0, 1.0})
    if (m * p <= target) return m * p;
  return p;
}

std::string number(double v) {
  std::ostringstream o;
  o << std::setprecision(15) << v;
  return o.str();
}

// A length for the scale bar's label: "500 m", "2 km", "0.5 m".
std::string lengthLabel(double m) {
  if (m >= 1000) return number(m / 1000) + " km";
  return number(m) + " m";
}

// The samples a map pixel covers along one axis, for each of `pixels` pixels of `pixelSize` m
// over `samples` samples `cell` m apart: those whose centres fall inside the pixel, or the
// nearest one when none does (a pixel smaller than a cell).
struct SampleSpan {
  int nearest, first, last;
};
std::vector<SampleSpan> sampleSpans(int pixels, double pixelSize, int samples, double cell) {
  std::vector<SampleSpan> spans(static_cast<std::size_t>(pixels));
  const auto clampIndex = [samples](double k) {
    return std::clamp(static_cast<int>(k), 0, samples - 1);
  };
  for (int u = 0; u < pixels; ++u) {
    SampleSpan& sp = spans[static_cast<std::size_t>(u)];
    sp.nearest = clampIndex(std::floor((u + 0.5) * pixelSize / cell));
    sp.first = clampIndex(std::ceil(u * pixelSize / cell - 0.5));
    sp.last = clampIndex(std::ceil((u + 1) * pixelSize / cell - 0.5) - 1);
    if (sp.last < sp.first) sp.first = sp.last = sp.nearest;
  }
  return spans;
}

// The colour of a value: its class's, or viridis between lo and hi (linear or by log10).
Rgb8 colourOf(const MapLayer& layer, double value, double lo, double hi) {
  const MapClasses& k = layer.classes;
  if (!k.edges.empty())
    return k.colours[static_cast<std::size_t>(
        std::upper_bound(k.edges.begin(), k.edges.end(), value) - k.edges.begin())];
  if (hi <= lo) return viridis(0.5);
  return viridis(layer.logScale ? std::log(std::max(value, lo) / lo) / std::log(hi / lo)
                                : (value - lo) / (hi - lo));
}

// The map area as RGBA, rows from the bottom (gnuplot's image order). A pixel shows the largest
// value among the samples it covers (a map smaller than its grid never hides a narrow track of
// high values between pixels), else the hillshade grey of the sample under its centre, else
// nothing (transparent).
std::vector<std::uint8_t> mapPixels(const Heightfield& dem, const MapLayer& layer,
                                    const MapFrame& f, double lo, double hi) {
  std::vector<std::uint8_t> rgba(static_cast<std::size_t>(f.plotWidth) * f.plotHeight * 4, 0);
  const auto columns = sampleSpans(f.plotWidth, (f.xMax - f.xMin) / f.plotWidth, f.ni, dem.cell);
  const auto rows = sampleSpans(f.plotHeight, (f.yMax - f.yMin) / f.plotHeight, f.nj, dem.cell);
  for (int v = 0; v < f.plotHeight; ++v) {
    const SampleSpan& row = rows[static_cast<std::size_t>(v)];
    for (int u = 0; u < f.plotWidth; ++u) {
      const SampleSpan& col = columns[static_cast<std::size_t>(u)];
      double value = std::nan("");
      for (int j = f.j0 + row.first; j <= f.j0 + row.last; ++j)
        for (int i = f.i0 + col.first; i <= f.i0 + col.last; ++i) {
          const double x = layer.values[static_cast<std::size_t>(j) * dem.nx + i];
          if (std::isfinite(x) && !(x <= value)) value = x;  // the first finite, then larger
        }
      std::uint8_t* p = &rgba[(static_cast<std::size_t>(v) * f.plotWidth + u) * 4];
      if (std::isfinite(value)) {
        const Rgb8 c = colourOf(layer, value, lo, hi);
        p[0] = c.r, p[1] = c.g, p[2] = c.b, p[3] = 255;
      } else if (const double shade = hillshadeAt(dem, f.i0 + col.nearest, f.j0 + row.nearest);
                 !std::isnan(shade)) {
        const auto g = static_cast<std::uint8_t>(
            std::lround(255 * (kHillshadeFloor + (1 - kHillshadeFloor) * shade)));
        p[0] = p[1] = p[2] = g, p[3] = 255;
      }
    }
  }
  return rgba;
}

// The release areas in map coordinates: polygons (closed) and lines as blank-line separated
// runs for `with lines`, single points for `with points`. Returns whether each file has any.
std::pair<bool, bool> writeReleaseAreas(const std::vector<std::vector<Vec2>>& areas,
                                        const MapFrame& f, const std::string& linesPath,
                                        const std::string& pointsPath) {
  std::ofstream lines(linesPath), points(pointsPath);
  lines << std::setprecision(15);
  points << std::setprecision(15);
  bool anyLine = false, anyPoint = false;
  for (const auto& area : areas) {
    if (area.empty()) continue;
    if (area.size() == 1) {
      points << area[0].x() - f.shiftX << ' ' << area[0].y() - f.shiftY << '\n';
      anyPoint = true;
      continue;
    }
    for (const Vec2& p : area) lines << p.x() - f.shiftX << ' ' << p.y() - f.shiftY << '\n';
    if (area.size() > 2) lines << area[0].x() - f.shiftX << ' ' << area[0].y() - f.shiftY << '\n';
    lines << "\n\n";
    anyLine = true;
  }
  return {anyLine, anyPoint};
}

// The polylines of one kind in map coordinates, as blank-line separated runs; returns whether
// there is any.
bool writePolylines(const std::vector<MapPolyline>& polylines, MapPolyline::Kind kind,
                    const MapFrame& f, const std::string& path) {
  std::ofstream o(path);
  o << std::setprecision(15);
  bool any = false;
  for (const MapPolyline& l : polylines) {
    if (l.kind != kind || l.points.size() < 2) continue;
    for (const Vec2& p : l.points) o << p.x() - f.shiftX << ' ' << p.y() - f.shiftY << '\n';
    o << "\n\n";
    any = true;
  }
  return any;
}

std::string hexColour(const Rgb8& c) {
  char hex[8];
  std::snprintf(hex, sizeof hex, "#%02x%02x%02x", c.r, c.g, c.b);
  return hex;
}

// The colour box's palette: viridis, 256 steps.
void writeViridisPalette(std::ostream& s) {
  s << "set palette maxcolors 256\nset palette defined (";
  const auto& table = viridisTable();
  for (int k = 0; k < 256; ++k) s << (k ? ", " : "") << k << " '" << hexColour(table[k]) << "'";
  s << ")\n";
}

// The colour box of a classed map: one step per class over 0 .. N, each labelled at its middle.
void writeClassLegend(std::ostream& s, const MapClasses& classes) {
  const std::size_t n = classes.colours.size();
  s << "set palette maxcolors " << n << "\nset palette defined (";
  for (std::size_t k = 0; k < n; ++k)
    s << (k ? ", " : "") << k << " '" << hexColour(classes.colours[k]) << "', " << k + 1 << " '"
      << hexColour(classes.colours[k]) << "'";
  s << ")\nset cbrange [0:" << n << "]\nset cbtics (";
  for (std::size_t k = 0; k < n; ++k)
    s << (k ? ", " : "") << gnuplotString(classes.labels[k]) << " " << k + 0.5;
  s << ")\n";
}

// Screen fraction of a pixel position (x from the left, y from the bottom).
std::string screenX(const MapFrame& f, double px) { return "screen " + number(px / f.width); }
std::string screenY(const MapFrame& f, double px) { return "screen " + number(px / f.height); }

}  // namespace

MapWindow affectedWindow(const Heightfield& dem, const std::vector<double>& passages,
                         const std::vector<std::vector<Vec2>>& releaseAreas) {
  int iLo = dem.nx, iHi = -1, jLo = dem.ny, jHi = -1;
  const auto take = [&](int i, int j) {
    iLo = std::min(iLo, i), iHi = std::max(iHi, i), jLo = std::min(jLo, j), jHi = std::max(jHi, j);
  };
  for (int j = 0; j < dem.ny; ++j)
    for (int i = 0; i < dem.nx; ++i) {
      const std::size_t c = static_cast<std::size_t>(j) * dem.nx + i;
      if (c < passages.size() && passages[c] > 0) take(i, j);
    }
  for (const auto& area : releaseAreas)
    for (const Vec2& p : area)
      take(std::clamp(static_cast<int>(std::lround((p.x() - dem.x0) / dem.cell)), 0, dem.nx - 1),
           std::clamp(static_cast<int>(std::lround((p.y() - dem.y0) / dem.cell)), 0, dem.ny - 1));
  if (iHi < 0) return {};
  const int margin = std::max(kMapMarginCells, (std::max(iHi - iLo, jHi - jLo) + 1) / 10);
  MapWindow w;
  w.i0 = std::max(0, iLo - margin);
  w.j0 = std::max(0, jLo - margin);
  w.ni = std::min(dem.nx - 1, iHi + margin) - w.i0 + 1;
  w.nj = std::min(dem.ny - 1, jHi + margin) - w.j0 + 1;
  return w;
}

MapWindow extentWindow(const Heightfield& dem, double xMin, double yMin, double xMax, double yMax) {
  if (!(xMin < xMax && yMin < yMax))
    throw std::invalid_argument(
        "the extent must be XMIN,YMIN,XMAX,YMAX with XMIN < XMAX and "
        "YMIN < YMAX");
  // Sample i sits at file x = x0 - shift + i cell.
  const double fx0 = dem.x0 - dem.shift.x(), fy0 = dem.y0 - dem.shift.y();
  const int i0 = std::max(0, static_cast<int>(std::ceil((xMin - fx0) / dem.cell)));
  const int i1 = std::min(dem.nx - 1, static_cast<int>(std::floor((xMax - fx0) / dem.cell)));
  const int j0 = std::max(0, static_cast<int>(std::ceil((yMin - fy0) / dem.cell)));
  const int j1 = std::min(dem.ny - 1, static_cast<int>(std::floor((yMax - fy0) / dem.cell)));
  if (i0 > i1 || j0 > j1) {
    std::ostringstream m;
    m << "the extent holds no sample of the DEM, whose samples span x " << fx0 << " .. "
      << fx0 + (dem.nx - 1) * dem.cell << ", y " << fy0 << " .. " << fy0 + (dem.ny - 1) * dem.cell
      << " (the DEM file's coordinates)";
    throw std::invalid_argument(m.str());
  }
  return {i0, j0, i1 - i0 + 1, j1 - j0 + 1};
}

MapFrame hazardMapFrame(const Heightfield& dem, const MapWindow& window) {
  MapFrame f;
  f.fileCoordinates = !dem.crsWkt.empty();
  if (f.fileCoordinates) f.shiftX = dem.shift.x(), f.shiftY = dem.shift.y();
  const bool whole = window.ni <= 0 || window.nj <= 0;
  f.i0 = whole ? 0 : window.i0;
  f.j0 = whole ? 0 : window.j0;
  f.ni = whole ? dem.nx : window.ni;
  f.nj = whole ? dem.ny : window.nj;
  f.xMin = dem.x0 + f.i0 * dem.cell - f.shiftX - dem.cell / 2;
  f.xMax = f.xMin + f.ni * dem.cell;
  f.yMin = dem.y0 + f.j0 * dem.cell - f.shiftY - dem.cell / 2;
  f.yMax = f.yMin + f.nj * dem.cell;
  const double aspect = static_cast<double>(f.nj) / f.ni;  // height over width
  f.plotWidth =
      aspect <= 1 ? kMapLongSidePx : std::max(1, int(std::lround(kMapLongSidePx / aspect)));
  f.plotHeight =
      aspect <= 1 ? std::max(1, int(std::lround(kMapLongSidePx * aspect))) : kMapLongSidePx;
  f.left = kLeftPx;
  f.top = kTopPx;
  f.width = kLeftPx + f.plotWidth + kRightPx;
  f.height = kTopPx + std::max(f.plotHeight, kMinLegendPx) + kBottomPx;
  return f;
}

MapClasses swissRockfallIntensity() {
  // Yellow, orange, brown (ColorBrewer's YlOrBr): ordered, and none is the release areas' red.
  return {{30.0, 300.0},
          {"low", "medium", "high"},
          {{0xfe, 0xe3, 0x91}, {0xfe, 0x99, 0x29}, {0x99, 0x34, 0x04}}};
}

MapClasses passingHeightClasses(const std::vector<double>& limits) {
  // ColorBrewer's sequential Purples: for k classes its (k + 1)-class scheme without the
  // lightest entry, which is all but white and would vanish on a light hillshade.
  static const std::vector<std::vector<Rgb8>> kPurples = {
      {{0xbc, 0xbd, 0xdc}, {0x75, 0x6b, 0xb1}},
      {{0xcb, 0xc9, 0xe2}, {0x9e, 0x9a, 0xc8}, {0x6a, 0x51, 0xa3}},
      {{0xcb, 0xc9, 0xe2}, {0x9e, 0x9a, 0xc8}, {0x75, 0x6b, 0xb1}, {0x54, 0x27, 0x8f}},
      {{0xda, 0xda, 0xeb},
       {0xbc, 0xbd, 0xdc},
       {0x9e, 0x9a, 0xc8},
       {0x75, 0x6b, 0xb1},
       {0x54, 0x27, 0x8f}},
      {{0xda, 0xda, 0xeb},
       {0xbc, 0xbd, 0xdc},
       {0x9e, 0x9a, 0xc8},
       {0x80, 0x7d, 0xba},
       {0x6a, 0x51, 0xa3},
       {0x4a, 0x14, 0x86}}};
  if (limits.empty() || limits.size() > kPurples.size())
    throw std::invalid_argument("passing-height classes need 1 to 5 limits");
  MapClasses c;
  c.edges = limits;
  c.colours = kPurples[limits.size() - 1];
  c.labels.push_back("< " + number(limits.front()) + " m");
  for (std::size_t k = 1; k < limits.size(); ++k)
    c.labels.push_back(number(limits[k - 1]) + "-" + number(limits[k]) + " m");
  c.labels.push_back("> " + number(limits.back()) + " m");
  return c;
}

bool mappedOnLogScale(const std::string& name) {
  return name == "passages" || name == "reach_probability" || name.rfind("energy_", 0) == 0;
}

std::vector<double> mappedValues(const std::string& name, const std::vector<double>& values,
                                 const std::vector<double>& passages) {
  std::vector<double> out = values;
  const bool deposits = name == "deposited";
  for (std::size_t c = 0; c < out.size(); ++c)
    if ((c < passages.size() && passages[c] == 0) || (deposits && out[c] == 0)) out[c] = NAN;
  return out;
}

namespace {

// The range of a layer's finite values (positive only on a log scale); lo > hi without any.
struct ValueRange {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  bool any() const { return lo <= hi; }
};

ValueRange valueRange(const MapLayer& layer) {
  ValueRange r;
  for (double v : layer.values)
    if (std::isfinite(v) && (!layer.logScale || v > 0))
      r.lo = std::min(r.lo, v), r.hi = std::max(r.hi, v);
  return r;
}

// The data files gnuplot reads for a map, in a scratch folder, and which of them hold anything.
struct MapData {
  std::string image, lines, points, evaluation, barriers, forest;
  bool anyLine = false, anyPoint = false, anyEvaluation = false, anyBarrier = false,
       anyForest = false;
};

MapData writeMapData(const fig::ScratchFolder& scratch, const Heightfield& dem,
                     const MapLayer& layer, const MapFrame& f, const ValueRange& range,
                     const std::vector<std::vector<Vec2>>& releaseAreas,
                     const std::vector<MapPolyline>& polylines, const std::string& pngPath) {
  MapData d;
  d.image = scratch.file("map.rgba");
  {
    const std::vector<std::uint8_t> rgba = mapPixels(dem, layer, f, range.lo, range.hi);
    std::ofstream o(d.image, std::ios::binary);
    o.write(reinterpret_cast<const char*>(rgba.data()), static_cast<std::streamsize>(rgba.size()));
    if (!o) throw InputError(pngPath, "cannot write the temporary file " + d.image);
  }
  d.lines = scratch.file("release_lines.dat");
  d.points = scratch.file("release_points.dat");
  std::tie(d.anyLine, d.anyPoint) = writeReleaseAreas(releaseAreas, f, d.lines, d.points);
  d.evaluation = scratch.file("evaluation_lines.dat");
  d.barriers = scratch.file("barriers.dat");
  d.anyEvaluation = writePolylines(polylines, MapPolyline::Kind::kEvaluationLine, f, d.evaluation);
  d.anyBarrier = writePolylines(polylines, MapPolyline::Kind::kBarrier, f, d.barriers);
  d.forest = scratch.file("forest_edges.dat");
  d.anyForest = writePolylines(polylines, MapPolyline::Kind::kForestEdge, f, d.forest);
  return d;
}

// The PNG terminal, the map area's margins and ranges, title and axes.
void writeMapAxes(std::ostringstream& s, const MapFrame& f, const MapLayer& layer,
                  const std::string& output) {
  const double w = f.xMax - f.xMin, h = f.yMax - f.yMin;
  const int plotBottom = f.height - f.top - f.plotHeight;  // px from the PNG's bottom edge
  s << "set terminal pngcairo noenhanced size " << f.width << "," << f.height
    << " font 'DejaVu Sans,11' background '#ffffff'\n"
    << "set encoding utf8\nset output " << gnuplotString(output) << "\n"
    << "set lmargin at " << screenX(f, f.left) << "\nset rmargin at "
    << screenX(f, f.left + f.plotWidth) << "\nset bmargin at " << screenY(f, plotBottom)
    << "\nset tmargin at " << screenY(f, plotBottom + f.plotHeight) << "\n"
    << "set xrange [" << number(f.xMin) << ":" << number(f.xMax) << "]\nset yrange ["
    << number(f.yMin) << ":" << number(f.yMax) << "]\n"
    << "set title " << gnuplotString(layer.title) << " font ',13'\n"
    << "set xlabel " << gnuplotString(f.fileCoordinates ? "Easting (m)" : "x (m)") << "\n"
    << "set ylabel " << gnuplotString(f.fileCoordinates ? "Northing (m)" : "y (m)") << "\n"
    << "set format x '" << (w >= 50 ? "%.0f" : "%g") << "'\nset format y '"
    << (h >= 50 ? "%.0f" : "%g") << "'\n"
    << "set tics out nomirror\nset border front\n";
}

// The colour box beside the map, as tall as the map (at least kMinLegendPx), and the small
// print: how the relief is drawn and which CRS the axes are in.
void writeMapLegend(std::ostringstream& s, const MapFrame& f, const MapLayer& layer,
                    const ValueRange& range, const Heightfield& dem) {
  // The colour box needs a range: an empty layer shows 0..1, a constant one its value +- 1.
  const double lo = range.lo, hi = range.hi;
  const double cbLo = !range.any() ? 0 : hi > lo ? lo : lo - 1;
  const double cbHi = !range.any() ? 1 : hi > lo ? hi : hi + 1;
  const int legendPx = std::max(f.plotHeight, kMinLegendPx);
  const int legendBottom = f.height - f.top - legendPx;
  const bool classed = !layer.classes.edges.empty();
  if (classed) {
    writeClassLegend(s, layer.classes);
  } else {
    writeViridisPalette(s);
    // gnuplot maps the colour box's palette by log10 too, so the legend reads as the pixels do.
    if (layer.logScale && range.any() && hi > lo) s << "set logscale cb\n";
    s << "set cbrange [" << number(cbLo) << ":" << number(cbHi) << "]\nset format cb '%g'\n";
  }
  s << "set colorbox user origin " << screenX(f, f.left + f.plotWidth + 30) << ", "
    << screenY(f, legendBottom) << " size " << screenX(f, 22) << ", " << screenY(f, legendPx)
    << "\nset cbtics out\n"
    << "set cblabel offset " << (classed ? "3.5" : "1.5") << ",0 "
    << gnuplotString(layer.title + (layer.units.empty() ? "" : " (" + layer.units + ")") +
                     (range.any() ? "" : ": no values"))
    << "\n";
  std::string note = "Hillshade: Horn slopes, sun azimuth 315°, altitude 45°. Grey: no value.";
  if (f.fileCoordinates)
    note += dem.crsName.empty() ? " Axes in the DEM's CRS." : " CRS " + dem.crsName + ".";
  s << "set label 1 " << gnuplotString(note) << " at " << screenX(f, 8) << ", " << screenY(f, 8)
    << " font ',9'\n";
}

// Scale bar, bottom left inside the map on a white panel: a black and a white half, 8 px tall;
// north arrow, top right inside the map (the grid is north-up).
void writeScaleAndNorth(std::ostringstream& s, const MapFrame& f) {
  const double w = f.xMax - f.xMin;
  const double mPerPx = w / f.plotWidth;  // same along y
  const double bar = roundLength(0.25 * w);
  const double bx = f.xMin + 20 * mPerPx, by = f.yMin + 20 * mPerPx, bh = 8 * mPerPx;
  const auto rect = [&s](int tag, double x0, double y0, double x1, double y1, const char* fill,
                         const std::string& border) {
    s << "set object " << tag << " rect from " << number(x0) << "," << number(y0) << " to "
      << number(x1) << "," << number(y1) << " front fc rgb '" << fill << "' fs solid 1.0 " << border
      << "\n";
  };
  rect(1, bx - 10 * mPerPx, by - 10 * mPerPx, bx + bar + 10 * mPerPx, by + bh + 30 * mPerPx,
       "#ffffff", "noborder");
  rect(2, bx, by, bx + bar / 2, by + bh, "#000000", "border lc rgb '#000000'");
  rect(3, bx + bar / 2, by, bx + bar, by + bh, "#ffffff", "border lc rgb '#000000'");
  s << "set label 2 " << gnuplotString(lengthLabel(bar)) << " at " << number(bx + bar / 2) << ","
    << number(by + bh + 12 * mPerPx) << " center front\n";
  const double nx = f.xMax - 25 * mPerPx, ny0 = f.yMax - 80 * mPerPx, ny1 = f.yMax - 40 * mPerPx;
  rect(4, nx - 15 * mPerPx, ny0 - 8 * mPerPx, nx + 15 * mPerPx, f.yMax - 4 * mPerPx, "#ffffff",
       "noborder");
  s << "set arrow 1 from " << number(nx) << "," << number(ny0) << " to " << number(nx) << ","
    << number(ny1) << " front filled size screen 0.015,25 lw 2 lc rgb '#000000'\n"
    << "set label 3 'N' at " << number(nx) << "," << number(ny1 + 14 * mPerPx)
    << " center front font ',12'\n";
}

// The key and the plot command: the map's pixels, then the release areas, evaluation lines,
// barriers and forest edges that have anything to draw.
void writeMapPlot(std::ostringstream& s, const MapFrame& f, const MapData& d) {
  const double mPerPx = (f.xMax - f.xMin) / f.plotWidth;
  // Under the colour box's lowest tick label: the release, lines and barriers may add rows.
  s << "set key at " << screenX(f, f.left + f.plotWidth + 10) << ", " << screenY(f, 6)
    << " left bottom Left reverse samplen 2\n";
  s << "plot " << gnuplotString(d.image) << " binary array=(" << f.plotWidth << "," << f.plotHeight
    << ") format='%uchar' dx=" << number(mPerPx) << " dy=" << number(mPerPx) << " origin=("
    << number(f.xMin + mPerPx / 2) << "," << number(f.yMin + mPerPx / 2)
    << ") with rgbalpha notitle";
  // Anything drawn with the palette shows the colour box; a point off the map draws nothing.
  s << ", '+' using (NaN):(NaN):(0) with points lc palette notitle";
  bool titled = false;
  const auto key = [&titled] {
    const bool first = !titled;
    titled = true;
    return first ? " title 'Release area'" : " notitle";
  };
  if (d.anyLine)
    s << ", " << gnuplotString(d.lines) << " using 1:2 with lines lw 3 lc rgb '" << kReleaseColour
      << "'" << key();
  if (d.anyPoint)
    s << ", " << gnuplotString(d.points) << " using 1:2 with points pt 7 ps 1.6 lc rgb '"
      << kReleaseColour << "'" << key();
  if (d.anyEvaluation)
    s << ", " << gnuplotString(d.evaluation)
      << " using 1:2 with lines lw 2.5 lc rgb '#0072b2' title 'Evaluation line'";
  if (d.anyBarrier)
    s << ", " << gnuplotString(d.barriers) << " using 1:2 with lines lw 4 lc rgb '#000000' title "
      << "'Barrier'";
  if (d.anyForest)
    s << ", " << gnuplotString(d.forest) << " using 1:2 with lines lw 1.5 lc rgb '" << kForestColour
      << "' title 'Forest edge'";
  s << "\nset output\n";
}

}  // namespace

void writeHazardMap(const Heightfield& dem, const MapLayer& layer,
                    const std::vector<std::vector<Vec2>>& releaseAreas, const std::string& pngPath,
                    const OutputRules& rules, const MapWindow& window,
                    const std::vector<MapPolyline>& polylines) {
  if (dem.nx < 1 || dem.ny < 1 || dem.z.size() != static_cast<std::size_t>(dem.nx) * dem.ny)
    throw InputError(pngPath, "hazard map: the DEM has no samples");
  if (layer.values.size() != dem.z.size())
    throw InputError(pngPath, "hazard map '" + layer.name + "': " +
                                  std::to_string(layer.values.size()) + " values for a grid of " +
                                  std::to_string(dem.nx) + " x " + std::to_string(dem.ny));
  OutputFile out(pngPath, rules);
  out.closeStream();  // gnuplot writes the temporary file by name

  const ValueRange range = valueRange(layer);
  const MapFrame f = hazardMapFrame(dem, window);
  const fig::ScratchFolder scratch;
  const MapData data =
      writeMapData(scratch, dem, layer, f, range, releaseAreas, polylines, pngPath);
  std::ostringstream s;
  writeMapAxes(s, f, layer, out.tempPath());
  writeMapLegend(s, f, layer, range, dem);
  writeScaleAndNorth(s, f);
  writeMapPlot(s, f, data);
  fig::runGnuplot(s.str(), pngPath);
  out.commit();
}

namespace {

// The type-1 quantile of sorted `x` (the inverse of its empirical CDF): x[ceil(p n) - 1].
double quantile(const std::vector<double>& sorted, double p) {
  const auto n = static_cast<double>(sorted.size());
  const auto k = static_cast<std::size_t>(std::max(1.0, std::ceil(p * n)));
  return sorted[std::min(k, sorted.size()) - 1];
}

// One panel: the empirical CDF of `values` (written to `csv`) with its median and p95 marked.
fig::Panel cdfPanel(std::vector<double> values, const std::string& what, const std::string& unit,
                    const std::string& csv, const std::string& pngPath) {
  std::erase_if(values, [](double v) { return !std::isfinite(v); });
  if (values.empty()) throw InputError(pngPath, "runout plot: no finite " + what + " to plot");
  std::sort(values.begin(), values.end());
  std::ofstream o(csv);
  o << std::setprecision(15) << what << ",cumulative_fraction\n" << values[0] << ",0\n";
  const auto n = static_cast<double>(values.size());
  for (std::size_t k = 0; k < values.size(); ++k) o << values[k] << "," << (k + 1) / n << "\n";
  if (!o) throw InputError(pngPath, "cannot write the temporary file " + csv);
  const double p50 = quantile(values, 0.5), p95 = quantile(values, 0.95);
  std::ostringstream title;
  const std::string u = unit == "°" ? unit : " " + unit;  // 33°, but 550 m
  title << std::setprecision(4) << "median " << p50 << u << ", 95th percentile " << p95 << u;
  fig::Panel p;
  p.title = title.str();
  p.xLabel = what + " (" + unit + ")";
  p.yLabel = "Fraction of realisations at or below";
  p.series.push_back({"", csv, "1:2", "steps", 0, false});
  p.settings = {"set yrange [0:1]",
                "set key off",
                "set arrow 1 from graph 0, first 0.5 to graph 1, first 0.5 nohead dt 2 lc rgb "
                "'#808080'",
                "set arrow 2 from graph 0, first 0.95 to graph 1, first 0.95 nohead dt 2 lc rgb "
                "'#808080'",
                "set arrow 3 from " + number(p50) + ", graph 0 to " + number(p50) +
                    ", first 0.5 nohead dt 3 lc rgb '#808080'",
                "set arrow 4 from " + number(p95) + ", graph 0 to " + number(p95) +
                    ", first 0.95 nohead dt 3 lc rgb '#808080'"};
  return p;
}

}  // namespace

void writeRunoutPlot(const std::vector<double>& runoutsM, const std::vector<double>& reachAnglesDeg,
                     const std::string& pngPath, const OutputRules& rules) {
  const fig::ScratchFolder scratch;
  fig::Figure f;
  f.width = kRunoutPlotWidthPx;
  f.height = kRunoutPlotHeightPx;
  f.panels.push_back(cdfPanel(runoutsM, "Runout", "m", scratch.file("runout.csv"), pngPath));
  f.panels.push_back(
      cdfPanel(reachAnglesDeg, "Reach angle", "°", scratch.file("reach_angle.csv"), pngPath));
  f.title = "Runout and reach angle of " + std::to_string(runoutsM.size()) + " realisations";
  f.footnote = "Empirical cumulative distributions; dashed: median and 95th percentile.";
  const auto missing =
      std::count_if(runoutsM.begin(), runoutsM.end(), [](double v) { return !std::isfinite(v); });
  if (missing > 0)
    f.footnote += " " + std::to_string(missing) + " realisation(s) without a runout left out.";
  fig::drawFigurePng(f, pngPath, rules);
}

}  // namespace vf
