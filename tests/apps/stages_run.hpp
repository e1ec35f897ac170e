#pragma once
// The stages from a scene text to a law (mesh, sweep, fit) in a scratch folder, and the CSV that
// dualcell-law writes read back: what the law stage tests share.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/exit_codes.hpp"
#include "test_util.hpp"

namespace dualcell::testing {

inline std::string q(const std::filesystem::path& p) { return quoted(p); }

// mesh → sweep → fit of a scene text, quietly, each stage expected to succeed. One scratch folder
// per test (ScratchDir): a second StagesRun in the same test reuses it.
struct StagesRun {
  ScratchDir dir;
  std::filesystem::path sweep, law;
  explicit StagesRun(const std::string& scene_text) {
    const auto scene = dir.write("s.toml", scene_text);
    const std::string cfg = " --quiet --config " + q(scene);
    EXPECT_EQ(run_command(bin("dualcell-mesh") + cfg + " --out " + q(dir / "mesh.h5")).exit_code, exit_ok);
    sweep = dir / "sweep.h5";
    const auto s = run_command(bin("dualcell-sweep") + cfg + " --mesh " + q(dir / "mesh.h5") + " --out " + q(sweep));
    EXPECT_EQ(s.exit_code, exit_ok) << s.output;
    law = dir / "law.h5";
    const auto f = run_command(bin("dualcell-fit") + " --sweep " + q(sweep) + " --out " + q(law));
    EXPECT_EQ(f.exit_code, exit_ok) << f.output;
    fit_output = f.output;
  }
  std::string fit_output;
};

// A CSV of numbers (dualcell-law's output), its header line into `header`.
inline std::vector<std::vector<double>> read_csv(const std::filesystem::path& file, std::string* header = nullptr) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  if (header) *header = line;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream fields(line);
    std::string field;
    while (std::getline(fields, field, ',')) row.push_back(std::stod(field));
    rows.push_back(row);
  }
  return rows;
}

}  // namespace dualcell::testing
