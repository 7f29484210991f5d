// The module ltca_ipopt.so (ipopt_bridge.hpp): the only code of ltca that includes Ipopt's headers
// and links libipopt (with MUMPS, SCOTCH and the Fortran runtime). It wraps the caller's
// NlpProblem in an Ipopt::TNLP that forwards every call unchanged, so a solve is the same as one
// made by a TNLP of the caller's own.
#include "ipopt_bridge.hpp"

#include <IpIpoptApplication.hpp>
#include <IpSolveStatistics.hpp>
#include <IpTNLP.hpp>

#include <string>
#include <type_traits>

#ifndef LTCA_VERSION
#define LTCA_VERSION "unknown"
#endif

namespace {

namespace bridge = ltca::solvers::ipopt;
using Ipopt::Index;
using Ipopt::Number;

static_assert(std::is_same_v<Index, int> && std::is_same_v<Number, double>, "the bridge passes int and double");
static_assert(static_cast<int>(bridge::Status::kSolveSucceeded) == Ipopt::Solve_Succeeded);
static_assert(static_cast<int>(bridge::Status::kSolvedToAcceptableLevel) == Ipopt::Solved_To_Acceptable_Level);
static_assert(static_cast<int>(bridge::Status::kInfeasibleProblemDetected) == Ipopt::Infeasible_Problem_Detected);
static_assert(static_cast<int>(bridge::Status::kSearchDirectionBecomesTooSmall) == Ipopt::Search_Direction_Becomes_Too_Small);
static_assert(static_cast<int>(bridge::Status::kDivergingIterates) == Ipopt::Diverging_Iterates);
static_assert(static_cast<int>(bridge::Status::kUserRequestedStop) == Ipopt::User_Requested_Stop);
static_assert(static_cast<int>(bridge::Status::kFeasiblePointFound) == Ipopt::Feasible_Point_Found);
static_assert(static_cast<int>(bridge::Status::kMaximumIterationsExceeded) == Ipopt::Maximum_Iterations_Exceeded);
static_assert(static_cast<int>(bridge::Status::kRestorationFailed) == Ipopt::Restoration_Failed);
static_assert(static_cast<int>(bridge::Status::kErrorInStepComputation) == Ipopt::Error_In_Step_Computation);
static_assert(static_cast<int>(bridge::Status::kMaximumCpuTimeExceeded) == Ipopt::Maximum_CpuTime_Exceeded);
static_assert(static_cast<int>(bridge::Status::kNotEnoughDegreesOfFreedom) == Ipopt::Not_Enough_Degrees_Of_Freedom);
static_assert(static_cast<int>(bridge::Status::kInvalidProblemDefinition) == Ipopt::Invalid_Problem_Definition);
static_assert(static_cast<int>(bridge::Status::kInvalidOption) == Ipopt::Invalid_Option);
static_assert(static_cast<int>(bridge::Status::kInvalidNumberDetected) == Ipopt::Invalid_Number_Detected);
static_assert(static_cast<int>(bridge::Status::kUnrecoverableException) == Ipopt::Unrecoverable_Exception);
static_assert(static_cast<int>(bridge::Status::kNonIpoptExceptionThrown) == Ipopt::NonIpopt_Exception_Thrown);
static_assert(static_cast<int>(bridge::Status::kInsufficientMemory) == Ipopt::Insufficient_Memory);
static_assert(static_cast<int>(bridge::Status::kInternalError) == Ipopt::Internal_Error);
static_assert(bridge::kSolverReturnSuccess == Ipopt::SUCCESS);
static_assert(bridge::kSolverReturnStopAtAcceptablePoint == Ipopt::STOP_AT_ACCEPTABLE_POINT);

/// The caller's problem as a TNLP: every method forwards, unchanged.
class ForwardingTnlp final : public Ipopt::TNLP {
 public:
  bridge::NlpProblem* problem = nullptr;

