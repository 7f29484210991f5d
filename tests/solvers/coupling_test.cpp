// Coupled compliance (issue 9 item 2): the approach of pin i is its law's w_i(F_i) plus (C F)_i,
// C a sparse symmetric positive semidefinite matrix over the pins. Hand-made linearised problems
// with the linear law (w = F / k), so that brute force is exact: every non-empty active set S is
// solved as a linear system,
//   F_i / k + (C F)_i = L_i psi - c_i  (i in S),   sum_S L_i F_i = T,   F_j = 0 (j not in S),
// and accepted when F_S >= 0 and every pin outside S keeps a gap (C F)_j - (L_j psi - c_j) >= 0.
// The answer must be unique; energy-qp must find it, the shared residual must judge with the
// coupled gap, and the backends without coupling must refuse with their named status.
#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <Eigen/SparseCore>
#include <doctest/doctest.h>

#include "ltca/contact/pin_bending.hpp"
#include "ltca/geometry/units.hpp"
#include "ltca/solvers/load_solver.hpp"
#include "ltca/solvers/registry.hpp"
#include "pairs.hpp"
#include "problems.hpp"

using ltca::contact::ContactKinematics;
using ltca::contact::ContactSettings;
using ltca::contact::LawKind;
using ltca::contact::MeshModel;
using ltca::contact::MeshState;
using ltca::solvers::ComputeResiduals;
using ltca::solvers::LoadProblem;
using ltca::solvers::LoadResult;
using ltca::solvers::MakeSolver;
using ltca::solvers::SolverNames;
using ltca::solvers::SolverOptions;
using ltca::solvers::SolverStatus;

namespace {

constexpr double kStiffnessPerLength = 2e4;  // N/mm per mm of contact length
// The pair only lends the face width (12 mm: k = 2.4e5 N/mm per pin), the pin-circle radius and
// the rotation window; the pins are the hand-made state's.
const MeshModel& Model() {
  static const MeshModel model(ltca::test::LiuPair(), {});
  return model;
}
double PinStiffness() { return kStiffnessPerLength * Model().pair().face_width; }

ContactSettings Linear() { return ltca::test::LinearLaw(kStiffnessPerLength); }

/// A hand-made problem: per pin its arm L (mm) and clearance c (mm), the coupling C (mm/N, dense
/// here, stored sparse) and the torque (N*mm).
struct Hand {
  const char* name;
  std::vector<double> arm, clearance;
  std::vector<std::vector<double>> coupling;
  double torque;
};

/// 1e-6 mm/N is a quarter of the law's own compliance 1 / k = 4.2e-6 mm/N.
std::vector<std::vector<double>> Scaled(std::vector<std::vector<double>> c, double scale) {
  for (auto& row : c) for (double& x : row) x *= scale;
  return c;
}

std::vector<Hand> Problems() {
  return {
      // Neighbours coupled (tridiagonal, off-diagonal half the diagonal); pin 3 stays open by 0.04 mm.
      {"three pins, the third stays open", {40, 32, 18}, {0, 0.003, 0.05},
       Scaled({{2, 1, 0}, {1, 2, 1}, {0, 1, 2}}, 1e-6), 2e5},
      // Strongly non-diagonal: each pin's force pulls its neighbours in (-0.45 of the diagonal,
      // which is the law's compliance); every pin loaded, pin 4 with 23 times its uncoupled force.
      {"four pins, neighbours pull each other in", {46, 41, 33, 21}, {0, 0.0008, 0.0025, 0.004},
       Scaled({{1, -0.45, 0, 0}, {-0.45, 1, -0.45, 0}, {0, -0.45, 1, -0.45}, {0, 0, -0.45, 1}}, 4e-6), 2e5},
      // Pin 2 touches and is compliant, pin 1 has clearance and is pushed away by pin 2's force:
      // the coupled rotation lies 18 % beyond the single-pin bound without the off-diagonal term,
      // and the loaded set differs from the uncoupled one ({2} alone). Pin 3 has a negative arm.
      {"three pins, the coupling turns the cycloid past the diagonal single-pin bound", {38, 37, -12},
       {0.033, 0, 0.02}, Scaled({{1.4, 4.0, 0}, {4.0, 11.5, 0}, {0, 0, 0}}, 1e-5), 2e4},
      // A singular coupling (rank 2 over six pins); pins 4, 5 (negative arm) and 6 stay open, where
      // uncoupled pins 1-4 would be loaded.
      {"six pins, a singular coupling of rank 2", {46, 40, 33, 24, -14, 10}, {0, 0.0088, 0.0016, 0.0008, 0.02, 0.03},
       Scaled({{28, 10, 16, 24, 0, 0},
               {10, 4, 7, 12, 0, 0},
               {16, 7, 13, 24, 0, 0},
               {24, 12, 24, 48, 0, 0},
               {0, 0, 0, 0, 0, 0},
               {0, 0, 0, 0, 0, 0}},
              1e-6),
       2e5},
  };
}

MeshState State(const Hand& h) {
  MeshState s;
  for (std::size_t i = 0; i < h.arm.size(); ++i) {
    ltca::contact::PinContact p;
    p.pin = static_cast<int>(i);
    p.length = Model().pair().face_width;  // the plane model: one slice over the face width
    p.angle = 0.1 * static_cast<double>(i + 1);
    p.clearance = h.clearance[i];
    p.arm = h.arm[i];
    p.cycloid_point = p.pin_point = Eigen::Vector2d::Zero();
    p.normal = Eigen::Vector2d::UnitX();
    p.cycloid_curvature = 0.1;  // convex, radius 10 mm (the linear law does not use it)
    p.pin_radius = 3.0;
    s.pins.push_back(p);
  }
  return s;
}

Eigen::SparseMatrix<double> Sparse(const std::vector<std::vector<double>>& dense) {
  const auto n = static_cast<Eigen::Index>(dense.size());
  Eigen::SparseMatrix<double> c(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = 0; j < n; ++j) {
      const double x = dense[static_cast<std::size_t>(i)][static_cast<std::size_t>(j)];
      if (x != 0.0) t.emplace_back(i, j, x);
    }
  }
  c.setFromTriplets(t.begin(), t.end());
  return c;
}

