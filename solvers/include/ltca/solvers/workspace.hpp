#pragma once
// Mutable state of the solves of one thread (pattern: Ceres' per-thread evaluation scratch, Drake's
// Context beside an immutable System). A LoadProblem is immutable and may be shared across threads;
// everything a solve writes lives here: the exact-kinematics foot points of the problem last
// evaluated (a Newton warm start), and each backend's own state (e.g. energy-qp's Ipopt
// application and its warm start from the previous position). One workspace per thread; a
// workspace must not be used by two threads at once. Results depend on what a workspace has seen
// (warm starts), never on what another thread does.
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "ltca/contact/laws.hpp"
#include "ltca/contact/mesh_state.hpp"

namespace ltca::solvers {

class Workspace {
 public:
  Workspace();
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  Workspace(Workspace&&) noexcept;
  Workspace& operator=(Workspace&&) noexcept;

  /// A backend's own state: derived in the backend's translation unit (Ipopt stays private).
  struct BackendState {
    virtual ~BackendState() = default;
  };
  /// The state stored under `key` (the backend's name), or nullptr.
  BackendState* Backend(const std::string& key) const;
  /// Stores (replacing) the state under `key` and returns it.
  BackendState* SetBackend(const std::string& key, std::unique_ptr<BackendState> state);

  /// Exact kinematics: the last foot point of every contact of one problem, to start the next
  /// closest-point search from (any value gives the same answer to rounding; only the Newton
  /// steps differ). Keyed by LoadProblem::id(); LoadProblem::At rebinds it.
  struct FootPoints {
    std::uint64_t problem = 0;  ///< 0: bound to none
    std::vector<contact::PinContact> last;
    /// The rotation each entry of `last` was evaluated at (NaN: not yet at any).
    std::vector<double> at;
    /// du/dpsi of each entry's foot parameter from its last two searches in one tooth space (NaN:
    /// not known): the next search starts from the foot point extrapolated to its rotation.
    std::vector<double> slope;
    /// The law of each entry of `last`, built since its last search (none: not asked for yet),
    /// kept because the evaluations at one rotation (a solver's last, the judge's, the outputs')
    /// ask for the same laws again.
    std::vector<std::optional<contact::ContactLaw>> law;
  };
  FootPoints& foot_points() { return foot_points_; }

 private:
  FootPoints foot_points_;
  std::map<std::string, std::unique_ptr<BackendState>> backends_;
};

}  // namespace ltca::solvers
