#include "render/draw_data.h"

namespace vf {

GpuTransform gpuTransform(const Mat4& model) {
  GpuTransform t;
  t.model = model.cast<float>();
  t.normal = model.block<3, 3>(0, 0).inverse().transpose().cast<float>();
  return t;
}

}  // namespace vf
