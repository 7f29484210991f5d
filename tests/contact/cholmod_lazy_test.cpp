// CHOLMOD loaded on its first call (contact/cholmod/cholmod_lazy.hpp): the library found at build
// time passes the check; a missing one, one that is not CHOLMOD and one of another version
// (tests/contact/stale_cholmod_library.cpp, 2.2.0) are refused with a message naming the file and
// the reason, never a crash.
#include <doctest/doctest.h>

#include <stdexcept>
#include <string>

#include "cholmod_lazy.hpp"

namespace {

std::string Refusal(const std::string& file) {
  try {
    ltca::cholmod::CholmodLibraryCheck(file);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

bool Says(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("contact: CHOLMOD is loaded on demand, and a missing or other-version library is refused by name") {
  // The build's own: CHOLMOD of the headers' main and sub version (cholmod_core.h).
  CHECK(ltca::cholmod::CholmodLibraryCheck(ltca::cholmod::CholmodSoname()) != nullptr);
  CHECK(std::string(ltca::cholmod::CholmodSoname()).rfind("libcholmod.so", 0) == 0);

  const std::string missing = Refusal("libltca-no-such-cholmod.so.3");
  CHECK(Says(missing, "libltca-no-such-cholmod.so.3"));
  CHECK(Says(missing, "cannot be loaded"));
  CHECK(Says(missing, "libsuitesparse-dev"));

  const std::string not_cholmod = Refusal("libm.so.6");  // glibc's: loads, but has no cholmod_version
  CHECK(Says(not_cholmod, "libm.so.6 is not CHOLMOD"));

  const std::string other = Refusal(LTCA_STALE_CHOLMOD);
  CHECK(Says(other, "version 2.2.0"));
  CHECK(Says(other, std::to_string(CHOLMOD_MAIN_VERSION) + "." + std::to_string(CHOLMOD_SUB_VERSION) + "."));
  CHECK(Says(other, LTCA_STALE_CHOLMOD));
}
