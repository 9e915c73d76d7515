// Polygon-based contact for convex polyhedra: the baseline the paper compares its voxel method
// against (Baraff, "Physically Based Modeling", SIGGRAPH '99 course notes: contacts are
// vertex-face and edge-edge pairs; digest section 7). It feeds the same eq.-15 solver, friction,
// step rule and diagnostics as the voxel method; only where contacts come from differs.
//
// Body-body, for two bodies whose bounding spheres come within the contact margin:
//   1. Separating axes over the mesh's own features: every triangle of A against every vertex
//      of B (and B's against A's), then every edge of A against every edge of B whose Gauss-map
//      arcs cross (Gregorius' "Minkowski face" test, which keeps exactly the edge pairs that can
//      touch). The cost is T_A V_B + T_B V_A + E_A E_B: it grows with the polygon count, which
//      is the reason the paper's method exists. Triangles are not merged into faces for this:
//      the baseline tests the mesh's polygons as they come. Any axis with a gap wider than the
//      margin ends the test (no contact).
//   2. If the deepest axis (least negative separation) is an edge pair, one edge-edge contact at
//      the closest points of the two edges, normal along their cross product.
//   3. Otherwise the reference face is the flat face (coplanar triangles) holding the deepest
//      triangle, and the incident face is the other body's face most opposed to it; clipping the
//      incident outline by the reference outline's side planes (Sutherland-Hodgman) gives the
//      vertex-face contacts (incident vertices over the reference face, reference corners under
//      the incident face) and the edge-edge contacts (crossings of the two outlines) of a
//      face-face touch. Points farther than the margin in front of the reference plane are
//      dropped. A tilted body landing on a corner keeps that corner only.
// Contact point: midway between the incident point and the reference plane (the sphere
// method's midpoint, fig. 5); normal: the reference face's, towards body 1.
//
// Body-plane and body-terrain: each mesh vertex below (or within the margin above) the
// surface is a contact, with the surface normal (Baraff's vertex-face contact with a static
// face). Terrain edges against body faces are not searched: over the terrain the polygon
// method is not compared in the paper.
//
// Where Baraff backs up in time to the moment of contact, this collider, like the paper's, runs
// at a fixed step and finds bodies already overlapping: how deep they get depends on the step,
// which is why the polygon method needs a far smaller step than eq. 20 gives the voxel method.
#include "sim/collide/polygon_contact.h"

#include <algorithm>
#include <cmath>

#include "sim/shape/convex_polyhedron.h"
#include "sim/shape/shape.h"

namespace vf {
namespace {

// A polyhedron in its world pose.
struct Posed {
  const ConvexPolyhedron& p;
  Vec3 centre;
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;    // per triangle
  std::vector<double> offsets;  // per triangle

