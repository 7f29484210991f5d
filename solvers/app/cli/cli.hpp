#pragma once
// The `ltca` command line, as a function so that tests run it in-process.
#include <ostream>
#include <string>
#include <vector>

namespace ltca::cli {

/// Runs `ltca` with the given arguments (without the program name). Returns the exit code:
/// 0 on success, non-zero on bad input (the message goes to err) or a failed command.
int Run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

/// Process set-up of the executables (not of Run, which tests call in-process): glibc returns
/// every freed block above 128 KB to the kernel, and a sweep of the slice model (800 points of
/// 150 bytes per position) then pays page faults for its per-position buffers at every
/// position (40 % of its time). Raising the mmap and trim thresholds keeps them in the heap.
void ConfigureProcess();

}  // namespace ltca::cli
