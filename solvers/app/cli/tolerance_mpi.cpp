// The MPI sample farm of `ltca tolerance` and `ltca optimise`: the module ltca_mpi.so (built only
// when find_package(MPI) finds MPI), loaded by MakeSampleFarm (tolerance_command.cpp) only when the
// process was started by mpirun, so no other run maps MPI's libraries (issue 54; app/modules.hpp).
// `mpirun -np K ltca tolerance DECK` splits the samples by rank statically (each rank runs its
// block on its own threads) and gathers the samples on rank 0 with MPI_Gatherv, which alone
// writes the outputs. MPI is initialised only when this process was started by mpirun (OpenMPI's
// OMPI_COMM_WORLD_SIZE or PMIx's PMIX_RANK in the environment): a plain `ltca tolerance` stays one
// process and never touches MPI.
//
// Every call goes through the profiling names (PMPI_*, part of the MPI standard): Ipopt's
// sequential MUMPS (Debian's libdmumps_seq, libmumps_common_seq) exports dummy MPI_Init and
// MPI_Comm_rank of its own, and as it comes first in the symbol search order the plain names
// would bind to those dummies (MPI_Init would do nothing and MPI_Comm_size would then abort).
#include <cstdlib>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>
#include <mpi.h>

#include "sample_farm.hpp"

namespace ltca::cli {
namespace {

void Check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(fmt::format("MPI: {} failed (code {})", what, code));
}

class MpiFarm final : public SampleFarm {
 public:
  MpiFarm() {
    int initialised = 0;
    PMPI_Initialized(&initialised);
    if (!initialised) {
      Check(PMPI_Init(nullptr, nullptr), "MPI_Init");
      owner_ = true;
    }
    PMPI_Comm_rank(MPI_COMM_WORLD, &rank_);
    PMPI_Comm_size(MPI_COMM_WORLD, &size_);
  }
  ~MpiFarm() override {
    if (owner_) PMPI_Finalize();
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }
  std::vector<std::string> Gather(const std::string& mine) override {
    if (mine.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw std::runtime_error("MPI: a rank's samples exceed 2 GiB; use more ranks or fewer samples per run");
    }
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    Check(PMPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Gather");
    std::string all;
    if (rank_ == 0) {
      long long total = 0;
      for (int r = 0; r < size_; ++r) {
        offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
        total += counts[static_cast<std::size_t>(r)];
      }
      if (total > std::numeric_limits<int>::max()) throw std::runtime_error("MPI: the gathered samples exceed 2 GiB");
      all.resize(static_cast<std::size_t>(total));
    }
    Check(PMPI_Gatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, 0, MPI_COMM_WORLD),
          "MPI_Gatherv");
    std::vector<std::string> out;
    if (rank_ == 0) {
      for (int r = 0; r < size_; ++r) {
        out.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                                 static_cast<std::size_t>(counts[static_cast<std::size_t>(r)])));
      }
    }
    return out;
  }
  [[noreturn]] void Abort(int code) override {
    PMPI_Abort(MPI_COMM_WORLD, code);
    std::_Exit(code);  // MPI_Abort does not return; should it, this rank ends all the same
  }
  std::vector<std::string> AllGather(const std::string& mine) override {
    if (mine.size() > static_cast<std::size_t>(std::numeric_limits<int>::max())) {
      throw std::runtime_error("MPI: a rank's bytes exceed 2 GiB");
    }
    const int count = static_cast<int>(mine.size());
    std::vector<int> counts(static_cast<std::size_t>(size_)), offsets(static_cast<std::size_t>(size_));
    Check(PMPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, MPI_COMM_WORLD), "MPI_Allgather");
    long long total = 0;
    for (int r = 0; r < size_; ++r) {
      offsets[static_cast<std::size_t>(r)] = static_cast<int>(total);
      total += counts[static_cast<std::size_t>(r)];
      if (total > std::numeric_limits<int>::max()) throw std::runtime_error("MPI: the gathered bytes exceed 2 GiB");
    }
    std::string all(static_cast<std::size_t>(total), '\0');
    Check(PMPI_Allgatherv(mine.data(), count, MPI_BYTE, all.data(), counts.data(), offsets.data(), MPI_BYTE, MPI_COMM_WORLD),
          "MPI_Allgatherv");
    std::vector<std::string> out;
    for (int r = 0; r < size_; ++r) {
      out.push_back(all.substr(static_cast<std::size_t>(offsets[static_cast<std::size_t>(r)]),
                               static_cast<std::size_t>(counts[static_cast<std::size_t>(r)])));
    }
    return out;
  }

 private:
  int rank_ = 0, size_ = 1;
  bool owner_ = false;
};

}  // namespace
}  // namespace ltca::cli

/// The module's entry point: the job's farm, owned by the caller (MPI_Init here when nobody has).
extern "C" __attribute__((visibility("default"))) ltca::cli::SampleFarm* ltca_mpi_sample_farm() {
  return new ltca::cli::MpiFarm();
}
