#include "ltca/solvers/load_problem.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <fmt/format.h>

namespace ltca::solvers {
namespace {

contact::ContactLaw MakeLaw(const contact::ContactSettings& settings, const contact::Material& material,
                            const contact::PinContact& pin, double length, double cap) {
  // An edge contact has no curvature: give it a placeholder law; solvers check `edge` first.
  const double curvature = pin.edge ? 0.0 : pin.cycloid_curvature;
  return contact::ContactLaw(settings, material, curvature, pin.pin_radius, length, cap);
}

std::uint64_t NextProblemId() {
  static std::atomic<std::uint64_t> next{1};
  return next.fetch_add(1, std::memory_order_relaxed);
}

LoadProblem::ModelPtr Require(LoadProblem::ModelPtr model) {
  if (model == nullptr) throw std::invalid_argument("LoadProblem: no mesh model");
  return model;
}

// The checked, symmetrised coupling (LoadProblem::WithCoupling), or nullptr for none.
std::shared_ptr<const Eigen::SparseMatrix<double>> CheckPositiveSemidefinite(
    std::shared_ptr<Eigen::SparseMatrix<double>> sym, int pins);

// psd_known: positive semidefinite by construction (a factored coupling whose K was checked), so
// the O(n^3) check of C is skipped.
std::shared_ptr<const Eigen::SparseMatrix<double>> CheckCouplingMatrix(Eigen::SparseMatrix<double> c, int pins,
                                                                       bool psd_known = false) {
  if (c.rows() == 0 && c.cols() == 0) return nullptr;
  if (c.rows() != c.cols()) {
    throw std::invalid_argument(fmt::format("LoadProblem coupling: {} x {} is not square", c.rows(), c.cols()));
  }
  if (c.rows() != pins) {
    throw std::invalid_argument(
        fmt::format("LoadProblem coupling: {} x {} does not match the {} pins", c.rows(), c.cols(), pins));
  }
  c.makeCompressed();
  double largest = 0.0;
  for (int k = 0; k < c.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(c, k); it; ++it) {
      if (!std::isfinite(it.value())) {
        throw std::invalid_argument(fmt::format("LoadProblem coupling: entry ({}, {}) = {} is not finite",
                                                it.row() + 1, it.col() + 1, it.value()));
      }
      largest = std::max(largest, std::abs(it.value()));
    }
  }
  const Eigen::SparseMatrix<double> transposed = c.transpose();
  // A structurally symmetric C (pin bending's blocks): the mirror of the entry at position p is
  // the transpose's entry at p, so the check and (C + C^T) / 2 are single passes (the same
  // numbers as the general path below, without its searches and sparse sums).
  const auto outer_size = static_cast<std::size_t>(c.outerSize());
  if (transposed.nonZeros() == c.nonZeros() &&
      std::equal(c.outerIndexPtr(), c.outerIndexPtr() + outer_size + 1, transposed.outerIndexPtr()) &&
      std::equal(c.innerIndexPtr(), c.innerIndexPtr() + c.nonZeros(), transposed.innerIndexPtr())) {
    const double* cv = c.valuePtr();
    const double* tv = transposed.valuePtr();
    for (int k = 0; k < c.outerSize(); ++k) {
      for (int p = c.outerIndexPtr()[k]; p < c.outerIndexPtr()[k + 1]; ++p) {
        if (std::abs(cv[p] - tv[p]) > 1e-12 * largest) {
          const int row = c.innerIndexPtr()[p];
          throw std::invalid_argument(fmt::format(
              "LoadProblem coupling: not symmetric: entry ({}, {}) = {} but ({}, {}) = {} (relative tolerance 1e-12)",
              row + 1, k + 1, cv[p], k + 1, row + 1, tv[p]));
        }
      }
    }
    auto sym = std::make_shared<Eigen::SparseMatrix<double>>(std::move(c));
    double* sv = sym->valuePtr();
    for (Eigen::Index p = 0; p < sym->nonZeros(); ++p) sv[p] = 0.5 * (sv[p] + tv[p]);
    sym->prune(0.0);
    sym->makeCompressed();
    if (sym->nonZeros() == 0) return nullptr;
    if (psd_known) return sym;
    return CheckPositiveSemidefinite(std::move(sym), pins);
  }
  for (int k = 0; k < c.outerSize(); ++k) {
    for (Eigen::SparseMatrix<double>::InnerIterator it(c, k); it; ++it) {
      const double mirror = transposed.coeff(it.row(), it.col());
      if (std::abs(it.value() - mirror) > 1e-12 * largest) {
        throw std::invalid_argument(fmt::format(
            "LoadProblem coupling: not symmetric: entry ({}, {}) = {} but ({}, {}) = {} (relative tolerance 1e-12)",
            it.row() + 1, it.col() + 1, it.value(), it.col() + 1, it.row() + 1, mirror));
      }
    }
  }
  auto sym = std::make_shared<Eigen::SparseMatrix<double>>(0.5 * (c + transposed));
  sym->prune(0.0);  // drops the explicit zeros: they would only widen energy-qp's Hessian
  sym->makeCompressed();
  if (sym->nonZeros() == 0) return nullptr;
  if (psd_known) return sym;
  return CheckPositiveSemidefinite(std::move(sym), pins);
}

std::shared_ptr<const Eigen::SparseMatrix<double>> CheckPositiveSemidefinite(
    std::shared_ptr<Eigen::SparseMatrix<double>> sym, int pins) {
  // Positive semidefinite, against the rounding of a few n eps of the matrix's scale. Up to
  // kDenseLimit pins: the smallest eigenvalue of the dense matrix (exact, O(n^3)). Beyond (a
  // deck may have 10,000 pins): C + tol I must be positive definite, i.e. lambda_min > -tol, by a
  // sparse LDL^T whose pivots must all be positive (tol against the largest absolute row sum,
  // a bound of the largest eigenvalue).
  constexpr int kDenseLimit = 200;
  const double rounding = std::max(1e-12, 8.0 * pins * std::numeric_limits<double>::epsilon());
  if (pins <= kDenseLimit) {
    const Eigen::MatrixXd dense = Eigen::MatrixXd(*sym);
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(dense, Eigen::EigenvaluesOnly);
    if (eigen.info() != Eigen::Success) {
      throw std::invalid_argument("LoadProblem coupling: its eigenvalues could not be computed");
    }
    const Eigen::VectorXd& lambda = eigen.eigenvalues();  // ascending
    const double scale = std::max(std::abs(lambda(0)), std::abs(lambda(lambda.size() - 1)));
    if (lambda(0) < -rounding * scale) {
      throw std::invalid_argument(fmt::format(
          "LoadProblem coupling: not positive semidefinite: smallest eigenvalue {:.6g} (largest {:.6g}) mm/N",
          lambda(0), lambda(lambda.size() - 1)));
    }
  } else {
    Eigen::VectorXd row_sum = Eigen::VectorXd::Zero(pins);
    for (Eigen::Index k = 0; k < sym->outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(*sym, k); it; ++it) row_sum(it.row()) += std::abs(it.value());
    }
    const double tol = rounding * row_sum.maxCoeff();
    Eigen::SparseMatrix<double> identity(pins, pins);
    identity.setIdentity();
    const Eigen::SparseMatrix<double> shifted = *sym + tol * identity;
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(shifted);
    if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().minCoeff() > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "LoadProblem coupling: not positive semidefinite: C + {:.3g} I has a non-positive LDL^T pivot", tol));
    }
  }
  return sym;
}

}  // namespace

