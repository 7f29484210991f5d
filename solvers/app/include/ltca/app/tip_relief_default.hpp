#pragma once
// The default tip relief of a deck whose tooth difference is 2 or more (issue 12). Chen 2008
// leaves the addendum of such a profile open; its sharp tip corners take load as edge contacts,
// which no line-contact law covers. Without [modification] tip_truncation_mm or
// tip_rounding_radius_mm in the deck, the relief is chosen for the deck's load:
//   the smallest rounding radius of the R10 preferred numbers from 0.01 mm (0.01, 0.0125, 0.016,
//   0.02, 0.025, 0.0315, 0.04, 0.05, 0.063, 0.08, 0.1, ..., up to the pin radius), no truncation,
//   for which every
//   position of the deck's sweep solves on both flanks (+-T, as `ltca stiffness` loads them;
//   compatibility solver, the deck's tolerance, under both linearised and exact kinematics) and every loaded contact on the rounding arc is within the contact law's
//   half-width bound (ContactLaw::valid_half_width) and below [material]
//   contact_stress_limit_mpa.
// Any rounding radius > 0 keeps a loaded contact off a corner (the relieved tip is smooth); the
// law and the stress limit make "smallest" mean the smallest tip the line-contact laws describe.
// It needs a load solve, so it lives in the application layer; the geometry layer only builds
// the relief it is given.
#include "ltca/app/deck.hpp"

namespace ltca::app {

/// The i-th rounding radius tried, mm: 0.01 x the R10 series (1, 1.25, 1.6, 2, 2.5, 3.15, 4, 5,
/// 6.3, 8) x 10^(i / 10).
double DefaultTipRoundingCandidate(int i);

/// Crank positions the choice solves at most: a longer sweep is sampled evenly (the note says so).
inline constexpr int kTipReliefChoicePositions = 181;

/// For a deck without tip relief keys: sets deck.modification.tip_relief, deck.tip_relief_source
/// ("default", or "none" with sharp tips) and deck.tip_relief_note (the rule and what it chose, or
/// why the tips stay sharp: no [load] / [material], zero torque, the element surface or a profile
/// deviation, or no radius of the series that fits the tooth meets the rule).
void ChooseDefaultTipRelief(Deck& deck);

}  // namespace ltca::app
