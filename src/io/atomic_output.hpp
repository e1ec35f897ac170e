#pragma once
// Output files are replaced whole or not at all. Each output is written to a temporary beside
// its target (every write checked, then fsync), and only when all of a stage's outputs are
// written are they renamed onto their targets (then the folder is fsync'ed, so that a power
// cut cannot leave a renamed but empty file). A failed write (a full disk, a file-size limit)
// is an InputError "<target>: cannot write: <reason>"; the temporaries are removed and the
// previous outputs stay byte-identical. Several outputs of one stage (an .h5 and its .xdmf)
// are committed together by one AtomicOutputs.
//
// Temporaries are named "<target>.tmp.<host>.<pid>". A process killed while writing cannot
// remove its own; the next run that writes the same target removes those whose process on this
// host is gone, so nothing is left for the user to clean by hand.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

namespace dualcell::io {

class AtomicOutputs {
 public:
  AtomicOutputs() = default;
  AtomicOutputs(const AtomicOutputs&) = delete;
  AtomicOutputs& operator=(const AtomicOutputs&) = delete;
  ~AtomicOutputs();  // removes temporaries that were not committed

  // Registers `target`: checks it (check_output_path), removes orphaned temporaries of it and
  // creates its temporary, so that an unwritable output fails before any work is done.
  void add(const std::filesystem::path& target);
  // Writes the whole content of a registered target to its temporary, checked and fsync'ed.
  void write(const std::filesystem::path& target, std::string_view bytes);
  // Appends to a registered target's temporary (an output written as it is computed, not held
  // whole); commit() syncs it. Not mixed with write() for one target.
  void append(const std::filesystem::path& target, std::string_view bytes);
  // Renames every temporary onto its target (all must have been written), then syncs the folders.
  void commit();

 private:
  struct Entry {
    std::filesystem::path target, temporary;
    bool written = false;
    int appending = -1;  // the temporary's descriptor while append() writes it
  };
  Entry& entry(const std::filesystem::path& target);
  std::vector<Entry> files_;
  bool committed_ = false;
};

// One output, replaced whole: add, write, commit.
void write_output(const std::filesystem::path& target, std::string_view bytes);

// The checks of an output path that need no work: not empty, its folder exists, and if it exists
// it is a regular file (not a folder, not a device: /dev/null is never replaced by a file) that
// is none of `inputs` (compared by file identity, so `--out ./law.h5 --law law.h5` and hard
// links are caught). An InputError naming the path otherwise.
void check_output_path(const std::filesystem::path& target, const std::vector<std::filesystem::path>& inputs = {});

// Every output of a stage checked before any work: each by check_output_path, no two the same,
// and each one actually creatable in its folder (a temporary is created and removed).
void check_outputs(const std::vector<std::filesystem::path>& outputs, const std::vector<std::filesystem::path>& inputs);

// The XDMF file written beside an HDF5 output ("solution.h5" -> "solution.xdmf").
std::filesystem::path xdmf_beside(const std::filesystem::path& h5);

}  // namespace dualcell::io
