// The ensemble journal (see ensemble_journal.h).
#include "sim/ensemble/ensemble_journal.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <sstream>

#include "sim/core/error.h"
#include "sim/core/hash.h"

namespace vf {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

namespace {

constexpr const char* kSignature = "VOXFALL-JOURNAL 1";
// Records hold the rock's tree impacts; a journal of another version holds other records and is
// refused (checkVersion) rather than read as zero hits, which a run through a forest did not have.
constexpr int kVersion = 3;
constexpr std::uint32_t kRecordMagic = 0x524a4656;  // "VFJR" little-endian
constexpr std::uint32_t kKindRealisation = 1;
constexpr std::uint32_t kKindRuns = 2;
constexpr std::size_t kHeadBytes = 16, kTailBytes = 8;

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, std::string("cannot read: ") + std::strerror(errno));
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The hash of bytes: their length, then 8-byte words (the last padded with zeros).
std::uint64_t bytesHash(const char* data, std::size_t size) {
  Hasher h;
  h.add(static_cast<std::uint64_t>(size));
  for (std::size_t at = 0; at < size; at += 8) {
    std::uint64_t word = 0;
    std::memcpy(&word, data + at, std::min<std::size_t>(8, size - at));
    h.add(word);
  }
  return h.value();
}

std::string hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

template <typename T>
Json optionalJson(const std::optional<T>& v) {
  return v ? Json(*v) : Json();
}

Json optionalText(const std::string& v) { return v.empty() ? Json() : Json(v); }

Json headerJson(const JournalHeader& h) {
  Json j;
  j["format"] = "voxfall-ensemble-journal";
  j["version"] = kVersion;
  j["voxfall"] = h.version;
  j["scene"] = {{"name", h.sceneName}, {"path", h.scenePath}, {"given", h.sceneGiven}};
  Json inputs = Json::array();
  for (const JournalInput& in : h.inputs) inputs.push_back({{"path", in.path}, {"hash", in.hash}});
  j["inputs"] = inputs;
  j["seed"] = h.seed;
  const SceneOverrides& o = h.overrides;
  j["options"] = {{"level", optionalJson(o.level)},
                  {"step", optionalText(o.step)},
                  {"collider", optionalText(o.collider)},
                  {"max_steps", optionalJson(o.maxSteps)},
                  {"max_speed", optionalJson(o.maxSpeed)},
                  {"repair", o.repair},
                  {"paths", h.paths}};
  j["shard"] = optionalText(h.shard);
  return j;
}

template <typename T>
std::optional<T> optionalFrom(const Json& j) {
  return j.is_null() ? std::nullopt : std::optional<T>(j.get<T>());
}

std::string textFrom(const Json& j) { return j.is_null() ? "" : j.get<std::string>(); }

JournalHeader headerFrom(const Json& j) {
  if (j.at("version").get<int>() != kVersion)
    throw std::runtime_error("version " + j.at("version").dump() + " is not supported");
  JournalHeader h;
  h.version = j.at("voxfall").get<std::string>();
  h.sceneName = j.at("scene").at("name").get<std::string>();
  h.scenePath = j.at("scene").at("path").get<std::string>();
  h.sceneGiven = j.at("scene").at("given").get<std::string>();
  for (const Json& in : j.at("inputs"))
    h.inputs.push_back({in.at("path").get<std::string>(), in.at("hash").get<std::string>()});
  h.seed = j.at("seed").get<std::uint64_t>();
  const Json& o = j.at("options");
  h.overrides.level = optionalFrom<int>(o.at("level"));
  h.overrides.step = textFrom(o.at("step"));
  h.overrides.collider = textFrom(o.at("collider"));
  h.overrides.maxSteps = optionalFrom<std::uint64_t>(o.at("max_steps"));
  h.overrides.maxSpeed = optionalFrom<double>(o.at("max_speed"));
  h.overrides.repair = o.at("repair").get<bool>();
  h.paths = o.at("paths").get<bool>();
  h.shard = textFrom(j.at("shard"));
  return h;
}

// An option's value as a reader would say it: the value, or "the scene's" when not given.
std::string said(const Json& v) {
  if (v.is_null()) return "none (the scene's)";
  if (v.is_boolean()) return v.get<bool>() ? "on" : "off";
  return v.is_string() ? v.get<std::string>() : v.dump();
}

std::string differs(const std::string& what, const std::string& journal, const std::string& run) {
  return what + ": the journal's run has " + journal + ", this run " + run;
}

std::string inputDifference(const JournalHeader& journal, const JournalHeader& run) {
  if (journal.inputs.size() != run.inputs.size())
    return "the scene reads " + std::to_string(run.inputs.size()) + " files, the journal's run " +
           std::to_string(journal.inputs.size()) + " (the scene file has changed)";
  for (std::size_t k = 0; k < run.inputs.size(); ++k)
    if (journal.inputs[k].hash != run.inputs[k].hash)
      return run.inputs[k].path + " has changed since the journal was written (its bytes differ)";
  return "";
}

}  // namespace