LoadProblem Uncoupled(const Hand& h) { return LoadProblem(Model(), State(h), Linear(), {}, h.torque); }
LoadProblem Coupled(const Hand& h) { return Uncoupled(h).WithCoupling(Sparse(h.coupling)); }

struct Answer {
  double psi = 0.0;
  std::vector<double> force;
};

/// Every feasible active set of the linear-law problem with coupling `c` (all zero: uncoupled).
std::vector<Answer> BruteForce(const Hand& h, const std::vector<std::vector<double>>& c) {
  const std::size_t n = h.arm.size();
  const double k = PinStiffness();
  double l_max = 0.0;
  for (const double l : h.arm) l_max = std::max(l_max, std::abs(l));
  const double f_tol = 1e-9 * h.torque / l_max, g_tol = 1e-12;  // N, mm: rounding, not physics
  std::vector<Answer> feasible;
  for (unsigned mask = 1; mask < (1u << n); ++mask) {
    std::vector<std::size_t> s;
    for (std::size_t i = 0; i < n; ++i) if (mask & (1u << i)) s.push_back(i);
    const auto m = static_cast<Eigen::Index>(s.size());
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(m + 1, m + 1);
    Eigen::VectorXd b = Eigen::VectorXd::Zero(m + 1);
    for (Eigen::Index r = 0; r < m; ++r) {
      const std::size_t i = s[static_cast<std::size_t>(r)];
      for (Eigen::Index q = 0; q < m; ++q) a(r, q) = c[i][s[static_cast<std::size_t>(q)]];
      a(r, r) += 1.0 / k;
      a(r, m) = -h.arm[i];  // unknowns: F_S, then psi
      b(r) = -h.clearance[i];
      a(m, r) = h.arm[i];
    }
    b(m) = h.torque;
    const Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (!lu.isInvertible()) continue;
    const Eigen::VectorXd x = lu.solve(b);
    Answer ans;
    ans.psi = x(m);
    ans.force.assign(n, 0.0);
    for (Eigen::Index r = 0; r < m; ++r) ans.force[s[static_cast<std::size_t>(r)]] = x(r);
    bool ok = std::all_of(ans.force.begin(), ans.force.end(), [&](double f) { return f >= -f_tol; });
    for (std::size_t j = 0; j < n && ok; ++j) {
      if (mask & (1u << j)) continue;
      double cf = 0.0;
      for (std::size_t q = 0; q < n; ++q) cf += c[j][q] * ans.force[q];
      ok = cf - (h.arm[j] * ans.psi - h.clearance[j]) >= -g_tol;
    }
    if (ok) feasible.push_back(ans);
  }
  return feasible;
}

/// The unique brute-force answer (fails the test when there is none or more than one).
Answer Unique(const Hand& h, const std::vector<std::vector<double>>& c) {
  const auto all = BruteForce(h, c);
  REQUIRE(all.size() == 1);
  return all.front();
}

std::vector<std::vector<double>> Zero(std::size_t n) { return std::vector<std::vector<double>>(n, std::vector<double>(n, 0.0)); }

double MaxForce(const std::vector<double>& f) {
  double m = 0.0;
  for (const double x : f) m = std::max(m, std::abs(x));
  return m;
}

double MaxDifference(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

/// A solver's answer against the brute-force one: forces to 1e-8 of the largest, psi to 1e-8
/// relative, the shared residual below 1e-9, and the same loaded set (an open pin carries exactly
/// nothing). Returns the force and psi errors.
std::pair<double, double> CheckAgainst(const Answer& truth, const LoadResult& r) {
  const double force_error = MaxDifference(r.force, truth.force) / MaxForce(truth.force);
  const double psi_error = std::abs(r.rotation - truth.psi) / std::abs(truth.psi);
  CHECK(force_error <= 1e-8);
  CHECK(psi_error <= 1e-8);
  CHECK(r.residuals.Normalised() < 1e-9);
  for (std::size_t i = 0; i < truth.force.size(); ++i) {
    CAPTURE(i);
    CHECK((r.force[i] > 0.0) == (truth.force[i] > 0.0));
  }
  return {force_error, psi_error};
}

/// n pins in a ring, each coupled to its neighbours: 2e-6 mm/N on the diagonal, 0.5e-6 beside it.
Eigen::SparseMatrix<double> NeighbourRing(int n) {
  Eigen::SparseMatrix<double> c(n, n);
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 2e-6);
    t.emplace_back(i, (i + 1) % n, 0.5e-6);
    t.emplace_back((i + 1) % n, i, 0.5e-6);
  }
  c.setFromTriplets(t.begin(), t.end());
  return c;
}

