#!/usr/bin/env python3
"""Generates the meshes of the paper's examples 3-6 and the cliff terrain of example 6.

Suzuki, Kubota & Ohtsubo (2003), section 5 (README: Reference) gives, for each
example body, only its triangle and vertex counts and its mass; this script builds closed,
outward-oriented meshes with exactly those counts and dimensions chosen to give those masses:

  scenes/meshes/highpoly_block.obj  example 3: 98 vertices, 192 triangles, 670 kg at 800 kg/m^3
  scenes/meshes/stack_block.obj     example 4: 14 vertices, 24 triangles, 44 kg at 800 kg/m^3
  scenes/meshes/cross.obj           example 5: 32 vertices, 60 triangles, non-convex
  scenes/meshes/barrel.obj          example 5b: an open-topped thick-walled cylinder (a cup)
  scenes/meshes/rock.obj            example 6: 14 vertices, 24 triangles, convex, irregular
  scenes/terrain/cliff.asc          example 6: a 9.5 m cliff on a 0.5 m ESRI ASCII grid

Run from anywhere: `python3 scenes/meshes/make_meshes.py`. Python 3 standard library only,
no randomness: the output is byte-identical on every run. Every mesh is checked here before it
is written (counts, every edge shared by two triangles in opposite directions, positive volume,
no degenerate triangle); tests/sim/example_meshes_test.cpp checks the files again through the
project's own importer.
"""

import math
import os

HERE = os.path.dirname(os.path.abspath(__file__))
SCENES = os.path.dirname(HERE)
WOOD = 800.0  # kg/m^3, examples 1-5
ROCK = 2500.0  # kg/m^3, example 6


# --- small vector helpers ---------------------------------------------------------------

def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def num(x):
    """Shortest round-trip text of x, rounded to 1e-10 m (kills 0.30000000000000004), no -0."""
    x = round(x, 10)
    if x == 0:
        x = 0.0
    s = repr(x)
    return s[:-2] if s.endswith(".0") else s


# --- mesh checks (the same conditions vf::validateClosedMesh enforces) -------------------

def volume(verts, tris):
    return sum(dot(verts[a], cross(verts[b], verts[c])) for a, b, c in tris) / 6.0


def check_closed(name, verts, tris, nv, nt):
    assert len(verts) == nv, (name, len(verts), nv)
    assert len(tris) == nt, (name, len(tris), nt)
    assert len(set(verts)) == len(verts), (name, "duplicate vertex positions")
    used = set(i for t in tris for i in t)
    assert used == set(range(len(verts))), (name, "unused vertex")
    edges = {}
    for t in tris:
        area2 = norm(cross(sub(verts[t[1]], verts[t[0]]), sub(verts[t[2]], verts[t[0]])))
        assert area2 > 1e-6, (name, "degenerate triangle", t)
        for k in range(3):
            e = (t[k], t[(k + 1) % 3])
            assert e not in edges, (name, "edge used twice in one direction", e)
            edges[e] = t
    for (a, b) in edges:
        assert (b, a) in edges, (name, "open or inconsistently oriented edge", (a, b))
    assert len(verts) - len(edges) // 2 + len(tris) == 2, (name, "not a sphere-like surface")
    vol = volume(verts, tris)
    assert vol > 0, (name, "inward (negative volume)")
    return vol


def write_obj(name, header, verts, tris):
    lines = ["# " + h if h else "#" for h in header]
    lines += ["v " + " ".join(num(c) for c in v) for v in verts]
    lines += ["f %d %d %d" % (a + 1, b + 1, c + 1) for a, b, c in tris]
    with open(os.path.join(HERE, name), "w", newline="\n") as f:
        f.write("\n".join(lines) + "\n")


def bbox_text(verts):
    lo = [min(v[k] for v in verts) for k in range(3)]
    hi = [max(v[k] for v in verts) for k in range(3)]
    return " x ".join("%.4g" % (hi[k] - lo[k]) for k in range(3))


# --- 1. example 3: a box with every face a 4 x 4 grid of quads --------------------------

