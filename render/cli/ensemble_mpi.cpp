// MPI for `voxfall ensemble` (see ensemble_mpi.h). Rank 0 gathers every rank's serialised
// realisations (sizes first, then the bytes, received rank by rank) and the command reduces
// them in index order, so the outputs are the bytes one process would write.
#include "render/cli/ensemble_mpi.h"

#include <algorithm>
#include <cstdlib>
#include <string>

#ifdef VOXFALL_WITH_MPI
#include <mpi.h>
#endif

#include "sim/core/error.h"

namespace vf::cli {

#ifdef VOXFALL_WITH_MPI

namespace {
// mpirun (OpenMPI, MPICH) and srun set one of these in every process they start.
bool launchedByMpi() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK", "MPI_LOCALNRANKS"})
    if (std::getenv(name) != nullptr) return true;
  return false;
}
}  // namespace

bool builtWithMpi() { return true; }

MpiSession::MpiSession() {
  if (!launchedByMpi()) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised && MPI_Init(nullptr, nullptr) != MPI_SUCCESS)
    throw InputError("", "MPI_Init failed");
  started_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() {
  if (started_) MPI_Finalize();
}

bool MpiSession::allOk(bool ok) {
  if (!started_) return ok;
  int mine = ok ? 1 : 0, all = 0;
  MPI_Allreduce(&mine, &all, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
  return all == 1;
}

std::vector<std::string> MpiSession::gather(const std::string& bytes) {
  if (!started_) return {bytes};
  // Sizes as 64-bit counts, then the bytes in chunks that fit MPI's int counts.
  const long long mine = static_cast<long long>(bytes.size());
  std::vector<long long> sizes(static_cast<std::size_t>(size_));
  MPI_Gather(&mine, 1, MPI_LONG_LONG, sizes.data(), 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  std::vector<std::string> out;
  if (rank_ == 0) {
    out.resize(static_cast<std::size_t>(size_));
    out[0] = bytes;
    for (int r = 1; r < size_; ++r) {
      std::string& s = out[static_cast<std::size_t>(r)];
      s.resize(static_cast<std::size_t>(sizes[static_cast<std::size_t>(r)]));
      for (std::size_t at = 0; at < s.size();) {
        const int chunk = static_cast<int>(std::min<std::size_t>(s.size() - at, 1u << 30));
        MPI_Recv(s.data() + at, chunk, MPI_BYTE, r, 0, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
        at += static_cast<std::size_t>(chunk);
      }
    }
  } else {
    for (std::size_t at = 0; at < bytes.size();) {
      const int chunk = static_cast<int>(std::min<std::size_t>(bytes.size() - at, 1u << 30));
      MPI_Send(bytes.data() + at, chunk, MPI_BYTE, 0, 0, MPI_COMM_WORLD);
      at += static_cast<std::size_t>(chunk);
    }
  }
  return out;
}

#else  // built without MPI: one process

bool builtWithMpi() { return false; }
MpiSession::MpiSession() {
  // Started as one of several processes by mpirun or srun: each would run the whole ensemble
  // and write the same files at once. Say so instead.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"}) {
    const char* v = std::getenv(name);
    if (v != nullptr && std::atoi(v) > 1)
      throw InputError("", std::string("started as one of ") + v +
                               " MPI processes, but this voxfall was built without MPI (configure "
                               "with MPI installed, or run one process with --jobs)");
  }
}
MpiSession::~MpiSession() = default;
bool MpiSession::allOk(bool ok) { return ok; }
std::vector<std::string> MpiSession::gather(const std::string& bytes) { return {bytes}; }

#endif

}  // namespace vf::cli