LoadResult Solve(const std::string& name, const LoadProblem& problem) {
  SolverOptions options;
  options.name = name;
  return MakeSolver(name)->Solve(problem, options);
}

}  // namespace

TEST_CASE("solvers: coupled compliance - energy-qp matches brute-force active-set enumeration on four hand-made problems") {
  // Forces to 1e-8 of the largest, psi to 1e-8 relative, the same loaded set, success, and the
  // shared residual small. Each problem also shows what it was made for.
  double worst_force = 0.0, worst_psi = 0.0, worst_residual = 0.0;
  for (const Hand& h : Problems()) {
    CAPTURE(h.name);
    const LoadProblem problem = Coupled(h);
    REQUIRE(problem.has_coupling());
    const Answer truth = Unique(h, h.coupling);
    const LoadResult r = Solve("energy-qp", problem);
    REQUIRE(r.status == SolverStatus::kSuccess);
    const auto [force_error, psi_error] = CheckAgainst(truth, r);
    // The energy of the answer: the law's F^2 / 2k plus the coupling's 1/2 F^T C F.
    double energy = 0.0;
    for (std::size_t i = 0; i < truth.force.size(); ++i) {
      energy += truth.force[i] * truth.force[i] / (2.0 * PinStiffness());
      for (std::size_t j = 0; j < truth.force.size(); ++j) energy += 0.5 * truth.force[i] * h.coupling[i][j] * truth.force[j];
    }
    CHECK(r.energy == doctest::Approx(energy).epsilon(1e-8));
    worst_force = std::max(worst_force, force_error);
    worst_psi = std::max(worst_psi, psi_error);
    worst_residual = std::max(worst_residual, r.residuals.Normalised());
    // The coupling matters: the uncoupled answer is another one.
    const Answer uncoupled = Unique(h, Zero(h.arm.size()));
    CHECK(std::abs(uncoupled.psi - truth.psi) > 0.1 * std::abs(truth.psi));
  }
  MESSAGE("energy-qp against brute force, worst over the problems: forces ", worst_force, " of the largest, psi ",
          worst_psi, " relative, shared residual ", worst_residual);

  const auto problems = Problems();
  // Problem 1: pin 3 stays open, by 0.04 mm.
  {
    const Hand& h = problems[0];
    const Answer a = Unique(h, h.coupling);
    CHECK(a.force[2] == 0.0);
    CHECK(a.force[0] > 0.0);
    CHECK(a.force[1] > 0.0);
    CHECK(h.coupling[1][2] * a.force[1] - (h.arm[2] * a.psi - h.clearance[2]) > 0.04);
  }
  // Problem 2: off-diagonal entries 0.45 of the diagonal; pin 4 carries 23 times its uncoupled force.
  {
    const Hand& h = problems[1];
    const Answer a = Unique(h, h.coupling), u = Unique(h, Zero(4));
    CHECK(std::abs(h.coupling[0][1]) >= 0.45 * h.coupling[0][0]);
    CHECK(a.force[3] > 20.0 * u.force[3]);
  }
  // Problem 3: the coupled rotation exceeds min over m of [c_m + w_m(T / L_m) + C_mm T / L_m] / L_m,
  // the single-pin bound that ignores the neighbours' pull; the judge's range uses the coupled one.
  {
    const Hand& h = problems[2];
    const Answer a = Unique(h, h.coupling);
    double diagonal_bound = INFINITY;
    for (std::size_t m = 0; m < h.arm.size(); ++m) {
      if (h.arm[m] <= 0.0) continue;
      const double f = h.torque / h.arm[m];
      diagonal_bound = std::min(diagonal_bound, (h.clearance[m] + f / PinStiffness() + h.coupling[m][m] * f) / h.arm[m]);
    }
    CHECK(a.psi > 1.15 * diagonal_bound);
    const auto range = Coupled(h).LoadedRotationRange();
    CHECK(a.psi <= range.single_pin);
    CHECK(a.psi >= range.first_contact);
    CHECK(Uncoupled(h).LoadedRotationRange().single_pin < a.psi);  // the uncoupled bound would reject it
    CHECK(a.force[2] == 0.0);
    CHECK(Unique(h, Zero(3)).force[0] == 0.0);  // uncoupled only pin 2 is loaded
  }
  // Problem 4: C is singular (positive semidefinite, not definite) and accepted; pins 4-6 stay open.
  {
    const Hand& h = problems[3];
    const Eigen::MatrixXd c = Eigen::MatrixXd(Sparse(h.coupling));
    CHECK(Eigen::FullPivLU<Eigen::MatrixXd>(c).rank() == 2);
    const Answer a = Unique(h, h.coupling), u = Unique(h, Zero(6));
    for (const std::size_t j : {3, 4, 5}) CHECK(a.force[j] == 0.0);
    CHECK(u.force[3] > 0.0);
  }
}

