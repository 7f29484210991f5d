// Built when find_package(MPI) finds no MPI: `ltca tolerance` runs in one process (threads only).
#include "tolerance_command.hpp"

namespace ltca::cli {

std::unique_ptr<SampleFarm> MakeSampleFarm() { return nullptr; }
std::string SampleFarmBuild() { return "none"; }

}  // namespace ltca::cli