LoadProblem::LoadProblem(const contact::MeshModel& model, double crank, const contact::ContactSettings& contact,
                         const contact::Material& material, double torque, contact::ContactKinematics kinematics)
    : LoadProblem(std::make_shared<const contact::MeshModel>(model), crank, contact, material, torque, kinematics) {}

LoadProblem::LoadProblem(const contact::MeshModel& model, contact::MeshState state,
                         const contact::ContactSettings& contact, const contact::Material& material, double torque)
    : LoadProblem(std::make_shared<const contact::MeshModel>(model), std::move(state), contact, material, torque) {}

LoadProblem::LoadProblem(ModelPtr model, double crank,
                         const contact::ContactSettings& contact, const contact::Material& material,
                         double torque, contact::ContactKinematics kinematics)
    : model_(Require(std::move(model))),
      id_(NextProblemId()),
      crank_(crank),
      contact_(contact),
      material_(material),
      torque_(std::abs(torque)),
      direction_(torque < 0.0 ? -1.0 : 1.0),
      kinematics_(kinematics),
      log_radius_cap_(contact.log_radius_cap > 0.0 ? contact.log_radius_cap
                                                   : model_->pair().pin_circle_radius),
      base_(model_->Evaluate(crank, 0.0)) {
  BuildBaseLaws();
}

LoadProblem::LoadProblem(ModelPtr model, contact::MeshState state,
                         const contact::ContactSettings& contact, const contact::Material& material, double torque)
    : LoadProblem(std::move(model), std::move(state), contact, material, torque, contact::ContactKinematics::kLinearised) {}

LoadProblem::LoadProblem(ModelPtr model, contact::MeshState state, const contact::ContactSettings& contact,
                         const contact::Material& material, double torque, contact::ContactKinematics kinematics)
    : LoadProblem(std::move(model), nullptr, std::move(state), contact, material, torque, kinematics) {}

LoadProblem::LoadProblem(ModelPtr first, ModelPtr second, double crank, const contact::ContactSettings& contact,
                         const contact::Material& material, double torque, contact::ContactKinematics kinematics)
    : LoadProblem(first, Require(second),
                  contact::EvaluateTwoDiscs(*Require(first), *second, crank, 0.0), contact, material, torque,
                  kinematics) {}

LoadProblem::LoadProblem(ModelPtr first, ModelPtr second, contact::MeshState evaluated,
                         const contact::ContactSettings& contact, const contact::Material& material, double torque,
                         contact::ContactKinematics kinematics)
    : model_(Require(std::move(first))),
      second_(std::move(second)),  // nullptr: one disc (the constructor above delegates here)
      id_(NextProblemId()),
      crank_(evaluated.crank),
      contact_(contact),
      material_(material),
      torque_(std::abs(torque)),
      direction_(torque < 0.0 ? -1.0 : 1.0),
      kinematics_(kinematics),
      log_radius_cap_(contact.log_radius_cap > 0.0 ? contact.log_radius_cap : model_->pair().pin_circle_radius),
      base_(std::move(evaluated)) {
  if (second_) contact::RequireSamePinRing(*model_, *second_);
  BuildBaseLaws();
}

LoadProblem LoadProblem::LinearisedOn(contact::MeshState state) const {
  if (second_ != nullptr) {
    return LoadProblem(model_, second_, std::move(state), contact_, material_, torque_,
                       contact::ContactKinematics::kLinearised);
  }
  return LoadProblem(model_, std::move(state), contact_, material_, torque_);
}

LoadProblem LoadProblem::Linearised() const {
  if (coupling_ != nullptr || reducer_ != nullptr) {
    throw std::logic_error("LoadProblem::Linearised: an uncoupled mesh problem expected");
  }
  LoadProblem out = *this;
  out.id_ = NextProblemId();
  out.kinematics_ = contact::ContactKinematics::kLinearised;
  out.reach_.clear();
  out.ComputeClosings();  // of the linearised kinematics: c / L
  return out;
}

