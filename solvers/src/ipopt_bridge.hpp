#pragma once
// Ipopt (A. Waechter, L. T. Biegler, Math. Program. 106 (2006) 25-57; Debian 12's 3.11 with MUMPS)
// through the module ltca_ipopt.so (ipopt_module.cpp), so that only a run that calls an Ipopt
// solver maps Ipopt, MUMPS, SCOTCH and the Fortran runtime (docs/architecture.md, "Modules").
// This header names no Ipopt type: a problem is an NlpProblem, whose methods are Ipopt's TNLP's
// (IpTNLP.hpp, C index style) in plain types, and the module wraps it in a TNLP. The module is
// refused unless it was built from these declarations (IpoptBridgeAbi).

#include <string>

namespace ltca::solvers::ipopt {

/// Ipopt's ApplicationReturnStatus (IpReturnCodes_inc.h), with Ipopt's numbers (the module checks
/// them at compile time).
enum class Status : int {
  kSolveSucceeded = 0,
  kSolvedToAcceptableLevel = 1,
  kInfeasibleProblemDetected = 2,
  kSearchDirectionBecomesTooSmall = 3,
  kDivergingIterates = 4,
  kUserRequestedStop = 5,
  kFeasiblePointFound = 6,
  kMaximumIterationsExceeded = -1,
  kRestorationFailed = -2,
  kErrorInStepComputation = -3,
  kMaximumCpuTimeExceeded = -4,
  kNotEnoughDegreesOfFreedom = -10,
  kInvalidProblemDefinition = -11,
  kInvalidOption = -12,
  kInvalidNumberDetected = -13,
  kUnrecoverableException = -100,
  kNonIpoptExceptionThrown = -101,
  kInsufficientMemory = -102,
  kInternalError = -199,
};

/// Ipopt's SolverReturn (IpAlgTypes.hpp) as finalize_solution reports it: the two values read here,
/// with Ipopt's numbers (checked by the module).
inline constexpr int kSolverReturnSuccess = 0;
inline constexpr int kSolverReturnStopAtAcceptablePoint = 4;

/// An optimisation problem min f(x) s.t. g_l <= g(x) <= g_u, x_l <= x <= x_u, as Ipopt's TNLP asks
/// for it (the same arguments, in the same order; indices from 0). A method returns false to tell
/// Ipopt that it cannot evaluate there.
class NlpProblem {
 public:
  virtual bool get_nlp_info(int& n, int& m, int& nnz_jac_g, int& nnz_h_lag) = 0;
  virtual bool get_bounds_info(int n, double* x_l, double* x_u, int m, double* g_l, double* g_u) = 0;
  /// User scaling (nlp_scaling_method = user-scaling); false: none (TNLP's default).
  virtual bool get_scaling_parameters(double& obj_scaling, bool& use_x_scaling, int n, double* x_scaling,
                                      bool& use_g_scaling, int m, double* g_scaling) {
    (void)obj_scaling, (void)use_x_scaling, (void)n, (void)x_scaling, (void)use_g_scaling, (void)m, (void)g_scaling;
    return false;
  }
  virtual bool get_starting_point(int n, bool init_x, double* x, bool init_z, double* z_l, double* z_u, int m,
                                  bool init_lambda, double* lambda) = 0;
  virtual bool eval_f(int n, const double* x, bool new_x, double& f) = 0;
  virtual bool eval_grad_f(int n, const double* x, bool new_x, double* grad_f) = 0;
  virtual bool eval_g(int n, const double* x, bool new_x, int m, double* g) = 0;
  virtual bool eval_jac_g(int n, const double* x, bool new_x, int m, int nele_jac, int* row, int* col,
                          double* values) = 0;
  virtual bool eval_h(int n, const double* x, bool new_x, double obj_factor, int m, const double* lambda,
                      bool new_lambda, int nele_hess, int* row, int* col, double* values) = 0;
  /// `status` is Ipopt's SolverReturn (kSolverReturnSuccess, ...).
  virtual void finalize_solution(int status, int n, const double* x, const double* z_l, const double* z_u, int m,
                                 const double* g, const double* lambda, double obj_value) = 0;

 protected:
  NlpProblem() = default;
  NlpProblem(const NlpProblem&) = default;
  NlpProblem& operator=(const NlpProblem&) = default;
  ~NlpProblem() = default;
};

/// The declarations the module must be built from: the project's version, kIpoptBridgeVersion
/// (raised with any change to this header) and the sizes it relies on. The module exports its own
/// (ltca_ipopt_abi) and the loader refuses a module whose text differs, naming both.
inline constexpr int kIpoptBridgeVersion = 1;
inline std::string IpoptBridgeAbi(const std::string& version) {
  return "ltca " + version + ", Ipopt bridge " + std::to_string(kIpoptBridgeVersion) + ", sizes " +
         std::to_string(sizeof(int)) + "/" + std::to_string(sizeof(double)) + "/" + std::to_string(sizeof(void*));
}

/// One IpoptApplication (IpoptApplicationFactory) of the module, and the TNLP it last optimised.
/// Not thread-safe: the caller serialises every use (Debian's MUMPS shares Fortran state between
/// threads), construction and destruction included. The constructor loads the module the first
/// time (std::runtime_error naming the module and the folders searched when it is missing, or both
/// versions when it was built from other declarations).
class Application {
 public:
  Application();
  ~Application();
  Application(const Application&) = delete;
  Application& operator=(const Application&) = delete;

  /// Ipopt's options (OptionsList::SetIntegerValue, ...): false when Ipopt refuses the value.
  bool SetInteger(const char* name, int value);
  bool SetNumeric(const char* name, double value);
  bool SetString(const char* name, const char* value);
  /// IpoptApplication::Initialize("") (no option file is read).
  Status Initialize();
  /// OptimizeTNLP of `problem`, wrapped in a new TNLP; with `reoptimize`, ReOptimizeTNLP of the TNLP
  /// of the last call, now pointing at `problem` (the structure must be the same: Ipopt keeps its
  /// linear solver's set-up). `iterations`: Ipopt's iteration count of this solve (0 without
  /// statistics).
  Status Optimize(NlpProblem& problem, bool reoptimize, int* iterations);

 private:
  void* handle_ = nullptr;
};

}  // namespace ltca::solvers::ipopt