  explicit Posed(const Collider& c) : p(*c.polyhedron), centre(c.x) {
    vertices.reserve(p.vertices.size());
    for (const Vec3& v : p.vertices) vertices.push_back(c.x + c.R * v);
    normals.reserve(p.triangles.size());
    offsets.reserve(p.triangles.size());
    for (std::size_t t = 0; t < p.triangles.size(); ++t) {
      normals.push_back(c.R * p.triangleNormals[t]);
      offsets.push_back(normals.back().dot(vertices[p.triangles[t][0]]));
    }
  }
};

struct FaceQuery {
  double separation = -INFINITY;
  std::uint32_t triangle = 0;
};

// Deepest separation along A's triangle normals: for each triangle, the lowest vertex of B
// measured from the triangle's plane. Stops early at a gap wider than `margin`.
FaceQuery queryFaces(const Posed& a, const Posed& b, double margin, std::uint64_t& tests) {
  FaceQuery best;
  for (std::size_t t = 0; t < a.normals.size(); ++t) {
    const Vec3& n = a.normals[t];
    double lowest = INFINITY;
    for (const Vec3& v : b.vertices) lowest = std::min(lowest, n.dot(v));
    tests += b.vertices.size();
    const double s = lowest - a.offsets[t];
    if (s > best.separation) best = {s, static_cast<std::uint32_t>(t)};
    if (s > margin) break;
  }
  return best;
}

// Do the Gauss-map arcs a-b and c-d (unit normals) cross? (Gregorius, GDC 2013.)
bool arcsCross(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 bxa = b.cross(a), dxc = d.cross(c);
  const double cba = c.dot(bxa), dba = d.dot(bxa), adc = a.dot(dxc), bdc = b.dot(dxc);
  return cba * dba < 0 && adc * bdc < 0 && cba * bdc > 0;
}

struct EdgeQuery {
  double separation = -INFINITY;
  std::uint32_t edgeA = 0, edgeB = 0;
  Vec3 axis = Vec3::UnitZ();  // unit, pointing out of A
};

EdgeQuery queryEdges(const Posed& a, const Posed& b, double margin, std::uint64_t& tests) {
  EdgeQuery best;
  for (std::size_t i = 0; i < a.p.edges.size(); ++i) {
    const ConvexPolyhedron::Edge& ea = a.p.edges[i];
    const Vec3 &pa = a.vertices[ea.v0], &na0 = a.normals[ea.t0], &na1 = a.normals[ea.t1];
    const Vec3 da = a.vertices[ea.v1] - pa;
    for (std::size_t j = 0; j < b.p.edges.size(); ++j) {
      const ConvexPolyhedron::Edge& eb = b.p.edges[j];
      ++tests;
      if (!arcsCross(na0, na1, -b.normals[eb.t0], -b.normals[eb.t1])) continue;
      const Vec3& pb = b.vertices[eb.v0];
      Vec3 n = da.cross(b.vertices[eb.v1] - pb);
      const double len = n.norm();
      if (len < 1e-12 * da.squaredNorm()) continue;  // parallel edges: a face axis covers them
      n /= len;
      if (n.dot(pa - a.centre) < 0) n = -n;
      const double s = n.dot(pb - pa);
      if (s > best.separation)
        best = {s, static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(j), n};
      if (s > margin) return best;
    }
  }
  return best;
}

// Closest points of segments p1-q1 and p2-q2 (clamped parameters).
void closestPointsOfSegments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2,
                             Vec3& c1, Vec3& c2) {
  const Vec3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = d1.squaredNorm(), e = d2.squaredNorm(), f = d2.dot(r);
  const double c = d1.dot(r), b = d1.dot(d2), denom = a * e - b * b;
  double s = denom > 0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
  double t = (b * s + f) / e;
  if (t < 0) {
    t = 0;
    s = std::clamp(-c / a, 0.0, 1.0);
  } else if (t > 1) {
    t = 1;
    s = std::clamp((b - c) / a, 0.0, 1.0);
  }
  c1 = p1 + s * d1;
  c2 = p2 + t * d2;
}

// A point of a clipped outline and the feature it came from (warm-starting key).
struct ClipPoint {
  Vec3 p;
  std::uint32_t feature;  // vertex index, or bit 31 set for an edge crossing
};

std::uint32_t crossingFeature(std::uint32_t from, std::uint32_t to, std::size_t side) {
  const std::uint64_t h = (static_cast<std::uint64_t>(from) * 0x9E3779B1u) ^
                          (static_cast<std::uint64_t>(to) * 0x85EBCA77u) ^ (side * 0xC2B2AE3Du);
  return static_cast<std::uint32_t>(h & 0x7FFFFFFFu) | 0x80000000u;
}

// Face-face contacts with `ref`'s flat face `face` as reference and `inc` as incident body.
// refIsB: the reference body is the paper's body 2 (normal as given), else body 1.
void clipFaces(const Posed& ref, std::uint32_t face, const Posed& inc, bool refIsB, int bodyA,
               int bodyB, double margin, std::vector<Contact>& out) {
  const ConvexPolyhedron::Face& rf = ref.p.faces[face];
  const std::uint32_t tri0 = static_cast<std::uint32_t>(
      std::find(ref.p.triangleFace.begin(), ref.p.triangleFace.end(), face) -
      ref.p.triangleFace.begin());
  const Vec3 n = ref.normals[tri0];
  const double d = ref.offsets[tri0];
  // Incident face: the one whose normal is most opposed to n.
  std::uint32_t incFace = 0;
  double mostOpposed = INFINITY;
  for (std::size_t t = 0; t < inc.normals.size(); ++t) {
    const double c = inc.normals[t].dot(n);
    if (c < mostOpposed) mostOpposed = c, incFace = inc.p.triangleFace[t];
  }
  std::vector<ClipPoint> poly, next;
  for (std::uint32_t v : inc.p.faces[incFace].loop) poly.push_back({inc.vertices[v], v});
  const std::vector<std::uint32_t>& loop = rf.loop;
  for (std::size_t i = 0; i < loop.size() && !poly.empty(); ++i) {
    const Vec3& p0 = ref.vertices[loop[i]];
    const Vec3 edge = ref.vertices[loop[(i + 1) % loop.size()]] - p0;
    if (edge.squaredNorm() == 0) continue;
    const Vec3 side = edge.cross(n);  // outward for a loop counter-clockwise about n
    next.clear();
    for (std::size_t k = 0; k < poly.size(); ++k) {
      const ClipPoint& u = poly[k];
      const ClipPoint& w = poly[(k + 1) % poly.size()];
      const double du = side.dot(u.p - p0), dw = side.dot(w.p - p0);
      if (du <= 0) next.push_back(u);
      if ((du <= 0) != (dw <= 0)) {
        const double s = du / (du - dw);
        next.push_back({u.p + s * (w.p - u.p), crossingFeature(u.feature, w.feature, i)});
      }
    }
    poly.swap(next);
  }
  for (const ClipPoint& q : poly) {
    const double s = n.dot(q.p) - d;  // > 0: in front of the reference face
    if (s > margin) continue;
    Contact c;
    c.a = bodyA;
    c.b = bodyB;
    c.point = q.p - 0.5 * s * n;
    c.normal = refIsB ? n : Vec3(-n);
    c.depth = -s;
    c.leafA = refIsB ? q.feature : (face | 0x40000000u);
    c.leafB = refIsB ? (face | 0x40000000u) : q.feature;
    out.push_back(c);
  }
}

double marginOf(const Collider& c) { return kPolygonContactMargin * c.polyhedron->boundingRadius; }

}  // namespace

