#pragma once
// Shared helpers for tests: a scratch folder per test, scene text, and running a stage.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "par/parallel.hpp"

namespace dualcell::testing {

// A fresh folder under the system temp dir, removed at the end of the test.
class ScratchDir {
 public:
  ScratchDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() / ("dualcell-" + std::string(info->test_suite_name()) + "-" +
                                                      info->name() + "-" + std::to_string(::getpid()));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { std::filesystem::remove_all(path_); }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }
  std::filesystem::path write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }

 private:
  std::filesystem::path path_;
};

struct CommandResult {
  int exit_code = -1;  // -1: could not be run
  std::string output;  // stdout and stderr together
};

inline CommandResult run_command(const std::string& command) {
  CommandResult result;
  FILE* pipe = ::popen((command + " 2>&1").c_str(), "r");
  if (!pipe) return result;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe)) result.output += buffer;
  const int status = ::pclose(pipe);
  // A command killed by a signal reports 128 + its number, as the shell does (kill -9: 137),
  // whether the shell ran it as a child or replaced itself with it.
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : WIFSIGNALED(status) ? 128 + WTERMSIG(status) : -1;
  return result;
}

// Quoted for the shell (built by appending: GCC 12 warns falsely about "'" + s + "'").
inline std::string quoted(const std::filesystem::path& p) {
  std::string q(1, '\'');
  q += p.string();
  q += '\'';
  return q;
}

inline std::string bin(const std::string& stage) { return std::string(DUALCELL_BIN_DIR) + "/" + stage; }

// The launcher of an MPI run of `ranks` ranks, oversubscribed (this machine has 2 cores).
// OpenMPI refuses root unless told twice (CI runs as root); every run is bounded (no hang).
// Under the sanitizers the ranks run without leak checking: OpenMPI's plugins, unloaded at
// MPI_Finalize, leave allocations LeakSanitizer can neither free nor name (measured: 14 direct
// leaks in "unknown module"s per rank); address and undefined-behaviour checks stay on, and
// the same code is leak-checked in the serial tests.
// A run that outlives `seconds` is stopped and exits with 124 (timeout's code).
inline std::string mpiexec(int ranks, int seconds = 300) {
  return "OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ASAN_OPTIONS=detect_leaks=0 timeout " +
         std::to_string(seconds) + " mpiexec -n " + std::to_string(ranks) + " --oversubscribe ";
}
inline std::string source_dir() { return DUALCELL_SOURCE_DIR; }

// Whether a stage launched by mpiexec shares its work over ranks: built with MPI and a
// launcher on the PATH (the serial build runs each launched process as one whole run).
inline bool mpi_runs() { return par::built_with_mpi() && run_command("command -v mpiexec").exit_code == 0; }

// How many times `what` occurs in `text` (e.g. an error line that must be printed once).
inline std::size_t occurrences(const std::string& text, const std::string& what) {
  std::size_t count = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++count;
  return count;
}

// The differences h5diff reports between two HDF5 files, one line each, but those naming a
// dataset or attribute that contains one of `ignored` (e.g. measured seconds); "" when the
// files are the same apart from those. Objects h5diff cannot compare count as differences.
inline std::string h5diff_except(const std::filesystem::path& a, const std::filesystem::path& b,
                                 const std::vector<std::string>& ignored) {
  const CommandResult r = run_command("h5diff " + a.string() + " " + b.string());
  if (r.exit_code > 1 || r.exit_code < 0) return "h5diff failed: " + r.output;
  std::istringstream lines(r.output);
  std::string line, other;
  while (std::getline(lines, line)) {
    const bool difference = line.rfind("dataset:", 0) == 0 || line.rfind("attribute:", 0) == 0 ||
                            line.find("not comparable") != std::string::npos;
    bool wanted = difference;
    for (const std::string& name : ignored) wanted = wanted && line.find(name) == std::string::npos;
    if (wanted) other += line + "\n";
  }
  return other;
}

// A small valid scene with inline materials; `extra` is appended (tables or keys); `element`
// ("p1", "p2") is written into [geometry] when given.
inline std::string scene_text(int ex = 1, int ey = 1, int degree = 2, double radius = 0.3,
                              const std::string& extra = "", const std::string& element = "") {
  return "[geometry]\ncells = [" + std::to_string(ex) + ", " + std::to_string(ey) +
         "]\ncell_size = 1.0\nfibre_radius = " + std::to_string(radius) + "\ndegree = " + std::to_string(degree) +
         (element.empty() ? "" : "\nelement = \"" + element + "\"") +
         "\n\n[fibre]\nE = 100.0\nnu = 0.2\n\n[matrix]\nE = 1.0\nnu = 0.35\n" + extra;
}

}  // namespace dualcell::testing
