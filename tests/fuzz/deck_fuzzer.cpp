// libFuzzer target for the deck reader: any byte string is either a deck or a
// std::invalid_argument that names what is wrong. Any other exception, a crash, a hang (libFuzzer
// -timeout) or a sanitizer report (the target is built with ASan and UBSan) is a finding.
// Build and run: cmake --preset fuzz && cmake --build --preset fuzz &&
//   build/fuzz/tests/fuzz/deck_fuzzer -dict=build/fuzz/deck.dict (tests/fuzz/README.md) <copy of tests/fuzz/corpus>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string_view>

#include "ltca/app/deck.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)ltca::app::ParseDeck(text, "fuzz");
  } catch (const std::invalid_argument&) {
    // The documented answer to a bad deck.
  }
  return 0;
}
