#include "core/memory.hpp"

#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "core/error.hpp"

namespace dualcell {

std::size_t physical_memory_bytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), page = ::sysconf(_SC_PAGESIZE);
  if (pages <= 0 || page <= 0) return 0;
  return static_cast<std::size_t>(pages) * static_cast<std::size_t>(page);
}

std::string memory_bound_text() {
  const double physical = static_cast<double>(physical_memory_bytes());
  double limit = physical;
  for (const int resource : {RLIMIT_DATA, RLIMIT_AS}) {
    rlimit r{};
    if (::getrlimit(resource, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
      limit = std::min(limit, static_cast<double>(r.rlim_cur));
  }
  if (limit < physical) return "this process's limit of " + gigabytes(limit) + " (ulimit)";
  return "this machine's " + gigabytes(physical);
}

std::string gigabytes(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.2g GB", bytes / 1e9);
  return text;
}

void refuse_beyond_memory(double estimate_bytes, const std::string& what, const std::string& remedy) {
  const double physical = static_cast<double>(physical_memory_bytes());
  if (physical > 0 && estimate_bytes > physical)
    throw InputError(what + " needs about " + gigabytes(estimate_bytes) + ", more than this machine's " +
                     gigabytes(physical) + " of memory: " + remedy);
}

}  // namespace dualcell
