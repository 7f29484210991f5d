#pragma once
// A load spectrum (issue 50, item 5): the stage's duty cycle as bins of torque, crank speed and
// time share, each bin solved as the deck's sweep at its torque, every life rated over the bins
// by the Palmgren-Miner rule (docs/stage.md, "Load spectrum").

#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "ltca/contact/contact_fatigue.hpp"

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
  /// ISO 281's modified lives (BearingLife::modified: each bin's a_ISO at its own speed, so its
  /// own nu_1 and kappa, and its own loads), per bearing, Miner over the bins; empty when not rated.
  std::vector<double> modified_hours;            ///< a_ISO L10
  std::vector<double> load_zone_modified_hours;  ///< a_ISO times the load-zone life
  /// Pitting lives (ContactFatigue), Miner over the bins: per disc the pins' then the teeth's. A
  /// bin's pin life is its most damaged pin's, which may be another pin in another bin: the sum
  /// bounds the damage of any one pin from above.
  std::vector<double> contact_life_hours;
  /// Static figures over the spectrum: the worst bin's (a static rating has no time in it, so the
  /// spectrum's figure is the worst of its bins, never a mean). Per bearing s_0 = C_0 / P_0,max with
  /// P_0,max the largest over every bin (ISO 76; NaN when a bin has no s_0) and the bin (0-based)
  /// that sets it; per bearing the largest roller contact stress (MPa) over every bin and its bin.
  std::vector<double> static_safety;
  std::vector<int> static_safety_bin;
  std::vector<double> max_roller_stress;
  std::vector<int> max_roller_stress_bin;
  /// The largest tooth-contact (pin-cycloid Hertz) stress over every bin, MPa, and its bin (-1: none).
  double max_contact_stress = std::numeric_limits<double>::quiet_NaN();
  int max_contact_stress_bin = -1;
  /// The pitting safety over the spectrum at the required life ([allowables] contact_life_hours),
  /// per disc the pins' then the teeth's (SpectrumContactSafety); empty without a required life.
  std::vector<double> contact_safety;
  double required_contact_hours = std::numeric_limits<double>::quiet_NaN();
  bool all_succeeded() const;
  double ShortestL10Hours() const;       ///< NaN when no bearing has one
  double ShortestLoadZoneHours() const;  ///< NaN when no bearing has one
  double ShortestModifiedHours() const;          ///< NaN when no bearing has one
  double ShortestLoadZoneModifiedHours() const;  ///< NaN when no bearing has one
  bool modified() const;                         ///< the bins' modified lives are rated
  double ShortestContactHours() const;   ///< NaN when no bin was rated
  /// The smallest s_0 over the bearings and its bin (0-based, -1 when none has one).
  std::pair<double, int> SmallestStaticSafety() const;
  /// The largest roller contact stress over the bearings (MPa) and its bin (-1 when none).
  std::pair<double, int> LargestRollerStress() const;
  double SmallestContactSafety() const;  ///< NaN when not rated
};

/// The pitting safety of one contact (a disc's pins, or its teeth) over a spectrum, ISO 6336-6's
/// way for a load spectrum: the factor S by which every bin's stress may be multiplied before
/// Miner's damage over the required life reaches 1, S = sup{S : sum_i n_i / N(S sigma_i) <= 1},
/// n_i = cycles_per_turn_i x turns per hour_i x share_i x required_hours and N the cycles to
/// pitting on ISO 6336-2's curve (contact::CyclesToPitting). Each bin's cycles are taken at that
/// bin's largest stress, as the single run's S_H takes them: one bin gives that run's
/// S_H = sigma_Hlim Z_NT(n) / sigma exactly. Bins with no cycles or no stress add nothing; NaN when
/// any input of a loaded bin is NaN; +inf when no bin is loaded.
struct SpectrumContactLoad {
  double cycles = 0.0;  ///< n_i, the bin's load cycles over the required life
  double stress = 0.0;  ///< sigma_i, MPa
};
double SpectrumContactSafety(const std::vector<SpectrumContactLoad>& loads, contact::LifeCurve curve, double sigma_hlim);

/// Combines the bins' solved sweeps (each with its bearing_life at its bin's speed) by Miner's rule.
SpectrumResult CombineSpectrum(std::vector<SpectrumBinResult> bins);

}  // namespace ltca::analysis
