#pragma once
// Whether two compressed sparse matrices are the same bit for bit (shape, structure and values):
// how the CHOLMOD kernels tell that a coupling is the one they factored (private to solvers/).
#include <algorithm>
#include <cstddef>

#include <Eigen/SparseCore>

namespace ltca::solvers {

/// False when either is not compressed (its arrays then hold gaps).
inline bool IdenticalSparse(const Eigen::SparseMatrix<double>& a, const Eigen::SparseMatrix<double>& b) {
  if (a.rows() != b.rows() || a.cols() != b.cols() || a.nonZeros() != b.nonZeros()) return false;
  if (!a.isCompressed() || !b.isCompressed()) return false;
  const auto n = static_cast<std::size_t>(a.outerSize());
  return std::equal(a.outerIndexPtr(), a.outerIndexPtr() + n + 1, b.outerIndexPtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr()) &&
         std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr());
}

}  // namespace ltca::solvers
