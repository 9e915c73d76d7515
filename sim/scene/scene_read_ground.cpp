// [ground]: the floor plane or a terrain grid, its CRS, offset and texture, and the ground
// materials and their classes.
#include <charconv>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "sim/ground/ground_material.h"
#include "sim/scene/scene_keys.h"
#include "sim/scene/scene_reader.h"
#include "sim/shape/crs.h"

namespace vf::scene_reading {

// --- [ground] -----------------------------------------------------------------------------

namespace {

// [ground.materials.NAME] scar: the soft-soil layer of a slip material, all four keys required
// (Lu et al. 2019 publish one set, the preset ramms_chant_sura_scar; no default fits every soil).
GroundMaterialSpec::Scar readScar(const Reader& r, const toml::table& t, const std::string& label) {
  r.checkKeys(t, sceneKeysOf("ground.materials.NAME.scar"), label + " scar");
  for (const std::string& key : sceneKeysOf("ground.materials.NAME.scar"))
    if (!t.get(key))
      r.fail(t, label + " scar needs density, fluid_drag, compaction_drag and modulus; '" + key +
                    "' is missing (or use the preset ramms_chant_sura_scar)");
  GroundMaterialSpec::Scar s;
  s.density = r.positive(*t.get("density"), "scar.density", " kg/m^3 (the soil's density)");
  s.fluidDrag = r.nonNegative(*t.get("fluid_drag"), "scar.fluid_drag", " (drag coefficient C_f)");
  s.compactionDrag =
      r.nonNegative(*t.get("compaction_drag"), "scar.compaction_drag", " (drag coefficient C_s)");
  s.modulus = r.positive(*t.get("modulus"), "scar.modulus", " MN/m^2 (deformation modulus M_e)");
  return s;
}

// [ground.materials.NAME]: the keys of its law only, each checked; a slip material needs all
// four of mu(s)'s coefficients (no published default fits every ground).
GroundMaterialSpec readGroundMaterial(const Reader& r, const toml::table& m,
                                      const std::string& name) {
  const std::string label = "[ground.materials." + name + "]";
  r.checkKeys(m, sceneKeysOf("ground.materials.NAME"), label);
  GroundMaterialSpec g;
  g.name = name;
  g.where = r.where(m);
  if (const auto* x = m.get("law")) {
    const std::string law = r.string(*x, "law");
    if (law == "slip")
      g.law = GroundLawKind::kSlip;
    else if (law != "stone")
      r.fail(*x,
             "'law' must be \"stone\" (STONE's bounce and rolling, the default) or \"slip\" "
             "(slippage-dependent friction, Leine et al. 2014), got \"" +
                 law + "\"");
  }
  const bool slip = g.law == GroundLawKind::kSlip;
  const std::vector<std::string> stoneKeys{"friction", "rolling_resistance",
                                           "tangential_restitution"},
      slipKeys{"mu_min", "mu_max", "kappa", "beta", "scar"};
  for (const std::string& key : slip ? stoneKeys : slipKeys)
    if (const auto* x = m.get(key))
      r.fail(*x, "'" + key + "' " +
                     (slip ? "is not used by law = \"slip\" (its friction is mu(s) from mu_min, "
                             "mu_max, kappa and beta)"
                           : "belongs to law = \"slip\"; give law = \"slip\" in " + label));
  if (const auto* x = m.get("restitution")) g.restitution = r.inRange(*x, "restitution", 0, 1);
  if (const auto* x = m.get("friction"))
    g.friction = r.nonNegative(*x, "friction", " (Coulomb coefficient)");
  if (const auto* x = m.get("rolling_resistance"))
    g.rollingResistance =
        r.nonNegative(*x, "rolling_resistance", " (tan of the rolling friction angle)");
  if (const auto* x = m.get("tangential_restitution"))
    g.tangentialRestitution = r.inRange(*x, "tangential_restitution", 0, 1);
  if (!slip) return g;
  for (const std::string key : {"mu_min", "mu_max", "kappa", "beta"})
    if (!m.get(key))
      r.fail(m, label + " has law = \"slip\" and needs mu_min, mu_max, kappa and beta; '" + key +
                    "' is missing (or use a preset: ramms_chant_sura, leine2014_demo)");
  g.muMin = r.nonNegative(*m.get("mu_min"), "mu_min", " (Coulomb coefficient)");
  g.muMax = r.nonNegative(*m.get("mu_max"), "mu_max", " (Coulomb coefficient)");
  if (*g.muMax < *g.muMin)
    r.fail(*m.get("mu_max"), "'mu_max' must be >= 'mu_min' (" + formatNumber(*g.muMin) +
                                 "): friction grows with slippage, got " + formatNumber(*g.muMax));
  g.kappa = r.nonNegative(*m.get("kappa"), "kappa", " 1/m (slippage hardening)");
  g.beta = r.nonNegative(*m.get("beta"), "beta", " 1/s (slippage softening)");
  if (const auto* x = m.get("scar")) g.scar = readScar(r, r.table(*x, "scar"), label);
  return g;
}

// 'edge': what the terrain's border does to a rock.
void readTerrainEdge(const Reader& r, const toml::node& n, SceneSpec& spec) {
  const std::string v = r.string(n, "edge");
  if (v == "remove")
    spec.terrainEdge = TerrainEdge::kRemove;
  else if (v == "stop")
    spec.terrainEdge = TerrainEdge::kStop;
  else if (v == "wall")
    spec.terrainEdge = TerrainEdge::kWall;
  else
    r.fail(n,
           "'edge' must be \"remove\" (the default without a plane), \"stop\" or \"wall\", got \"" +
               v + "\"");
}

// 'heightfield' and what places and drapes it: 'offset', 'crs', 'texture'.
void readTerrainGrid(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                     SceneSpec& spec) {
  if (const auto* n = t.get("heightfield")) {
    spec.terrainPath = existingFile(r, *n, "heightfield", sceneFolder, "terrain grid",
                                    " (a DEM GDAL reads, e.g. GeoTIFF or ESRI ASCII; relative "
                                    "paths resolve against the scene file's folder)");
  }
  if (const auto* n = t.get("offset")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'offset' moves the heightfield; give 'heightfield' too");
    spec.terrainShift = r.vec3(*n, "offset");
  }
  if (const auto* n = t.get("crs")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'crs' is the heightfield's coordinate reference system; give 'heightfield' too");
    spec.terrainCrs = r.string(*n, "crs");
    try {
      parseCrs(spec.terrainCrs);
    } catch (const std::invalid_argument& e) {
      r.fail(*n, std::string("'crs': ") + e.what());
    }
  }
  if (const auto* n = t.get("texture")) {
    if (spec.terrainPath.empty())
      r.fail(*n, "'texture' is draped on the heightfield; give 'heightfield' too");
    spec.terrainTexturePath =
        existingFile(r, *n, "texture", sceneFolder, "texture raster",
                     " (an RGB or grey raster GDAL reads, e.g. an orthophoto GeoTIFF; relative "
                     "paths resolve against the scene file's folder)");
  }
}

// A ground material's name at n: one of the scene's [ground.materials] or a preset.
std::string materialName(const Reader& r, const SceneSpec& spec, const toml::node& n,
                         const std::string& key) {
  const std::string name = r.string(n, key);
  std::vector<std::string> valid;
  for (const auto& g : spec.groundMaterials) valid.push_back(g.name);
  for (const auto& p : groundPresetNames()) valid.push_back(p);
  if (std::find(valid.begin(), valid.end(), name) != valid.end()) return name;
  std::string message = "unknown ground material '" + name + "'";
  if (auto guess = nearestName(name, valid))
    message += "; did you mean '" + *guess + "'?";
  else
    message += "; presets: " + joinNames(groundPresetNames()) + " (or define [ground.materials." +
               name + "])";
  r.fail(n, message);
}

// 'classes' (at n), the class raster, and 'class_materials', its class -> material table.
void readGroundClasses(const Reader& r, const toml::table& t, const toml::node& n,
                       const fs::path& sceneFolder, SceneSpec& spec) {
  if (spec.terrainPath.empty())
    r.fail(n, "'classes' is a raster on the heightfield's grid; give 'heightfield' too");
  if (spec.groundMaterial.empty())
    r.fail(n, "give 'material' too: it applies where the class raster has no mapped class");
  spec.groundClassesPath = existingFile(r, n, "classes", sceneFolder, "class raster");
  const toml::node* map = t.get("class_materials");
  if (map == nullptr) r.fail(n, "give 'class_materials' too: a table class = \"material\"");
  const toml::table& m = r.table(*map, "class_materials");
  for (auto&& [k, v] : m) {
    int cls = -1;
    const std::string key(k.str());
    const auto res = std::from_chars(key.data(), key.data() + key.size(), cls);
    if (res.ec != std::errc() || res.ptr != key.data() + key.size() || cls < 0 || cls > 65535)
      r.fail(k.source(),
             "'class_materials' keys must be class numbers 0..65535, got '" + key + "'");
    spec.classMaterials.emplace_back(cls, materialName(r, spec, v, "class_materials." + key));
  }
}

// 'variability' and 'variability_seed': the per-cell perturbation of the ground's coefficients.
void readGroundVariability(const Reader& r, const toml::table& t, SceneSpec& spec) {
  if (const auto* n = t.get("variability")) {
    const double v = r.number(*n, "variability");
    if (v < 0 || v >= 1)
      r.fail(*n,
             "'variability' must be >= 0 and < 1 (0.1: each coefficient within +-10 % per "
             "cell), got " +
                 formatNumber(v));
    if (v > 0 && spec.terrainPath.empty())
      r.fail(*n, "'variability' perturbs the ground per DEM cell; give 'heightfield' too");
    if (v > 0 && spec.groundMaterial.empty())
      r.fail(*n, "'variability' perturbs the ground material's coefficients; give 'material' too");
    spec.groundVariability = v;
  }
  if (const auto* n = t.get("variability_seed")) {
    if (!t.get("variability"))
      r.fail(*n, "'variability_seed' seeds 'variability'; give 'variability' too");
    spec.groundVariabilitySeed = static_cast<std::uint64_t>(
        r.integerInRange(*n, "variability_seed", 0, std::numeric_limits<std::int64_t>::max()));
  }
}

}  // namespace

void readGround(const Reader& r, const toml::table& t, const fs::path& sceneFolder,
                SceneSpec& spec) {
  r.checkKeys(t, sceneKeysOf("ground"), "[ground]");
  if (const auto* n = t.get("edge")) readTerrainEdge(r, *n, spec);
  if (const auto* n = t.get("plane")) spec.groundPlane = r.number(*n, "plane");
  readTerrainGrid(r, t, sceneFolder, spec);
  if (const auto* n = t.get("materials")) {
    const toml::table& all = r.table(*n, "materials");
    for (auto&& [k, v] : all) {
      const std::string name(k.str());
      spec.groundMaterials.push_back(
          readGroundMaterial(r, r.table(v, "ground.materials." + name), name));
    }
  }
  if (const auto* n = t.get("material"))
    spec.groundMaterial = materialName(r, spec, *n, "material");
  if (const auto* n = t.get("classes")) {
    readGroundClasses(r, t, *n, sceneFolder, spec);
  } else if (const auto* n = t.get("class_materials")) {
    r.fail(*n, "'class_materials' needs 'classes' (the class raster)");
  }
  readGroundVariability(r, t, spec);
}

}  // namespace vf::scene_reading
