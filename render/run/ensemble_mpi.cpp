// MPI for `voxfall ensemble` (see ensemble_mpi.h). Every rank sends each realisation to rank 0
// as it completes, and rank 0 appends it to the journal at once (sim/ensemble/
// ensemble_journal.h), so a rank that is killed loses only the realisations it had in flight;
// the command then reduces the journal in index order, so the outputs are the bytes one process
// would write. Only the thread that called MPI_Init calls MPI (MPI_THREAD_FUNNELED): the
// worker threads hand their results to it.
#include "render/run/ensemble_mpi.h"

#include <cstdlib>
#include <string>

#ifdef VOXFALL_WITH_MPI
#include <mpi.h>
#endif

#include "sim/core/error.h"

namespace vf {

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
  int provided = 0;
  if (!initialised &&
      MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
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

namespace {
constexpr int kTagResult = 1, kTagDone = 2;

int messageSize(std::size_t bytes) {
  if (bytes > static_cast<std::size_t>(1) << 30)
    throw InputError("", "a realisation's result is over 1 GiB, too large to send over MPI");
  return static_cast<int>(bytes);
}
}  // namespace

void MpiSession::broadcast(std::string& bytes) {
  if (!started_) return;
  long long size = static_cast<long long>(bytes.size());
  MPI_Bcast(&size, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD);
  bytes.resize(static_cast<std::size_t>(size));
  MPI_Bcast(bytes.data(), messageSize(bytes.size()), MPI_BYTE, 0, MPI_COMM_WORLD);
}

void MpiSession::send(const std::string& bytes) {
  if (!started_) return;
  MPI_Send(bytes.data(), messageSize(bytes.size()), MPI_BYTE, 0, kTagResult, MPI_COMM_WORLD);
}

void MpiSession::sendDone() {
  if (started_) MPI_Send(nullptr, 0, MPI_BYTE, 0, kTagDone, MPI_COMM_WORLD);
}

void MpiSession::receive(bool untilDone, const std::function<void(const std::string&)>& take) {
  if (!started_ || rank_ != 0) return;
  for (;;) {
    MPI_Status status;
    int waiting = 0;
    if (untilDone && done_ < size_ - 1) {
      MPI_Probe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &status);
      waiting = 1;
    } else {
      MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &waiting, &status);
    }
    if (!waiting) return;
    int count = 0;
    MPI_Get_count(&status, MPI_BYTE, &count);
    std::string bytes(static_cast<std::size_t>(count), '\0');
    MPI_Recv(bytes.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, MPI_COMM_WORLD,
             MPI_STATUS_IGNORE);
    if (status.MPI_TAG == kTagDone)
      ++done_;
    else
      take(bytes);
  }
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
void MpiSession::broadcast(std::string&) {}
void MpiSession::send(const std::string&) {}
void MpiSession::sendDone() {}
void MpiSession::receive(bool, const std::function<void(const std::string&)>&) {}

#endif

}  // namespace vf
