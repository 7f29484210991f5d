#pragma once
// The one test helper every layer's tests share for the decks of cases/.
#include <string>

namespace ltca::test {

/// The path of a deck in cases/ (LTCA_CASES_DIR, a compile definition of every test suite).
inline std::string Case(const std::string& rel) { return std::string(LTCA_CASES_DIR) + "/" + rel; }

}  // namespace ltca::test
