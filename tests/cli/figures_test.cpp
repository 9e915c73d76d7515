// voxfall figures, filmstrip and plot end to end (the built binary, VOXFALL_EXE):
//   - `figures fig10 --quick` writes PNG, SVG and CSV, and its CSV shows the error falling as
//     the level rises from 1 to 4 (the paper's fig. 10 claim);
//   - a filmstrip's frame at t = k / fps is, pixel for pixel, the PNG `render --frames k:k`
//     writes (read back with libpng);
//   - `plot` writes its files, and the numbers it plots agree with independent sources: the
//     last frame's energies with `simulate --summary` (World::measure), each body's speed and
//     position with the run CSV's rows.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "render/figures/filmstrip.h"
#include "render/figures/gnuplot.h"
#include "render/output/png_writer.h"
#include "tests/render/render_test_util.h"
#include "tests/support/voxfall_command.h"

namespace vf {
namespace {

namespace fs = std::filesystem;

const std::string kExe = VOXFALL_EXE;
const std::string kScenes = std::string(VOXFALL_SOURCE_DIR) + "/scenes";

int voxfall(const std::string& args) {
  const int status = std::system(("'" + kExe + "' " + args + " >/dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::vector<std::vector<std::string>> readCsv(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> fields;
    std::stringstream s(line);
    for (std::string f; std::getline(s, f, ',');) fields.push_back(f);
    rows.push_back(fields);
  }
  return rows;
}

bool startsWith(const std::string& path, const std::string& magic) {
  std::ifstream in(path, std::ios::binary);
  std::string head(magic.size(), '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  return head == magic;
}

bool contains(const std::string& path, const std::string& text) {
  std::ifstream in(path);
  std::stringstream s;
  s << in.rdbuf();
  return s.str().find(text) != std::string::npos;
}

TEST(FiguresCommand, QuickFig10WritesItsFilesAndTheErrorFallsWithTheLevel) {
  test::ScratchDir dir("figures_fig10");
  const std::string out = dir.file("figs");
  ASSERT_EQ(voxfall("figures fig10 --quick --quiet --scenes '" + kScenes + "' -o '" + out + "'"),
            0);
  EXPECT_TRUE(startsWith(out + "/fig10.png", "\x89PNG"));
  EXPECT_TRUE(contains(out + "/fig10.svg", "<svg"));
  EXPECT_TRUE(contains(out + "/README.md", "## Fig. 10"));
  const auto rows = readCsv(out + "/fig10.csv");
  ASSERT_EQ(rows.size(), 5u);  // header + levels 1..4
  ASSERT_EQ(rows[0][0], "level");
  ASSERT_EQ(rows[0][3], "mean_distance_m");
  double previous = INFINITY;
  for (int lv = 1; lv <= 4; ++lv) {
    EXPECT_EQ(std::stoi(rows[lv][0]), lv);
    const double error = std::stod(rows[lv][3]);
    EXPECT_LT(error, previous) << "level " << lv;
    previous = error;
  }
  // Nothing left under a temporary name.
  for (const auto& e : fs::directory_iterator(out))
    EXPECT_EQ(e.path().filename().string().find(".partial"), std::string::npos) << e.path();
}

TEST(FiguresCommand, UnknownFigureIsAUsageError) { EXPECT_EQ(voxfall("figures fig99"), 2); }

// The gnuplot point type of the legend sample drawn after the legend text `label` in an SVG
// (gnuplot's SVG names point type N as gpPt(N-1)): gpPt6 is the filled circle, gpPt5 the open
// one. -1 when there is none.
int legendPointAfter(const std::string& svg, const std::string& label) {
  const std::size_t text = svg.find("<text>" + label + "</text>");
  const std::size_t use = svg.find("xlink:href='#gpPt", text);
  if (text == std::string::npos || use == std::string::npos) return -1;
  return std::atoi(svg.c_str() + use + 17);
}

// Hollow marks mean a run that interpenetrated (the footnote says so), so a legend must show
// each series filled, whether or not its runs are clean: fig. 14 (points) and fig. 16 (lines
// and points) read from their SVGs; fig. 13's bars come from the same code as fig. 14's.
TEST(FiguresCommand, LegendsShowTheSeriesFilled) {
  test::ScratchDir dir("figures_legends");
  const std::string out = (dir.path() / "figs").string();
  ASSERT_EQ(voxfall("figures fig13 fig14 fig16 --quick --quiet --scenes '" + kScenes + "' -o '" +
                    out + "'"),
            0);
  const std::string fig14 = test::readFile(out + "/fig14.svg");
  for (const char* label : {"voxel method", "polygon method"})
    EXPECT_EQ(legendPointAfter(fig14, label), 6) << label;
  const std::string fig16 = test::readFile(out + "/fig16.svg");
  for (const char* label : {"Lv 4 at 1/150", "polygon at 1/600", "polygon at 1/1200"})
    EXPECT_EQ(legendPointAfter(fig16, label), 6) << label;
  // And a figure that would give a hollow series a legend entry is refused before drawing.
  fig::Figure f;
  f.panels.push_back(
      {"p", "x", "y", false, false, {{"runs", "a.csv", "1:2", "points", 0, true}}, {}});
  EXPECT_THROW(fig::drawFigure(f, (dir.path() / "bad").string()), std::logic_error);
}

TEST(FilmstripCommand, EachFrameIsExactlyTheRenderedFrame) {
  test::ScratchDir dir("filmstrip");
  const std::string scene = kScenes + "/cubes.toml";  // 30 fps
  ASSERT_EQ(voxfall("filmstrip '" + scene + "' --times 0.5,1,1.5 --columns 2 --size 96x64 -o '" +
                    dir.file("strip.png") + "'"),
            0);
  const Image strip = readPng(dir.file("strip.png"));
  const std::vector<int> frames{15, 30, 45};
  for (std::size_t i = 0; i < frames.size(); ++i) {
    const std::string k = std::to_string(frames[i]);
    ASSERT_EQ(voxfall("render '" + scene + "' --quiet --size 96x64 --frames " + k + ":" + k +
                      " -o '" + dir.file("f_####.png") + "'"),
              0);
    char name[32];
    std::snprintf(name, sizeof name, "f_%04d.png", frames[i]);
    const Image frame = readPng(dir.file(name));
    const fig::FrameSlot s = fig::filmstripSlot(static_cast<int>(i), 2, 96, 64);
    int differing = 0;
    for (int y = 0; y < 64; ++y)
      for (int x = 0; x < 96; ++x)
        for (int c = 0; c < 3; ++c)
          differing += strip.pixel(s.x + x, s.y + y)[c] != frame.pixel(x, y)[c];
    EXPECT_EQ(differing, 0) << "frame " << k;
    // The label band above the frame holds dark text pixels.
    int dark = 0;
    for (int y = s.y - fig::kFilmstripLabelBand; y < s.y; ++y)
      for (int x = s.x; x < s.x + 96; ++x) dark += strip.pixel(x, y)[0] < 0x80;
    EXPECT_GT(dark, 20) << "no label over frame " << k;
  }
  EXPECT_EQ(strip.width, 2 * 96 + 3 * fig::kFilmstripGap);
  EXPECT_EQ(strip.height, 2 * (64 + fig::kFilmstripLabelBand) + 3 * fig::kFilmstripGap);
}

// The figures replace their own README.md on a second run, but a README.md they did not write
// (a user's folder given as -o) is refused before any run, and nothing is written there.
TEST(FiguresCommand, AReadmeItDidNotWriteIsNeverReplaced) {
  test::ScratchDir dir("figures_readme");
  const std::string out = dir.file("project");
  fs::create_directories(out);
  std::ofstream(out + "/README.md") << "# My project\n";
  const std::string args = "figures fig10 --quick --quiet --scenes '" + kScenes + "' -o '";
  EXPECT_EQ(voxfall(args + out + "'"), 1);
  EXPECT_TRUE(contains(out + "/README.md", "# My project"));
  EXPECT_FALSE(fs::exists(out + "/fig10.csv"));
  // Its own README.md is replaced by the next run.
  const std::string figs = dir.file("figs");
  ASSERT_EQ(voxfall(args + figs + "'"), 0);
  std::ofstream(figs + "/README.md", std::ios::app) << "stale line\n";
  ASSERT_EQ(voxfall(args + figs + "'"), 0);
  EXPECT_FALSE(contains(figs + "/README.md", "stale line"));
  EXPECT_TRUE(contains(figs + "/README.md", "## Fig. 10"));
}

TEST(PlotCommand, WritesItsFilesAndPlotsWhatTheRunSays) {
  test::ScratchDir dir("plot");
  const std::string scene = kScenes + "/cubes.toml";
  ASSERT_EQ(voxfall("simulate '" + scene + "' --quiet --csv '" + dir.file("run.csv") +
                    "' --summary '" + dir.file("summary.json") + "'"),
            0);
  const std::string out = dir.file("plots");
  ASSERT_EQ(voxfall("plot '" + dir.file("run.csv") + "' --scene '" + scene + "' -o '" + out + "'"),
            0);
  for (const std::string name : {"energy", "speed", "trajectories"}) {
    EXPECT_TRUE(startsWith(out + "/" + name + ".png", "\x89PNG")) << name;
    EXPECT_TRUE(contains(out + "/" + name + ".svg", "<svg")) << name;
  }
  // Energies of the last frame = the summary's (World::measure: 1/2 P.v + 1/2 L.w, -M g.x).
  std::ifstream json(dir.file("summary.json"));
  std::stringstream js;
  js << json.rdbuf();
  auto number = [&](const std::string& key) {
    const std::string text = js.str();
    const auto at = text.find("\"" + key + "\":");
    EXPECT_NE(at, std::string::npos) << key;
    return std::stod(text.substr(text.find(':', at) + 1));
  };
  const auto energy = readCsv(out + "/energy.csv");
  const auto run = readCsv(dir.file("run.csv"));
  ASSERT_EQ(energy[0],
            (std::vector<std::string>{"frame", "time_s", "kinetic_J", "potential_J", "total_J"}));
  EXPECT_EQ(energy.size(), 1 + 61u);  // 2 s at 30 fps: frames 0..60
  const double ke = std::stod(energy.back()[2]), pe = std::stod(energy.back()[3]);
  // The summary's energies are the last step's (at most dt_max before 2 s); frame 60 shows that
  // step's state carried on by free motion to t = 2 s (README, "Frames and steps"). The two
  // cubes (2 x 21.6 kg) are at rest by then, so in between they gain at most |g| dt_max of
  // speed and fall at most |g| dt_max^2 / 2: that bounds both differences.
  const double g = 9.81, dt = number("dt_max"), mass = 2 * 800 * 0.3 * 0.3 * 0.3;
  EXPECT_NEAR(ke, number("kinetic_energy"), 0.5 * mass * (g * dt) * (g * dt) + 1e-9);
  EXPECT_NEAR(pe, number("potential_energy"), mass * g * (0.5 * g * dt * dt) + 1e-9);
  // Speeds and positions: every run row appears once, |v| and x recomputed from the run CSV.
  const auto bodies = readCsv(out + "/bodies.csv");
  ASSERT_EQ(bodies.size(), run.size());
  std::map<std::pair<int, std::string>, std::vector<std::string>> byKey;
  for (std::size_t i = 1; i < run.size(); ++i) byKey[{std::stoi(run[i][2]), run[i][1]}] = run[i];
  for (std::size_t i = 1; i < bodies.size(); ++i) {
    const auto& r = byKey.at({std::stoi(bodies[i][0]), bodies[i][1]});
    const double vx = std::stod(r[10]), vy = std::stod(r[11]), vz = std::stod(r[12]);
    EXPECT_NEAR(std::stod(bodies[i][2]), std::sqrt(vx * vx + vy * vy + vz * vz), 1e-12);
    EXPECT_EQ(std::stod(bodies[i][3]), std::stod(r[3]));
    EXPECT_EQ(std::stod(bodies[i][5]), std::stod(r[5]));
  }
}

// A run CSV that is not what `simulate --csv` writes is one error naming the file and line, and
// nothing is plotted. The frame and body columns are counts: a body id of 1e30 must not be cast
// to int (undefined behaviour), nor a negative frame go through.
TEST(PlotCommand, AMalformedRunCsvIsOneErrorNamingItsLine) {
  test::ScratchDir dir("plot_bad_csv");
  const std::string header = "frame,time,body,x,y,z,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz\n";
  const std::string row = ",0,0,0,0,1,1,0,0,0,0,0,0,0,0,0\n";  // after the frame
  const std::pair<std::string, std::string> cases[] = {
      {"time,frame\n", "run.csv:1: not a voxfall run CSV: the first line must be frame,time"},
      {header + "0" + row + "0,0,1e30,0,0,1,1,0,0,0,0,0,0,0,0,0\n",
       "run.csv:3: the body id must be a whole number from 0 to 2147483647, got 1e+30"},
      {header + "-1" + row, "run.csv:2: the frame must be a whole number from 0 to"},
      {header + "2.5" + row, "run.csv:2: the frame must be a whole number"},
      {header + "0" + row + "1,0.1,0,nan,0,1,1,0,0,0,0,0,0,0,0,0\n",
       "run.csv:3: field 4 'nan' is not a finite number"},
      {header + "0,0,0,0,0,1\n", "run.csv:2: expected 16 fields"},
      {header, "run.csv: the run CSV has no rows"},
  };
  for (const auto& [text, message] : cases) {
    std::ofstream(dir.file("run.csv")) << text;
    const test::CommandResult r = test::runVoxfall(kExe, dir.path(), "plot run.csv -o plots");
    EXPECT_EQ(r.code, 1) << text;
    EXPECT_EQ(r.err.rfind("voxfall: error: " + message, 0), 0u) << r.err;
    EXPECT_FALSE(fs::exists(dir.file("plots/energy.csv"))) << text;
  }
}

// The plots replace their own earlier files but never what they read: a run CSV named like
// one of the outputs, plotted into its own folder, or a scene file there, is refused before
// anything is written.
TEST(PlotCommand, NeverOverwritesTheRunOrTheScene) {
  test::ScratchDir dir("plot_inputs");
  const std::string scene = kScenes + "/cubes.toml";
  ASSERT_EQ(voxfall("simulate '" + scene + "' --quiet --csv '" + dir.file("energy.csv") + "'"), 0);
  std::ifstream in(dir.file("energy.csv"));
  std::stringstream before;
  before << in.rdbuf();
  EXPECT_EQ(voxfall("plot '" + dir.file("energy.csv") + "' -o '" + dir.path().string() + "'"), 1);
  std::ifstream again(dir.file("energy.csv"));
  std::stringstream after;
  after << again.rdbuf();
  EXPECT_EQ(after.str(), before.str());
  EXPECT_FALSE(fs::exists(dir.file("bodies.csv")));  // nothing written
  // The scene given for the masses is an input too.
  fs::copy_file(dir.file("energy.csv"), dir.file("run.csv"));
  fs::create_directories(dir.file("scene/meshes"));
  fs::copy_file(kScenes + "/meshes/cube.obj", dir.file("scene/meshes/cube.obj"));
  fs::copy_file(scene, dir.file("scene/speed.svg"));
  EXPECT_EQ(voxfall("plot '" + dir.file("run.csv") + "' --scene '" + dir.file("scene/speed.svg") +
                    "' -o '" + dir.file("scene") + "'"),
            1);
  EXPECT_FALSE(fs::exists(dir.file("scene/energy.csv")));
  // Into another folder the same plot is written, and written again over its earlier files.
  EXPECT_EQ(voxfall("plot '" + dir.file("energy.csv") + "' -o '" + dir.file("plots") + "'"), 0);
  EXPECT_EQ(voxfall("plot '" + dir.file("energy.csv") + "' -o '" + dir.file("plots") + "'"), 0);
  EXPECT_TRUE(fs::exists(dir.file("plots/bodies.csv")));
}

}  // namespace
}  // namespace vf
