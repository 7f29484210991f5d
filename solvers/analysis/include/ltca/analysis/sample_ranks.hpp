#pragma once
// The ranks of a distributed run, in a header of its own: the MPI module (ltca_mpi.so) implements it
// without the rest of the analysis layer.

#include <string>
#include <vector>

namespace ltca::analysis {

/// The ranks of a distributed run (e.g. the processes of an MPI job): each rank runs a static
/// block of the samples on its threads, and rank 0 gathers them.
class SampleRanks {
 public:
  virtual ~SampleRanks() = default;
  virtual int rank() const = 0;
  virtual int size() const = 0;
  /// Every rank passes its bytes; rank 0 gets every rank's bytes in rank order, the others none.
  virtual std::vector<std::string> Gather(const std::string& mine) = 0;
};

}  // namespace ltca::analysis
