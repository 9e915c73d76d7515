// The stop policy (render/run/stop_policy.h) once for every command, with real child processes:
// each command that does not poll (filmstrip, diff, regress, figures, plot, ensemble-merge) is
// started on inputs slow enough to be caught mid-work, sent SIGINT or SIGTERM once something
// observable says it is working (a temporary ".partial-" file or a first finished output), and
// must be ended by that signal (WIFSIGNALED) with no temporary file left anywhere in its folder
// and every output it left whole. The commands that poll are stopped by both signals in
// output_rules_test (simulate, render), interrupted_outputs_test (export, ensemble by SIGTERM)
// and ensemble_command_test (ensemble by SIGINT); the last test here checks that every command
// `voxfall --help` lists is covered by one of them.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <ostream>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "render/image.h"
#include "render/output/png_writer.h"
#include "tests/support/chute_dem.h"
#include "tests/support/voxfall_command.h"

namespace {

namespace fs = std::filesystem;
using vf::test::readFile;
using vf::test::runVoxfall;

const std::string kExe = VOXFALL_EXE;
const fs::path kScenes = fs::path(VOXFALL_SOURCE_DIR) / "scenes";

// The commands that poll, and the tests that stop them with both signals.
const std::set<std::string> kPollingCommands = {"simulate", "render", "export", "ensemble"};

// Every temporary output file (".NAME.partial-...") under `folder`, at any depth.
std::vector<std::string> partialsUnder(const fs::path& folder) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().find(".partial-") != std::string::npos)
      out.push_back(it->path().string());
  return out;
}