def gridded_box(size, n):
    """Box centred at the origin, each face an n x n grid of quads (2 triangles each).
    Vertices are the surface points of the (n+1)^3 lattice: (n+1)^3 - (n-1)^3 of them."""
    index = {}
    verts = []

    def vid(i, j, k):
        key = (i, j, k)
        if key not in index:
            index[key] = len(verts)
            verts.append(tuple((c / n - 0.5) * s for c, s in zip(key, size)))
        return index[key]

    tris = []
    # For each axis and side: the lattice point of (u, v) on that face, with (u, v) ordered so
    # that u x v points outward; quads split along alternating diagonals (a symmetric pattern).
    for axis in range(3):
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3  # right-handed: e_a1 x e_a2 = e_axis
        for side in (0, n):
            for u in range(n):
                for v in range(n):
                    def p(du, dv):
                        c = [0, 0, 0]
                        c[axis] = side
                        if side == n:
                            c[a1], c[a2] = u + du, v + dv
                        else:  # mirrored so the face still winds outward (-axis)
                            c[a2], c[a1] = u + du, v + dv
                        return vid(*c)
                    q00, q10, q11, q01 = p(0, 0), p(1, 0), p(1, 1), p(0, 1)
                    if (u + v) % 2 == 0:
                        tris += [(q00, q10, q11), (q00, q11, q01)]
                    else:
                        tris += [(q00, q10, q01), (q10, q11, q01)]
    return verts, tris


def make_highpoly_block():
    # 670 kg / 800 kg/m^3 = 0.8375 m^3 = 837 500 000 mm^3 = 2^5 * 5^8 * 67 mm^3. Whole-mm edges
    # with exactly that product: 1250 x 1000 x 670 mm (so the height in mm equals the mass in kg).
    a, b, c = 1.25, 1.0, 0.67
    verts, tris = gridded_box((a, b, c), 4)
    vol = check_closed("highpoly_block", verts, tris, 98, 192)
    assert abs(vol - 0.8375) < 1e-12
    write_obj("highpoly_block.obj", [
        "The high-polygon block of the paper's example 3 (Suzuki, Kubota & Ohtsubo 2003, section 5;",
        "README: Reference): 98 vertices, 192 triangles, 670 kg of wood at 800 kg/m^3.",
        "A box centred at the origin, in metres, counter-clockwise seen from outside, closed.",
        "Each of its 6 faces is a 4 x 4 grid of quads, 2 triangles each: 6 * 16 * 2 = 192",
        "triangles; the vertices are the surface points of a 5 x 5 x 5 lattice: 5^3 - 3^3 = 98.",
        "Edges a x b x c = 1.25 x 1.0 x 0.67 m (x, y, z), lying on its largest face.",
        "  670 kg at 800 kg/m^3:  a b c = 670 / 800 = 0.8375 m^3 exactly (1.25 * 1.0 * 0.67).",
        "The paper gives no dimensions, only the mass. 0.8375 m^3 = 2^5 * 5^8 * 67 mm^3, so the",
        "whole-millimetre boxes of exactly that volume are few; 1250 x 1000 x 670 mm is the",
        "block-like one (not a cube, not a plate), so the mass is exact, not rounded.",
        "Generated by make_meshes.py in this folder; edit that, not this file.",
    ], verts, tris)
    return vol


# --- 2. example 4: a box with every face fanned around its centre ----------------------

def fanned_box(size):
    hx, hy, hz = (s / 2 for s in size)
    verts = [(sx * hx, sy * hy, sz * hz) for sz in (-1, 1) for sy in (-1, 1) for sx in (-1, 1)]
    corner = {v: i for i, v in enumerate(verts)}
    tris = []
    for axis in range(3):
        a1, a2 = (axis + 1) % 3, (axis + 2) % 3
        h = (hx, hy, hz)
        for sign in (-1, 1):
            centre = [0.0, 0.0, 0.0]
            centre[axis] = sign * h[axis]
            c = len(verts)
            verts.append(tuple(centre))
            # The face's corners in counter-clockwise order seen from outside.
            ring = []
            for s1, s2 in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis] = sign * h[axis]
                if sign > 0:
                    p[a1], p[a2] = s1 * h[a1], s2 * h[a2]
                else:
                    p[a2], p[a1] = s1 * h[a2], s2 * h[a1]
                ring.append(corner[tuple(p)])
            for k in range(4):
                tris.append((c, ring[k], ring[(k + 1) % 4]))
    return verts, tris


