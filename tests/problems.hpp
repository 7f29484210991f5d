#pragma once
// Load cases typed in from the papers' text, built from the geometry and contact layers only: the
// solver tests build their problems here, without the application's deck reader (issue 24). Each
// case names the deck of cases/ that holds the same data; tests/app checks the two agree.
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "ltca/contact/material.hpp"
#include "ltca/contact/mesh_state.hpp"
#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_problem.hpp"
#include "ltca/solvers/registry.hpp"
#include "pairs.hpp"

namespace ltca::test {

/// The linear contact law F = k B delta, k in N/mm per mm of contact length (the closed forms'
/// law: 2e4, about a steel line contact).
inline contact::ContactSettings LinearLaw(double stiffness_per_length = 2e4) {
  contact::ContactSettings c;
  c.law = contact::LawKind::kLinear;
  c.stiffness_per_length = stiffness_per_length;
  return c;
}

/// Options that name the solver (the rest default).
inline solvers::SolverOptions Named(const std::string& solver, solvers::SolverOptions options = {}) {
  options.name = solver;
  return options;
}

/// The named solver's answer to the problem, with the default options (or the given ones).
inline solvers::LoadResult SolveWith(const std::string& solver, const solvers::LoadProblem& problem,
                                     const solvers::SolverOptions& options = {}) {
  return solvers::MakeSolver(solver)->Solve(problem, Named(solver, options));
}

/// The named solver's answer with the torque balanced to 1e-13 (the rest default).
inline solvers::LoadResult SolveTight(const std::string& solver, const solvers::LoadProblem& problem) {
  solvers::SolverOptions options;
  options.torque_tolerance = 1e-13;
  return SolveWith(solver, problem, options);
}

/// Pin bending's coupling of `points` in the factored form the solvers use (as analysis::Stage
/// builds it for a deck with [pins]).
inline solvers::LoadProblem::CheckedCoupling FactoredBending(const std::vector<contact::PinContact>& points,
                                                             const contact::PinBeam& beam, double face_width,
                                                             int point_count) {
  contact::FactoredPinBending f = contact::PinBendingFactors(points, beam, face_width);
  return solvers::LoadProblem::CheckCoupling(contact::PinBendingCoupling(points, beam, face_width), point_count,
                                             {std::move(f.stiffness), std::move(f.loads), std::move(f.local)});
}

struct PaperCase {
  geometry::PairParameters pair;
  geometry::Modification modification;
  geometry::ManufacturingErrors errors;
  contact::ContactSettings contact;
  geometry::GeometrySettings geometry;
  contact::Material material;  ///< E = 206 GPa, nu = 0.3 for cycloid and pins (the default)
  std::optional<contact::PinSupport> pins;  ///< pin bending; none: rigid pins
  double torque = 0;           ///< N*mm
  double crank_start = 0, crank_end = 0;  ///< rad
  int positions = 1;

  std::shared_ptr<const contact::MeshModel> Model() const {
    return std::make_shared<const contact::MeshModel>(geometry::RealPair(pair, modification, errors, {}), geometry,
                                                      /*coupled_along_width=*/pins.has_value());
  }
  /// Each pin a beam of the nominal pin radius (only with pins).
  contact::PinBeam Beam() const { return contact::PinBeam(pins.value(), material, pair.pin_radius); }
  /// The sweep's cranks, ends included (as a deck's [sweep]).
  std::vector<double> Cranks() const {
    std::vector<double> cranks(static_cast<std::size_t>(positions));
    for (int i = 0; i < positions; ++i) {
      cranks[static_cast<std::size_t>(i)] =
          positions == 1 ? crank_start : crank_start + (crank_end - crank_start) * i / (positions - 1);
    }
    return cranks;
  }
  solvers::LoadProblem Problem(const std::shared_ptr<const contact::MeshModel>& model, double crank,
                               contact::ContactKinematics kinematics) const {
    solvers::LoadProblem problem(model, crank, contact, material, torque, kinematics);
    if (!pins) return problem;
    const auto points = model->Evaluate(crank).pins;
    return problem.WithCoupling(FactoredBending(points, Beam(), pair.face_width, model->point_count()));
  }
  solvers::LoadProblem Problem(double crank, contact::ContactKinematics kinematics) const {
    return Problem(Model(), crank, kinematics);
  }
};

/// Liu 2021 Table 1 (cases/liu2021_table1.toml, also the built-in default): z_p 40, z_c 39, r_rp 3,
/// R_p 64, e 1.3, B 12 mm; perfect surfaces; 206 GPa, 0.3; T = 206 N*m; one mesh period, 0.1 deg.
inline PaperCase LiuTable1() {
  PaperCase c;
  c.pair = LiuPair();
  c.torque = units::NmToNmm(206.0);
  c.crank_end = units::DegToRad(9.0);
  c.positions = 91;
  return c;
}

/// The same with |rho_c| in Liu eq. 25 (cases/liu2021_table1_absolute.toml).
inline PaperCase LiuTable1Absolute() {
  PaperCase c = LiuTable1();
  c.contact.rho_convention = contact::RhoConvention::kAbsolute;
  return c;
}

/// Liu 2021 section 5.2's base modification, dR_rp = -4 um, dR_p = -17 um, no errors
/// (cases/liu2021_sec52_base.toml).
inline PaperCase LiuSec52Base() {
  PaperCase c = LiuTable1Absolute();
  c.modification = Mod(-4.0, -17.0);
  return c;
}

/// Pin bending (cases/pin_bending.toml, ltca issue 11, a designer's case): the section 5.2 pair
/// in 20 slices, clamped 6 mm pins over a 20 mm span, the face 4 mm from the first support.
inline PaperCase PinBendingCase() {
  PaperCase c = LiuSec52Base();
  c.geometry.width_slices = 20;
  contact::PinSupport support;
  support.span = 20.0;
  support.support = contact::PinSupportKind::kClamped;
  support.face_offset = 4.0;
  c.pins = support;
  c.positions = 31;
  return c;
}

/// A clamped pin of radius r, `span` mm between the supports, the face `offset` mm from the first.
inline contact::PinBeam ClampedPin(const contact::Material& material, double r, double span, double offset) {
  contact::PinSupport support;
  support.span = span;
  support.support = contact::PinSupportKind::kClamped;
  support.face_offset = offset;
  return contact::PinBeam(support, material, r);
}

/// The plane model's state at a crank (deg) with every pin split into n slices of B / n
/// (pin-major points, slice k = k): the face-width model emulated by hand.
inline contact::MeshState Sliced(const contact::MeshModel& plane, double crank_deg, int n) {
  contact::MeshState s = plane.Evaluate(units::DegToRad(crank_deg));
  std::vector<contact::PinContact> points;
  for (const auto& pin : s.pins) {
    for (int k = 0; k < n; ++k) {
      contact::PinContact p = pin;
      p.slice = k;
      p.length = plane.pair().face_width / n;
      points.push_back(p);
    }
  }
  s.pins = std::move(points);
  return s;
}

}  // namespace ltca::test
