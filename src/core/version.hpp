#pragma once
// The version recorded in every output file (provenance): "<project version>+<git describe>".
// Defined in a file generated at configure time (src/core/version.cpp.in; CMake re-configures
// when .git/HEAD or .git/index change), so that a new commit recompiles one file, not the
// whole library.
namespace dualcell {
extern const char* const code_version;
}  // namespace dualcell