JournalHeader makeJournalHeader(const SceneSpec& spec, const std::string& sceneFile,
                                const std::string& version, std::uint64_t seed,
                                const SceneOverrides& overrides, bool paths,
                                const std::string& shard) {
  JournalHeader h;
  h.version = version;
  h.sceneName = spec.name;
  h.scenePath = fs::absolute(sceneFile).lexically_normal().string();
  h.sceneGiven = sceneFile;
  std::vector<std::string> files{sceneFile};
  // A generated rock reads no file: the scene file holds all of it.
  for (const ShapeSpec& s : spec.shapes)
    if (!s.meshPath.empty()) files.push_back(s.meshPath);
  if (!spec.terrainPath.empty()) files.push_back(spec.terrainPath);
  if (!spec.groundClassesPath.empty()) files.push_back(spec.groundClassesPath);
  if (spec.ensemble)
    for (const ReleaseSpec& r : spec.ensemble->releases)
      if (!r.path.empty()) files.push_back(r.path);
  for (const std::string& f : files) {
    const std::string bytes = readBytes(f);
    h.inputs.push_back({f, hex(bytesHash(bytes.data(), bytes.size()))});
  }
  h.seed = seed;
  h.overrides = overrides;
  h.overrides.threads.reset();  // not a change of the run
  h.paths = paths;
  h.shard = shard;
  return h;
}

std::string journalDifference(const JournalHeader& journal, const JournalHeader& run,
                              bool compareShard) {
  if (journal.version != run.version)
    return differs("the voxfall version", journal.version, run.version);
  if (journal.sceneName != run.sceneName)
    return differs("the scene", "'" + journal.sceneName + "'", "'" + run.sceneName + "'");
  if (std::string d = inputDifference(journal, run); !d.empty()) return d;
  if (journal.seed != run.seed)
    return differs("--seed", std::to_string(journal.seed), std::to_string(run.seed));
  const Json a = headerJson(journal).at("options"), b = headerJson(run).at("options");
  for (const auto& [key, value] : a.items())
    if (value != b.at(key)) {
      std::string option = "--" + key;
      for (char& c : option)
        if (c == '_') c = '-';
      return differs(option, said(value), said(b.at(key)));
    }
  if (compareShard && journal.shard != run.shard)
    return differs("--shard", journal.shard.empty() ? "none" : journal.shard,
                   run.shard.empty() ? "none" : run.shard);
  return "";
}

// --- reading ---------------------------------------------------------------------------------