void LoadProblem::ComputeClosings() {
  const double min_arm = 1e-9 * model_->pair().pin_circle_radius;
  first_contact_ = INFINITY;
  closing_.assign(base_.pins.size(), INFINITY);
  for (std::size_t i = 0; i < base_.pins.size(); ++i) {
    if (base_.pins[i].arm <= min_arm) continue;
    closing_[i] = Closing(base_.pins[i]);
    first_contact_ = std::min(first_contact_, closing_[i]);
  }
  // Pin m alone reaches the torque at its closing rotation plus w_m(T / L_m) / L_m (exact for
  // linearised kinematics; to first order in the deformation for exact kinematics).
  single_pin_ = SinglePinBound();
}

std::vector<double> LoadProblem::DiscTorques(double psi, const std::vector<double>& forces,
                                             Workspace& workspace) const {
  std::vector<contact::ContactLaw> scratch;
  const auto pins = At(psi, workspace, &scratch);
  std::vector<double> out(static_cast<std::size_t>(disc_count()), 0.0);
  for (std::size_t i = 0; i < pins.size() && i < forces.size(); ++i) {
    out[static_cast<std::size_t>(base_.pins[i].disc)] += direction_ * forces[i] * pins[i].arm;
  }
  return out;
}

LoadProblem LoadProblem::WithCoupling(Eigen::SparseMatrix<double> coupling) const {
  return WithCoupling(CheckCoupling(std::move(coupling), point_count()));
}

LoadProblem::CheckedCoupling LoadProblem::CheckCoupling(Eigen::SparseMatrix<double> coupling, int points) {
  return {CheckCouplingMatrix(std::move(coupling), points), points, nullptr, nullptr};
}

LoadProblem::CheckedCoupling LoadProblem::CheckCoupling(Eigen::SparseMatrix<double> coupling, int points,
                                                        PositiveSemidefiniteByConstruction) {
  return {CheckCouplingMatrix(std::move(coupling), points, true), points, nullptr, nullptr};
}

LoadProblem::CheckedCoupling LoadProblem::CheckCoupling(Eigen::MatrixXd c, int points, PositiveSemidefiniteByConstruction) {
  // The dense twin of CheckCouplingMatrix (psd_known): the same checks and the same stored numbers.
  if (c.rows() == 0 && c.cols() == 0) return {nullptr, points, nullptr, nullptr};
  if (c.rows() != c.cols()) {
    throw std::invalid_argument(fmt::format("LoadProblem coupling: {} x {} is not square", c.rows(), c.cols()));
  }
  if (c.rows() != points) {
    throw std::invalid_argument(
        fmt::format("LoadProblem coupling: {} x {} does not match the {} pins", c.rows(), c.cols(), points));
  }
  const Eigen::Index n = c.rows();
  if (!c.allFinite()) {
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = 0; i < n; ++i) {
        if (!std::isfinite(c(i, j))) {
          throw std::invalid_argument(
              fmt::format("LoadProblem coupling: entry ({}, {}) = {} is not finite", i + 1, j + 1, c(i, j)));
        }
      }
    }
  }
  const double largest = c.cwiseAbs().maxCoeff();
  // (C + C^T) / 2 in place: entry by entry the sparse path's 0.5 (c_ij + c_ji) (an entry whose
  // mirror is zero: 0.5 (c_ij + 0), as its sum with the transpose gives); the diagonal's
  // 0.5 (c_ii + c_ii) is c_ii exactly.
  Eigen::Index stored = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    for (Eigen::Index i = j + 1; i < n; ++i) {
      const double a = c(i, j), b = c(j, i);
      if (std::abs(a - b) > 1e-12 * largest) {
        throw std::invalid_argument(fmt::format(
            "LoadProblem coupling: not symmetric: entry ({}, {}) = {} but ({}, {}) = {} (relative tolerance 1e-12)",
            i + 1, j + 1, a, j + 1, i + 1, b));
      }
      c(i, j) = c(j, i) = 0.5 * (a + b);
      if (c(i, j) != 0.0) stored += 2;
    }
    if (c(j, j) != 0.0) ++stored;
  }
  if (stored == 0) return {nullptr, points, nullptr, nullptr};
  // The sparse matrix without its zeros, column by column (compressed, rows ascending).
  auto sparse = std::make_shared<Eigen::SparseMatrix<double>>(n, n);
  sparse->resizeNonZeros(stored);
  int* outer = sparse->outerIndexPtr();
  int* inner = sparse->innerIndexPtr();
  double* value = sparse->valuePtr();
  int p = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    outer[j] = p;
    const double* column = c.col(j).data();
    for (Eigen::Index i = 0; i < n; ++i) {
      if (column[i] != 0.0) inner[p] = static_cast<int>(i), value[p] = column[i], ++p;
    }
  }
  outer[n] = p;
  return {std::move(sparse), points, nullptr, std::make_shared<const Eigen::MatrixXd>(std::move(c))};
}

LoadProblem::CheckedCoupling LoadProblem::CheckCoupling(Eigen::SparseMatrix<double> coupling, int points,
                                                        CouplingFactors factors) {
  const Eigen::Index dofs = factors.stiffness.rows();
  if (factors.stiffness.cols() != dofs || factors.loads.rows() != points || factors.loads.cols() != dofs ||
      factors.local.size() != points || !factors.local.allFinite() || (factors.local.array() < 0.0).any()) {
    throw std::invalid_argument(fmt::format(
        "LoadProblem coupling factors: K {} x {}, loads {} x {}, local {} do not fit {} points",
        factors.stiffness.rows(), factors.stiffness.cols(), factors.loads.rows(), factors.loads.cols(),
        factors.local.size(), points));
  }
  // C = B K^-1 B^T + E is positive semidefinite when K is positive definite and E >= 0: K's
  // LDL^T (banded, O(dofs)) replaces the O(n^3) check of C.
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::NaturalOrdering<int>> k_ldlt(
      factors.stiffness);
  if (k_ldlt.info() != Eigen::Success || !(k_ldlt.vectorD().minCoeff() > 0.0)) {
    throw std::invalid_argument("LoadProblem coupling factors: K is not positive definite");
  }
  CheckedCoupling out{CheckCouplingMatrix(std::move(coupling), points, true), points, nullptr, nullptr};
  if (out.matrix == nullptr) return out;
  factors.stiffness.makeCompressed();
  factors.loads.makeCompressed();
  out.factors = std::make_shared<const CouplingFactors>(std::move(factors));
  return out;
}

