#pragma once
// The unloaded backlash of a stage's mesh (Liu 2021 eq. 17: theta_c1 - theta_c2, the rotations to
// first contact in and against the load direction), one rule for every figure that carries it:
// `ltca backlash`, the tolerance study's samples, the optimiser and the report.
// Two discs ([second_disc]) turn the output together, so the output stops at the first contact of
// either disc on each flank: theta_c1 is the smaller of the discs', theta_c2 the larger, and the
// stage's backlash is their difference (never one disc's alone).
#include <cstddef>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "ltca/analysis/stage.hpp"
#include "ltca/contact/unloaded.hpp"

namespace ltca::analysis {

/// The stage's unloaded contact at one crank.
struct BacklashPosition {
  /// The first disc's analysis, with theta_c1, theta_c2, backlash and the first pins of the stage
  /// (either disc's); clearance and clearance_at_c1 stay the first disc's.
  contact::UnloadedContact contact;
  int disc_c1 = 1, disc_c2 = 1;          ///< the disc (1 or 2) that touches first on each flank
  std::vector<double> second_clearance;  ///< two discs: the second disc's pin clearances, mm
  /// A preloaded position (contact.interference > 0) with [material]: the torque that unloads the
  /// coast flank (turning the load direction to theta_c2, where its last pin opens) and the drive
  /// flank (the other way, to theta_c1), N*mm, both >= 0: sum_i F_i(delta_i) L_i of the pins still
  /// pressed there, with the pins' own laws (no coupling). NaN otherwise.
  double unload_torque_nmm = std::numeric_limits<double>::quiet_NaN();
  double unload_torque_reverse_nmm = std::numeric_limits<double>::quiet_NaN();
  bool ok = false;                       ///< a pin closes on both flanks within the rotation window
  std::string failure;                   ///< why not
};

/// At one crank (rad), under `kinematics`.
BacklashPosition UnloadedBacklashAt(const Stage& stage, double crank, contact::ContactKinematics kinematics);

/// The sweep's summary, added position by position (`ltca backlash` streams its positions).
class BacklashSummary {
 public:
  /// `repeated_state`: the last position of a closed period (Stage::closed_period), which weighs
  /// once in the mean (its state is the first's).
  void Add(const BacklashPosition& p, bool repeated_state);
  /// Over the successful positions, rad; NaN when none succeeded.
  double mean() const;
  double pp() const;
  std::size_t positions() const { return positions_; }
  std::size_t succeeded() const { return succeeded_; }
  std::size_t failed() const { return positions_ - succeeded_; }
  const std::string& first_failure() const { return first_failure_; }  ///< "crank x deg: why"
  /// Successful positions whose flanks overlap (contact.interference > 0): a preloaded pair's.
  std::size_t preloaded() const { return preloaded_; }
  /// The largest interference over the successful positions, rad (0: none preloaded).
  double max_interference() const { return max_interference_; }
  /// The smallest torque that unloads a flank (either way) over the preloaded positions, N*mm;
  /// NaN when none was computed.
  double min_unload_torque() const { return min_unload_; }

 private:
  std::size_t preloaded_ = 0;
  double max_interference_ = 0.0;
  double min_unload_ = std::numeric_limits<double>::quiet_NaN();
  std::size_t positions_ = 0, succeeded_ = 0, in_mean_ = 0;
  double sum_ = 0.0, lo_ = std::numeric_limits<double>::infinity(), hi_ = -std::numeric_limits<double>::infinity();
  std::string first_failure_;
};

/// The unloaded backlash of a stage over its checked cranks: what ran and what it found.
struct BacklashResult {
  contact::ContactKinematics kinematics = contact::ContactKinematics::kLinearised;
  int discs = 1;
  std::size_t positions = 0;
  /// The last crank repeats the first crank's state (Stage::closed_period): it weighs once in the mean.
  bool closed_period = false;
  BacklashSummary summary;
  std::vector<std::string> notes;  ///< about the sweep itself (Stage::SamplingNote)
  double wall_seconds = 0.0;
};
/// Receives every position in crank order as it is computed (memory stays bounded in positions).
using BacklashSink = std::function<void(const BacklashPosition&)>;

/// The sweep at the stage's checked cranks, each position to `sink` when given.
BacklashResult Backlash(const Stage& stage, contact::ContactKinematics kinematics, const BacklashSink& sink = {});

}  // namespace ltca::analysis