namespace {

// A journal of another format version cannot be continued or merged: its records hold other
// fields. Left to headerFrom when the header has no integer version (a damaged header).
void checkVersion(const std::string& path, const Json& header) {
  const auto v = header.find("version");
  if (v == header.end() || !v->is_number_integer() || v->get<int>() == kVersion) return;
  const int version = v->get<int>();
  throw InputError(path, "journal version " + std::to_string(version) + " was written by " +
                             (version < kVersion ? "an older" : "a newer") +
                             " voxfall (this one reads version " + std::to_string(kVersion) +
                             "); it cannot be resumed or merged: run the ensemble again");
}

// The header lines; `pos` is left at the first record.
JournalHeader readHeader(const std::string& path, const std::string& bytes, std::size_t& pos) {
  const std::size_t first = bytes.find('\n');
  if (first == std::string::npos || bytes.compare(0, first, kSignature) != 0)
    throw InputError(path, std::string("not a voxfall ensemble journal (its first line is not '") +
                               kSignature + "')");
  const std::size_t second = bytes.find('\n', first + 1);
  if (second == std::string::npos)
    throw InputError(path,
                     "the journal's header is cut short (the run was killed as it started;"
                     " remove the file and run again)");
  Json header;
  try {
    pos = second + 1;
    header = Json::parse(bytes.substr(first + 1, second - first - 1));
  } catch (const std::exception& e) {
    throw InputError(path + ":2", std::string("damaged journal header: ") + e.what());
  }
  checkVersion(path, header);
  try {
    return headerFrom(header);
  } catch (const std::exception& e) {
    throw InputError(path + ":2", std::string("damaged journal header: ") + e.what());
  }
}

std::uint64_t recordChecksum(const char* record, std::size_t bytes) {
  return bytesHash(record, bytes);
}

// The record at `pos`: its kind and payload, or false when it is cut short or damaged.
bool readRecord(const std::string& bytes, std::size_t pos, std::uint32_t& kind,
                std::string& payload, std::size_t& end) {
  if (bytes.size() - pos < kHeadBytes) return false;
  std::uint32_t magic;
  std::uint64_t length;
  std::memcpy(&magic, bytes.data() + pos, 4);
  std::memcpy(&kind, bytes.data() + pos + 4, 4);
  std::memcpy(&length, bytes.data() + pos + 8, 8);
  if (magic != kRecordMagic || length > bytes.size() - pos - kHeadBytes - kTailBytes ||
      bytes.size() - pos < kHeadBytes + kTailBytes)
    return false;
  std::uint64_t sum;
  std::memcpy(&sum, bytes.data() + pos + kHeadBytes + length, 8);
  if (sum != recordChecksum(bytes.data() + pos, kHeadBytes + length)) return false;
  payload = bytes.substr(pos + kHeadBytes, length);
  end = pos + kHeadBytes + length + kTailBytes;
  return true;
}

void takeRecord(JournalContents& j, std::uint32_t kind, const std::string& payload) {
  std::size_t at = 0;
  if (kind == kKindRealisation) {
    j.results.push_back(deserializeResult(payload, at));
  } else if (kind == kKindRuns && payload.size() == 8) {
    std::memcpy(&j.runsRequested, payload.data(), 8);
  }
}

}  // namespace

JournalContents readJournal(const std::string& path) {
  const std::string bytes = readBytes(path);
  JournalContents j;
  std::size_t pos = 0;
  j.header = readHeader(path, bytes, pos);
  std::uint32_t kind = 0;
  std::string payload;
  for (std::size_t end = pos; pos < bytes.size(); pos = end) {
    if (!readRecord(bytes, pos, kind, payload, end)) {
      // Only the last record can be cut short (records are appended one at a time): a bad
      // record with a whole record's worth of bytes after it is damage, not a kill.
      std::uint64_t length = 0;
      if (bytes.size() - pos >= kHeadBytes) std::memcpy(&length, bytes.data() + pos + 8, 8);
      if (bytes.size() - pos >= kHeadBytes + kTailBytes &&
          length < bytes.size() - pos - kHeadBytes - kTailBytes)
        throw InputError(path, "damaged at byte " + std::to_string(pos) +
                                   " (a record's checksum does not match), with records after "
                                   "it; it cannot be continued");
      j.tornBytes = bytes.size() - pos;
      break;
    }
    takeRecord(j, kind, payload);
  }
  j.goodBytes = pos;
  return j;
}

