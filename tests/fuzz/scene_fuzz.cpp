// libFuzzer target: the scene parser (dualcell::parse_scene, with toml++ compiled in and
// instrumented) on arbitrary bytes. An InputError is the parser doing its job; anything else
// (another exception, a crash, a sanitizer report, a leak, a hang, unbounded memory) is a finding.
//
//   make -C pipelines fuzz                    build (preset fuzz, clang) and run 60 s, seeded
//   make -C pipelines fuzz FUZZ_SECONDS=600   longer
//
// The run starts in data/hostile/scenes, so that `material = "..."` in the seeds resolves; new
// inputs go to build-fuzz/corpus, crashes to build-fuzz/findings/ (add them to the corpus).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "core/error.hpp"
#include "core/scene.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    (void)dualcell::parse_scene(text, "fuzz.toml");
  } catch (const dualcell::InputError&) {
  }
  return 0;
}
