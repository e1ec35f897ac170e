#pragma once
// Content hash of a file (64-bit FNV-1a, hex), recorded in outputs so that a later stage can
// tell which input produced them. Not cryptographic: it detects accidents, not attacks.
#include <filesystem>
#include <string>
#include <string_view>

namespace dualcell::io {

std::string file_hash(const std::filesystem::path& file);
std::string text_hash(std::string_view text);

}  // namespace dualcell::io
