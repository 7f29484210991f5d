#include "output.hpp"

#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

namespace ltca::cli {

void WriteTo(const std::string& path, std::ostream& out,
             const std::function<void(std::ostream&)>& write) {
  if (path == "-") {
    write(out);
    return;
  }
  std::ofstream file(path);
  if (!file) throw std::invalid_argument(fmt::format("cannot write the file '{}'", path));
  write(file);
  if (!file) throw std::invalid_argument(fmt::format("writing the file '{}' failed", path));
}

}  // namespace ltca::cli