def make_stack_block():
    # 44 kg / 800 kg/m^3 = 0.055 m^3 = 2^6 * 5^7 * 11 mm^3; 550 x 400 x 250 mm is exact and
    # brick-like (proportions about 2.2 : 1.6 : 1), so stacked blocks overlap and can bridge.
    a, b, c = 0.55, 0.4, 0.25
    verts, tris = fanned_box((a, b, c))
    vol = check_closed("stack_block", verts, tris, 14, 24)
    assert abs(vol - 0.055) < 1e-12
    write_obj("stack_block.obj", [
        "The stacking block of the paper's example 4 (Suzuki, Kubota & Ohtsubo 2003, section 5;",
        "README: Reference): 14 vertices, 24 triangles, 44 kg of wood at 800 kg/m^3.",
        "A box centred at the origin, in metres, counter-clockwise seen from outside, closed.",
        "Each of its 6 faces is fanned into 4 triangles around a vertex at the face centre:",
        "8 corners + 6 face centres = 14 vertices, 6 * 4 = 24 triangles.",
        "Edges a x b x c = 0.55 x 0.4 x 0.25 m (x, y, z), lying on its largest face.",
        "  44 kg at 800 kg/m^3:  a b c = 44 / 800 = 0.055 m^3 exactly (0.55 * 0.4 * 0.25).",
        "The paper gives only the mass; these whole-millimetre edges give it exactly and make a",
        "brick-like block (2.2 : 1.6 : 1) that stacks in layers.",
        "Generated by make_meshes.py in this folder; edit that, not this file.",
    ], verts, tris)
    return vol


# --- 3. example 5: an extruded plus sign with pointed arm tips --------------------------

def area2d(poly):
    return 0.5 * sum(poly[i][0] * poly[(i + 1) % len(poly)][1] -
                     poly[(i + 1) % len(poly)][0] * poly[i][1] for i in range(len(poly)))


def orient2d(a, b, c):
    return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])


def min_angle(a, b, c):
    def ang(p, q, r):
        u = (q[0] - p[0], q[1] - p[1])
        v = (r[0] - p[0], r[1] - p[1])
        return math.acos(max(-1.0, min(1.0, (u[0] * v[0] + u[1] * v[1]) /
                                       (math.hypot(*u) * math.hypot(*v)))))
    return min(ang(a, b, c), ang(b, c, a), ang(c, a, b))


def ear_clip(poly):
    """Triangulates a simple counter-clockwise polygon. At every step, of all the ears (strictly
    convex corners whose triangle holds no other remaining vertex, not even on its boundary),
    clips the one with the largest smallest angle (ties: lowest index), so no triangle is
    inverted or degenerate and slivers are avoided."""
    idx = list(range(len(poly)))
    tris = []
    while len(idx) > 3:
        best = None
        for k in range(len(idx)):
            i, j, l = idx[k - 1], idx[k], idx[(k + 1) % len(idx)]
            a, b, c = poly[i], poly[j], poly[l]
            if orient2d(a, b, c) <= 1e-12:
                continue  # reflex or collinear corner
            if any(orient2d(a, b, poly[m]) >= 0 and orient2d(b, c, poly[m]) >= 0 and
                   orient2d(c, a, poly[m]) >= 0 for m in idx if m not in (i, j, l)):
                continue  # another vertex inside or on the candidate ear
            q = min_angle(a, b, c)
            if best is None or q > best[0] + 1e-12:
                best = (q, k, (i, j, l))
        assert best is not None, "no ear: polygon not simple"
        tris.append(best[2])
        del idx[best[1]]
    tris.append(tuple(idx))
    return tris


