#pragma once
// The ranks of one MPI job as `ltca tolerance` and `ltca optimise` use them; a header of its own so
// that the MPI module (tolerance_mpi.cpp, ltca_mpi.so) needs nothing else of ltca.

#include <string>
#include <vector>

#include "ltca/analysis/sample_ranks.hpp"

namespace ltca::cli {

/// The ranks of one MPI job, behind an interface so that MPI stays out of every header
/// (tolerance_mpi.cpp, the module ltca_mpi.so, implements it when MPI is found). A tolerance
/// study distributes its samples over them (analysis::SampleRanks: rank, size, Gather).
class SampleFarm : public analysis::SampleRanks {
 public:
  /// Every rank passes its bytes and gets every rank's bytes in rank order (ltca optimise: the
  /// ranks run one search in lockstep and share the work that divides).
  virtual std::vector<std::string> AllGather(const std::string& mine) = 0;
  /// Ends every rank of the job with this exit code (MPI_Abort): a rank that fails must not leave
  /// the others waiting in a collective.
  [[noreturn]] virtual void Abort(int code) = 0;
};

}  // namespace ltca::cli
