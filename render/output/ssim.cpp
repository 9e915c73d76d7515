#include "render/output/ssim.h"

#include <array>
#include <cmath>
#include <vector>

#include "sim/core/error.h"

namespace vf {
namespace {

constexpr int kWindow = 11;
constexpr double kSigma = 1.5;
constexpr double kC1 = (0.01 * 255) * (0.01 * 255);
constexpr double kC2 = (0.03 * 255) * (0.03 * 255);

double luma(const std::uint8_t* p) { return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2]; }

// One window's SSIM from its weighted moments.
double ssimOf(double mx, double my, double xx, double yy, double xy) {
  const double vx = xx - mx * mx, vy = yy - my * my, cxy = xy - mx * my;
  return ((2 * mx * my + kC1) * (2 * cxy + kC2)) / ((mx * mx + my * my + kC1) * (vx + vy + kC2));
}

// The five planes whose weighted sums give a window's moments: x, y, x^2, y^2, x y.
std::array<std::vector<double>, 5> momentPlanes(const Image& e, const Image& a,
                                                const PixelMask& mask) {
  const std::size_t n = static_cast<std::size_t>(e.width) * e.height;
  std::array<std::vector<double>, 5> p;
  for (auto& v : p) v.resize(n);
  for (int y = 0; y < e.height; ++y)
    for (int x = 0; x < e.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * e.width + x;
      const double u = luma(e.pixel(x, y));
      const double v = masked(mask, x, y) ? u : luma(a.pixel(x, y));
      p[0][i] = u, p[1][i] = v, p[2][i] = u * u, p[3][i] = v * v, p[4][i] = u * v;
    }
  return p;
}

// An image too small for the window: one window over all of it, uniform weights.
double wholeImageSsim(const std::array<std::vector<double>, 5>& p) {
  std::array<double, 5> m{};
  for (int k = 0; k < 5; ++k) {
    for (double v : p[k]) m[k] += v;
    m[k] /= static_cast<double>(p[k].size());
  }
  return ssimOf(m[0], m[1], m[2], m[3], m[4]);
}

std::array<double, kWindow> gaussianWeights() {
  std::array<double, kWindow> w{};
  double sum = 0;
  for (int i = 0; i < kWindow; ++i) {
    const double d = i - kWindow / 2;
    w[i] = std::exp(-d * d / (2 * kSigma * kSigma));
    sum += w[i];
  }
  for (double& v : w) v /= sum;  // the 2-D window is the outer product: its weights sum to 1
  return w;
}

}  // namespace

double meanSsim(const Image& e, const Image& a, const PixelMask& mask) {
  VF_ASSERT(e.width == a.width && e.height == a.height);
  const auto planes = momentPlanes(e, a, mask);
  if (e.width < kWindow || e.height < kWindow) return wholeImageSsim(planes);
  const auto w = gaussianWeights();
  const int outW = e.width - kWindow + 1, outH = e.height - kWindow + 1;
  // Separable filtering: rows first into `rows`, then columns, each over the valid range.
  std::array<std::vector<double>, 5> rows;
  for (int k = 0; k < 5; ++k) {
    rows[k].assign(static_cast<std::size_t>(outW) * e.height, 0);
    for (int y = 0; y < e.height; ++y)
      for (int x = 0; x < outW; ++x) {
        double s = 0;
        for (int i = 0; i < kWindow; ++i)
          s += w[i] * planes[k][static_cast<std::size_t>(y) * e.width + x + i];
        rows[k][static_cast<std::size_t>(y) * outW + x] = s;
      }
  }
  double total = 0;
  long long windows = 0;
  for (int y = 0; y < outH; ++y)
    for (int x = 0; x < outW; ++x) {
      if (masked(mask, x + kWindow / 2, y + kWindow / 2)) continue;
      std::array<double, 5> m{};
      for (int k = 0; k < 5; ++k)
        for (int i = 0; i < kWindow; ++i)
          m[k] += w[i] * rows[k][static_cast<std::size_t>(y + i) * outW + x];
      total += ssimOf(m[0], m[1], m[2], m[3], m[4]);
      ++windows;
    }
  return windows > 0 ? total / static_cast<double>(windows) : 1.0;
}

}  // namespace vf
