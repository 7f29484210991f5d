#pragma once
// The command line run in-process, shared by the application-layer tests: its exit code and what it
// wrote to standard output and standard error (and, from helpers.hpp, the path of a deck in cases/).
#include <sstream>
#include <string>
#include <vector>

#include "helpers.hpp"
#include "cli.hpp"

namespace ltca::test {

struct Outcome {
  int code;
  std::string out, err;
};

inline Outcome RunCli(const std::vector<std::string>& args) {
  std::ostringstream out, err;
  const int code = ltca::cli::Run(args, out, err);
  return {code, out.str(), err.str()};
}

}  // namespace ltca::test
