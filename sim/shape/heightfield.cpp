#include "sim/shape/heightfield.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "sim/core/error.h"

namespace vf {

bool Heightfield::hasCell(int i, int j) const {
  return i >= 0 && j >= 0 && i + 1 < nx && j + 1 < ny && !std::isnan(at(i, j)) &&
         !std::isnan(at(i + 1, j)) && !std::isnan(at(i, j + 1)) && !std::isnan(at(i + 1, j + 1));
}

double Heightfield::heightAt(double x, double y) const {
  const double gx = (x - x0) / cell, gy = (y - y0) / cell;
  const double fi = std::floor(gx), fj = std::floor(gy);
  // The far edge of the grid belongs to the last cell.
  const int i = static_cast<int>(std::min(fi, static_cast<double>(nx - 2)));
  const int j = static_cast<int>(std::min(fj, static_cast<double>(ny - 2)));
  if (!(gx >= 0 && gy >= 0 && gx <= nx - 1 && gy <= ny - 1) || !hasCell(i, j))
    return std::numeric_limits<double>::quiet_NaN();
  const double u = gx - i, v = gy - j;
  const double z00 = at(i, j), z10 = at(i + 1, j), z01 = at(i, j + 1), z11 = at(i + 1, j + 1);
  if (u >= v) return z00 + u * (z10 - z00) + v * (z11 - z10);  // triangle (p00, p10, p11)
  return z00 + v * (z01 - z00) + u * (z11 - z01);               // triangle (p00, p11, p01)
}

Vec3 Heightfield::normalAt(double x, double y) const {
  const double gx = (x - x0) / cell, gy = (y - y0) / cell;
  const int i = static_cast<int>(std::clamp(std::floor(gx), 0.0, static_cast<double>(nx - 2)));
  const int j = static_cast<int>(std::clamp(std::floor(gy), 0.0, static_cast<double>(ny - 2)));
  if (!hasCell(i, j)) return Vec3::UnitZ();
  Vec3 tri[2][3];
  cellTriangles(i, j, tri);
  const Vec3* t = (gx - i) >= (gy - j) ? tri[0] : tri[1];
  return (t[1] - t[0]).cross(t[2] - t[0]).normalized();
}

void Heightfield::cellRange(double x, double y, double r, int& i0, int& i1, int& j0,
                            int& j1) const {
  auto lo = [&](double v, int n) {
    return static_cast<int>(std::clamp(std::floor(v / cell), 0.0, static_cast<double>(n - 2)));
  };
  const double gx0 = x - r - x0, gx1 = x + r - x0, gy0 = y - r - y0, gy1 = y + r - y0;
  const double wx = (nx - 1) * cell, wy = (ny - 1) * cell;
  if (gx1 < 0 || gy1 < 0 || gx0 > wx || gy0 > wy) {
    i0 = j0 = 0;
    i1 = j1 = -1;
    return;
  }
  i0 = lo(gx0, nx);
  i1 = lo(gx1, nx);
  j0 = lo(gy0, ny);
  j1 = lo(gy1, ny);
}

double Heightfield::maxHeightNear(double x, double y, double r) const {
  int i0, i1, j0, j1;
  cellRange(x, y, r, i0, i1, j0, j1);
  double top = -INFINITY;
  for (int j = j0; j <= j1 + 1 && j < ny; ++j)  // a cell's samples run to i + 1, j + 1
    for (int i = i0; i <= i1 + 1 && i < nx; ++i)
      if (!std::isnan(at(i, j))) top = std::max(top, at(i, j));
  return top;
}

void Heightfield::cellTriangles(int i, int j, Vec3 tri[2][3]) const {
  const Vec3 p00(x0 + i * cell, y0 + j * cell, at(i, j));
  const Vec3 p10(x0 + (i + 1) * cell, y0 + j * cell, at(i + 1, j));
  const Vec3 p01(x0 + i * cell, y0 + (j + 1) * cell, at(i, j + 1));
  const Vec3 p11(x0 + (i + 1) * cell, y0 + (j + 1) * cell, at(i + 1, j + 1));
  tri[0][0] = p00, tri[0][1] = p10, tri[0][2] = p11;
  tri[1][0] = p00, tri[1][1] = p11, tri[1][2] = p01;
}

TriMesh Heightfield::toMesh() const {
  TriMesh m;
  m.vertices.reserve(z.size());
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i)
      m.vertices.push_back(Vec3(x0 + i * cell, y0 + j * cell, std::isnan(at(i, j)) ? 0 : at(i, j)));
  auto id = [&](int i, int j) { return static_cast<std::uint32_t>(j * nx + i); };
  for (int j = 0; j + 1 < ny; ++j)
    for (int i = 0; i + 1 < nx; ++i)
      if (hasCell(i, j)) {
        m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      }
  return m;
}

