// The processes of an ensemble run: one, or the ranks of an `mpirun` launch when voxfall was
// built with MPI (render/cli/ensemble_mpi.cpp is the only MPI include, and the only file
// compiled with VOXFALL_WITH_MPI). MPI is started only by the ensemble command, and only when
// the process was launched by mpirun or srun; every other voxfall invocation never touches it.
#pragma once

#include <string>
#include <vector>

namespace vf::cli {

class MpiSession {
 public:
  MpiSession();   // MPI_Init when built with MPI and launched by mpirun/srun
  ~MpiSession();  // MPI_Finalize
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Collective: true on every rank when `ok` is true on every rank.
  bool allOk(bool ok);
  // Collective: every rank's `bytes`, in rank order, on rank 0; empty on the other ranks.
  std::vector<std::string> gather(const std::string& bytes);

 private:
  int rank_ = 0;
  int size_ = 1;
  bool started_ = false;
};

// True when this voxfall was built with MPI.
bool builtWithMpi();

}  // namespace vf::cli
