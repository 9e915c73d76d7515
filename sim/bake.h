// A run saved to a file: simulate once, render many. The bake holds every
// body's state after every step of the scene's step sequence, and what drawing needs (the
// shapes' mesh files, scales and colours, each body's colour and mass constants, the ground,
// the terrain file, the camera and the output settings), so `voxfall render BAKE` and
// `voxfall export BAKE` draw it without simulating. The file format is in docs/output-formats.md
// ("Bake files"). Only bake_write.cpp and bake_read.cpp include the JSON library.
#pragma once

#include <cstdint>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "sim/frame_interp.h"
#include "sim/recorder.h"
#include "sim/scene/scene.h"
#include "sim/world.h"

namespace vf {

// Per body: what drawing and free motion between steps need.
struct BakeBody {
  int shape = 0;  // index into Bake::scene.shapes
  Color color{0.8f, 0.8f, 0.8f};
  bool isStatic = false;
  double invMass = 0;                  // 1/kg; 0 for a static body
  Mat3 inertiaBodyInv = Mat3::Zero();  // body frame, 1/(kg m^2); zero for a static body
};

// The state of every body right after one step (the first record: before any step).
using BakeRecord = StepState;

struct Bake {
  // The scene's drawing and timing data: path, name, duration, fps, gravity, ground plane,
  // terrain path, shapes (mesh path, scale, density, level, colour), camera, output. Its
  // bodies and emitters are empty: the bodies are below.
  SceneSpec scene;
  std::vector<BakeBody> bodies;
  std::vector<BakeRecord> records;  // in time order
  // The run that made the bake (checksum, steps, ...). Absent (null in the file) in a subset of
  // an ensemble (ensembleBake): each body is a realisation that was stepped alone, so there is
  // no run to summarise.
  std::optional<RunSummary> summary;

  // Every body's state and active flag at time t, exactly as the run that made the bake
  // sampled it (Recorder): from the last record at or before t (within the world's 1e-9 s) and
  // the next one (sampleSteps); past the last record, the last record.
  std::vector<BodyState> statesAt(double t, std::vector<char>& active) const;
};

// Per shape of bake.scene.shapes, the mesh in the body frame exactly as the simulation had it
// (Shape::mesh: scaled, centre of mass at the origin) with name and mass properties; no sphere
// tree (drawing and export only). Mesh files are read once each; errors name the file.
std::vector<std::shared_ptr<const Shape>> bakeShapes(const Bake& bake);

// The bake header of a built scene (no records yet, summary empty).
Bake bakeHeader(const SceneSpec& spec, const BuiltScene& built);
// Appends the world's current time and states as a record.
void addBakeRecord(Bake& bake, const World& world);
// Writes the bake (format in docs/output-formats.md); `bakePath` is where it will live, so mesh and
// terrain paths are stored relative to its folder. Throws InputError on I/O failure.
void writeBake(std::FILE* out, const std::string& bakePath, const Bake& bake);
// True when the file starts with the bake signature.
bool isBakeFile(const std::string& path);
// Reads a bake; errors (not a bake, a bad header, a short body) name the file.
Bake readBake(const std::string& path);

}  // namespace vf