LoadProblem LoadProblem::WithCoupling(const CheckedCoupling& coupling) const {
  if (coupling.points != point_count()) {
    throw std::invalid_argument(fmt::format("LoadProblem coupling: checked for {} points, the problem has {}",
                                            coupling.points, point_count()));
  }
  // Two discs in the mesh alone take a coupling within each disc only (each disc's elastic body:
  // its points on its own); pin bending, whose beams would couple both discs' contacts on one pin,
  // is not supported with two discs. In a stage the reducer system's coupled set takes any.
  if (second_ != nullptr && coupling.matrix != nullptr && reducer_ == nullptr) {
    const Eigen::SparseMatrix<double>& c = *coupling.matrix;
    for (int k = 0; k < c.outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(c, k); it; ++it) {
        const contact::PinContact& a = base_.pins[static_cast<std::size_t>(it.row())];
        const contact::PinContact& b = base_.pins[static_cast<std::size_t>(it.col())];
        if (a.disc == b.disc || it.value() == 0.0) continue;
        throw std::invalid_argument(fmt::format(
            "LoadProblem coupling: point {} (pin {} of disc {}) couples with point {} (pin {} of disc {}): two discs take "
            "a coupling within each disc only (pin bending, which couples both discs' contacts on a pin, is not "
            "supported with two discs)",
            it.row(), a.pin + 1, a.disc + 1, it.col(), b.pin + 1, b.disc + 1));
      }
    }
  }
  LoadProblem out(*this);
  out.coupling_ = coupling.matrix;
  out.coupling_factors_ = coupling.matrix != nullptr ? coupling.factors : nullptr;
  out.coupling_dense_ = coupling.matrix != nullptr ? coupling.dense : nullptr;
  out.stage_body_ = nullptr;  // made for the coupling it replaces
  out.single_pin_ = out.SinglePinBound();
  return out;
}

LoadProblem LoadProblem::WithLawScales(const std::vector<double>& scales) const {
  if (!scalable_laws()) {
    throw std::invalid_argument(
        "LoadProblem::WithLawScales: expected linearised kinematics without a coupling or a stage (their laws are "
        "rebuilt or are not the mesh's alone)");
  }
  if (scales.size() != base_laws_.size()) {
    throw std::invalid_argument(fmt::format("LoadProblem::WithLawScales: {} scales for {} points", scales.size(),
                                            base_laws_.size()));
  }
  LoadProblem out(*this);
  for (std::size_t i = 0; i < scales.size(); ++i) {
    if (!(std::isfinite(scales[i]) && scales[i] > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "LoadProblem::WithLawScales: point {} (pin {}) has scale {}: expected a finite number above 0", i,
          base_.pins[i].pin + 1, scales[i]));
    }
    out.base_laws_[i] = base_laws_[i].Scaled(scales[i]);
  }
  out.single_pin_ = out.SinglePinBound();  // the closing rotations are geometry's; this bound is the laws'
  return out;
}

LoadProblem LoadProblem::WithReducer(std::shared_ptr<const ReducerSettings> stage) const {
  if (stage != nullptr) stage->Validate(model_->pair().eccentricity);
  LoadProblem out(*this);
  out.reducer_ = std::move(stage);
  return out;
}

LoadProblem LoadProblem::WithStageLoads(StageLoads loads) const {
  if (reducer_ == nullptr) throw std::invalid_argument("LoadProblem::WithStageLoads: expected a problem with a stage");
  if (loads.discs.size() > static_cast<std::size_t>(disc_count())) {
    throw std::invalid_argument(fmt::format("LoadProblem::WithStageLoads: loads on {} discs, the stage has {}",
                                            loads.discs.size(), disc_count()));
  }
  bool finite = std::isfinite(loads.output_moment);
  for (const StageLoads::Disc& d : loads.discs) finite = finite && d.force.allFinite() && std::isfinite(d.moment);
  if (!finite) throw std::invalid_argument("LoadProblem::WithStageLoads: expected finite loads");
  LoadProblem out(*this);
  out.stage_loads_ = std::make_shared<const StageLoads>(std::move(loads));
  return out;
}

LoadProblem LoadProblem::WithStageBodyCoupling(StageBodyCoupling coupling) const {
  // A stage of output pins (one contact per pin of every disc), or a stage of crankshafts on
  // needle rollers (one contact per roller of every crank bearing of every disc).
  const bool pins = reducer_ != nullptr && reducer_->kind == OutputKind::kPins;
  const bool rollers = reducer_ != nullptr && reducer_->kind == OutputKind::kCranks &&
                       reducer_->bearing.kind == contact::BearingKind::kRollers;
  if (!pins && !rollers) {
    throw std::invalid_argument(
        "LoadProblem::WithStageBodyCoupling: expected a stage of output pins or a stage of crankshafts on roller "
        "bearings");
  }
  if (coupling_ == nullptr || !coupling.total || !coupling.body) {
    throw std::invalid_argument("LoadProblem::WithStageBodyCoupling: expected the problem's coupling and both matrices");
  }
  const int elements =
      disc_count() * (pins ? reducer_->pins.count : reducer_->cranks.count * reducer_->bearing.roller_count);
  const Eigen::Index n = point_count() + coupling.output_points;
  if (coupling.output_points != elements || coupling.total->rows() != n || coupling.total->cols() != n ||
      coupling.body->rows() != n || coupling.body->cols() != n) {
    throw std::invalid_argument(fmt::format(
        "LoadProblem::WithStageBodyCoupling: expected {} x {} matrices (the points and {} {})", n, n, elements,
        pins ? "output pins" : "needle rollers"));
  }
  if (!Eigen::MatrixXd(coupling.total->topLeftCorner(point_count(), point_count()) - *coupling_).isZero(0.0)) {
    throw std::invalid_argument("LoadProblem::WithStageBodyCoupling: the top-left block is not the problem's coupling");
  }
  LoadProblem out(*this);
  out.stage_body_ = std::make_shared<const StageBodyCoupling>(std::move(coupling));
  return out;
}

