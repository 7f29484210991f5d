#pragma once
#include <ostream>
#include <string>

#include "ltca/contact/unloaded.hpp"
#include "ltca/solvers/deck.hpp"

namespace ltca::cli {

struct BacklashOptions {
  std::string json_path;
  std::string csv_path;
  contact::ContactKinematics kinematics = contact::ContactKinematics::kExact;
};

/// `ltca backlash`: unloaded TCA over the deck's sweep (Liu eq. 17).
void RunBacklash(const solvers::Deck& deck, const BacklashOptions& options, std::ostream& out);

struct MeshOptions {
  std::string json_path;
  double crank_deg = 0.0;
};

/// `ltca mesh`: the mesh state table at one crank angle.
void RunMesh(const solvers::Deck& deck, const MeshOptions& options, std::ostream& out);

contact::ContactKinematics ParseKinematics(const std::string& text);

}  // namespace ltca::cli