TEST_CASE("solvers: coupled compliance - the shared residual judges with the coupled gap") {
  // The brute-force answer passes on the coupled problem and fails on the uncoupled one; the
  // uncoupled answer fails on the coupled problem. A judge that ignored C would pass both wrong ones.
  for (const Hand& h : Problems()) {
    CAPTURE(h.name);
    const LoadProblem coupled = Coupled(h), uncoupled = Uncoupled(h);
    const Answer truth = Unique(h, h.coupling), plain = Unique(h, Zero(h.arm.size()));
    CHECK(ComputeResiduals(coupled, truth.psi, truth.force).Normalised() < 1e-10);
    CHECK(ComputeResiduals(uncoupled, plain.psi, plain.force).Normalised() < 1e-10);
    CHECK(ComputeResiduals(uncoupled, truth.psi, truth.force).Normalised() > 1e-2);
    CHECK(ComputeResiduals(coupled, plain.psi, plain.force).Normalised() > 1e-2);
    // What energy-qp answers without the coupling is judged wrong on the coupled problem.
    const LoadResult r = Solve("energy-qp", uncoupled);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(ComputeResiduals(coupled, r.rotation, r.force).Normalised() > 1e-2);
  }
  // The gap itself, on problem 1 at the truth: pin 3's is (C F)_3 - (L_3 psi - c_3), pin 1's zero.
  const Hand h = Problems()[0];
  const Answer truth = Unique(h, h.coupling);
  std::vector<double> pushed = truth.force;
  pushed[2] = 1.0;  // 1 N on the open pin: complementarity F g with the coupled gap
  const double gap = 1.0 / PinStiffness() + h.coupling[2][1] * truth.force[1] + h.coupling[2][2] * 1.0 -
                     (h.arm[2] * truth.psi - h.clearance[2]);
  const auto res = ComputeResiduals(Coupled(h), truth.psi, pushed);
  CHECK(res.complementarity_nmm == doctest::Approx(1.0 * gap).epsilon(1e-9));
}

TEST_CASE("solvers: coupled compliance - bisection, compatibility and energy-groups match brute-force active-set enumeration") {
  // The same four hand-made problems as energy-qp above (forces to 1e-8 of the largest, psi to
  // 1e-8, the same loaded set, shared residual < 1e-9): bisection's trial rotations solve the
  // coupled complementarity problem, compatibility solves Newton on (psi, F), energy-groups
  // solves each tooth group's coupled problem and keeps the feasible one (issue 11).
  for (const std::string name : {"bisection", "compatibility", "energy-groups"}) {
    CAPTURE(name);
    CHECK(MakeSolver(name)->supports_coupling());
    double worst_force = 0.0, worst_psi = 0.0;
    for (const Hand& h : Problems()) {
      CAPTURE(h.name);
      const Answer truth = Unique(h, h.coupling);
      const LoadResult r = Solve(name, Coupled(h));
      REQUIRE(r.status == SolverStatus::kSuccess);
      const auto [force_error, psi_error] = CheckAgainst(truth, r);
      worst_force = std::max(worst_force, force_error);
      worst_psi = std::max(worst_psi, psi_error);
    }
    MESSAGE(name, " against brute force, worst: forces ", worst_force, " of the largest, psi ", worst_psi, " relative");
  }
}

namespace {

// A backend without coupling support (the default of LoadSolver::supports_coupling): every
// registered solver supports it since issue 11, so the refusal is checked on this one.
class UncoupledOnly final : public ltca::solvers::LoadSolver {
 public:
  std::string name() const override { return "uncoupled-only"; }

 private:
  void DoSolve(const LoadProblem& problem, const SolverOptions& options, ltca::solvers::Workspace& workspace,
               LoadResult* result) const override {
    *result = ltca::solvers::MakeSolver("bisection")->Solve(problem, options, workspace);
  }
};

}  // namespace