double LoadProblem::SinglePinBound() const {
  // As in BuildBaseLaws, with the coupling's terms when there is one (LoadedRotationRange).
  const double min_arm = 1e-9 * model_->pair().pin_circle_radius;
  const std::size_t n = base_.pins.size();
  // Per pin m: the largest C_mj / L_j over the other pins j that can carry load (positive part).
  std::vector<double> pull(n, 0.0), self(n, 0.0);
  if (coupling_ != nullptr) {
    for (int k = 0; k < coupling_->outerSize(); ++k) {
      for (Eigen::SparseMatrix<double>::InnerIterator it(*coupling_, k); it; ++it) {
        const auto m = static_cast<std::size_t>(it.row()), j = static_cast<std::size_t>(it.col());
        if (m == j) {
          self[m] = it.value();
        } else if (!base_.pins[j].edge && base_.pins[j].arm > min_arm) {
          pull[m] = std::max(pull[m], it.value() / base_.pins[j].arm);
        }
      }
    }
  }
  double bound = INFINITY;
  for (std::size_t i = 0; i < n; ++i) {
    const auto& pin = base_.pins[i];
    if (pin.arm <= min_arm || pin.edge) continue;
    const double closing = closing_[i];
    const double force = torque_ / pin.arm;
    const double deflection =
        coupling_ == nullptr ? base_laws_[i].Approach(force)
                             : base_laws_[i].Approach(force) + self[i] * force + pull[i] * torque_;
    bound = std::min(bound, closing + deflection / pin.arm);
  }
  return bound;
}

double LoadProblem::Closing(const contact::PinContact& pin) const {
  contact::PinContact in_model_frame = pin;  // ClosingRotation works in the model's direction
  in_model_frame.arm *= direction_;
  return direction_ * contact::ClosingRotation(DiscModel(pin.disc), in_model_frame, DiscCrank(pin.disc), kinematics_);
}

void LoadProblem::BuildBaseLaws() {
  if (!std::isfinite(torque_)) throw std::invalid_argument("LoadProblem: the torque must be finite");
  // The frame of the torque: a negative torque turns the cycloid the other way (coast flank).
  for (auto& pin : base_.pins) {
    if (pin.disc != 0 && (pin.disc != 1 || second_ == nullptr)) {
      throw std::invalid_argument(fmt::format("LoadProblem: pin {} belongs to disc {}, the problem has {}", pin.pin + 1,
                                              pin.disc + 1, disc_count() == 1 ? "one disc" : "two discs"));
    }
    if (!(pin.length > 0.0)) {
      throw std::invalid_argument(fmt::format("LoadProblem: the contact point of pin {}, slice {} has contact length {} mm: expected > 0",
                                              pin.pin + 1, pin.slice, pin.length));
    }
    pin.arm *= direction_;
  }
  base_laws_.reserve(base_.pins.size());
  for (const auto& pin : base_.pins) {
    base_laws_.push_back(MakeLaw(contact_, material_, pin, pin.length, log_radius_cap_));
  }
  // Closing rotation of every pin that can close in the load direction (a pin whose arm is zero
  // to rounding closes only after a rotation far beyond any other: skipped), computed once and
  // kept: the first contact and the single-pin bound of the judge's range (LoadedRotationRange)
  // come from it, here and again in WithCoupling.
  ComputeClosings();
  // The rate bound of At's Freshness::kLoadedOnly: turning the disc by psi about its centre moves
  // a pin's centre, in the disc's frame, along a circle of radius rho; the gap (its distance to
  // the profile, less the pin radius and a layer constant in psi) moves by at most rho |psi|.
  // Analytic surface only: the element surface's gap is measured to the element facing the pin.
  reach_.clear();
  const bool analytic = model_->discrete() == nullptr && (second_ == nullptr || second_->discrete() == nullptr);
  if (kinematics_ == contact::ContactKinematics::kExact && analytic) {
    reach_.reserve(base_.pins.size());
    int disc = -1;
    double z = NAN;
    Eigen::Vector2d centre = Eigen::Vector2d::Zero();
    for (const auto& pin : base_.pins) {
      const contact::MeshModel& model = DiscModel(pin.disc);
      if (pin.disc != disc || !(pin.z == z)) {  // the disc's centre, once for its points of one section
        disc = pin.disc, z = pin.z;
        centre = model.CyclePose(DiscCrank(pin.disc), 0.0, pin.z).centre;
      }
      const double rho = (model.PinCentre(pin.pin) - centre).norm();
      reach_.push_back(rho * (1.0 + 1e-9));  // a margin over the rounding of rho
    }
  }
}

std::vector<LoadProblem::PinAt> LoadProblem::At(double psi, Workspace& workspace,
                                                std::vector<contact::ContactLaw>* scratch) const {
  std::vector<PinAt> out;
  At(psi, workspace, scratch, &out);
  return out;
}

void LoadProblem::At(double psi, Workspace& workspace, std::vector<contact::ContactLaw>* scratch,
                     std::vector<PinAt>* pins) const {
  At(psi, workspace, scratch, pins, Freshness::kAll);
}

