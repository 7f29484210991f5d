#pragma once
// Case decks: TOML files whose keys carry their unit (docs/decks.md). One small struct per
// section, each with its own validation; unknown sections and keys and missing required keys
// are errors that name the key. Values are converted to the internal units (mm, N, MPa, N*mm,
// rad) on reading.
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/geometry/discrete_profile.hpp"
#include "ltca/geometry/errors.hpp"
#include "ltca/geometry/pair.hpp"
#include "ltca/solvers/load_solver.hpp"

namespace ltca::solvers {

/// [case]: provenance.
struct CaseInfo {
  std::string title;
  std::string source;  ///< paper, table / section; free text.
};

/// [load]: the torque carried by this cycloid gear.
struct LoadCase {
  double torque = 0.0;  ///< N*mm (deck: torque_nm), >= 0.
  void Validate() const;
};

/// [sweep]: crank positions; default one mesh period in 91 positions (Liu's 0.1 deg step at z_p = 40).
struct Sweep {
  double crank_start = 0.0;  ///< rad (deck: crank_start_deg).
  double crank_end = 0.0;    ///< rad (deck: crank_end_deg), inclusive.
  int positions = 91;
  void Validate() const;
  /// The crank angles, rad: positions values from start to end inclusive.
  std::vector<double> CrankAngles() const;
};

struct Deck {
  std::string name;  ///< file path, or "built-in default"
  CaseInfo info;
  geometry::PairParameters pair;
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;        ///< [errors], optional, default none
  geometry::GeometrySettings geometry;         ///< [geometry], optional, default analytic
  contact::ContactSettings contact;            ///< [contact], optional, default hertz-line / signed
  SolverOptions solver;                        ///< [solver], optional, default bisection / linearised
  std::optional<contact::Material> material;  ///< required by the load commands
  std::optional<LoadCase> load;               ///< required by the load commands
  Sweep sweep;

  /// The pair as the contact layer sees it (modifications, errors, geometry mode).
  contact::MeshModel MakeModel() const { return {pair, modification, errors, geometry}; }

  /// Throws std::invalid_argument naming the deck and the missing section.
  const contact::Material& RequireMaterial() const;
  const LoadCase& RequireLoad() const;
};

/// Parses and validates a deck, including the geometry (an undercut profile is rejected).
/// Throws std::invalid_argument with a message that starts with the deck name.
Deck ParseDeck(std::string_view toml_text, const std::string& name);
Deck LoadDeck(const std::filesystem::path& path);

/// The built-in default case: Liu 2021 Table 1 (the text of cases/liu2021_table1.toml).
std::string_view DefaultDeckText();
Deck DefaultDeck();

}  // namespace ltca::solvers