def make_cross():
    span, width, thick, tip = 0.6, 0.2, 0.15, 0.03
    r, w = span / 2, width / 2
    e = r - tip  # arm end corners; the tip point sticks out `tip` beyond them
    # The outline, counter-clockwise seen from +z, starting at the +x arm's lower corner.
    quarter = [(e, -w), (r, 0.0), (e, w), (w, w)]
    poly = []
    for q in range(4):  # rotate the +x arm by q * 90 degrees
        for x, y in quarter:
            for _ in range(q):
                x, y = -y, x
            poly.append((x + 0.0, y + 0.0))
    assert len(poly) == 16 and area2d(poly) > 0
    cap = ear_clip(poly)
    assert len(cap) == 14
    assert abs(sum(area2d([poly[i] for i in t]) for t in cap) - area2d(poly)) < 1e-12
    assert min(area2d([poly[i] for i in t]) for t in cap) > 1e-4
    n = len(poly)
    h = thick / 2
    verts = [(x, y, -h) for x, y in poly] + [(x, y, h) for x, y in poly]
    tris = []
    for i in range(n):  # side walls: outward is to the right of a counter-clockwise edge
        j = (i + 1) % n
        tris += [(i, j, n + j), (i, n + j, n + i)]
    tris += [(n + a, n + b, n + c) for a, b, c in cap]  # top, seen from +z
    tris += [(a, c, b) for a, b, c in cap]  # bottom, reversed
    vol = check_closed("cross", verts, tris, 32, 60)
    assert abs(vol - area2d(poly) * thick) < 1e-12
    write_obj("cross.obj", [
        "The non-convex cross of the paper's example 5 (Suzuki, Kubota & Ohtsubo 2003, section 5;",
        "README: Reference): 32 vertices, 60 triangles, wood at 800 kg/m^3.",
        "A plus sign extruded along z, centred at the origin, in metres, counter-clockwise seen",
        "from outside, closed. Its outline has 16 vertices: a plus sign (12 corners) whose four",
        "arm ends each carry a shallow point (3 vertices per arm end instead of 2). Extruded:",
        "2 * 16 = 32 vertices, 2 * 16 side triangles + 2 * 14 cap triangles = 60 triangles (each",
        "cap ear-clipped by make_meshes.py: no degenerate or inverted triangle).",
        "The paper gives only the counts; chosen: span 0.6 m tip to tip along x and along y (the",
        "arm-end corners at +-0.27 m, the tip points 0.03 m beyond them), arm width 0.2 m,",
        "thickness 0.15 m (z from -0.075 to 0.075). Bounding box 0.6 x 0.6 x 0.15 m.",
        "Outline area 0.188 m^2, volume %s m^3, %s kg at 800 kg/m^3." % (
            num(vol), "%.2f" % (vol * WOOD)),
        "Generated by make_meshes.py in this folder; edit that, not this file.",
    ], verts, tris)
    return vol


# --- 4. example 6: a convex irregular rock, the hull of 14 points -----------------------

def hull_faces(pts):
    """Brute-force convex hull of points in general position: every triple whose plane has all
    other points strictly on one side is a face, wound so the others lie behind it."""
    faces = []
    n = len(pts)
    margin = float("inf")  # the smallest distance of any other point to a face plane
    for i in range(n):
        for j in range(i + 1, n):
            for k in range(j + 1, n):
                nrm = cross(sub(pts[j], pts[i]), sub(pts[k], pts[i]))
                nrm_len = norm(nrm)
                d = [dot(nrm, sub(pts[m], pts[i])) / nrm_len
                     for m in range(n) if m not in (i, j, k)]
                if all(x < 0 for x in d):
                    faces.append((i, j, k))
                elif all(x > 0 for x in d):
                    faces.append((i, k, j))
                else:
                    continue
                margin = min(margin, min(abs(x) for x in d))
    return faces, margin


def make_rock():
    # 14 directions spread over the sphere (a Fibonacci spiral), each nudged by a few degrees
    # with fixed sines, at radii of a 0.56 x 0.48 x 0.40 m ellipsoid varied by up to 12 %, then
    # rounded to the millimetre. Fixed sines, not random numbers, so the rock never changes; the
    # checks below prove that all 14 points are hull vertices in general position. (The sine
    # frequencies were picked, among a few tried, for the widest margin, 18 mm, of non-face
    # vertices behind the face planes.)
    n = 14
    golden = math.pi * (3 - math.sqrt(5))
    pts = []
    for i in range(n):
        z = 1 - (2 * i + 1) / n
        z = max(-0.97, min(0.97, z + 0.08 * math.sin(2.7 * i + 0.4)))
        phi = golden * i + 0.35 * math.sin(2.1 * i + 1.1)
        s = math.sqrt(1 - z * z)
        d = (s * math.cos(phi), s * math.sin(phi), z)
        rad = 1 + 0.08 * math.sin(3.7 * i + 0.5) + 0.04 * math.cos(5.3 * i)
        pts.append(tuple(round(rad * c * a, 3) for c, a in zip(d, (0.28, 0.24, 0.20))))
    # Centre the box of the points on the origin (the millimetre grid is kept: shifts are whole mm).
    centre = [round((max(p[k] for p in pts) + min(p[k] for p in pts)) / 2, 3) for k in range(3)]
    pts = [tuple(round(p[k] - centre[k], 3) for k in range(3)) for p in pts]
    faces, margin = hull_faces(pts)
    assert margin > 0.01, margin  # every non-face point is over 1 cm behind every face plane
    vol = check_closed("rock", pts, faces, 14, 24)  # all 14 on the hull: 2 * 14 - 4 = 24 faces
    edge_set = set()
    for t in faces:
        for k in range(3):
            edge_set.add(tuple(sorted((t[k], t[(k + 1) % 3]))))
    lengths = sorted(norm(sub(pts[a], pts[b])) for a, b in edge_set)
    assert len(edge_set) == 36 and lengths[-1] > 1.5 * lengths[0]
    write_obj("rock.obj", [
        "The rock of the paper's example 6 (Suzuki, Kubota & Ohtsubo 2003, section 5;",
        "README: Reference): 14 vertices, 24 triangles, convex and irregular.",
        "In metres, the centre of its bounding box at the origin, counter-clockwise seen from",
        "outside, closed. It is the convex hull of 14 points in general position, every one of",
        "them a hull vertex, so the hull has exactly 2 * 14 - 4 = 24 triangular faces (Euler).",
        "The points: a Fibonacci spiral of 14 directions, each nudged by fixed sines, at the radii",
        "of a 0.56 x 0.48 x 0.40 m ellipsoid varied by up to 12 %, rounded to the millimetre",
        "(make_meshes.py; no random numbers). Every non-face vertex lies over 1 cm behind every",
        "face plane; edges run from %.3f to %.3f m." % (lengths[0], lengths[-1]),
        "The paper gives only the counts and 'about 0.5 m'; bounding box %s m." % bbox_text(pts),
        "Volume %s m^3; the scene's density 2500 kg/m^3 gives %.1f kg." % (num(vol), vol * ROCK),
        "Generated by make_meshes.py in this folder; edit that, not this file.",
    ], pts, faces)
    return vol


