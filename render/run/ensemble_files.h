// The reduced outputs of an ensemble (rasters, runs.csv, summary.json and the optional tables,
// maps, bake and video), written from complete realisations in index order. Shared by
// `voxfall ensemble` and `voxfall ensemble-merge`, so a merge of shards writes what one run
// writes, byte for byte. Every file goes through render/output/output_file.h.
#pragma once

#include <cstdint>
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "render/maps/hazard_map.h"
#include "render/output/output_file.h"
#include "render/run/stop_policy.h"
#include "sim/ensemble/ensemble.h"
#include "sim/ensemble/ensemble_stats.h"

namespace vf {

// What to write, and how (the options of the command).
struct EnsembleFileOptions {
  std::string outDir;
  bool converge = false;       // converge.csv
  bool paths = false;          // paths.csv
  bool maps = false;           // a PNG per statistic and runout.png
  std::vector<double> extent;  // --extent XMIN,YMIN,XMAX,YMAX of the maps; empty: the reached area
  int videoRuns = 0;           // ensemble_subset.bake and trajectories.mp4
  bool lines = false;          // the scene has evaluation lines: crossings.csv, lines.csv
  bool barriers = false;       // the scene has barriers: barriers.csv
  std::vector<double> heightClasses;  // the scene's height_classes: with maps, height_classes.png
  bool overwrite = false, neverOverwrite = false, quiet = false;
};

// The maps' window of --extent (four numbers, DEM file coordinates) on `dem`; throws an
// InputError naming --extent when it is malformed or holds no sample of the DEM.
MapWindow mapExtent(const std::vector<double>& extent, const Heightfield& dem);

// What the outputs hold, for summary.json.
struct EnsembleRunInfo {
  std::uint64_t seed = 0;
  std::int64_t runsRequested = 0;
  std::optional<std::int64_t> only;  // --only
  int stopSignal = 0;                // SIGINT or SIGTERM when the run was stopped
};

class EnsembleFiles {
 public:
  // Checks every output path and the maps' extent against `dem` (an InputError names
  // --extent) and creates each temporary file, before any realisation runs.
  EnsembleFiles(const EnsembleFileOptions& options, const OutputRules& rules,
                const Heightfield& dem);
  ~EnsembleFiles();
  // Reduces `runs` (complete, in index order) into every file; returns done, or the status of
  // the video's render (stopped when it was interrupted).
  RunStatus write(const Ensemble& ensemble, const EnsembleRunInfo& info,
                  const std::vector<RealisationResult>& runs);
  // The files written, by name: "passages.tif, ..., summary.json".
  const std::string& written() const { return written_; }
  const EnsembleFileOptions& options() const { return options_; }

 private:
  struct Files;
  void writeRasters(const Ensemble& ensemble, const std::vector<StatLayer>& layers);
  void writeRasterFile(OutputFile& file, int format, const std::vector<double>& values,
                       const Ensemble& ensemble);
  RunStatus writeVideo(const Ensemble& ensemble, const EnsembleRunInfo& info,
                       const std::vector<RealisationResult>& runs);
  void writeMaps(const Ensemble& ensemble, const std::vector<StatLayer>& layers,
                 const std::vector<RealisationResult>& runs);
  void commit(OutputFile& file);
  std::optional<MapWindow> extent_;  // --extent as samples of the DEM

  EnsembleFileOptions options_;
  OutputRules rules_;
  std::unique_ptr<Files> files_;
  std::string written_;
};

// The lines an ensemble prints when its files are written: the states on stdout, the files,
// and the warning about realisations cut off by the duration (stderr, --quiet or not).
void reportEnsemble(const Ensemble& ensemble, const EnsembleRunInfo& info,
                    const std::vector<RealisationResult>& runs, const EnsembleFiles& files);

}  // namespace vf
