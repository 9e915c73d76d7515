// Mass properties of a closed triangle mesh by signed tetrahedra (divergence theorem).
//
// Method. Pick a reference point r. Each outward triangle (a, b, c), taken relative to r,
// spans the tetrahedron T = (0, a, b, c), signed by D = a . (b x c) (positive when the
// triangle faces away from r). Summing over a closed mesh, the signed tetrahedra cancel
// outside the solid and add up to it exactly, so every volume integral of a polynomial is the
// sum of the same integral over the T's:
//
//   T is the image of the canonical tetrahedron (0, e1, e2, e3) under A = [a b c], with
//   Jacobian D. Over the canonical one
//     vol = 1/6,   int x dV = 1/24 (each axis),   int x_i x_j dV = (1 + delta_ij) / 120,
//   i.e. the second moment matrix is (I + 1 1^T) / 120. Mapping by A:
//     V_T  = D / 6
//     M1_T = int x dV  = D / 24 * (a + b + c)
//     C_T  = int x x^T dV = D / 120 * (A (I + 1 1^T) A^T)
//          = D / 120 * (a a^T + b b^T + c c^T + s s^T),   s = a + b + c.
//
// Then V = sum V_T, centre of mass g = M1 / V (relative to r), the second moments about the
// centre of mass C_g = C - V g g^T (parallel-axis theorem for second moments), and the
// inertia tensor I = density * (trace(C_g) * Id - C_g), since I = int (|x|^2 Id - x x^T) dm.
//
// r is the bounding-box centre: with r far away the per-triangle terms grow like |r|^2 and
// cancel in the sum, losing digits; near the centre every term is of the size of the result.
#include "sim/geometry/mass_properties.h"

namespace vf {

MassProperties computeMassProperties(const TriMesh& mesh, double density) {
  const Vec3 ref = mesh.bounds().center();
  double volume6 = 0;             // 6 V
  Vec3 moment24 = Vec3::Zero();   // 24 * int x dV
  Mat3 second120 = Mat3::Zero();  // 120 * int x x^T dV
  for (const auto& t : mesh.triangles) {
    const Vec3 a = mesh.vertices[t[0]] - ref;
    const Vec3 b = mesh.vertices[t[1]] - ref;
    const Vec3 c = mesh.vertices[t[2]] - ref;
    const double d = a.dot(b.cross(c));
    const Vec3 s = a + b + c;
    volume6 += d;
    moment24 += d * s;
    second120 +=
        d * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }

  MassProperties mp;
  mp.volume = volume6 / 6;
  mp.mass = density * mp.volume;
  // Kept independent of density on purpose: centredMesh (density 1) and makeShape (real
  // density) must move the mesh by bit-identical offsets so their sphere trees match.
  const Vec3 g = (moment24 / 24) / mp.volume;
  mp.centerOfMass = ref + g;
  const Mat3 second = second120 / 120 - mp.volume * g * g.transpose();  // about the COM
  Mat3 inertia = density * (second.trace() * Mat3::Identity() - second);
  mp.inertia = 0.5 * (inertia + inertia.transpose());  // exact symmetry despite round-off
  return mp;
}

}  // namespace vf
