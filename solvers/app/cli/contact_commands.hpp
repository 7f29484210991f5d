#pragma once
#include <optional>
#include <ostream>
#include <string>

#include "ltca/contact/unloaded.hpp"
#include "ltca/app/deck.hpp"
#include "output.hpp"

namespace ltca::cli {

struct BacklashOptions {
  std::string json_path;
  std::string csv_path;
  std::string svg_path;  ///< backlash and the rotations to first contact over crank angle
  /// --kinematics; empty: the deck's [solver] kinematics (the rule of every command).
  std::optional<contact::ContactKinematics> kinematics;
};

/// `ltca backlash`: unloaded TCA over the deck's sweep (Liu eq. 17). Returns the exit code: 1 when
/// a position has no first contact on a flank (its figures null, the summary over the others).
int RunBacklash(const app::Deck& deck, const BacklashOptions& options, const Streams& streams);

struct MeshOptions {
  std::string json_path;
  std::string svg_path;  ///< the clearance and arm of every pin
  double crank_deg = 0.0;
};

/// `ltca mesh`: the mesh state table at one crank angle; rejects an interfering pair (std::invalid_argument).
void RunMesh(const app::Deck& deck, const MeshOptions& options, const Streams& streams);

}  // namespace ltca::cli