TEST_CASE("solvers: coupled compliance - every solver supports it, a backend that does not is refused with coupling-unsupported") {
  // Refused before solving, with the solver named, and no number claimed: rotation and TE NaN,
  // every force zero, no loaded pin. On the uncoupled copy it succeeds (the status is about the
  // coupling, nothing else).
  CHECK(std::string(ltca::solvers::ToString(SolverStatus::kCouplingUnsupported)) == "coupling-unsupported");
  for (const auto& name : SolverNames()) {
    CAPTURE(name);
    CHECK(MakeSolver(name)->supports_coupling());
  }
  const UncoupledOnly refusing;
  CHECK_FALSE(refusing.supports_coupling());
  for (const Hand& h : Problems()) {
    CAPTURE(h.name);
    SolverOptions options;
    options.name = "bisection";
    const LoadResult r = refusing.Solve(Coupled(h), options);
    CHECK(r.status == SolverStatus::kCouplingUnsupported);
    CHECK(r.message.find("uncoupled-only") != std::string::npos);
    CHECK(std::isnan(r.rotation));
    CHECK(std::isnan(r.te));
    CHECK(MaxForce(r.force) == 0.0);
    CHECK(r.active.empty());
    const LoadResult plain = refusing.Solve(Uncoupled(h), options);
    CHECK(plain.status == SolverStatus::kSuccess);
    const Answer a = Unique(h, Zero(h.arm.size()));
    CHECK(MaxDifference(plain.force, a.force) <= 1e-6 * MaxForce(a.force));
  }
  // Zero torque is no exception: the refusal comes first.
  Hand idle = Problems()[0];
  idle.torque = 0.0;
  SolverOptions options;
  CHECK(refusing.Solve(Coupled(idle), options).status == SolverStatus::kCouplingUnsupported);
  CHECK(Solve("bisection", Coupled(idle)).status == SolverStatus::kSuccess);
  CHECK(Solve("energy-groups", Coupled(idle)).status == SolverStatus::kSuccess);
}

TEST_CASE("solvers: coupled compliance - a coupling that is not symmetric, positive semidefinite, finite or n x n is rejected") {
  const LoadProblem problem = Uncoupled(Problems()[0]);  // three pins
  const auto reject = [&](const std::vector<std::vector<double>>& c, const char* what) {
    CAPTURE(what);
    CHECK_THROWS_WITH_AS(problem.WithCoupling(Sparse(c)), doctest::Contains(what), std::invalid_argument);
  };
  reject({{2e-6, 1e-6, 0}, {0.5e-6, 2e-6, 0}, {0, 0, 1e-6}}, "not symmetric");
  reject({{1e-6, 2e-6, 0}, {2e-6, 1e-6, 0}, {0, 0, 1e-6}}, "not positive semidefinite");  // eigenvalue -1e-6
  reject({{-1e-9, 0, 0}, {0, 1e-6, 0}, {0, 0, 1e-6}}, "not positive semidefinite");
  reject({{1e-6, 0}, {0, 1e-6}}, "does not match the 3 pins");
  reject({{NAN, 0, 0}, {0, 1e-6, 0}, {0, 0, 1e-6}}, "not finite");
  CHECK_THROWS_WITH_AS(problem.WithCoupling(Eigen::SparseMatrix<double>(3, 2)), doctest::Contains("not square"),
                       std::invalid_argument);
  // Accepted: a singular one, and an asymmetry within 1e-12 (stored symmetrised).
  CHECK(problem.WithCoupling(Sparse({{1e-6, 1e-6, 0}, {1e-6, 1e-6, 0}, {0, 0, 0}})).has_coupling());
  const LoadProblem nearly = problem.WithCoupling(Sparse({{2e-6, 1e-6, 0}, {1e-6 * (1 + 1e-13), 2e-6, 0}, {0, 0, 1e-6}}));
  REQUIRE(nearly.has_coupling());
  CHECK(nearly.coupling()->coeff(0, 1) == nearly.coupling()->coeff(1, 0));
  // Beyond 200 pins the check is a sparse LDL^T of C + tol I: a ring of 250 pins, each coupled to
  // its neighbours by -1 with 2 on the diagonal (singular: the all-ones vector), is accepted; with
  // 1.9 on the diagonal (smallest eigenvalue -0.1) it is rejected.
  Hand ring{"ring", std::vector<double>(250, 10.0), std::vector<double>(250, 0.01), {}, 1e5};
  const LoadProblem big = Uncoupled(ring);
  const auto ring_coupling = [](double diagonal) {
    Eigen::SparseMatrix<double> c(250, 250);
    std::vector<Eigen::Triplet<double>> t;
    for (int i = 0; i < 250; ++i) {
      t.emplace_back(i, i, diagonal * 1e-6);
      t.emplace_back(i, (i + 1) % 250, -1e-6);
      t.emplace_back((i + 1) % 250, i, -1e-6);
    }
    c.setFromTriplets(t.begin(), t.end());
    return c;
  };
  CHECK(big.WithCoupling(ring_coupling(2.0)).has_coupling());
  CHECK_THROWS_WITH_AS(big.WithCoupling(ring_coupling(1.9)), doctest::Contains("not positive semidefinite"),
                       std::invalid_argument);
}

