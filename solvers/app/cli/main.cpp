#include <iostream>
#include <string>
#include <vector>

#include "cli.hpp"

int main(int argc, char** argv) {
  ltca::cli::ConfigureProcess();
  std::vector<std::string> args(argv + 1, argv + argc);
  return ltca::cli::Run(args, std::cout, std::cerr);
}