# --- 5. example 5b: a barrel, an open-topped thick-walled cylinder ----------------------

def make_barrel():
    ro, ri, height, floor, seg = 0.5, 0.44, 1.0, 0.06, 24
    ring = [(math.cos(2 * math.pi * k / seg), math.sin(2 * math.pi * k / seg)) for k in range(seg)]
    rings = [(ro, 0.0), (ro, height), (ri, height), (ri, floor)]  # outer bottom .. inner floor
    verts = [(r * c, r * s, z) for r, z in rings for c, s in ring]
    bottom_centre, floor_centre = len(verts), len(verts) + 1
    verts += [(0.0, 0.0, 0.0), (0.0, 0.0, floor)]

    def v(ring_index, k):
        return ring_index * seg + k % seg

    tris = []
    # Rings 0 -> 1 -> 2 -> 3 walk the profile outer wall up, rim inward, inner wall down; the
    # band between consecutive rings faces outward of the solid for (r, k), (r, k+1), (r+1, k+1).
    for r in range(3):
        for k in range(seg):
            a, b, c, d = v(r, k), v(r, k + 1), v(r + 1, k + 1), v(r + 1, k)
            tris += [(a, b, c), (a, c, d)]
    for k in range(seg):
        tris.append((bottom_centre, v(0, k + 1), v(0, k)))  # outer bottom, facing -z
        tris.append((floor_centre, v(3, k), v(3, k + 1)))  # inner floor, facing +z (the cavity)
    vol = check_closed("barrel", verts, tris, 4 * seg + 2, 8 * seg)
    poly = 0.5 * seg * math.sin(2 * math.pi / seg)  # area of a unit-circumradius 24-gon
    assert abs(vol - poly * (ro * ro * height - ri * ri * (height - floor))) < 1e-12
    write_obj("barrel.obj", [
        "The barrel of the paper's example 5b (Suzuki, Kubota & Ohtsubo 2003, section 5, figs.",
        "24-25; README: Reference): a non-convex container that blocks are thrown into.",
        "An open-topped, thick-walled cylinder (a cup), axis along z, bottom at z = 0, in metres,",
        "counter-clockwise seen from outside: one closed 2-manifold (genus 0) surface made of the",
        "outer wall, the top rim annulus, the inner wall, the inner floor disc and the outer",
        "bottom disc. %d segments: %d vertices (4 rings of 24 + the 2 disc centres), %d triangles."
        % (seg, len(verts), len(tris)),
        "The paper gives no dimensions; chosen: outer radius 0.5 m, inner radius 0.44 m (wall",
        "0.06 m), height 1.0 m, bottom thickness 0.06 m (inner floor at z = 0.06); the radii are",
        "those of the 24-gons' vertices. Bounding box %s m." % bbox_text(verts),
        "Volume %s m^3, %.1f kg at 800 kg/m^3 (wood, as examples 1-5)." % (num(vol), vol * WOOD),
        "Generated by make_meshes.py in this folder; edit that, not this file.",
    ], verts, tris)
    return vol


