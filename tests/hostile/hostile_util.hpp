#pragma once
// What the hostile tests share: running a stage bounded in time with its stderr kept, a path
// quoted for the shell, a file's bytes, and the shape of a refusal (one line, its exit code).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/exit_codes.hpp"
#include "test_util.hpp"

namespace dualcell::testing {

struct Outcome {
  int exit_code;
  std::string err;  // stderr only
};

// `command` under `timeout` (a hang is 124, a crash 128 + signal), stdout discarded.
inline Outcome run_bounded(const std::string& command, int seconds = 20) {
  const auto r = run_command("{ timeout " + std::to_string(seconds) + " " + command + " 2>&1 >/dev/null; }");
  return {r.exit_code, r.output};
}

inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// One line "<stage>: error: ..." of bounded length containing `substring`, and the exit code.
inline void expect_refused(const Outcome& r, const std::string& stage, const std::string& substring,
                           int code = exit_input_error) {
  EXPECT_EQ(r.exit_code, code) << "exit code (124: hung, 128+n: killed by signal n, 3: internal error): " << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "not one line: " << r.err;
  EXPECT_TRUE(!r.err.empty() && r.err.back() == '\n') << r.err;
  EXPECT_EQ(r.err.rfind(stage + ": error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find(substring), std::string::npos) << "expected \"" << substring << "\" in: " << r.err;
  EXPECT_LE(r.err.size(), 1200u) << "an unreadably long line";
}

// No temporary ("*.tmp.*", or HDF5's in-memory names) anywhere below `folder`.
inline void expect_no_temporary(const std::filesystem::path& folder) {
  for (const auto& e : std::filesystem::recursive_directory_iterator(folder)) {
    const std::string name = e.path().filename().string();
    EXPECT_EQ(name.find(".tmp."), std::string::npos) << "left behind: " << e.path();
    EXPECT_EQ(name.find(".in-memory."), std::string::npos) << "left behind: " << e.path();
  }
}

}  // namespace dualcell::testing
