#pragma once
// Content hash of a file (64-bit FNV-1a, hex), recorded in outputs so that a later stage can
// tell which input produced them. Not cryptographic: it detects accidents, not attacks.
#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace dualcell {

std::string file_hash(const std::filesystem::path& file);
std::string text_hash(std::string_view text);
// The same hash as a number (the umat's card carries it in two 32-bit constants).
std::uint64_t text_hash_value(std::string_view text);

}  // namespace dualcell
