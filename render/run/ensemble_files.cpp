// The reduced outputs of an ensemble (see ensemble_files.h).
#include "render/run/ensemble_files.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <stdexcept>

#include "render/maps/hazard_map.h"
#include "render/run/ensemble_output.h"
#include "render/run/lines_output.h"
#include "render/run/render_run.h"
#include "sim/core/error.h"
#include "sim/ensemble/ensemble_bake.h"
#include "sim/ensemble/raster_output.h"
#include "sim/ground/forest_outline.h"

namespace vf {

namespace fs = std::filesystem;

namespace {

// The cells with the most passages that --converge follows.
constexpr int kConvergenceCells = 3;

const char* const kLayerNames[] = {"passages",   "reach_probability", "energy_mean",
                                   "energy_p50", "energy_p95",        "energy_max",
                                   "height_p95", "speed_p95",         "deposited"};

}  // namespace

// One output per statistic and format, the runs table, the summary and the optional files.
struct EnsembleFiles::Files {
  struct Raster {
    std::unique_ptr<OutputFile> tif, asc, prj;
  };
  std::vector<Raster> rasters;  // per layer, in cellStatistics' order
  std::unique_ptr<OutputFile> runs, summary, converge, paths, bake;
  // --maps: per layer NAME.png, intensity.png, height_classes.png (with the scene's
  // height_classes), then runout.png
  std::vector<fs::path> maps;
  std::unique_ptr<LineFiles> lines;  // evaluation lines (plots with --maps)
  std::unique_ptr<OutputFile> barriers;
};

MapWindow mapExtent(const std::vector<double>& extent, const Heightfield& dem) {
  if (extent.size() != 4) throw InputError("--extent", "give four numbers: XMIN,YMIN,XMAX,YMAX");
  try {
    return extentWindow(dem, extent[0], extent[1], extent[2], extent[3]);
  } catch (const std::invalid_argument& e) {
    throw InputError("--extent", e.what());
  }
}

EnsembleFiles::EnsembleFiles(const EnsembleFileOptions& o, const OutputRules& rules,
                             const Heightfield& dem)
    : options_(o), rules_(rules), files_(std::make_unique<Files>()) {
  if (!o.extent.empty()) extent_ = mapExtent(o.extent, dem);
  const bool hasCrs = !dem.crsWkt.empty();
  const fs::path dir(o.outDir);
  auto open = [&](const std::string& name) {
    return std::make_unique<OutputFile>((dir / name).string(), rules);
  };
  for (const char* name : kLayerNames) {
    Files::Raster r;
    r.tif = open(std::string(name) + ".tif");
    r.asc = open(std::string(name) + ".asc");
    if (hasCrs) r.prj = open(std::string(name) + ".prj");
    files_->rasters.push_back(std::move(r));
  }
  files_->runs = open("runs.csv");
  files_->summary = open("summary.json");
  if (o.converge) files_->converge = open("converge.csv");
  if (o.paths) files_->paths = open("paths.csv");
  if (o.videoRuns > 0) {
    files_->bake = open("ensemble_subset.bake");
    // Rendered from the bake once it is written (renderToFile opens it then).
    checkOutputPath((dir / "trajectories.mp4").string(), rules);
  }
  if (o.barriers) files_->barriers = open("barriers.csv");
  if (o.lines) files_->lines = std::make_unique<LineFiles>(dir, rules, o.maps);
  if (o.maps) {
    // The maps are written by render/maps (each through its own OutputFile); -y/-n and the
    // inputs are checked here, before any realisation runs.
    for (const char* name : kLayerNames) files_->maps.push_back(dir / (std::string(name) + ".png"));
    files_->maps.push_back(dir / "intensity.png");
    if (!o.heightClasses.empty()) files_->maps.push_back(dir / "height_classes.png");
    files_->maps.push_back(dir / "runout.png");
    for (const fs::path& png : files_->maps) checkOutputPath(png.string(), rules);
  }
}

EnsembleFiles::~EnsembleFiles() = default;

void EnsembleFiles::commit(OutputFile& f) {
  f.commit();
  written_ += (written_.empty() ? "" : ", ") + fs::path(f.path()).filename().string();
}

// One statistic as a raster into `file`: an error names the output, not its temporary name.
void EnsembleFiles::writeRasterFile(OutputFile& file, int format, const std::vector<double>& values,
                                    const Ensemble& ens) {
  file.closeStream();
  try {
    writeRaster(file.tempPath(), static_cast<RasterFormat>(format), values, ens.dem().nx,
                ens.dem().ny, ens.spec().terrainPath, ens.dem().crsWkt);
  } catch (const InputError& e) {
    std::string message = e.message();
    for (std::size_t at; (at = message.find(file.tempPath() + ": ")) != std::string::npos;)
      message.erase(at, file.tempPath().size() + 2);
    throw InputError(file.path(), message);
  }
  commit(file);
}

void EnsembleFiles::writeRasters(const Ensemble& ens, const std::vector<StatLayer>& layers) {
  const std::vector<double>& heights = ens.dem().z;
  for (std::size_t k = 0; k < layers.size(); ++k) {
    Files::Raster& r = files_->rasters[k];
    // Where the DEM has no data no rock can be, and 0 passages there would claim a result:
    // every statistic is NODATA, so a GIS sees the valid area as the DEM's own.
    std::vector<double> values = layers[k].values;
    for (std::size_t c = 0; c < values.size() && c < heights.size(); ++c)
      if (std::isnan(heights[c])) values[c] = NAN;
    writeRasterFile(*r.tif, static_cast<int>(RasterFormat::kGeoTiff), values, ens);
    writeRasterFile(*r.asc, static_cast<int>(RasterFormat::kEsriAscii), values, ens);
    if (r.prj) {  // the ASCII grid's CRS: the DEM's own WKT
      std::fputs(ens.dem().crsWkt.c_str(), r.prj->stream());
      commit(*r.prj);
    }
  }
}

// The first --video-runs realisations (or the --only one), stepped again frame by frame for
// `voxfall render ensemble_subset.bake`, and their video over the terrain, as `voxfall render`
// draws the bake (not after an interrupt: the realisations' files come first).
RunStatus EnsembleFiles::writeVideo(const Ensemble& ens, const EnsembleRunInfo& info,
                                    const std::vector<RealisationResult>& runs) {
  std::vector<std::int64_t> chosen;
  for (std::size_t k = 0; k < runs.size() && static_cast<int>(k) < options_.videoRuns; ++k)
    chosen.push_back(runs[k].index);
  const Bake bake = ensembleBake(ens, info.seed, chosen);
  writeBake(files_->bake->stream(), files_->bake->path(), bake);
  commit(*files_->bake);
  if (info.stopSignal) return RunStatus::done();
  RenderRequest render;
  render.input = files_->bake->path();
  render.output = (fs::path(options_.outDir) / "trajectories.mp4").string();
  render.overwrite = options_.overwrite;
  render.neverOverwrite = options_.neverOverwrite;
  render.quiet = options_.quiet;
  const RunStatus status = runRender(render);
  if (status.isDone()) written_ += ", trajectories.mp4";
  return status;
}

// Hazard maps over the DEM's hillshade with the release areas, and the runout plot.
void EnsembleFiles::writeMaps(const Ensemble& ens, const std::vector<StatLayer>& layers,
                              const std::vector<RealisationResult>& runs) {
  std::vector<std::vector<Vec2>> areas;
  for (const std::vector<Point2>& area : ens.releaseAreas()) {
    areas.emplace_back();
    for (const Point2& p : area) areas.back().emplace_back(p[0], p[1]);
  }
  std::vector<MapPolyline> polylines;
  for (const EvaluationLine& l : ens.lines()) {
    polylines.emplace_back();
    for (const auto& p : l.points) polylines.back().points.emplace_back(p[0], p[1]);
  }
  for (const Barrier& b : ens.barriers()) {
    polylines.push_back(MapPolyline{{}, MapPolyline::Kind::kBarrier});
    for (const auto& p : b.points) polylines.back().points.emplace_back(p[0], p[1]);
  }
  if (const Forest* forest = ens.forest())
    for (const auto& edge : forestOutline(*forest))
      polylines.push_back(MapPolyline{{Vec2(edge[0][0], edge[0][1]), Vec2(edge[1][0], edge[1][1])},
                                      MapPolyline::Kind::kForestEdge});
  const std::vector<double>& passages = layers[0].values;
  // Every map shows the same window: --extent, or the reached area and the release areas with
  // a margin.
  const MapWindow window = extent_ ? *extent_ : affectedWindow(ens.dem(), passages, areas);
  for (std::size_t k = 0; k < layers.size(); ++k) {
    MapLayer layer{layers[k].name, layers[k].title, layers[k].units,
                   mappedValues(layers[k].name, layers[k].values, passages),
                   mappedOnLogScale(layers[k].name)};
    writeHazardMap(ens.dem(), layer, areas, files_->maps[k].string(), rules_, window, polylines);
    written_ += ", " + files_->maps[k].filename().string();
  }
  // The energy's and the passing height's 95th percentiles in classes.
  const auto layerOf = [&](const char* name) -> const StatLayer& {
    return layers[static_cast<std::size_t>(
        std::find(std::begin(kLayerNames), std::end(kLayerNames), std::string(name)) -
        std::begin(kLayerNames))];
  };
  std::vector<MapLayer> classed{{"intensity",
                                 "Intensity: energy p95 low < 30, medium 30-300, high > 300 kJ", "",
                                 mappedValues("energy_p95", layerOf("energy_p95").values, passages),
                                 false, swissRockfallIntensity()}};
  if (!options_.heightClasses.empty())
    classed.push_back({"height_classes", "Passing height p95", "",
                       mappedValues("height_p95", layerOf("height_p95").values, passages), false,
                       passingHeightClasses(options_.heightClasses)});
  for (std::size_t k = 0; k < classed.size(); ++k) {
    const fs::path& png = files_->maps[layers.size() + k];
    writeHazardMap(ens.dem(), classed[k], areas, png.string(), rules_, window, polylines);
    written_ += ", " + png.filename().string();
  }

  std::vector<double> runouts, reach;
  for (const RealisationResult& r : runs) {
    runouts.push_back(r.runout);
    reach.push_back(r.reachAngle);
  }
  writeRunoutPlot(runouts, reach, files_->maps.back().string(), rules_);
  written_ += ", " + files_->maps.back().filename().string();
}

RunStatus EnsembleFiles::write(const Ensemble& ens, const EnsembleRunInfo& info,
                               const std::vector<RealisationResult>& runs) {
  const Heightfield& dem = ens.dem();
  const std::vector<StatLayer> layers = cellStatistics(dem, runs);
  writeRasters(ens, layers);
  writeRunsCsv(files_->runs->stream(), ens, runs);
  commit(*files_->runs);
  if (files_->paths) {
    writePathsCsv(files_->paths->stream(), dem, runs);
    commit(*files_->paths);
  }
  const RunStatus video = files_->bake ? writeVideo(ens, info, runs) : RunStatus::done();
  std::vector<ConvergenceRow> conv;
  if (files_->converge) {
    conv = convergence(dem, runs, kConvergenceCells);
    writeConvergence(files_->converge->stream(), stderr, dem, conv);
    commit(*files_->converge);
  }
  if (options_.maps) writeMaps(ens, layers, runs);
  if (files_->barriers) {
    // Summed over the realisations, in index order.
    std::vector<BarrierResult> sum(ens.barriers().size());
    std::vector<std::int64_t> failed(sum.size(), 0);
    for (const RealisationResult& r : runs)
      for (std::size_t b = 0; b < r.barriers.size() && b < sum.size(); ++b) {
        sum[b].hits += r.barriers[b].hits;
        sum[b].stopped += r.barriers[b].stopped;
        sum[b].passed += r.barriers[b].passed;
        sum[b].maxEnergy = std::max(sum[b].maxEnergy, r.barriers[b].maxEnergy);
        failed[b] += r.barriers[b].failed ? 1 : 0;
      }
    writeBarriersCsv(files_->barriers->stream(), ens.barriers(), sum, failed);
    commit(*files_->barriers);
  }
  if (files_->lines) {
    // Realisations in index order, each one's crossings in time order: the same rows for any
    // --jobs, ranks or shards.
    std::vector<LineCrossing> crossings;
    for (const RealisationResult& r : runs)
      crossings.insert(crossings.end(), r.crossings.begin(), r.crossings.end());
    written_ += ", " + files_->lines->write(ens.lines(), crossings,
                                            static_cast<std::int64_t>(runs.size()), dem.shift);
  }
  writeEnsembleSummary(files_->summary->stream(), ens.spec(), dem, info, runs, layers, conv);
  commit(*files_->summary);
  return video;
}

void reportEnsemble(const Ensemble& ens, const EnsembleRunInfo& info,
                    const std::vector<RealisationResult>& runs, const EnsembleFiles& files) {
  const SceneSpec& spec = ens.spec();
  int states[4] = {0, 0, 0, 0};
  for (const RealisationResult& r : runs) ++states[static_cast<int>(r.state)];
  std::printf(
      "%s: %zu realisations (seed %llu): %d stopped, %d left the DEM, %d buried, %d "
      "still moving at %.4g s\n",
      spec.name.c_str(), runs.size(), static_cast<unsigned long long>(info.seed), states[1],
      states[2], states[3], states[0], spec.duration);
  std::printf("  wrote %s in %s\n", files.written().c_str(), files.options().outDir.c_str());
  // A realisation cut off by the duration records its rock where it was then: the hazard
  // products understate the reach without saying so unless told here (--quiet or not).
  if (states[0] > 0)
    std::fprintf(stderr,
                 "voxfall: warning: %d of %zu realisations ended at the scene's duration (%.4g s) "
                 "with the rock still moving; runs.csv, the runouts and the maps show those "
                 "rocks where they were then, not where they stop: raise [simulation] "
                 "duration\n",
                 states[0], runs.size(), spec.duration);
}

}  // namespace vf