TEST_CASE("solvers: coupled compliance - no coupling (absent, empty or all zero) leaves every number bit-identical") {
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const MeshModel model = *sec52.Model();
  const LoadProblem plain(model, 0.3, sec52.contact, sec52.material, sec52.torque, ContactKinematics::kLinearised);
  const auto n = static_cast<Eigen::Index>(plain.point_count());
  Eigen::SparseMatrix<double> zeros(n, n);  // explicit zero entries only
  std::vector<Eigen::Triplet<double>> t{{0, 0, 0.0}, {1, 2, 0.0}, {2, 1, 0.0}};
  zeros.setFromTriplets(t.begin(), t.end());
  const LoadProblem all_zero = plain.WithCoupling(Sparse(Zero(static_cast<std::size_t>(n))));
  const std::vector<LoadProblem> variants = {plain.WithCoupling(Eigen::SparseMatrix<double>()),
                                             plain.WithCoupling(Eigen::SparseMatrix<double>(n, n)),
                                             plain.WithCoupling(zeros), all_zero};
  for (const auto& name : SolverNames()) {
    CAPTURE(name);
    const LoadResult reference = Solve(name, plain);
    REQUIRE(reference.status == SolverStatus::kSuccess);
    for (const LoadProblem& p : variants) {
      CHECK_FALSE(p.has_coupling());
      CHECK(p.coupling() == nullptr);
      const LoadResult r = Solve(name, p);
      CHECK(r.status == reference.status);
      CHECK(r.rotation == reference.rotation);
      CHECK(r.force == reference.force);
      CHECK(r.energy == reference.energy);
      CHECK(r.residuals.normalised == reference.residuals.normalised);
      CHECK(p.LoadedRotationRange().single_pin == plain.LoadedRotationRange().single_pin);
    }
  }
  // Removing a coupling restores the uncoupled bound bit for bit.
  Eigen::SparseMatrix<double> c(n, n);
  for (Eigen::Index i = 0; i < n; ++i) c.insert(i, i) = 1e-6;
  const LoadProblem with = plain.WithCoupling(c);
  CHECK(with.LoadedRotationRange().single_pin > plain.LoadedRotationRange().single_pin);
  CHECK(with.WithCoupling(Eigen::SparseMatrix<double>()).LoadedRotationRange().single_pin == plain.LoadedRotationRange().single_pin);
}

TEST_CASE("solvers: coupled compliance - energy-qp rebuilds its Ipopt problem when the Hessian pattern changes") {
  // One workspace, the same pin count each time: energy-qp re-optimises its TNLP (Ipopt's
  // ReOptimizeTNLP, detail "reoptimisations") only when the size and the coupling's Hessian
  // pattern are those of the last solve, and every answer matches brute force (warm starts from
  // another problem change the iterations, not the answer).
  const auto problems = Problems();
  Hand other = problems[1];  // problem 2 with pins 1 and 4 coupled as well (still definite)
  other.coupling[0][3] = other.coupling[3][0] = 0.3e-6;
  Hand scaled = problems[1];  // the same pattern, other values
  for (auto& row : scaled.coupling) for (double& x : row) x *= 0.5;
  struct Step {
    const Hand* hand;
    bool coupled;
    int reoptimised;  // expected
  };
  const std::vector<Step> steps = {{&problems[1], true, 0}, {&problems[1], true, 1}, {&scaled, true, 1},
                                   {&other, true, 0},       {&problems[1], true, 0}, {&problems[1], false, 0},
                                   {&other, false, 1},      {&other, true, 0}};
  ltca::solvers::Workspace workspace;
  SolverOptions options;
  options.name = "energy-qp";
  const auto solver = MakeSolver("energy-qp");
  for (std::size_t s = 0; s < steps.size(); ++s) {
    const Hand& h = *steps[s].hand;
    CAPTURE(s);
    const LoadProblem problem = steps[s].coupled ? Coupled(h) : Uncoupled(h);
    const LoadResult r = solver->Solve(problem, options, workspace);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(r.details.at("reoptimisations") == steps[s].reoptimised);
    const Answer truth = Unique(h, steps[s].coupled ? h.coupling : Zero(4));
    CHECK(MaxDifference(r.force, truth.force) <= 1e-8 * MaxForce(truth.force));
    CHECK(std::abs(r.rotation - truth.psi) <= 1e-8 * std::abs(truth.psi));
  }
}

TEST_CASE("solvers: coupled compliance - energy-qp on a 40-pin pair, linearised and exact, with neighbouring pins coupled") {
  // No brute force at 40 pins: the shared residual judges, the exact answer lies within
  // 0.05 arcsec of the linearised one (as uncoupled, judge_test.cpp), and the coupling adds its
  // compliance: the coupled TE is larger than the uncoupled one.
  const ltca::test::PaperCase sec52 = ltca::test::LiuSec52Base();
  const MeshModel model = *sec52.Model();
  const int n = model.pin_count();
  const Eigen::SparseMatrix<double> c = NeighbourRing(n);
  double te[2] = {NAN, NAN}, te_plain = NAN;
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    CAPTURE(static_cast<int>(kinematics));
    const LoadProblem plain(model, 0.3, sec52.contact, sec52.material, sec52.torque, kinematics);
    const LoadProblem problem = plain.WithCoupling(c);
    SolverOptions options;
    options.name = "energy-qp";
    const LoadResult r = MakeSolver("energy-qp")->Solve(problem, options);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(r.residuals.Normalised() < 1e-8);
    te[kinematics == ContactKinematics::kExact ? 1 : 0] = r.te;
    if (kinematics == ContactKinematics::kLinearised) {
      // A pin that carries force has its coupled gap closed: an interior-point force left on a pin
      // that the neighbours' forces hold open (pin 12 here: approach 1.2e-4 mm, opened 3e-7 mm
      // by the coupling) is set to zero, as an open pin is without coupling.
      const Eigen::Map<const Eigen::VectorXd> f(r.force.data(), n);
      const Eigen::VectorXd cf = c * f;
      for (int i = 0; i < n; ++i) {
        const auto k = static_cast<std::size_t>(i);
        if (!(r.force[k] > 0.0)) continue;
        CAPTURE(i);
        CHECK(std::abs(problem.base_laws()[k].Approach(r.force[k]) + cf(i) - r.approach[k]) < 1e-9);
      }
    }
    if (kinematics == ContactKinematics::kLinearised) te_plain = MakeSolver("energy-qp")->Solve(plain, options).te;
  }
  CHECK(std::abs(ltca::units::RadToArcsec(te[1] - te[0])) < 0.05);
  CHECK(std::abs(te[0]) > std::abs(te_plain));
}