std::uint64_t collidePolygonPolygon(const Collider& a, const Collider& b,
                                    std::vector<Contact>& out) {
  const double margin = std::min(marginOf(a), marginOf(b));
  const double reach = a.polyhedron->boundingRadius + b.polyhedron->boundingRadius + margin;
  std::uint64_t tests = 1;
  if ((a.x - b.x).squaredNorm() >= reach * reach) return tests;  // bounding spheres
  const Posed pa(a), pb(b);
  const FaceQuery fa = queryFaces(pa, pb, margin, tests);
  if (fa.separation > margin) return tests;
  const FaceQuery fb = queryFaces(pb, pa, margin, tests);
  if (fb.separation > margin) return tests;
  const EdgeQuery e = queryEdges(pa, pb, margin, tests);
  if (e.separation > margin) return tests;

  // Faces win ties (a face touch gives several contacts, which a pile needs to rest); an
  // edge pair must be deeper by a tenth of the margin.
  const double tie = 0.1 * margin;
  if (e.separation > std::max(fa.separation, fb.separation) + tie) {
    const ConvexPolyhedron::Edge& ea = pa.p.edges[e.edgeA];
    const ConvexPolyhedron::Edge& eb = pb.p.edges[e.edgeB];
    Vec3 ca, cb;
    closestPointsOfSegments(pa.vertices[ea.v0], pa.vertices[ea.v1], pb.vertices[eb.v0],
                            pb.vertices[eb.v1], ca, cb);
    Contact c;
    c.a = a.body;
    c.b = b.body;
    c.point = 0.5 * (ca + cb);
    c.normal = -e.axis;  // the force on body 1 points into it from B
    c.depth = -e.separation;
    c.leafA = e.edgeA | 0x20000000u;
    c.leafB = e.edgeB | 0x20000000u;
    out.push_back(c);
    return tests;
  }
  if (fa.separation > fb.separation + tie)
    clipFaces(pa, pa.p.triangleFace[fa.triangle], pb, false, a.body, b.body, margin, out);
  else
    clipFaces(pb, pb.p.triangleFace[fb.triangle], pa, true, a.body, b.body, margin, out);
  return tests;
}

std::uint64_t collidePolygonPlane(const Collider& a, const Collider& plane,
                                  std::vector<Contact>& out) {
  const ConvexPolyhedron& p = *a.polyhedron;
  const double margin = marginOf(a);
  if (plane.normal.dot(a.x) - plane.offset >= p.boundingRadius + margin) return 1;
  for (std::size_t i = 0; i < p.vertices.size(); ++i) {
    const Vec3 v = a.x + a.R * p.vertices[i];
    const double h = plane.normal.dot(v) - plane.offset;
    if (h >= margin) continue;
    Contact c;
    c.a = a.body;
    c.b = plane.body;
    c.point = v - h * plane.normal;
    c.normal = plane.normal;
    c.depth = -h;
    c.leafA = static_cast<std::uint32_t>(i);
    out.push_back(c);
  }
  return 1 + p.vertices.size();
}

std::uint64_t collidePolygonHeightfield(const Collider& a, const Collider& terrain,
                                        std::vector<Contact>& out) {
  const ConvexPolyhedron& p = *a.polyhedron;
  const Heightfield& field = *terrain.terrain;
  const double margin = marginOf(a);
  const double r = p.boundingRadius;
  if (a.x.z() - r - margin >= field.maxHeightNear(a.x.x(), a.x.y(), r)) return 1;
  for (std::size_t i = 0; i < p.vertices.size(); ++i) {
    const Vec3 v = a.x + a.R * p.vertices[i];
    const double h = field.heightAt(v.x(), v.y());
    if (std::isnan(h) || v.z() - h >= margin) continue;
    Contact c;
    c.a = a.body;
    c.b = terrain.body;
    c.normal = field.normalAt(v.x(), v.y());
    c.point = Vec3(v.x(), v.y(), h);
    c.depth = (h - v.z()) * c.normal.z();
    c.leafA = static_cast<std::uint32_t>(i);
    c.leafB = kTerrainLeaf;  // not the plane's contact of the same vertex (contact.h)
    out.push_back(c);
  }
  return 1 + p.vertices.size();
}

}  // namespace vf
