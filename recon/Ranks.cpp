#include "recon/Ranks.h"

#include <cstdlib>
#include <stdexcept>

#if VKRECON_HAVE_MPI
#include <mpi.h>
#endif

namespace vkr::recon {
namespace {

#if VKRECON_HAVE_MPI
// Started by mpirun/mpiexec (Open MPI, MPICH/Hydra) or srun with PMI/PMIx. Without a
// launcher MPI is not touched: a singleton MPI_Init would work, but it costs start-up time
// and prints Open MPI's warnings for nothing.
bool UnderLauncher() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
    if (std::getenv(name)) return true;
  return false;
}

void Check(int code, const char* call) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string(call) + " failed");
}
#endif

}  // namespace

Ranks& Ranks::World() {
  static Ranks ranks(true);
  return ranks;
}

const Ranks& Ranks::One() {
  static const Ranks one(false);
  return one;
}

bool Ranks::Built() {
#if VKRECON_HAVE_MPI
  return true;
#else
  return false;
#endif
}

Ranks::Ranks([[maybe_unused]] bool join) {  // unused in a build without MPI
#if VKRECON_HAVE_MPI
  if (!join || !UnderLauncher()) return;
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    Check(MPI_Init(nullptr, nullptr), "MPI_Init");
    joined_ = true;
  }
  // A rank that fails ends the job (the default, said here because the design relies on
  // it: no rank may wait forever on one that died; docs/guide/SCALE_OUT.md, "Faults").
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_ARE_FATAL);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
  MPI_Comm node;
  Check(MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, rank_, MPI_INFO_NULL, &node),
        "MPI_Comm_split_type");
  MPI_Comm_rank(node, &local_rank_);
  MPI_Comm_size(node, &local_size_);
  MPI_Comm_free(&node);
#endif
}

Ranks::~Ranks() {
#if VKRECON_HAVE_MPI
  int finalised = 0;
  MPI_Finalized(&finalised);
  if (joined_ && !finalised) MPI_Finalize();
#endif
}

void Ranks::AllGather(const double* mine, const std::vector<int>& counts, const std::vector<int>& offsets,
                      double* all) const {
  if (int(counts.size()) != size_ || int(offsets.size()) != size_)
    throw std::logic_error("Ranks::AllGather: one count and offset per rank");
#if VKRECON_HAVE_MPI
  if (size_ > 1) {
    Check(MPI_Allgatherv(mine, counts[rank_], MPI_DOUBLE, all, counts.data(), offsets.data(), MPI_DOUBLE,
                         MPI_COMM_WORLD),
          "MPI_Allgatherv");
    return;
  }
#endif
  for (int i = 0; i < counts[0]; ++i) all[offsets[0] + i] = mine[i];
}

void Ranks::Broadcast(std::string* text, int root) const {
#if VKRECON_HAVE_MPI
  if (size_ == 1) return;
  unsigned long long length = text->size();
  Check(MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG_LONG, root, MPI_COMM_WORLD), "MPI_Bcast");
  text->resize(size_t(length));
  if (length > 0) Check(MPI_Bcast(text->data(), int(length), MPI_CHAR, root, MPI_COMM_WORLD), "MPI_Bcast");
#else
  (void)text;
  (void)root;
#endif
}

void Ranks::Broadcast(unsigned char* bytes, int n, int root) const {
#if VKRECON_HAVE_MPI
  if (size_ > 1) Check(MPI_Bcast(bytes, n, MPI_UNSIGNED_CHAR, root, MPI_COMM_WORLD), "MPI_Bcast");
#else
  (void)bytes;
  (void)n;
  (void)root;
#endif
}

std::vector<double> Ranks::GatherToRoot(const std::vector<double>& values) const {
#if VKRECON_HAVE_MPI
  if (size_ > 1) {
    std::vector<double> all(rank_ == 0 ? values.size() * size_t(size_) : 0);
    Check(MPI_Gather(values.data(), int(values.size()), MPI_DOUBLE, all.data(), int(values.size()), MPI_DOUBLE, 0,
                     MPI_COMM_WORLD),
          "MPI_Gather");
    return all;
  }
#endif
  return values;
}

void Ranks::Abort(int status) const {
#if VKRECON_HAVE_MPI
  if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, status);
#endif
  std::exit(status);
}

}  // namespace vkr::recon