  bool get_nlp_info(Index& n, Index& m, Index& nnz_jac_g, Index& nnz_h_lag, IndexStyleEnum& style) override {
    style = C_STYLE;
    return problem->get_nlp_info(n, m, nnz_jac_g, nnz_h_lag);
  }
  bool get_bounds_info(Index n, Number* x_l, Number* x_u, Index m, Number* g_l, Number* g_u) override {
    return problem->get_bounds_info(n, x_l, x_u, m, g_l, g_u);
  }
  bool get_scaling_parameters(Number& obj_scaling, bool& use_x_scaling, Index n, Number* x_scaling, bool& use_g_scaling,
                              Index m, Number* g_scaling) override {
    return problem->get_scaling_parameters(obj_scaling, use_x_scaling, n, x_scaling, use_g_scaling, m, g_scaling);
  }
  bool get_starting_point(Index n, bool init_x, Number* x, bool init_z, Number* z_l, Number* z_u, Index m,
                          bool init_lambda, Number* lambda) override {
    return problem->get_starting_point(n, init_x, x, init_z, z_l, z_u, m, init_lambda, lambda);
  }
  bool eval_f(Index n, const Number* x, bool new_x, Number& f) override { return problem->eval_f(n, x, new_x, f); }
  bool eval_grad_f(Index n, const Number* x, bool new_x, Number* g) override {
    return problem->eval_grad_f(n, x, new_x, g);
  }
  bool eval_g(Index n, const Number* x, bool new_x, Index m, Number* g) override {
    return problem->eval_g(n, x, new_x, m, g);
  }
  bool eval_jac_g(Index n, const Number* x, bool new_x, Index m, Index nele_jac, Index* row, Index* col,
                  Number* values) override {
    return problem->eval_jac_g(n, x, new_x, m, nele_jac, row, col, values);
  }
  bool eval_h(Index n, const Number* x, bool new_x, Number obj_factor, Index m, const Number* lambda, bool new_lambda,
              Index nele_hess, Index* row, Index* col, Number* values) override {
    return problem->eval_h(n, x, new_x, obj_factor, m, lambda, new_lambda, nele_hess, row, col, values);
  }
  void finalize_solution(Ipopt::SolverReturn status, Index n, const Number* x, const Number* z_l, const Number* z_u,
                         Index m, const Number* g, const Number* lambda, Number obj_value, const Ipopt::IpoptData*,
                         Ipopt::IpoptCalculatedQuantities*) override {
    problem->finalize_solution(static_cast<int>(status), n, x, z_l, z_u, m, g, lambda, obj_value);
  }
};

struct Application {
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app;
  Ipopt::SmartPtr<ForwardingTnlp> tnlp;  // the TNLP last optimised (ReOptimizeTNLP takes it again)
};

Application* Cast(void* handle) { return static_cast<Application*>(handle); }

}  // namespace

#define LTCA_IPOPT_ENTRY extern "C" __attribute__((visibility("default")))

/// The declarations this module was built from (ipopt_bridge.hpp, IpoptBridgeAbi).
LTCA_IPOPT_ENTRY const char* ltca_ipopt_abi() {
  static const std::string abi = bridge::IpoptBridgeAbi(LTCA_VERSION);
  return abi.c_str();
}

LTCA_IPOPT_ENTRY void* ltca_ipopt_create() {
  auto* a = new Application;
  a->app = IpoptApplicationFactory();
  return a;
}

LTCA_IPOPT_ENTRY void ltca_ipopt_destroy(void* handle) {
  Application* a = Cast(handle);
  a->tnlp = nullptr;  // the TNLP before the application that holds it
  a->app = nullptr;
  delete a;
}

LTCA_IPOPT_ENTRY bool ltca_ipopt_set_integer(void* handle, const char* name, int value) {
  return Cast(handle)->app->Options()->SetIntegerValue(name, value);
}
LTCA_IPOPT_ENTRY bool ltca_ipopt_set_numeric(void* handle, const char* name, double value) {
  return Cast(handle)->app->Options()->SetNumericValue(name, value);
}
LTCA_IPOPT_ENTRY bool ltca_ipopt_set_string(void* handle, const char* name, const char* value) {
  return Cast(handle)->app->Options()->SetStringValue(name, value);
}

LTCA_IPOPT_ENTRY int ltca_ipopt_initialize(void* handle) {
  return static_cast<int>(Cast(handle)->app->Initialize(""));  // "": no option file is read
}

LTCA_IPOPT_ENTRY int ltca_ipopt_optimize(void* handle, bridge::NlpProblem* problem, bool reoptimize, int* iterations) {
  Application* a = Cast(handle);
  const bool again = reoptimize && Ipopt::IsValid(a->tnlp);
  if (!again) a->tnlp = new ForwardingTnlp();
  a->tnlp->problem = problem;
  const Ipopt::ApplicationReturnStatus status =
      again ? a->app->ReOptimizeTNLP(Ipopt::GetRawPtr(a->tnlp)) : a->app->OptimizeTNLP(Ipopt::GetRawPtr(a->tnlp));
  *iterations = Ipopt::IsValid(a->app->Statistics()) ? a->app->Statistics()->IterationCount() : 0;
  return static_cast<int>(status);
}
