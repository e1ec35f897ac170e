#include "io/atomic_output.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <system_error>

#include "core/error.hpp"

namespace dualcell::io {

std::filesystem::path AtomicOutputs::add(const std::filesystem::path& target) {
  std::filesystem::path folder = target.parent_path();
  if (folder.empty()) folder = ".";
  std::error_code ec;  // a name too long for the file system is a message, not an exception
  if (!std::filesystem::is_directory(folder, ec))
    throw InputError(target.string() + ": cannot write output: folder " + folder.string() + " does not exist");
  if (std::filesystem::is_directory(target, ec))
    throw InputError(target.string() + ": cannot write output: it is a directory");
  std::filesystem::path temporary = target;
  temporary += ".tmp." + std::to_string(::getpid());
  {
    std::ofstream probe(temporary, std::ios::binary | std::ios::trunc);
    if (!probe) throw InputError(target.string() + ": cannot write output: " + std::strerror(errno));
  }
  files_.emplace_back(temporary, target);
  return temporary;
}

void AtomicOutputs::commit() {
  for (const auto& [temporary, target] : files_) {
    std::error_code ec;
    std::filesystem::rename(temporary, target, ec);
    if (ec) throw InputError(target.string() + ": cannot move finished output into place: " + ec.message());
  }
  committed_ = true;
}

AtomicOutputs::~AtomicOutputs() {
  if (committed_) return;
  for (const auto& file : files_) {
    std::error_code ec;
    std::filesystem::remove(file.first, ec);
  }
}

}  // namespace dualcell::io