// --- issue 11: pin bending over face-width slices ------------------------------------------------
namespace {

/// Liu Table 1 (cases/liu2021_table1.toml): the pair of the validation section.
const ltca::test::PaperCase& Liu() {
  static const ltca::test::PaperCase liu = ltca::test::LiuTable1();
  return liu;
}
std::shared_ptr<const MeshModel> LiuModel() {
  static const auto model = Liu().Model();
  return model;
}

/// A clamped pin of the pair's radius, 16 mm between the supports, the 12 mm face 2 mm from the first.
ltca::contact::PinBeam Pin(const ltca::contact::Material& material, double span = 16.0, double offset = 2.0) {
  return ltca::test::ClampedPin(material, LiuModel()->pair().pin_radius, span, offset);
}

/// The plane model's state at a crank with every pin split into n slices of length B / n: what the
/// face-width model (issue 11) produces, emulated.
LoadProblem SlicedProblem(double crank_deg, int n) {
  return LoadProblem(LiuModel(), ltca::test::Sliced(*LiuModel(), crank_deg, n), Liu().contact, Liu().material, Liu().torque);
}

Eigen::SparseMatrix<double> Bending(const LoadProblem& p, const ltca::contact::PinBeam& beam) {
  return ltca::contact::PinBendingCoupling(p.base_state().pins, beam, LiuModel()->pair().face_width);
}

LoadResult SolveWith(const std::string& name, const LoadProblem& problem, ContactKinematics /*kinematics: the problem's*/,
                     ltca::solvers::Workspace* workspace = nullptr) {
  SolverOptions options;
  options.name = name;
  return workspace != nullptr ? MakeSolver(name)->Solve(problem, options, *workspace)
                              : MakeSolver(name)->Solve(problem, options);
}

/// bisection, compatibility and energy-qp agree on a coupled problem: TE to 1e-6 relative, forces
/// to 1e-6 of the largest, the shared residual below 1e-8 for each. Returns bisection's result.
LoadResult Agree(const LoadProblem& problem, ContactKinematics kinematics) {
  const LoadResult reference = SolveWith("bisection", problem, kinematics);
  REQUIRE(reference.status == SolverStatus::kSuccess);
  CHECK(reference.residuals.Normalised() < 1e-8);
  for (const std::string name : {"compatibility", "energy-qp", "energy-groups"}) {
    CAPTURE(name);
    const LoadResult r = SolveWith(name, problem, kinematics);
    REQUIRE(r.status == SolverStatus::kSuccess);
    CHECK(r.residuals.Normalised() < 1e-8);
    CHECK(std::abs(r.te - reference.te) <= 1e-6 * std::abs(reference.te));
    CHECK(MaxDifference(r.force, reference.force) <= 1e-6 * MaxForce(reference.force));
  }
  return reference;
}

}  // namespace

TEST_CASE("solvers: coupled compliance - Liu Table 1 with pin bending over 10 slices: every solver agrees with bisection (linearised)") {
  // 40 pins x 10 slices = 400 points, block-diagonal 10 x 10 pin-bending blocks (clamped pins,
  // 16 mm span). Pin bending adds compliance: the TE grows over the uncoupled slice model's, and
  // the slices of a loaded pin carry more near the supports (the pin bends away in the middle).
  for (const double crank : {0.0, 1.7, 4.5}) {
    CAPTURE(crank);
    const LoadProblem plain = SlicedProblem(crank, 10);
    const LoadProblem problem = plain.WithCoupling(Bending(plain, Pin(Liu().material)));
    const LoadResult r = Agree(problem, ContactKinematics::kLinearised);
    const LoadResult u = SolveWith("bisection", plain, ContactKinematics::kLinearised);
    REQUIRE(u.status == SolverStatus::kSuccess);
    CHECK(std::abs(r.te) > 1.05 * std::abs(u.te));
    // The most loaded pin: its end slices carry more than its middle ones.
    const auto top = static_cast<std::size_t>(std::max_element(r.force.begin(), r.force.end()) - r.force.begin()) / 10;
    CHECK(r.force[top * 10] > r.force[top * 10 + 5]);
    CHECK(r.force[top * 10 + 9] > r.force[top * 10 + 4]);
  }
}

