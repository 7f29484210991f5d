#pragma once
#include <ostream>
#include <string>

#include "output.hpp"

namespace ltca::cli {

struct ValidateOptions {
  std::string cases_dir;     ///< "" = the source tree's cases/
  std::string markdown_path; ///< write the generated tables
  std::string doc_path;      ///< replace the generated block of this document (docs/validation.md)
};

/// `ltca validate`: every checkable published number, with its verdict.
int RunValidate(const ValidateOptions& options, const Streams& streams);

}  // namespace ltca::cli