// The processes whose working folder is `folder`: a helper program (gnuplot) or a worker process
// the command started there that outlived it, and could still write into it.
std::vector<std::string> processesIn(const fs::path& folder) {
  std::vector<std::string> out;
  std::error_code ec;
  for (fs::directory_iterator it("/proc", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string pid = it->path().filename().string();
    if (pid.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code gone;
    if (fs::read_symlink(it->path() / "cwd", gone) == folder)
      out.push_back(pid + " " + readFile(it->path() / "comm"));
  }
  return out;
}

bool anyPartialIn(const fs::path& folder) {
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->path().filename().string().find(".partial-") != std::string::npos) return true;
  return false;
}

bool present(const fs::path& p) {
  std::error_code ec;
  return fs::exists(p, ec);
}

// A file a command finished is whole: a PNG decodes, an SVG is closed, a CSV, text or JSON file
// ends with its last line.
void expectWhole(const fs::path& file) {
  const std::string ext = file.extension().string();
  const std::string bytes = readFile(file);
  if (ext == ".png") {
    EXPECT_NO_THROW(vf::readPng(file.string())) << file;
  } else if (ext == ".svg") {
    EXPECT_NE(bytes.rfind("</svg>"), std::string::npos) << file;
  } else if (ext == ".csv" || ext == ".md" || ext == ".txt" || ext == ".json") {
    EXPECT_TRUE(!bytes.empty() && bytes.back() == '\n') << file;
  }
}

void expectAllWhole(const fs::path& folder) {
  std::error_code ec;
  for (fs::recursive_directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (it->is_regular_file()) expectWhole(it->path());
}

// A picture of stripes, for diff's inputs: large and varied enough that encoding a diff image
// takes a while, so a stop lands while one is being written.
void writePicture(const fs::path& path, int width, int height, int stride) {
  vf::Image image(width, height);
  for (std::size_t i = 0; i < image.rgb.size(); ++i)
    image.rgb[i] = static_cast<std::uint8_t>((i * stride) % 251);
  vf::writePng(path.string(), image);
}

// cubes.toml and its mesh in `dir`, and long.toml: the same scene lasting 600 s, which takes
// seconds to simulate.
void writeCubes(const fs::path& dir) {
  vf::test::copyCubesScene(kScenes, dir, {{"long.toml", 600}});
}

// A suite of two cases: the cubes (seconds) and then the 600 s scene, its last frame.
void writeSuite(const fs::path& dir) {
  writeCubes(dir);
  fs::create_directories(dir / "suite");
  std::ofstream(dir / "suite" / "suite.toml")
      << "[[case]]\nscene = \"../cubes.toml\"\nframes = [0]\nsize = [64, 48]\n"
         "[[case]]\nscene = \"../long.toml\"\nframes = [17990]\nsize = [64, 48]\n";
}

// One row of the table: how to prepare a command's slow inputs, its arguments, when it is
// working, and what it may leave.
struct StopCase {
  std::string command;
  std::function<void(const fs::path& dir)> prepare;
  std::vector<std::string> args;
  std::function<bool(const fs::path& dir)> working;
  std::function<void(const fs::path& dir)> checkLeft;
};

std::vector<StopCase> stopCases() {
  std::vector<StopCase> cases;
  // The filmstrip's PNG is open as a temporary file while the 600 s scene is simulated.
  cases.push_back(
      {"filmstrip",
       writeCubes,
       {"filmstrip", "long.toml", "--times", "590", "--size", "64x48", "-o", "out/strip.png"},
       [](const fs::path& d) { return anyPartialIn(d / "out"); },
       [](const fs::path& d) { EXPECT_TRUE(fs::is_empty(d / "out")); }});
  // 3000 pairs of frames (hard links to two pictures); stopped while a diff image is being
  // written. Those finished must be the bytes of the one diff of the two pictures.
  cases.push_back({"diff",
                   [](const fs::path& d) {
                     writePicture(d / "a.png", 1000, 750, 7);
                     writePicture(d / "b.png", 1000, 750, 13);
                     fs::create_directories(d / "expected");
                     fs::create_directories(d / "actual");
                     for (int k = 0; k < 3000; ++k) {
                       const std::string name = "frame_" + std::to_string(10000 + k) + ".png";
                       fs::create_hard_link(d / "a.png", d / "expected" / name);
                       fs::create_hard_link(d / "b.png", d / "actual" / name);
                     }
                     ASSERT_EQ(runVoxfall(kExe, d, "diff a.png b.png -o one.png").code, 1);
                   },
                   {"diff", "expected", "actual", "-o", "diffs"},
                   [](const fs::path& d) { return anyPartialIn(d / "diffs"); },
                   [](const fs::path& d) {
                     const std::string one = readFile(d / "one.png");
                     int whole = 0;
                     for (const auto& e : fs::directory_iterator(d / "diffs")) {
                       EXPECT_TRUE(readFile(e.path()) == one) << e.path() << " is not whole";
                       ++whole;
                     }
                     EXPECT_LT(whole, 3000) << "stopped mid-work";
                   }});
  // Two cases with --update: the cubes' goldens are written, then the 600 s scene simulated; in
  // one process, and in two worker processes, which must end with the command.
  for (const bool workers : {false, true}) {
    std::vector<std::string> args = {"regress", "suite", "--update", "-o", "report"};
    if (workers) args.insert(args.end(), {"--jobs", "2"});
    cases.push_back(
        {workers ? "regress --jobs 2" : "regress", writeSuite, args,
         [](const fs::path& d) { return present(d / "suite" / "cubes" / "checksum.txt"); },
         [](const fs::path& d) {
           expectAllWhole(d / "suite");
           EXPECT_FALSE(present(d / "suite" / "long")) << "stopped mid-work";
           EXPECT_TRUE(!present(d / "report") || fs::is_empty(d / "report"))
               << "no report of a run that did not finish";
         }});
  }
  // The four figures, reduced: stopped once the first figure's files are being written.
  cases.push_back({"figures",
                   nullptr,
                   {"figures", "--quick", "-q", "--scenes", kScenes.string(), "-o", "figs"},
                   [](const fs::path& d) { return anyPartialIn(d / "figs"); },
                   [](const fs::path& d) {
                     expectAllWhole(d / "figs");
                     EXPECT_FALSE(present(d / "figs" / "README.md")) << "stopped mid-work";
                   }});
  // A run of 6000 frames of three bodies: stopped once its data files are written, while gnuplot
  // draws.
  cases.push_back({"plot",
                   [](const fs::path& d) {
                     std::ofstream f(d / "run.csv");
                     f << "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
                     for (int k = 0; k < 6000; ++k)
                       for (int b = 0; b < 3; ++b)
                         f << k << ',' << k / 30.0 << ',' << b << ',' << k * 0.01 << ',' << b
                           << ",1,1,0,0,0,0.3,0,0,0,0,0\n";
                   },
                   {"plot", "run.csv", "-o", "plots"},
                   [](const fs::path& d) { return present(d / "plots" / "bodies.csv"); },
                   [](const fs::path& d) {
                     expectAllWhole(d / "plots");
                     EXPECT_FALSE(present(d / "plots" / "trajectories.svg")) << "stopped mid-work";
                   }});
  // An ensemble's journal merged with its maps: stopped once runs.csv is written, while the maps
  // are drawn.
  cases.push_back({"ensemble-merge",
                   [](const fs::path& d) {
                     ASSERT_TRUE(vf::test::writeChuteDem(d / "chute.tif"));
                     vf::test::writeChuteScene(d, vf::test::kChuteEnsemble);
                     ASSERT_EQ(runVoxfall(kExe, d, "ensemble scene.toml --runs 4 -q -o e").code, 0);
                   },
                   {"ensemble-merge", "e", "--maps", "-q", "-o", "m"},
                   [](const fs::path& d) { return present(d / "m" / "runs.csv"); },
                   [](const fs::path& d) {
                     // Whatever it finished is the bytes the ensemble wrote.
                     for (const auto& e : fs::directory_iterator(d / "m")) {
                       const std::string name = e.path().filename().string();
                       if (name == "summary.json" || name == "ensemble.journal") continue;
                       EXPECT_TRUE(readFile(e.path()) == readFile(d / "e" / name))
                           << name << " is not whole";
                     }
                   }});
  return cases;
}

struct StopParam {
  std::size_t row;
  int signal;
};

// How test names and failures show a row: the command and the signal.
void PrintTo(const StopParam& p, std::ostream* out) {
  *out << stopCases()[p.row].command << (p.signal == SIGINT ? " SIGINT" : " SIGTERM");
}

class StopEveryCommand : public ::testing::TestWithParam<StopParam> {
 protected:
  void SetUp() override {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = info->name();
    std::replace(name.begin(), name.end(), '/', '_');
    dir_ = vf::test::scratchFolder("voxfall_stop", name);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_P(StopEveryCommand, EndsByTheSignalWithNoTemporaryFileAndWholeOutputs) {
  const StopCase c = stopCases()[GetParam().row];
  const int sig = GetParam().signal;
  if (c.prepare) c.prepare(dir_);
  ASSERT_FALSE(HasFatalFailure());
  bool caught = false;
  const int status =
      vf::test::interruptVoxfall(kExe, dir_, c.args, sig, [&] { return caught = c.working(dir_); });
  ASSERT_TRUE(caught) << c.command << " never showed it was working";
  ASSERT_TRUE(WIFSIGNALED(status))
      << c.command << " exited with " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  EXPECT_EQ(WTERMSIG(status), sig);
  EXPECT_EQ(processesIn(dir_), std::vector<std::string>{}) << "left running after " << c.command;
  EXPECT_EQ(partialsUnder(dir_), std::vector<std::string>{});
  c.checkLeft(dir_);
}

std::vector<StopParam> allParams() {
  std::vector<StopParam> out;
  for (std::size_t row = 0; row < stopCases().size(); ++row)
    for (const int sig : {SIGINT, SIGTERM}) out.push_back({row, sig});
  return out;
}

INSTANTIATE_TEST_SUITE_P(CommandBySignal, StopEveryCommand, ::testing::ValuesIn(allParams()),
                         [](const ::testing::TestParamInfo<StopParam>& info) {
                           std::string name = stopCases()[info.param.row].command;
                           std::replace(name.begin(), name.end(), ' ', '_');
                           name.erase(std::remove(name.begin(), name.end(), '-'), name.end());
                           return name + (info.param.signal == SIGINT ? "_SIGINT" : "_SIGTERM");
                         });

// Every command `voxfall --help` lists is stopped by both signals: in the table above, or (the
// commands that poll) in the tests named at the top.
TEST(StopEveryCommandCoverage, EveryListedCommandIsCovered) {
  const fs::path dir = vf::test::scratchFolder("voxfall_stop", "coverage");
  const auto help = runVoxfall(kExe, dir, "--help");
  fs::remove_all(dir);
  ASSERT_EQ(help.code, 0);
  std::set<std::string> covered = kPollingCommands;
  for (const StopCase& c : stopCases()) covered.insert(c.command.substr(0, c.command.find(' ')));
  std::istringstream in(help.out.substr(help.out.find("Subcommands:")));
  std::string line;
  std::getline(in, line);
  int listed = 0;
  const std::regex command("^  ([a-z][a-z-]*) ");
  while (std::getline(in, line)) {
    std::smatch m;
    if (!std::regex_search(line, m, command)) continue;
    ++listed;
    EXPECT_EQ(covered.count(m[1]), 1u) << m[1] << " is never stopped by a signal in a test";
  }
  EXPECT_GE(listed, 10) << help.out;
}

}  // namespace
