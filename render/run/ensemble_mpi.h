// The processes of an ensemble run: one, or the ranks of an `mpirun` launch when voxfall was
// built with MPI (render/run/ensemble_mpi.cpp is the only MPI include, and the only file
// compiled with VOXFALL_WITH_MPI). MPI is started only by the ensemble command, and only when
// the process was launched by mpirun or srun; every other voxfall invocation never touches it.
#pragma once

#include <functional>
#include <string>

namespace vf {

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
  // Rank 0's bytes on every rank (collective).
  void broadcast(std::string& bytes);
  // On a rank other than 0: one message (a realisation's result) to rank 0, as it completes.
  void send(const std::string& bytes);
  // On a rank other than 0: no more messages.
  void sendDone();
  // On rank 0: hands every message that has arrived to `take`, in the order each rank sent
  // them; with `untilDone`, waits until every other rank has called sendDone().
  void receive(bool untilDone, const std::function<void(const std::string&)>& take);

 private:
  int rank_ = 0;
  int size_ = 1;
  int done_ = 0;  // rank 0: ranks that said they are done
  bool started_ = false;
};

// True when this voxfall was built with MPI.
bool builtWithMpi();

}  // namespace vf