void LoadProblem::At(double psi, Workspace& workspace, std::vector<contact::ContactLaw>* scratch,
                     std::vector<PinAt>* pins, Freshness freshness) const {
  std::vector<PinAt>& out = *pins;
  out.resize(base_.pins.size());
  if (kinematics_ == contact::ContactKinematics::kLinearised) {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto& pin = base_.pins[i];
      out[i] = {contact::LinearisedApproach(pin, psi), pin.arm, pin.edge, pin.edge ? nullptr : &base_laws_[i]};
    }
    return;
  }
  // Re-evaluate every pin at the rotated pose, searched from its last foot point; build laws only
  // for the pins that are pressed (the others carry no force).
  Workspace::FootPoints& feet = BoundFootPoints(workspace);
  scratch->clear();
  scratch->reserve(out.size());
  const bool skip = freshness != Freshness::kAll && !reach_.empty();
  const bool near = freshness == Freshness::kNear && !reach_.empty();
  // What a fresh search could still resolve as closed (GapResolution), with a margin.
  const double margin = 4.0 * GapResolution();
  PoseAt pose;  // the disc's pose at psi, taken once for the pins of a disc and section
  for (std::size_t i = 0; i < out.size(); ++i) {
    contact::PinContact& pin = feet.last[i];
    if (feet.at[i] != psi) {  // (the judge and the sweep ask for the answer again: kept)
      const double closest = skip && std::isfinite(feet.at[i])
                                 ? pin.clearance - reach_[i] * std::abs(psi - feet.at[i])
                                 : -INFINITY;
      if (closest > margin) {  // cannot be closed at psi: no search (Freshness::kLoadedOnly)
        out[i] = {-closest, pin.arm, pin.edge, pin.edge ? nullptr : &base_laws_[i]};
        continue;
      }
      if (near && std::isfinite(feet.at[i])) {  // clearly open on its extrapolation (Freshness::kNear)
        const double move = psi - feet.at[i];
        const double estimate = pin.arm * move - pin.clearance;
        if (estimate < -(0.5 * std::abs(pin.arm * move) + reach_[i] * reach_[i] * move * move + margin)) {
          out[i] = {estimate, pin.arm, pin.edge, pin.edge ? nullptr : &base_laws_[i]};
          continue;
        }
      }
      SearchPin(feet, i, psi, &pose);
    }
    out[i] = {-pin.clearance, pin.arm, pin.edge, nullptr};
    if (!pin.edge && pin.clearance < 0.0) {
      if (!feet.law[i]) feet.law[i] = LawOf(pin);
      scratch->push_back(*feet.law[i]);
      out[i].law = &scratch->back();  // stable: reserved above
    } else if (!pin.edge) {
      out[i].law = &base_laws_[i];  // unloaded: any law of this pin gives zero force
    }
  }
}

Workspace::FootPoints& LoadProblem::BoundFootPoints(Workspace& workspace) const {
  Workspace::FootPoints& feet = workspace.foot_points();
  if (feet.problem != id_) {
    feet.problem = id_;
    feet.last = base_.pins;
    // The base state is the exact geometry at psi = 0 (the unloaded pose): where the rate bound of
    // Freshness::kLoadedOnly applies (reach_), the first trial need not search a pin whose gap
    // there is beyond the reach of its rotation from 0.
    const bool at_zero = !reach_.empty() && base_.loaded_rotation == 0.0;
    feet.at.assign(base_.pins.size(), at_zero ? 0.0 : std::numeric_limits<double>::quiet_NaN());
    feet.slope.assign(base_.pins.size(), std::numeric_limits<double>::quiet_NaN());
    feet.law.assign(base_.pins.size(), std::nullopt);  // built where a pressed pin asks for its law
  }
  return feet;
}

const std::vector<contact::PinContact>& LoadProblem::ExactPins(double psi, Workspace& workspace) const {
  Workspace::FootPoints& feet = BoundFootPoints(workspace);
  PoseAt pose;
  for (std::size_t i = 0; i < feet.last.size(); ++i) {
    if (feet.at[i] == psi) continue;
    SearchPin(feet, i, psi, &pose);
  }
  return feet.last;
}

contact::PinContact LoadProblem::EvaluatePin(const contact::PinContact& near, double psi) const {
  return EvaluatePin(near, psi, Eigen::Vector2d::Zero());
}

contact::PinContact LoadProblem::EvaluatePin(const contact::PinContact& near, double phi,
                                             const Eigen::Vector2d& centre_shift) const {
  contact::PinContact pin =
      DiscModel(near.disc).EvaluatePoint(near, DiscCrank(near.disc), direction_ * phi, centre_shift);
  pin.disc = near.disc;
  pin.arm *= direction_;
  return pin;
}

contact::PinContact LoadProblem::EvaluatePin(const contact::PinContact& near, double psi, PoseAt* pose) const {
  const contact::MeshModel& model = DiscModel(near.disc);
  const double crank = DiscCrank(near.disc);
  if (near.disc != pose->disc || !(near.z == pose->z)) {
    *pose = {near.disc, near.z, model.CyclePose(crank, direction_ * psi, near.z).Frame()};
  }
  // near is a contact of this pin at this problem's crank (the base state's, or a search's from
  // it), so its angle from the line of centres is the one a search would compute again.
  contact::PinContact pin = model.EvaluatePointInFrame(near, pose->frame, near.angle);
  pin.disc = near.disc;
  pin.arm *= direction_;
  return pin;
}

