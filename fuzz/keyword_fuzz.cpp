// libFuzzer target for the keyword reader: each input is a deck. An InputError is the expected
// answer to bad input; any other exception, a sanitizer report, a leak or a hang is a bug.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "deck_check.hpp"
#include "spall/core/error.hpp"
#include "spall/core/memory.hpp"

// A small memory budget (as `--memory-limit 0.016`): a card generating particles (*DEFINE_SPH_MESH_BOX,
// *ELEMENT_SPH NEND) or set members beyond it is refused at its card, as on a machine without the
// memory. The code is the same for 10^4 particles as for 10^6; at 256 MB, generating them took a
// third of the fuzzer's time.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  spall::memory::set_limit(16'000'000);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    spall::fuzz::check_deck_text(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const spall::InputError&) {
  }
  return 0;
}