TEST_CASE("solvers: coupled compliance - the plane model with pin bending or neighbours coupled: the solvers agree under both kinematics") {
  // One slice per pin (the face as a whole: a diagonal coupling from the beam), and the 40-pin
  // ring of neighbouring pins of the energy-qp test above, on Liu Table 1; linearised and exact.
  const Eigen::SparseMatrix<double> ring = NeighbourRing(LiuModel()->pin_count());
  for (const auto kinematics : {ContactKinematics::kLinearised, ContactKinematics::kExact}) {
    for (const double crank : {0.9, 3.3}) {
      CAPTURE(static_cast<int>(kinematics));
      CAPTURE(crank);
      const LoadProblem plain = Liu().Problem(LiuModel(), ltca::units::DegToRad(crank), kinematics);
      Agree(plain.WithCoupling(Bending(plain, Pin(Liu().material))), kinematics);
      Agree(plain.WithCoupling(ring), kinematics);
    }
  }
}

TEST_CASE("solvers: coupled compliance - a stiff pin (E x 1e6) gives the uncoupled answer") {
  // The beam's compliance scales with 1 / E: at E x 1e6 the coupled slice model is the uncoupled
  // one to within 1e-6 (TE relative, forces of the largest), for both coupled solvers.
  ltca::contact::Material stiff = Liu().material;
  stiff.pin_young_modulus *= 1e6;
  for (const double crank : {0.0, 2.2}) {
    CAPTURE(crank);
    const LoadProblem plain = SlicedProblem(crank, 4);
    const LoadResult u = SolveWith("bisection", plain, ContactKinematics::kLinearised);
    REQUIRE(u.status == SolverStatus::kSuccess);
    const LoadProblem problem = plain.WithCoupling(Bending(plain, Pin(stiff)));
    for (const std::string name : {"bisection", "compatibility"}) {
      CAPTURE(name);
      const LoadResult r = SolveWith(name, problem, ContactKinematics::kLinearised);
      REQUIRE(r.status == SolverStatus::kSuccess);
      CHECK(std::abs(r.te - u.te) <= 1e-6 * std::abs(u.te));
      CHECK(MaxDifference(r.force, u.force) <= 1e-6 * MaxForce(u.force));
    }
  }
}

TEST_CASE("solvers: coupled compliance - 40 pins x 20 slices with pin bending: bisection and compatibility agree over a mesh period") {
  // The size issue 11 aims at (800 points, 40 dense 20 x 20 blocks), linearised, 10 positions of
  // one mesh period, one workspace per solver as in a sweep. The time per position is printed
  // (not asserted: machines differ); LoadResult::wall_seconds includes the shared judge.
  ltca::solvers::Workspace bisection_ws, compatibility_ws;
  double seconds[2] = {0.0, 0.0}, wall[2] = {0.0, 0.0}, worst_te = 0.0, worst_force = 0.0;
  double factorisations[2] = {0.0, 0.0}, solves[2] = {0.0, 0.0};
  const int positions = 10;
  for (int k = 0; k < positions; ++k) {
    const double crank = 9.0 * k / positions;
    CAPTURE(crank);
    const LoadProblem plain = SlicedProblem(crank, 20);
    const LoadProblem problem = plain.WithCoupling(Bending(plain, Pin(Liu().material)));
    LoadResult r[2];
    ltca::solvers::Workspace* ws[2] = {&bisection_ws, &compatibility_ws};
    const char* names[2] = {"bisection", "compatibility"};
    for (int s = 0; s < 2; ++s) {
      const auto start = std::chrono::steady_clock::now();
      r[s] = SolveWith(names[s], problem, ContactKinematics::kLinearised, ws[s]);
      seconds[s] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      wall[s] += r[s].wall_seconds;
      factorisations[s] += r[s].details.at("factorisations");
      solves[s] += r[s].details.at("solves");
      REQUIRE(r[s].status == SolverStatus::kSuccess);
      CHECK(r[s].residuals.Normalised() < 1e-8);
    }
    const double te_error = std::abs(r[1].te - r[0].te) / std::abs(r[0].te);
    const double force_error = MaxDifference(r[1].force, r[0].force) / MaxForce(r[0].force);
    CHECK(te_error <= 1e-6);
    CHECK(force_error <= 1e-6);
    worst_te = std::max(worst_te, te_error);
    worst_force = std::max(worst_force, force_error);
  }
  MESSAGE("800 points with pin bending, linearised, per position: bisection ", 1e3 * seconds[0] / positions, " ms (",
          factorisations[0] / positions, " factorisations, ", solves[0] / positions, " solves), compatibility ",
          1e3 * seconds[1] / positions, " ms (", factorisations[1] / positions, " factorisations, ",
          solves[1] / positions, " solves); LoadResult::wall_seconds ", 1e3 * wall[0] / positions,
          " / ", 1e3 * wall[1] / positions, " ms; TE agrees to ", worst_te, ", forces to ", worst_force);
}
