// One case of a regression suite, run and judged (regress_run.h says what a case checks).
// Private to render/run/.
#pragma once

#include <filesystem>
#include <string>

#include "render/gl/gl_context.h"
#include "render/regress_suite.h"
#include "render/run/regress_report.h"

namespace vf {

// Simulates and draws the case, compares checksum and frames with the goldens in
// `suiteDir/<name>/`, writes the pictures of failing frames under `reportDir/<name>/` (and,
// with `update`, the goldens that are missing or fail) and returns what it found. Throws for a
// case that cannot run (a broken scene, a frame outside the scene, a mask off the frame).
CaseResult runRegressionCase(const SuiteCase& c, const std::filesystem::path& suiteDir,
                             const std::filesystem::path& reportDir, bool update,
                             gl::Context& context, const std::string& shaderDir);

}  // namespace vf
