#pragma once
// The modules loaded on demand (ltca/solvers/modules.hpp), by their application-layer names.

#include "ltca/solvers/modules.hpp"

namespace ltca::app {

using solvers::ModuleFunction;
using solvers::ModuleSymbol;

}  // namespace ltca::app
