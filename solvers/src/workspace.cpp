#include "ltca/solvers/workspace.hpp"

namespace ltca::solvers {

Workspace::Workspace() = default;
Workspace::~Workspace() = default;
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

Workspace::BackendState* Workspace::Backend(const std::string& key) const {
  const auto it = backends_.find(key);
  return it == backends_.end() ? nullptr : it->second.get();
}

Workspace::BackendState* Workspace::SetBackend(const std::string& key, std::unique_ptr<BackendState> state) {
  auto& slot = backends_[key];
  slot = std::move(state);
  return slot.get();
}

}  // namespace ltca::solvers