void LoadProblem::SearchPin(Workspace::FootPoints& feet, std::size_t i, double psi, PoseAt* pose) const {
  // The foot parameter moves smoothly with psi: start the search from its secant extrapolation,
  // u + (du/dpsi) (psi - psi_last), where the last two searches of this pin stayed in one tooth
  // space; the Newton search converges to the same foot point from either start, in fewer steps
  // from the nearer one. A start moved by more than 1 % of a tooth pitch is not trusted.
  const contact::PinContact& last = feet.last[i];
  contact::PinContact near = last;
  const double move = feet.slope[i] * (psi - feet.at[i]);
  if (std::abs(move) <= 0.01 * DiscModel(last.disc).profile().tooth_pitch()) {  // false for a NaN slope
    near.u += move;
  }
  contact::PinContact found = EvaluatePin(near, psi, pose);
  const bool same_space = found.tooth_space == last.tooth_space && std::isfinite(feet.at[i]) && psi != feet.at[i];
  feet.slope[i] = same_space ? (found.u - last.u) / (psi - feet.at[i]) : std::numeric_limits<double>::quiet_NaN();
  feet.last[i] = std::move(found);
  feet.at[i] = psi;
  feet.law[i].reset();
}

contact::ContactLaw LoadProblem::LawOf(const contact::PinContact& pin) const {
  return MakeLaw(contact_, material_, pin, pin.length, log_radius_cap_);
}

Loading LoadAt(const std::vector<LoadProblem::PinAt>& pins, std::vector<double>* hints) {
  Loading l;
  LoadAt(pins, hints, &l);
  return l;
}

void LoadAt(const std::vector<LoadProblem::PinAt>& pins, std::vector<double>* hints, Loading* out) {
  Loading& l = *out;
  l.torque = 0.0;
  l.edge = l.saturated = false;
  l.force.assign(pins.size(), 0.0);
  if (hints != nullptr) hints->resize(pins.size(), 0.0);
  for (std::size_t i = 0; i < pins.size(); ++i) {
    if (pins[i].approach <= 0.0) continue;
    if (pins[i].law == nullptr) {
      l.edge = true;
      continue;
    }
    if (pins[i].approach >= pins[i].law->max_approach()) l.saturated = true;
    l.force[i] = hints != nullptr ? pins[i].law->Force(pins[i].approach, &(*hints)[i]) : pins[i].law->Force(pins[i].approach);
    l.torque += l.force[i] * pins[i].arm;
  }
}

double LoadProblem::OutputTorque(double psi, Workspace& workspace) const {
  std::vector<contact::ContactLaw> scratch;
  return LoadAt(At(psi, workspace, &scratch)).torque;
}

double LoadProblem::OutputTorque(double psi) const {
  Workspace workspace;
  return OutputTorque(psi, workspace);
}

double LoadProblem::GapResolution() const {
  if (kinematics_ == contact::ContactKinematics::kLinearised) return 0.0;
  return 16.0 * std::numeric_limits<double>::epsilon() * model_->pair().pin_circle_radius;
}

namespace {

// The torque the arithmetic cannot resolve at psi (LoadProblem::TorqueResolution), N*mm.
// With the pins' forces at hand (forces != nullptr, F_i = Force(approach_i)), each stiffness is
// 1 / Compliance(F_i) in closed form instead of a law inversion per pin (Stiffness(approach)).
double Resolution(const std::vector<LoadProblem::PinAt>& pins, double psi, double gap_resolution,
                  const std::vector<double>* forces = nullptr) {
  double stiffness = 0.0, gap_stiffness = 0.0;
  for (std::size_t i = 0; i < pins.size(); ++i) {
    const LoadProblem::PinAt& p = pins[i];
    if (p.law == nullptr || !(p.approach > 0.0)) continue;
    double k = 0.0;
    if (forces == nullptr) {
      k = p.law->Stiffness(p.approach);
    } else if (p.approach < p.law->max_approach()) {
      const double compliance = p.law->Compliance((*forces)[i]);
      k = compliance > 0.0 ? 1.0 / compliance : 0.0;
    }
    stiffness += k * p.arm * p.arm;
    gap_stiffness += k * std::abs(p.arm);
  }
  const double ulp = std::nextafter(std::abs(psi), INFINITY) - std::abs(psi);
  return 4.0 * stiffness * ulp + gap_stiffness * gap_resolution;
}

}  // namespace

double LoadProblem::TorqueResolution(double psi, Workspace& workspace) const {
  std::vector<contact::ContactLaw> scratch;
  return Resolution(At(psi, workspace, &scratch), psi, GapResolution());
}

namespace {

// The convergence rule of LoadProblem::Balanced; the resolution (a full evaluation, or a pass over
// pins at hand) is asked for only once the miss is below 1e-6 T.
template <class ResolutionAt>
bool BalancedRule(double torque_out, double torque, double tolerance, ResolutionAt resolution) {
  const double miss = std::abs(torque_out - torque);
  if (miss <= tolerance * torque) return true;
  if (miss > 1e-6 * torque + 1e-6) return false;
  return miss <= resolution();
}

}  // namespace

bool LoadProblem::Balanced(double psi, double torque_out, double tolerance, Workspace& workspace) const {
  return BalancedRule(torque_out, torque_, tolerance, [&] { return TorqueResolution(psi, workspace); });
}

double LoadProblem::TorqueResolution(double psi, const std::vector<PinAt>& pins, const std::vector<double>* forces) const {
  if (forces != nullptr && forces->size() != pins.size()) {
    throw std::logic_error("LoadProblem::TorqueResolution: one force a pin expected");
  }
  return Resolution(pins, psi, GapResolution(), forces);
}

bool LoadProblem::Balanced(double psi, double torque_out, double tolerance, const std::vector<PinAt>& pins,
                           const std::vector<double>* forces) const {
  return BalancedRule(torque_out, torque_, tolerance, [&] { return TorqueResolution(psi, pins, forces); });
}

