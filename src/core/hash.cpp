#include "core/hash.hpp"

#include <cstdint>
#include <cstdio>
#include <fstream>

#include "core/error.hpp"

namespace dualcell {

namespace {

constexpr std::uint64_t fnv_offset = 0xcbf29ce484222325ULL, fnv_prime = 0x100000001b3ULL;

void add_bytes(std::uint64_t& h, const char* data, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    h ^= static_cast<unsigned char>(data[i]);
    h *= fnv_prime;
  }
}

std::string hex(std::uint64_t h) {
  char text[17];
  std::snprintf(text, sizeof text, "%016llx", static_cast<unsigned long long>(h));
  return text;
}

}  // namespace

std::string file_hash(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(file.string() + ": cannot open to hash");
  std::uint64_t h = fnv_offset;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof buffer) || in.gcount() > 0) {
    add_bytes(h, buffer, static_cast<std::size_t>(in.gcount()));
    if (!in) break;
  }
  return hex(h);
}

std::uint64_t text_hash_value(std::string_view text) {
  std::uint64_t h = fnv_offset;
  add_bytes(h, text.data(), text.size());
  return h;
}

std::string text_hash(std::string_view text) { return hex(text_hash_value(text)); }

}  // namespace dualcell
