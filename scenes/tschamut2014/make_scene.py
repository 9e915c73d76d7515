#!/usr/bin/env python3
"""Writes the Tschamut 2014 validation scene from the data files next to it (copied from the
EnviDat data set, doi:10.16904/envidat.34, Volkwein & Gerber 2018, ODbL 1.0 + DbCL):
block.obj, a unit ellipsoid-like polyhedron (icosphere, one subdivision, 80 triangles) that each
block scales to its measured principal lengths, and tschamut2014.toml with one [[bodies]] per
run, at the measured release point with the measured release velocity. Python 3 standard library
only, no randomness: byte-identical on every run."""
import csv, math, os

here = os.path.dirname(os.path.abspath(__file__))

def icosphere():
    t = (1 + 5 ** 0.5) / 2
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t), (0, -1, -t),
         (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
         (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    mid = {}
    def m(a, b):
        k = (min(a, b), max(a, b))
        if k not in mid:
            p = [(x + y) / 2 for x, y in zip(v[a], v[b])]
            n = math.sqrt(sum(x * x for x in p))
            v.append(tuple(x / n for x in p))
            mid[k] = len(v) - 1
        return mid[k]
    g = []
    for a, b, c in f:
        ab, bc, ca = m(a, b), m(b, c), m(c, a)
        g += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return v, g

v, f = icosphere()
with open(os.path.join(here, "block.obj"), "w") as out:
    out.write("# unit-radius icosphere (1 subdivision, 80 triangles); scaled per block to its\n"
              "# half principal lengths by tschamut2014.toml. Written by make_scene.py.\n")
    for p in v:
        out.write("v %.9f %.9f %.9f\n" % p)
    for a, b, c in f:
        out.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))

blocks = {}
with open(os.path.join(here, "block_metadata.csv")) as fh:
    for row in csv.DictReader(fh):
        blocks[row["block_id"]] = row

# The two ground laws compared on this site. Every choice is written here before any run of the
# slip law, with its source; none is fitted to the observed runouts.
STONE = {
    "file": "tschamut2014.toml",
    "title": "",
    "contact": "# Coulomb friction: the paper's section-5 default (STONE has no Coulomb coefficient).",
    "ground": [
        "# STONE per-lithology table (Guzzetti et al. 2002): glacial deposits, rolling friction 0.65,",
        "# normal restitution 35 %, tangential 55 %. Chosen before any run as the class for an alpine meadow on",
        "# moraine-covered slope (our reading of the site, not a published classification); NOT fitted.",
        'material = "glacial_deposits"',
    ],
}
SLIP = {
    "file": "tschamut2014_slip.toml",
    "title": "\n# Ground law: the rigid-body slip-dependent friction (RAMMS type); tschamut2014.toml: STONE.",
    "contact": "# Between bodies only: on the ground the slip law's mu(s) replaces this friction.",
    "ground": [
        "# The slip-dependent friction law of Leine et al. 2014 (Multibody Syst Dyn 32:241-271) with",
        "# the only parameter set published for real terrain: mu_min 0.55, mu_max 2.0, kappa 3 1/m,",
        "# beta 185 1/s (Lu et al. 2019, Landslides 16:2353-2367, citing Bartelt et al. 2016, for the",
        "# rebound plane at Chant Sura); normal restitution 0 (Leine et al. 2014: 'typically very",
        "# small'). Chosen before any run of this law on this site; NOT fitted.",
        'material = "ramms_chant_sura"',
    ],
}
SCAR = {
    "file": "tschamut2014_scar.toml",
    "title": "\n# Ground law: the slip law under Lu et al. 2019's soft-soil scar layer; tschamut2014.toml: STONE.",
    "contact": SLIP["contact"],
    "ground": [
        "# The slip law of tschamut2014_slip.toml (Lu et al. 2019's rebound plane at Chant Sura:",
        "# mu_min 0.55, mu_max 2.0, kappa 3 1/m, beta 185 1/s, normal restitution 0) under the",
        "# soft-soil scar layer that set was fitted beneath (Lu et al. 2019, Landslides 16:2353-2367,",
        "# eqs. 9-12): soil density 1700 kg/m^3, C_f 1.0, and their whole-trajectory C_s 1.5 and",
        "# M_e 15 MN/m^2 (Table 5). Chosen before any run of this law on this site; NOT fitted.",
        'material = "ramms_chant_sura_scar"',
    ],
}


def shape_lines(bid, b, law):
    size = (float(b["size_x_m"]), float(b["size_y_m"]), float(b["size_z_m"]))
    out = ["[shapes.block_%s]  # %s" % (bid, b["name"])]
    if law is STONE:
        out += ['mesh = "block.obj"',
                "scale = [%.4f, %.4f, %.4f]   # half the measured principal lengths, m" %
                tuple(x / 2 for x in size)]
    else:
        # Without a scan of the block, the EOTA polyhedron scaled to the block's principal
        # lengths (the shape rule of shared/rockfall-models.md 9.3, after Leine et al. 2021).
        out += ['rock = { class = "eota_111", size = [%.4f, %.4f, %.4f] }   # measured principal'
                ' lengths, m' % size]
    out.append("mass = %.1f   # kg, measured" % float(b["mass_kg"]))
    return out + [""]


def scene(law):
    lines = []
    w = lines.append
    w("# Tschamut 2014 full-scale rock fall experiments (Swiss Alps): validation scene." + law["title"])
    w("# Data: EnviDat doi:10.16904/envidat.34 (Volkwein & Gerber 2018), ODbL 1.0 + DbCL; the")
    w("# terrain is a 5 m proxy interpolated from the public LPS ground points (not an official")
    w("# DEM). Written by make_scene.py from release_points.csv and block_metadata.csv: edit those")
    w("# or the script, not this file. Every run starts at once here; runs are independent")
    w("# experiments, so tests/scenario/tschamut_test.cpp simulates each [[bodies]] alone.")
    w("")
    w("[simulation]")
    w("duration = 60.0")
    w("level = 4")
    w('step = "auto"')
    w('rotation = "midpoint"   # keeps the energy of free tumbling (README)')
    w('stop = "all_at_rest"')
    w("fps = 10")
    w("")
    w("[contact]")
    w(law["contact"])
    w("friction = { body_body = 0.3, body_ground = 0.8 }")
    w("")
    w("[ground]")
    w('heightfield = "terrain_proxy_5m.asc"')
    lines += law["ground"]
    w("")
    for bid, b in sorted(blocks.items()):
        lines += shape_lines(bid, b, law)
    with open(os.path.join(here, "release_points.csv")) as fh:
        for row in csv.DictReader(fh):
            w("[[bodies]]  # run %s" % row["trajectory_id"])
            w('shape = "block_%s"' % row["block_id"])
            w("position = [%s, %s, %s]" % (row["x_m"], row["y_m"], row["z_m"]))
            w("velocity = [%s, %s, %s]" % (row["vx_mps"], row["vy_mps"], row["vz_mps"]))
            w("drop_height = 0.0   # resting on the surface under the release point")
            w("")
    w("[camera]")
    w("position = [160.0, 120.0, 90.0]")
    w("look_at = [60.0, 190.0, 45.0]")
    w("fov = 50")
    with open(os.path.join(here, law["file"]), "w") as out:
        out.write("\n".join(lines) + "\n")


for law in (STONE, SLIP, SCAR):
    scene(law)
