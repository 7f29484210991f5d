#pragma once
// The documents of the derived geometry of a deck's pair (geometry::RealPair, the pair as made:
// modification and [errors] applied): its JSON summary, text, the profile as CSV and the drawing.
// `ltca geometry`, the default job, `ltca report` and the Python module all build theirs here.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "ltca/analysis/inspection.hpp"
#include "ltca/app/deck.hpp"
#include "ltca/app/plots.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/profile.hpp"
#include "ltca/geometry/real_pair.hpp"

namespace ltca::app::documents {

/// The JSON summary: case, K1, phi_max, contact ratio, theta_max, alpha_max (deg), the least radius
/// of curvature and the undercut margin (mm; null when there is none), mesh period (deg crank),
/// transmission ratio, the pin circle as assembled and the tip relief that runs.
nlohmann::json Json(const Deck& deck, const geometry::RealPair& real);

/// The text: the pair, its modification and errors, then the derived figures with their sources.
std::string Text(const Deck& deck, const geometry::RealPair& real);

/// The whole profile as CSV, tooth space by tooth space in the body frame (mm; u_deg empty on a tip
/// relief's cap), 2 x `samples_per_flank` + 1 points a flank.
std::string Csv(const geometry::CycloidProfile& profile, int samples_per_flank);

/// The CSV's columns as numbers (u_deg NaN on a tip relief's cap, curvature_radius_mm infinite
/// on a straight part) and the part names: what the Python module hands out as arrays.
struct ProfileColumns {
  std::vector<double> tooth_space, u_deg, x_mm, y_mm, normal_x, normal_y, curvature_radius_mm;
  std::vector<std::string> part;
};
ProfileColumns Columns(const geometry::CycloidProfile& profile, int samples_per_flank);

/// The deviation chart of the deck's measured profile trace ([errors] profile_measured_csv)
/// against the design (the profile as made without it), with [inspection] profile_tolerance_um's
/// band: nullopt without a trace (docs/export.md, "Deviation chart").
std::optional<analysis::DeviationChart> DeviationChartOf(const Deck& deck, const geometry::RealPair& real);
/// Its CSV: u_deg, measured_um, fitted_um, residual_um, band_lower_um, band_upper_um (empty
/// without a band), one row per measured point.
std::string DeviationCsv(const analysis::DeviationChart& chart);
/// Its figure: the measured and the fitted deviation along u, their difference, the band.
plots::Figure DeviationFigure(const Deck& deck, const geometry::RealPair& real, const analysis::DeviationChart& chart);

/// The cycloid as made and the pins at `unloaded.crank` (rad), each pin's radius reduced by its
/// unloaded clearance (the least over its slices, from `unloaded`, the mesh state at that crank)
/// times a round exaggeration factor; the stage's output elements to scale when the deck has them.
plots::Figure Figure(const Deck& deck, const geometry::RealPair& real, const contact::MeshState& unloaded,
                     int samples_per_flank);

}  // namespace ltca::app::documents
