#pragma once
// The `ltca` command line, as a function so that tests run it in-process.
#include <ostream>
#include <string>
#include <vector>

namespace ltca::cli {

/// Runs `ltca` with the given arguments (without the program name). Returns the exit code:
/// 0 on success, non-zero on bad input (the message goes to err) or a failed command.
int Run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace ltca::cli