// --- writing ---------------------------------------------------------------------------------

namespace {

void writeAll(int fd, const std::string& bytes, const std::string& path) {
  for (std::size_t at = 0; at < bytes.size();) {
    const ssize_t n = ::write(fd, bytes.data() + at, bytes.size() - at);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      throw InputError(path, std::string("cannot write the journal: ") + std::strerror(errno));
    at += static_cast<std::size_t>(n);
  }
}

}  // namespace

JournalWriter::JournalWriter(const std::string& path, const JournalHeader& header) : path_(path) {
  const fs::path target(path);
  std::string name = ".";
  name.append(target.stem().string())
      .append(".partial-")
      .append(std::to_string(static_cast<long>(::getpid())))
      .append("-j")
      .append(target.extension().string());
  const fs::path temp = target.parent_path() / name;
  const std::string text = std::string(kSignature) + "\n" + headerJson(header).dump() + "\n";
  fd_ = ::open(temp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd_ < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  try {
    writeAll(fd_, text, path);
    if (::fdatasync(fd_) != 0 || std::rename(temp.c_str(), path.c_str()) != 0)
      throw InputError(path, std::string("cannot write the journal: ") + std::strerror(errno));
  } catch (...) {
    ::close(fd_);
    fd_ = -1;
    std::remove(temp.c_str());
    throw;
  }
  size_ = text.size();
}

JournalWriter::JournalWriter(const std::string& path, std::uint64_t goodBytes)
    : path_(path), size_(goodBytes) {
  fd_ = ::open(path.c_str(), O_WRONLY | O_CLOEXEC);
  if (fd_ < 0) throw InputError(path, std::string("cannot write: ") + std::strerror(errno));
  if (::ftruncate(fd_, static_cast<off_t>(goodBytes)) != 0 ||
      ::lseek(fd_, static_cast<off_t>(goodBytes), SEEK_SET) < 0) {
    const int err = errno;
    ::close(fd_);
    throw InputError(path, std::string("cannot continue the journal: ") + std::strerror(err));
  }
}

JournalWriter::~JournalWriter() {
  if (fd_ < 0) return;
  if (!syncEach_) ::fdatasync(fd_);
  ::close(fd_);
}

void JournalWriter::append(std::uint32_t kind, const std::string& payload) {
  std::string record(kHeadBytes, '\0');
  const std::uint64_t length = payload.size();
  std::memcpy(record.data(), &kRecordMagic, 4);
  std::memcpy(record.data() + 4, &kind, 4);
  std::memcpy(record.data() + 8, &length, 8);
  record += payload;
  const std::uint64_t sum = recordChecksum(record.data(), record.size());
  record.append(reinterpret_cast<const char*>(&sum), 8);
  try {
    writeAll(fd_, record, path_);
    if (syncEach_ && ::fdatasync(fd_) != 0)
      throw InputError(path_, std::string("cannot write the journal: ") + std::strerror(errno));
  } catch (...) {
    // A full disk: the journal keeps its whole records only.
    if (::ftruncate(fd_, static_cast<off_t>(size_)) == 0)
      ::lseek(fd_, static_cast<off_t>(size_), SEEK_SET);
    throw;
  }
  size_ += record.size();
}

void JournalWriter::addRuns(std::int64_t runs) {
  append(kKindRuns, std::string(reinterpret_cast<const char*>(&runs), sizeof runs));
}

void JournalWriter::add(const RealisationResult& result) {
  std::string payload;
  serializeResult(result, payload);
  append(kKindRealisation, payload);
}

void JournalWriter::flush() {
  if (::fdatasync(fd_) != 0)
    throw InputError(path_, std::string("cannot write the journal: ") + std::strerror(errno));
}

}  // namespace vf
