// A golden-frame regression run as a library call: what `voxfall regress` does, for the command
// and for any program or test that wants it without argv.
//
// A suite is a folder: SUITE_DIR/suite.toml lists cases (a scene, the frames to check, a size,
// optionally a tolerance and a mask), and SUITE_DIR/<case name>/ holds the goldens:
// frame_NNNN.png per checked frame and checksum.txt, the trajectory checksum of the run. For
// each case the scene is simulated and the frames drawn exactly as `voxfall render --frames k:k`
// draws them; then
//   - the checksum must equal the golden one: the states are bit-identical by design, so any
//     difference means the physics changed, even when the pixels barely move;
//   - each frame must be within the case's tolerance of its golden (image_diff.h).
// A case with `runs = K` checks an ensemble scene's first K realisations instead, drawn
// together as `voxfall ensemble --video-runs K` draws them; its checksum.txt holds K words.
//
// --update writes the goldens that are missing or fail (each through a temporary file and a
// rename) and keeps the ones within tolerance, so that a review shows only what changed.
//
// With jobs > 1 the cases are shared among that many worker processes (case i to worker
// i mod jobs), each with its own GL context; the results are gathered in case order, so the
// reports are the same bytes as with one job.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "render/run/regress_report.h"

namespace vf {

struct RegressRequest {
  std::string suite;               // the suite folder
  std::string reportDir;           // "": out/regress
  std::string junitFile;           // "": no JUnit XML
  bool update = false;             // write missing or failing goldens
  std::vector<std::string> cases;  // run only these (empty: all)
  std::string gl = "osmesa";       // osmesa or egl
  std::string shaders;             // GLSL folder ("": found as render finds it)
  int jobs = 1;                    // worker processes
};

// Who wants to hear of a run as it goes: onStart once the GL backend is known (the result holds
// the suite, the backend and whether it updates), onCase for each case in case order, as soon
// as it is done (with several jobs, once all are done).
struct RegressProgress {
  std::function<void(const SuiteResult&)> onStart;
  std::function<void(const CaseResult&)> onCase;
};

// Runs the suite and writes its reports: REPORT_DIR/report.txt, index.html and timings.txt,
// the pictures of failing frames under REPORT_DIR/<case>/, and the JUnit file when asked for.
// Bad input (no suite, an unknown --case, an unwritable report folder) throws InputError; a case
// that cannot run is a failed case, and the others still run.
SuiteResult runRegression(const RegressRequest& request, const RegressProgress& progress = {});

// The report folder a request writes into.
std::string reportFolder(const RegressRequest& request);

}  // namespace vf
