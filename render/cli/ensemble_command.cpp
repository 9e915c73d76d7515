// voxfall ensemble SCENE --runs N: many independent realisations of the scene's [ensemble]
// release (sim/ensemble/), reduced into per-cell rasters on the DEM's grid, a table of runs and
// a summary (README, "Ensembles and hazard maps").
//
// The command is thin: options, output files (render/output/output_file.h: temporary names,
// renamed when complete; -y/-n; inputs never written), threads and MPI ranks, the progress
// line. Every number comes from sim/ensemble; the reduction reads the realisations in index
// order only, so the files are the same bytes for any --jobs and any number of MPI ranks.
// Outputs are written by rank 0 alone.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "render/cli/commands.h"
#include "render/cli/ensemble_mpi.h"
#include "render/cli/ensemble_output.h"
#include "render/cli/options.h"
#include "render/cli/run_output.h"
#include "render/maps/hazard_map.h"
#include "render/output/output_file.h"
#include "render/progress.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_bake.h"
#include "sim/ensemble/ensemble_stats.h"
#include "sim/ensemble/raster_output.h"
#include "sim/scene/scene.h"

namespace vf::cli {
namespace {

namespace fs = std::filesystem;

struct EnsembleOptions {
  std::string scene;
  std::int64_t runs = 0;
  std::optional<std::uint64_t> seed;
  int jobs = 1;
  std::optional<std::int64_t> only;
  std::string outDir;
  bool converge = false;
  bool paths = false;
  int videoRuns = 0;
  bool quiet = false;
  bool maps = false;         // --maps: a PNG per statistic and the runout plot
  SceneOverrides overrides;  // --level, --step, --collider, run limits, --repair
  bool overwrite = false;
  bool neverOverwrite = false;
};

// The cells with the most passages that --converge follows.
constexpr int kConvergenceCells = 3;

// One output per statistic and format, the runs table, the summary and the optional files; all
// opened (checked) before any realisation runs.
struct Outputs {
  struct Raster {
    std::unique_ptr<OutputFile> tif, asc, prj;
  };
  std::vector<Raster> rasters;  // per layer, in cellStatistics' order
  std::unique_ptr<OutputFile> runs, summary, converge, paths, bake;
  std::vector<fs::path> maps;  // --maps: per layer NAME.png, then runout.png
};

const char* const kLayerNames[] = {"passages",   "reach_probability", "energy_mean",
                                   "energy_p50", "energy_p95",        "energy_max",
                                   "height_p95", "speed_p95",         "deposited"};

Outputs openOutputs(const EnsembleOptions& o, const OutputRules& rules, bool hasCrs) {
  Outputs out;
  const fs::path dir(o.outDir);
  auto open = [&](const std::string& name) {
    return std::make_unique<OutputFile>((dir / name).string(), rules);
  };
  for (const char* name : kLayerNames) {
    Outputs::Raster r;
    r.tif = open(std::string(name) + ".tif");
    r.asc = open(std::string(name) + ".asc");
    if (hasCrs) r.prj = open(std::string(name) + ".prj");
    out.rasters.push_back(std::move(r));
  }
  out.runs = open("runs.csv");
  out.summary = open("summary.json");
  if (o.converge) out.converge = open("converge.csv");
  if (o.paths) out.paths = open("paths.csv");
  if (o.videoRuns > 0) {
    out.bake = open("ensemble_subset.bake");
    // Rendered from the bake once it is written (renderToFile opens it then).
    checkOutputPath((dir / "trajectories.mp4").string(), rules);
  }
  if (o.maps) {
    // The maps are written by render/maps (each through its own OutputFile); -y/-n and the
    // inputs are checked here, before any realisation runs.
    for (const char* name : kLayerNames) out.maps.push_back(dir / (std::string(name) + ".png"));
    out.maps.push_back(dir / "runout.png");
    for (const fs::path& png : out.maps) checkOutputPath(png.string(), rules);
  }
  return out;
}

int runEnsemble(const EnsembleOptions& o) {
  SceneSpec spec = loadScene(o.scene);
  applyOverrides(spec, o.overrides);
  if (!spec.ensemble)
    throw InputError(spec.path,
                     "the scene has no [ensemble] table (what varies between realisations; see "
                     "the README, \"Ensembles and hazard maps\")");
  if (o.only && (*o.only < 0 || *o.only >= o.runs))
    throw InputError("", "--only " + std::to_string(*o.only) + " is not a realisation of --runs " +
                             std::to_string(o.runs) + " (0 .. " + std::to_string(o.runs - 1) + ")");
  const std::uint64_t seed = o.seed.value_or(spec.ensemble->seed);
  EnsembleOptions opts = o;
  if (opts.outDir.empty()) opts.outDir = "out/" + spec.name + "_ensemble";

  MpiSession mpi;
  const bool root = mpi.rank() == 0;
  // Outputs are checked and opened by rank 0 before any realisation runs; every rank learns
  // whether that worked, so none waits for a rank that gave up.
  OutputRules rules = runOutputRules(spec, o.scene, o.overwrite, o.neverOverwrite);
  if (!spec.ensemble->cellsPath.empty()) rules.inputs.push_back(spec.ensemble->cellsPath);
  if (!spec.groundClassesPath.empty()) rules.inputs.push_back(spec.groundClassesPath);
  std::optional<Outputs> outputs;
  std::optional<Ensemble> ensemble;
  std::exception_ptr failure;
  try {
    ensemble.emplace(spec);  // terrain and shapes, once (a few seconds at most)
    if (root) outputs = openOutputs(opts, rules, !ensemble->dem().crsWkt.empty());
  } catch (...) {
    failure = std::current_exception();
  }
  if (!mpi.allOk(!failure)) {
    if (failure) std::rethrow_exception(failure);
    return 1;  // another rank reported the problem
  }
  installStopHandlers();

  // Realisations of this rank: every size-th from its rank (round robin balances ranks when
  // realisation costs drift with the index, which they do not by construction, but cheaply).
  std::vector<std::int64_t> indices;
  if (o.only) {
    if (root) indices.push_back(*o.only);
  } else {
    for (std::int64_t i = mpi.rank(); i < o.runs; i += mpi.size()) indices.push_back(i);
  }
  const int jobs = std::max(1, o.jobs);
  const auto started = std::chrono::steady_clock::now();
  Progress progress(spec.name + " ensemble", static_cast<int>(indices.size()), root && !o.quiet);
  const auto report = [&](int done) {
    const double s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    char detail[96];
    std::snprintf(detail, sizeof detail, "%.2f realisations/s%s", s > 0 ? done / s : 0.0,
                  mpi.size() > 1 ? " on rank 0" : "");
    progress.update(done, detail);
  };
  std::vector<RealisationResult> mine;
  try {
    mine = runRealisations(*ensemble, indices, seed, jobs, o.paths, report,
                           [] { return stopSignal() != 0; });
  } catch (...) {
    failure = std::current_exception();
  }
  progress.finish();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (!mpi.allOk(!failure)) {
    if (failure) std::rethrow_exception(failure);
    return 1;
  }

  // Every rank's realisations on rank 0, in index order.
  const std::vector<std::string> gathered = mpi.gather(serializeResults(mine));
  if (!root) return stopSignal() ? 128 + stopSignal() : 0;
  std::vector<RealisationResult> all;
  for (const std::string& bytes : gathered) {
    std::vector<RealisationResult> part = deserializeResults(bytes);
    for (RealisationResult& r : part) all.push_back(std::move(r));
  }
  std::sort(all.begin(), all.end(), [](const RealisationResult& a, const RealisationResult& b) {
    return a.index < b.index;
  });
  // An interrupted ensemble keeps its complete prefix 0 .. k-1: exactly the ensemble --runs k
  // would give, so what it wrote can be reproduced.
  std::size_t complete = 0;
  while (complete < all.size() && all[complete].complete) ++complete;
  all.resize(complete);
  const int stop = stopSignal();
  if (all.empty()) {
    std::fprintf(stderr, "voxfall: %s; no realisation complete, no output written\n",
                 stop ? "interrupted" : "nothing ran");
    return stop ? 128 + stop : 1;
  }

  const Ensemble& ens = *ensemble;
  const Heightfield& dem = ens.dem();
  const std::vector<StatLayer> layers = cellStatistics(dem, all);
  std::string written;
  const auto commit = [&](OutputFile& f) {
    f.commit();
    written += (written.empty() ? "" : ", ") + fs::path(f.path()).filename().string();
  };
  for (std::size_t k = 0; k < layers.size(); ++k) {
    Outputs::Raster& r = outputs->rasters[k];
    r.tif->closeStream();
    writeRaster(r.tif->tempPath(), RasterFormat::kGeoTiff, layers[k].values, dem.nx, dem.ny,
                spec.terrainPath);
    commit(*r.tif);
    r.asc->closeStream();
    writeRaster(r.asc->tempPath(), RasterFormat::kEsriAscii, layers[k].values, dem.nx, dem.ny,
                spec.terrainPath);
    commit(*r.asc);
    if (r.prj) {  // the ASCII grid's CRS: the DEM's own WKT
      std::fputs(dem.crsWkt.c_str(), r.prj->stream());
      commit(*r.prj);
    }
  }
  writeRunsCsv(outputs->runs->stream(), ens, all);
  commit(*outputs->runs);
  if (outputs->paths) {
    writePathsCsv(outputs->paths->stream(), dem, all);
    commit(*outputs->paths);
  }

  int videoCode = 0;  // the video's render: 130/143 when it was interrupted
  if (outputs->bake) {
    // The first --video-runs complete realisations (or the --only one), stepped again frame by
    // frame for `voxfall render ensemble_subset.bake`.
    std::vector<std::int64_t> chosen;
    for (std::size_t k = 0; k < all.size() && static_cast<int>(k) < o.videoRuns; ++k)
      chosen.push_back(all[k].index);
    const Bake bake = ensembleBake(ens, seed, chosen);
    writeBake(outputs->bake->stream(), outputs->bake->path(), bake);
    commit(*outputs->bake);
    // ... and their video over the terrain, as `voxfall render` draws the bake (not after an
    // interrupt: the realisations' files come first).
    if (!stop) {
      const std::string video = (fs::path(opts.outDir) / "trajectories.mp4").string();
      videoCode =
          renderToFile(outputs->bake->path(), video, o.overwrite, o.neverOverwrite, o.quiet);
      if (videoCode == 0) written += ", trajectories.mp4";
    }
  }

  std::vector<ConvergenceRow> conv;
  if (o.converge) {
    conv = convergence(dem, all, kConvergenceCells);
    writeConvergence(outputs->converge->stream(), stderr, dem, conv);
    commit(*outputs->converge);
  }

  if (o.maps) {
    // Hazard maps over the DEM's hillshade with the release areas, and the runout plot.
    std::vector<std::vector<Vec2>> areas;
    for (const std::vector<Point2>& area : ens.releaseAreas()) {
      areas.emplace_back();
      for (const Point2& p : area) areas.back().emplace_back(p[0], p[1]);
    }
    // A cell no realisation reached has no value on a map (the rasters say 0 passages there):
    // it shows the hillshade, so the reached area stands out.
    const std::vector<double>& passages = layers[0].values;
    for (std::size_t k = 0; k < layers.size(); ++k) {
      MapLayer layer{layers[k].name, layers[k].title, layers[k].units, layers[k].values};
      for (std::size_t c = 0; c < passages.size(); ++c)
        if (passages[c] == 0) layer.values[c] = NAN;
      writeHazardMap(dem, layer, areas, outputs->maps[k].string(), rules);
      written += ", " + outputs->maps[k].filename().string();
    }
    std::vector<double> runouts, reach;
    for (const RealisationResult& r : all) {
      runouts.push_back(r.runout);
      reach.push_back(r.reachAngle);
    }
    writeRunoutPlot(runouts, reach, outputs->maps.back().string(), rules);
    written += ", " + outputs->maps.back().filename().string();
  }

  writeEnsembleSummary(outputs->summary->stream(), spec, dem, seed, o.only ? 1 : o.runs, o.only,
                       all, layers, conv);
  commit(*outputs->summary);

  int states[4] = {0, 0, 0, 0};
  for (const RealisationResult& r : all) ++states[static_cast<int>(r.state)];
  std::printf(
      "%s: %zu realisations (seed %llu): %d stopped, %d left the DEM, %d buried, %d "
      "still moving at %.4g s\n",
      spec.name.c_str(), all.size(), static_cast<unsigned long long>(seed), states[1], states[2],
      states[3], states[0], spec.duration);
  std::fprintf(stderr, "voxfall: %zu realisations in %.2f s (%.2f realisations/s, %d thread%s%s)\n",
               all.size(), seconds, seconds > 0 ? all.size() / seconds : 0.0, jobs,
               jobs == 1 ? "" : "s",
               mpi.size() > 1 ? (" x " + std::to_string(mpi.size()) + " ranks").c_str() : "");
  std::printf("  wrote %s in %s\n", written.c_str(), opts.outDir.c_str());
  // A realisation cut off by the duration records its rock where it was then: the hazard
  // products understate the reach without saying so unless told here (--quiet or not).
  if (states[0] > 0)
    std::fprintf(stderr,
                 "voxfall: warning: %d of %zu realisations ended at the scene's duration (%.4g s) "
                 "with the rock still moving; runs.csv, the runouts and the maps show those "
                 "rocks where they were then, not where they stop: raise [simulation] "
                 "duration\n",
                 states[0], all.size(), spec.duration);
  if (stop) {
    std::fprintf(stderr,
                 "voxfall: interrupted; the first %zu realisations (0 .. %zu) are written, the "
                 "same as --runs %zu\n",
                 all.size(), all.size() - 1, all.size());
    return 128 + stop;
  }
  return videoCode;
}

}  // namespace

void addEnsembleCommand(CLI::App& app, int& exitCode) {
  auto o = std::make_shared<EnsembleOptions>();
  CLI::App* sub = app.add_subcommand(
      "ensemble",
      "Run many independent realisations of a scene's [ensemble] release and write per-cell "
      "hazard rasters (GeoTIFF and ESRI ASCII), runs.csv and summary.json");
  sub->add_option("SCENE", o->scene, "scene file (TOML) with an [ensemble] table")
      ->required()
      ->type_name("");
  sub->add_option("--runs", o->runs, "number of realisations N")
      ->required()
      ->type_name("N")
      ->check(CLI::Range(std::int64_t{1}, std::int64_t{100000000}));
  sub->add_option("--seed", o->seed,
                  "ensemble seed S (default: [ensemble] seed); realisation i uses a seed made "
                  "from S and i only")
      ->type_name("S")
      ->check(integerIn(0, std::numeric_limits<std::uint64_t>::max()));
  sub->add_option("--jobs,-j", o->jobs,
                  "threads running realisations (outputs are the same bytes for any value)")
      ->type_name("J")
      ->check(CLI::Range(1, 1024));
  sub->add_option("--only", o->only,
                  "run realisation i of the N alone (the same trajectory as inside the ensemble)")
      ->type_name("i");
  sub->add_option("-o,--output", o->outDir, "output folder (default out/SCENE_ensemble)")
      ->type_name("DIR");
  sub->add_flag("--converge", o->converge,
                "write converge.csv and print how reach probability and p95 energy at the 3 "
                "busiest cells change over N/8, N/4, N/2, N realisations");
  sub->add_flag("--paths", o->paths,
                "write paths.csv: every realisation's centre of mass after every step");
  sub->add_option("--video-runs", o->videoRuns,
                  "write the first K realisations' trajectories as ensemble_subset.bake and render "
                  "it to trajectories.mp4 (the scene's [output] and [camera])")
      ->type_name("K")
      ->check(CLI::Range(1, 10000));
  sub->add_flag("--maps", o->maps,
                "also draw a hazard map PNG per statistic (over a hillshade of the DEM, with the "
                "release areas) and runout.png (runout and reach-angle distributions)");
  addPhysicsOptions(*sub, o->overrides);
  sub->add_flag("--quiet,-q", o->quiet, "no progress line on stderr");
  addOverwriteFlags(*sub, o->overwrite, o->neverOverwrite);
  sub->callback([o, &exitCode] { exitCode = runEnsemble(*o); });
}

}  // namespace vf::cli