double LoadProblem::TorqueCapacity() const {
  double capacity = 0.0;
  for (std::size_t i = 0; i < base_.pins.size(); ++i) {
    const auto& pin = base_.pins[i];
    if (pin.edge || pin.arm <= 0.0) continue;
    capacity += base_laws_[i].max_force() * pin.arm;
  }
  return capacity;
}

double LoadProblem::FirstContactRotation() const { return first_contact_; }

bool LoadProblem::overlapping() const {
  const double tolerance = model_->interference_tolerance();
  return std::any_of(base_.pins.begin(), base_.pins.end(),
                     [&](const contact::PinContact& c) { return c.clearance < -tolerance; });
}

LoadProblem LoadProblem::Unloaded(double fraction) const {
  LoadProblem out(*this);
  out.torque_ = fraction * torque_;
  out.stage_loads_.reset();  // the loads besides T belong to the loaded state (a loop's friction), not its preload
  out.single_pin_ = out.SinglePinBound();
  return out;
}

bool LoadProblem::preloaded() const { return !contact::JamReport(base_, model_->interference_tolerance()).empty(); }

LoadProblem::RotationRange LoadProblem::LoadedRotationRange() const {
  return {first_contact_, single_pin_, contact::RotationWindow(*model_)};
}

std::vector<std::size_t> CandidatePins(const std::vector<LoadProblem::PinAt>& pins, double torque, double min_arm) {
  // Any single pin m alone reaches the torque after turning (w_m(T / L_m) - approach_m) / L_m.
  double bound = INFINITY;
  for (const auto& p : pins) {
    if (p.law == nullptr || p.arm <= min_arm) continue;
    bound = std::min(bound, (p.law->Approach(torque / p.arm) - p.approach) / p.arm);
  }
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < pins.size(); ++i) {
    const auto& p = pins[i];
    if (p.law == nullptr) continue;
    // A pin already pressed at psi is a candidate whatever its arm: under exact kinematics a pin
    // at the far end of the line of centres (arm -0.004 mm on Liu Table 1 at crank 0.018 deg)
    // is pressed 5e-8 mm at second order in the rotation and must carry its force. Approaches
    // below 1e-11 mm are the rounding of a touching pin (a free variable there only collects
    // interior-point noise); left out, they cost at most 1e-11 mm of penetration.
    if (p.approach > 1e-11 && p.arm <= min_arm) {
      out.push_back(i);
      continue;
    }
    if (p.arm <= min_arm) continue;
    if (p.approach + p.arm * bound > 0.0) out.push_back(i);  // closes before the bound
  }
  return out;
}

Residuals ComputeResiduals(const LoadProblem& problem, double psi, const std::vector<double>& forces) {
  Workspace workspace;
  return ComputeResiduals(problem, psi, forces, workspace);
}

Residuals ComputeResiduals(const LoadProblem& problem, double psi, const std::vector<double>& forces,
                           Workspace& workspace) {
  if (problem.has_reducer()) {
    // The pin-ring forces alone cannot show a stage's balance: judge the whole result.
    throw std::invalid_argument("ComputeResiduals: a stage problem is judged from its whole LoadResult "
                                "(ComputeResiduals(problem, result))");
  }
  std::vector<contact::ContactLaw> scratch;
  const auto pins = problem.At(psi, workspace, &scratch);
  Residuals r;
  // A gap is known only to the resolution of the geometry: violations below it are rounding.
  const double resolution = problem.GapResolution();
  double torque = 0.0, f_max = 0.0, w_max = 0.0;
  // Coupled: (C F)_i, F as given (a negative force is judged as it is, not clipped).
  const bool coupled = problem.has_coupling();
  Eigen::VectorXd coupled_deflection;
  if (coupled) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(pins.size()));
    for (std::size_t i = 0; i < pins.size() && i < forces.size(); ++i) f(static_cast<Eigen::Index>(i)) = forces[i];
    coupled_deflection = *problem.coupling() * f;
  }
  for (std::size_t i = 0; i < pins.size(); ++i) {
    const double f = i < forces.size() ? forces[i] : 0.0;
    torque += f * pins[i].arm;
    f_max = std::max(f_max, std::abs(f));
    w_max = std::max(w_max, std::abs(pins[i].approach) * (f > 0.0 ? 1.0 : 0.0));
    // Deformed gap: the law's deflection under F (plus the coupling's) minus the geometric approach.
    double deflection = pins[i].law != nullptr ? pins[i].law->Approach(f) : 0.0;
    if (coupled) deflection += coupled_deflection(static_cast<Eigen::Index>(i));
    const double gap = deflection - pins[i].approach;
    r.force_violation_n = std::max(r.force_violation_n, std::max(0.0, -f));
    r.gap_violation_mm = std::max(r.gap_violation_mm, std::max(0.0, -gap - resolution));
    r.complementarity_nmm =
        std::max(r.complementarity_nmm, std::max(f, 0.0) * std::max(0.0, std::abs(gap) - resolution));
  }
  // A torque miss below what the arithmetic resolves at psi is rounding, as in Balanced(). The
  // resolution costs a law inversion per loaded pin, so it is consulted only for a miss that
  // could matter (above 1e-9, far below any acceptance; a typical solve misses by 1e-12).
  double miss = std::abs(torque - problem.torque());
  r.torque_miss_relative = problem.torque() != 0.0 ? miss / std::abs(problem.torque()) : 0.0;
  if (miss > 1e-9 * std::max(problem.torque(), 1.0)) miss = std::max(0.0, miss - Resolution(pins, psi, resolution));
  r.torque_relative = miss / std::max(problem.torque(), 1.0);
  const double f_scale = std::max(f_max, 1e-300), w_scale = std::max(w_max, 1e-12);
  r.normalised = std::max({r.torque_relative, r.force_violation_n / f_scale, r.gap_violation_mm / w_scale,
                           r.complementarity_nmm / (f_scale * w_scale)});
  return r;
}

}  // namespace ltca::solvers
