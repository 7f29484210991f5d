#pragma once
// Contact (pitting) fatigue of the pin-cycloid contact over a sweep: the load cycles each pin and
// each disc tooth sees, counted from the solved positions, rated by Palmgren-Miner on ISO
// 6336-2's life-factor curve (contact/contact_fatigue.hpp); docs/stage.md, "Contact fatigue".
//
// Counting. A pin is loaded over a run of consecutive positions; each run is one load cycle of the
// pin's surface (conservatively the same material point: a pin turning in its seat spreads the
// cycles) at the run's largest Hertz pressure. Over a crank turn the pins' runs are every
// engagement of the ring; they fall on the disc's z_c teeth evenly in the long run (the loaded
// sector turns z_p / z_c times a crank turn relative to the disc for d = 1: the disc turns -1/z_c
// while the load follows the eccentric), so a tooth's damage a crank turn is the ring's total over
// z_c. Two bases:
//  - a sweep over whole crank turns (its positions evenly cover n x 360 deg): every pin's runs,
//    the run across the end joined to the one at the start;
//  - a closed mesh period (the last position repeats the first, SweepSummary::closed_period) of a
//    pair whose pins all see the same history: the pins' run starts in the period are the cycles a
//    pin sees a crank turn (a period is 1 / z_p of a turn and z_p pins share it), each at the
//    period's largest pressure of that disc.
// A run whose peak is below a tenth of its disc's largest pressure (the load handed over and back
// between neighbouring positions) is not a load cycle. Any other sweep has no basis (the figures are NaN, the basis says why); so has a sweep with a
// failed position (a peak may be missing).
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "ltca/contact/contact_fatigue.hpp"
#include "ltca/contact/material.hpp"

namespace ltca::analysis {

struct Sweep;

/// The load cycles of a sweep: per pin (disc-major with two discs), the peak Hertz pressure of
/// each cycle (MPa), seen over `crank_turns` crank turns; `basis` says how they were counted, and
/// is a reason when they were not (crank_turns NaN).
struct ContactCycles {
  int discs = 1;
  std::vector<std::vector<double>> peaks;
  double crank_turns = std::numeric_limits<double>::quiet_NaN();
  std::string basis;
  bool counted() const { return crank_turns > 0.0; }
};

/// Counts the cycles position by position (a sweep's positions in crank order).
class ContactCycleCounter {
 public:
  /// A solved position's per-pin largest Hertz pressure, MPa (PositionResult::contact_stress).
  void Add(const std::vector<double>& contact_stress);
  /// A failed position: the count has a gap and no basis.
  void Fail() { failed_ = true; }
  /// The cycles of the sweep so far (its first and last crank and its positions in `sweep`);
  /// discs 1 or 2 (the per-pin pressures run over disc 1's pins, then disc 2's), closed_period
  /// as the summary's.
  ContactCycles Finish(const Sweep& sweep, bool closed_period, int discs) const;

 private:
  /// The s with the last position's pressures of disc `disc` equal to the first's of the pins s
  /// further on (a repeating mesh period), or -1.
  int PeriodShift(int disc, int pin_count, double largest) const;
  struct Pin {
    bool loaded_first = false;  // loaded at the first position
    double first_peak = 0.0;    // the run that began at the first position, while it is open or done
    bool first_open = false;
    bool loaded = false;        // loaded at the last position added
    double peak = 0.0;          // the open run's peak
    std::vector<double> peaks;  // closed runs, the first run excluded
    double largest = 0.0;
    std::int64_t gap = 0;          // unloaded positions since the last loaded one
    std::int64_t first_start = -1;  // where its first run began, when not at the first position
  };
  std::vector<Pin> pins_;
  // The first and the last position's pressures: in a repeating mesh period the last is the first
  // turned by one pin, which carries a run open at the end over to the run it continues.
  std::vector<double> first_stress_, last_stress_;
  std::int64_t positions_ = 0;
  bool failed_ = false;
};

/// The rating of one disc's contact: its pins and its teeth.
struct ContactFatigueDisc {
  double max_stress = std::numeric_limits<double>::quiet_NaN();  ///< MPa, the largest cycle peak
  /// Load cycles a crank turn: the pin with the most damage (the most cycles when none is
  /// damaged), and a tooth of the disc (the ring's cycles over z_c).
  double pin_cycles_per_turn = std::numeric_limits<double>::quiet_NaN();
  double tooth_cycles_per_turn = std::numeric_limits<double>::quiet_NaN();
  int worst_pin = -1;  ///< 0-based pin of this disc
  /// Damage a crank turn by Palmgren-Miner: sum over the cycles of 1 / N(sigma) (CyclesToPitting).
  double pin_damage_per_turn = std::numeric_limits<double>::quiet_NaN();
  double tooth_damage_per_turn = std::numeric_limits<double>::quiet_NaN();
  /// Life in hours at the crank speed (+inf: no cycle above the curve's floor; NaN: no speed).
  double pin_life_hours = std::numeric_limits<double>::quiet_NaN();
  double tooth_life_hours = std::numeric_limits<double>::quiet_NaN();
  /// S_H = sigma_Hlim Z_NT(N_L) / max_stress at the required life's N_L cycles (NaN without one).
  double pin_safety = std::numeric_limits<double>::quiet_NaN();
  double tooth_safety = std::numeric_limits<double>::quiet_NaN();
};

struct ContactFatigue {
  std::string basis;
  contact::LifeCurve curve = contact::LifeCurve::kSteel;
  double fatigue_limit = std::numeric_limits<double>::quiet_NaN();  ///< sigma_Hlim, MPa
  double crank_rpm = std::numeric_limits<double>::quiet_NaN();
  double required_hours = std::numeric_limits<double>::quiet_NaN();  ///< the life S_H is rated at
  std::vector<ContactFatigueDisc> discs;  ///< empty when the cycles were not counted
  /// The shortest life of the pins and teeth (NaN when none is rated).
  double ShortestHours() const;
  /// The smallest S_H of the pins and teeth (NaN when none is rated).
  double SmallestSafety() const;
};

/// Rates the counted cycles. tooth_count z_c; crank_speed rad/s (NaN: no hours); required_hours
/// the life S_H is rated at (none: no S_H).
ContactFatigue RateContactFatigue(const ContactCycles& cycles, const contact::Material& material, int tooth_count,
                                  double crank_speed, std::optional<double> required_hours);

}  // namespace ltca::analysis
