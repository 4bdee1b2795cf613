#pragma once
// The processes of one run (docs/guide/SCALE_OUT.md): under `mpirun -n R` (or `srun`) in a build
// with MPI, R ranks of MPI_COMM_WORLD; otherwise one rank and no MPI at all, so a build
// without MPI, or a run started without a launcher, behaves exactly as a single process.
// This and Ranks.cpp are the only place that knows MPI exists (the VKRECON_HAVE_MPI seam).

#include <cstddef>
#include <string>
#include <vector>

namespace vkr::recon {

class Ranks {
 public:
  // The run's ranks. The first call joins the MPI job when the process was started by an
  // MPI launcher (Open MPI's or PMIx/PMI environment variables); MPI_Finalize runs at exit.
  static Ranks& World();
  // One rank that never touches MPI: a scene of `vkrecon run LIST` runs in one process
  // while the job's ranks run other scenes (ReconstructList, SceneList.h).
  static const Ranks& One();
  // Whether this binary was built with MPI (`vkrecon run --help` and the tests ask).
  static bool Built();

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Rank among those on this node (MPI_COMM_TYPE_SHARED): picks the node's GPU.
  int local_rank() const { return local_rank_; }
  int local_size() const { return local_size_; }
  bool distributed() const { return size_ > 1; }

  // Every rank contributes counts[rank()] values (offsets[r] where rank r's go in `all`);
  // every rank receives all of them. MPI_Allgatherv.
  void AllGather(const double* mine, const std::vector<int>& counts, const std::vector<int>& offsets,
                 double* all) const;
  // Rank `root`'s bytes (its `text`, any length) to every rank. MPI_Bcast, twice.
  void Broadcast(std::string* text, int root = 0) const;
  // Rank `root`'s n bytes to every rank: one MPI_Bcast (the per-frame decisions).
  void Broadcast(unsigned char* bytes, int n, int root = 0) const;
  // Rank 0 gets every rank's `values` one after the other (each rank the same count);
  // the others get an empty vector. MPI_Gather.
  std::vector<double> GatherToRoot(const std::vector<double>& values) const;
  // Ends every rank of the job with `status` (MPI_Abort); in one process, std::exit.
  [[noreturn]] void Abort(int status) const;

  ~Ranks();
  Ranks(const Ranks&) = delete;
  Ranks& operator=(const Ranks&) = delete;

 private:
  explicit Ranks(bool join);
  int rank_ = 0, size_ = 1, local_rank_ = 0, local_size_ = 1;
  bool joined_ = false;  // MPI_Init was called here
};

}  // namespace vkr::recon
