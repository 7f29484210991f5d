#pragma once
// The exit codes of `ltca` (README "Use", `ltca --help`), which the Python module's
// Result.exit_code mirrors: one meaning on every front-end.

namespace ltca::app {

inline constexpr int kExitSuccess = 0;        ///< every position of every solver succeeded
inline constexpr int kExitNotSucceeded = 1;   ///< the run finished, something did not succeed
inline constexpr int kExitBadInput = 2;       ///< bad deck or options
inline constexpr int kExitOutputError = 3;    ///< an output could not be opened or written
inline constexpr int kExitInternalError = 4;  ///< a bug: please report it

}  // namespace ltca::app
