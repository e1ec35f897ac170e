#pragma once
// What a stage may allocate, known before it allocates: the machine's physical memory, and the
// line that refuses an input whose estimate exceeds it (docs/reference/limits.md).
#include <cstddef>
#include <string>

namespace dualcell {

// Physical memory of this machine in bytes (sysconf), 0 when unknown.
std::size_t physical_memory_bytes();

// What this process may hold: "this machine's 25 GB", or "this process's limit of 0.24 GB"
// when a resource limit (ulimit -d or -v) is below the physical memory.
std::string memory_bound_text();

// "2.5 GB" (decimal gigabytes, 2 significant digits past 10 GB).
std::string gigabytes(double bytes);

// An InputError "<what> needs about <estimate>, more than this machine's <physical> of memory:
// <remedy>" when estimate > physical memory; nothing otherwise (or when it is unknown).
void refuse_beyond_memory(double estimate_bytes, const std::string& what, const std::string& remedy);

}  // namespace dualcell
