#include <iostream>
#include <string>
#include <vector>

#include "cli.hpp"
#include "output.hpp"

int main(int argc, char** argv) {
  ltca::cli::ConfigureProcess();
  ltca::cli::InstallInterruptCleanup();  // Ctrl-C leaves no temporary file behind
  std::vector<std::string> args(argv + 1, argv + argc);
  return ltca::cli::Run(args, std::cout, std::cerr);
}
