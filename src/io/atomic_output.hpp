#pragma once
// Output files are written to a temporary name beside the target and renamed on commit(), so
// an interrupted or failed stage leaves either the previous complete file or none. Several
// outputs of one stage (an .h5 and its .xdmf) are committed together by one AtomicOutputs.
#include <filesystem>
#include <string>
#include <vector>

namespace dualcell::io {

class AtomicOutputs {
 public:
  AtomicOutputs() = default;
  AtomicOutputs(const AtomicOutputs&) = delete;
  AtomicOutputs& operator=(const AtomicOutputs&) = delete;
  ~AtomicOutputs();  // removes temporaries that were not committed

  // Registers `target` and returns the temporary path to write instead. Checks at once that
  // the folder exists and is writable (InputError otherwise), before any work is done.
  std::filesystem::path add(const std::filesystem::path& target);
  // Renames every temporary onto its target.
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::filesystem::path>> files_;  // (temporary, target)
  bool committed_ = false;
};

}  // namespace dualcell::io