namespace {

// Reads whitespace-separated tokens and knows the line each came from.
class Tokens {
 public:
  explicit Tokens(std::istream& in) : in_(in) {}
  bool next(std::string& token) {
    while (true) {
      while (pos_ < line_.size() && std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
      if (pos_ < line_.size()) break;
      if (!std::getline(in_, line_)) return false;
      ++lineNo_;
      pos_ = 0;
    }
    const std::size_t start = pos_;
    while (pos_ < line_.size() && !std::isspace(static_cast<unsigned char>(line_[pos_]))) ++pos_;
    token = line_.substr(start, pos_ - start);
    return true;
  }
  int line() const { return lineNo_; }

 private:
  std::istream& in_;
  std::string line_;
  std::size_t pos_ = 0;
  int lineNo_ = 0;
};

bool parseNumber(const std::string& s, double& v) {
  std::istringstream ss(s);
  ss.imbue(std::locale::classic());
  ss >> v;
  return ss && ss.peek() == std::char_traits<char>::eof() && std::isfinite(v);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

}  // namespace

Heightfield loadEsriAsciiGrid(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path, "cannot open terrain grid (no such file or not readable)");
  Tokens tokens(in);
  auto fail = [&](const std::string& what) -> InputError {
    return InputError(sourceLocation(path, tokens.line()), what);
  };
  double ncols = -1, nrows = -1, xll = NAN, yll = NAN, cellsize = -1, nodata = NAN;
  bool centre = false;
  std::string key, value;
  // Header: "key value" pairs until the first token that is a number.
  while (true) {
    if (!tokens.next(key)) throw fail("grid ends inside its header");
    double probe;
    if (parseNumber(key, probe)) break;  // first data value
    if (!tokens.next(value)) throw fail("header key '" + key + "' has no value");
    double v;
    if (!parseNumber(value, v)) throw fail("header value '" + value + "' of '" + key + "' is not a number");
    const std::string k = lower(key);
    if (k == "ncols") ncols = v;
    else if (k == "nrows") nrows = v;
    else if (k == "xllcorner" || k == "xllcenter") { xll = v; centre = k == "xllcenter"; }
    else if (k == "yllcorner" || k == "yllcenter") yll = v;
    else if (k == "cellsize") cellsize = v;
    else if (k == "nodata_value") nodata = v;
    else throw fail("unknown header key '" + key + "' (expected ncols, nrows, xllcorner, yllcorner, cellsize, NODATA_value)");
  }
  if (ncols < 2 || nrows < 2 || ncols != std::floor(ncols) || nrows != std::floor(nrows))
    throw fail("ncols and nrows must be whole numbers of at least 2");
  if (!(cellsize > 0)) throw fail("cellsize must be positive");
  if (std::isnan(xll) || std::isnan(yll)) throw fail("header needs xllcorner (or xllcenter) and yllcorner (or yllcenter)");

  Heightfield h;
  h.nx = static_cast<int>(ncols);
  h.ny = static_cast<int>(nrows);
  h.cell = cellsize;
  h.x0 = centre ? xll : xll + cellsize / 2;
  h.y0 = centre ? yll : yll + cellsize / 2;
  h.z.assign(static_cast<std::size_t>(h.nx) * h.ny, NAN);
  const std::size_t count = h.z.size();
  std::string token = key;  // the first data value, already read
  for (std::size_t n = 0; n < count; ++n) {
    if (n > 0 && !tokens.next(token))
      throw fail("grid has " + std::to_string(n) + " values; the header promises " + std::to_string(count));
    double v;
    if (!parseNumber(token, v)) throw fail("'" + token + "' is not a number");
    const int row = static_cast<int>(n / h.nx);  // from the north
    const int i = static_cast<int>(n % h.nx);
    const int j = h.ny - 1 - row;
    h.z[static_cast<std::size_t>(j) * h.nx + i] = (!std::isnan(nodata) && v == nodata) ? NAN : v;
  }
  if (tokens.next(token)) throw fail("grid has more values than ncols x nrows = " + std::to_string(count));
  h.zMin = INFINITY;
  h.zMax = -INFINITY;
  for (double v : h.z)
    if (!std::isnan(v)) h.zMin = std::min(h.zMin, v), h.zMax = std::max(h.zMax, v);
  if (!std::isfinite(h.zMin)) throw InputError(path, "grid has no data (every value is NODATA)");
  return h;
}

}  // namespace vf
