#pragma once
// A load spectrum (issue 50, item 5): the stage's duty cycle as bins of torque, crank speed and
// time share, each bin solved as the deck's sweep at its torque, every life rated over the bins
// by the Palmgren-Miner rule (docs/stage.md, "Load spectrum").

#include <limits>
#include <string>
#include <vector>

#include "ltca/analysis/sweep.hpp"

namespace ltca::analysis {

/// One bin of [[load_spectrum]].
struct LoadBin {
  double torque = 0.0;       ///< N*mm (deck: torque_nm), finite, signed like [load] torque_nm
  double input_speed = 0.0;  ///< crank (input) speed, rad/s (deck: speed_rpm), > 0
  double time_share = 0.0;   ///< the bin's share of the operating time (deck: time_share), in (0, 1]
};

/// The shares must add to 1 within this (absolute): a spectrum is not normalised silently.
inline constexpr double kTimeShareTolerance = 1e-9;

/// Throws std::invalid_argument naming the entry ([[load_spectrum]] #i, counted from 1), the key,
/// its value and what is expected: torque finite, speed finite in (0, 100,000] rpm, share in
/// (0, 1], the shares adding to 1 within kTimeShareTolerance. An empty spectrum is valid (none).
void ValidateSpectrum(const std::vector<LoadBin>& bins);

/// Palmgren-Miner over the bins: the damage per hour of bin i is 1 / L_i, so a life in hours over
/// the spectrum is L = 1 / sum_i(share_i / L_i). An infinite L_i (no load) adds no damage; a NaN
/// L_i (not rated in that bin) makes the result NaN. `hours[i]` is the life in bin i.
double MinerHours(const std::vector<double>& hours, const std::vector<double>& shares);

/// A bin's figures: its solved sweep's summary (bearing lives at the bin's speed).
struct SpectrumBinResult {
  LoadBin bin;
  SweepSummary summary;
};

/// Every bin and the lives combined over them (per bearing; NaN where a bin has no rating).
struct SpectrumResult {
  std::vector<SpectrumBinResult> bins;
  std::vector<double> l10_hours;        ///< ISO 281 basic life per bearing, Miner over the bins
  std::vector<double> load_zone_hours;  ///< load-zone life per bearing, Miner over the bins
  /// Pitting lives (ContactFatigue), Miner over the bins: per disc the pins' then the teeth's. A
  /// bin's pin life is its most damaged pin's, which may be another pin in another bin: the sum
  /// bounds the damage of any one pin from above.
  std::vector<double> contact_life_hours;
  bool all_succeeded() const;
  double ShortestL10Hours() const;       ///< NaN when no bearing has one
  double ShortestLoadZoneHours() const;  ///< NaN when no bearing has one
  double ShortestContactHours() const;   ///< NaN when no bin was rated
};

/// Combines the bins' solved sweeps (each with its bearing_life at its bin's speed) by Miner's rule.
SpectrumResult CombineSpectrum(std::vector<SpectrumBinResult> bins);

}  // namespace ltca::analysis