# --- 6. example 6: the cliff, an ESRI ASCII grid ----------------------------------------

CLIFF_TOP = 9.5
# The cliff's profile across the slope: (distance along +x from the plateau's brink, m; height, m),
# linear in between. A 9.5 m plateau, a ~68 degree face broken by a ledge, a small bump at its
# foot, a ~27 degree talus slope with one more bump, an ~11 degree apron, a flat valley floor at
# 0 and a ~4 degree counter-slope up to 1.5 m (the far side of the valley, where rocks stop).
PROFILE = [(-10.0, 9.5), (0.0, 9.5), (1.4, 6.0), (2.0, 5.75), (2.9, 3.4), (3.4, 3.5), (6.0, 2.2),
           (6.6, 2.35), (9.5, 0.9), (14.0, 0.0), (18.0, 0.0), (38.0, 1.5), (60.0, 1.5)]
BRINK_X = 3.0  # mean x of the brink, m


def profile(s):
    for (s0, h0), (s1, h1) in zip(PROFILE, PROFILE[1:]):
        if s0 <= s <= s1:
            return h0 + (h1 - h0) * (s - s0) / (s1 - s0)
    raise ValueError(s)


def cliff_height(x, y):
    # The brink wanders +-0.25 m along y, so the face is not the same in every vertical slice.
    brink = BRINK_X + 0.25 * math.sin(2 * math.pi * y / 8.0 + 0.3)
    s = x - brink
    h = profile(s)
    # Roughness (sums of sines, +-0.15 m at most) on the face and the slopes, none on the plateau
    # or on the run-out: weight 0 before the brink and from 14 m past it, 1 between 1 and 11 m.
    if s <= 0 or s >= 14:
        weight = 0.0
    else:
        weight = min(1.0, s / 1.0, (14 - s) / 3.0)
    rough = (0.06 * math.sin(2.1 * x + 0.7 * y) + 0.05 * math.sin(1.3 * y - 0.9 * x + 1.0) +
             0.04 * math.sin(3.7 * x + 2.3 * y + 2.0))
    return min(CLIFF_TOP, max(0.0, h + weight * rough))


def make_cliff():
    ncols, nrows, cell, xll, yll = 80, 48, 0.5, 0.0, 0.0
    # Samples at the cell centres (xllcorner is the lower-left CORNER of the lower-left cell).
    rows = []
    for row in range(nrows):  # the first row is the northern-most (largest y)
        y = yll + (nrows - 1 - row + 0.5) * cell
        rows.append(["%.3f" % cliff_height(xll + (i + 0.5) * cell, y) for i in range(ncols)])
    z = [[float(t) for t in r] for r in rows]
    flat = [h for r in z for h in r]
    assert max(flat) == CLIFF_TOP and min(flat) == 0.0
    steepest = 0.0
    for r in range(nrows):
        for i in range(ncols):
            if i + 1 < ncols:
                steepest = max(steepest, abs(z[r][i + 1] - z[r][i]))
            if r + 1 < nrows:
                steepest = max(steepest, abs(z[r + 1][i] - z[r][i]))
    angle = math.degrees(math.atan(steepest / cell))
    assert 60 <= angle <= 75, angle
    text = ["ncols %d" % ncols, "nrows %d" % nrows, "xllcorner %s" % num(xll),
            "yllcorner %s" % num(yll), "cellsize %s" % num(cell), "NODATA_value -9999"]
    text += [" ".join(r) for r in rows]
    os.makedirs(os.path.join(SCENES, "terrain"), exist_ok=True)
    with open(os.path.join(SCENES, "terrain", "cliff.asc"), "w", newline="\n") as f:
        f.write("\n".join(text) + "\n")
    return angle


def main():
    vols = {
        "highpoly_block": make_highpoly_block(),
        "stack_block": make_stack_block(),
        "cross": make_cross(),
        "rock": make_rock(),
        "barrel": make_barrel(),
    }
    for name, vol in vols.items():
        density = ROCK if name == "rock" else WOOD
        print("%-15s volume %.6f m^3  mass %.2f kg" % (name, vol, vol * density))
    print("cliff.asc       steepest cell-to-cell slope %.1f degrees" % make_cliff())


if __name__ == "__main__":
    main()
