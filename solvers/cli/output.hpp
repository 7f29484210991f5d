#pragma once
// Writing outputs: "-" means standard output.
#include <functional>
#include <ostream>
#include <string>

namespace ltca::cli {

/// Calls write with a stream to the file (or to out for "-"); throws std::invalid_argument
/// naming the file when it cannot be opened.
void WriteTo(const std::string& path, std::ostream& out,
             const std::function<void(std::ostream&)>& write);

}  // namespace ltca::cli
