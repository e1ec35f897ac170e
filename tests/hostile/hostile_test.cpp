// Hostile input, nothing lost (docs/reference/hostile-input.md): every stage run on every file of the committed
// corpus data/hostile/ (malformed scene files, truncated and corrupted HDF5 inputs; expectations in its expected.tsv
// files) answers within seconds with exit code 1 and exactly one line
// "<stage>: error: ..." containing the expected words, never a crash, a hang or an internal
// error, and leaves nothing in its output folder; or accepts the file where the manifest says
// so. And an output is only ever replaced whole: a refused or killed run leaves the previous
// file byte-identical, and a killed sweep resumes to the same data.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>

#include "core/exit_codes.hpp"
#include "hostile/hostile_util.hpp"
#include "io/sweep_file.hpp"

namespace dualcell {
namespace {

namespace fs = std::filesystem;
using testing::bin;

const fs::path corpus = fs::path(testing::source_dir()) / "data" / "hostile";

struct Row {
  std::vector<std::string> fields;  // as in the manifest: file, [kind,] outcome, substring, what
};

std::vector<Row> manifest(const fs::path& file) {
  std::ifstream in(file);
  EXPECT_TRUE(in) << file;
  std::vector<Row> rows;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    Row row;
    std::stringstream s(line);
    std::string field;
    while (std::getline(s, field, '\t')) row.fields.push_back(field);
    rows.push_back(row);
  }
  return rows;
}

using testing::expect_no_temporary;
using testing::expect_refused;
using testing::Outcome;
using testing::slurp;

// Every hostile input answers within 20 s.
Outcome run(const std::string& command) { return testing::run_bounded(command, 20); }

std::string quoted(const fs::path& p) { return testing::quoted(p); }

void expect_accepted(const Outcome& r) { EXPECT_EQ(r.exit_code, 0) << r.err; }

// The output folder after a refused run: nothing at all (no output, no *.tmp.*, no parts).
void expect_empty(const fs::path& folder) {
  for (const auto& e : fs::directory_iterator(folder)) ADD_FAILURE() << "left behind: " << e.path().filename();
}

void reset(const fs::path& folder) {
  fs::remove_all(folder);
  fs::create_directories(folder);
}

// --- scene files -------------------------------------------------------------------------------

const fs::path scenes = corpus / "scenes";
const fs::path h5 = corpus / "h5";

// Every scene of the corpus through one stage that reads scenes.
void scenes_through(const std::string& stage, const std::string& before_out) {
  testing::ScratchDir dir;
  const fs::path out = dir / "out";
  const auto rows = manifest(scenes / "expected.tsv");
  ASSERT_GT(rows.size(), 100u);
  for (const auto& row : rows) {
    ASSERT_EQ(row.fields.size(), 4u) << row.fields[0];
    const std::string& file = row.fields[0];
    const bool ok = row.fields[1] == "ok";
    // Accepted scenes need not match the corpus mesh: only dualcell-mesh must take them. What
    // only the mesher can see (an RVE's fibres: mesh-input) only dualcell-mesh must refuse.
    if ((ok || row.fields[1] == "mesh-input") && stage != "dualcell-mesh") continue;
    SCOPED_TRACE(stage + " on scenes/" + file + " (" + row.fields[3] + ")");
    reset(out);
    const Outcome r = run(bin(stage) + " --quiet --config " + quoted(scenes / file) + before_out + " --out " +
                          quoted(out / "out.h5"));
    if (ok) {
      expect_accepted(r);
      EXPECT_TRUE(fs::exists(out / "out.h5") && fs::exists(out / "out.xdmf"));
      expect_no_temporary(out);
    } else {
      ASSERT_TRUE(row.fields[1] == "input" || row.fields[1] == "mesh-input") << row.fields[1];
      expect_refused(r, stage, row.fields[2]);
      expect_empty(out);
    }
  }
}

TEST(HostileScenes, ManifestNamesEveryFile) {
  std::set<std::string> listed;
  for (const auto& row : manifest(scenes / "expected.tsv")) {
    EXPECT_TRUE(listed.insert(row.fields[0]).second) << "twice: " << row.fields[0];
    EXPECT_TRUE(row.fields[1] == "ok" || row.fields[1] == "input" || row.fields[1] == "mesh-input") << row.fields[0];
    EXPECT_TRUE(fs::is_regular_file(scenes / row.fields[0])) << row.fields[0];
  }
  for (const auto& e : fs::directory_iterator(scenes))
    if (e.path().extension() == ".toml") {
      EXPECT_TRUE(listed.count(e.path().filename().string())) << e.path();
    }
}

TEST(HostileScenes, MeshStage) { scenes_through("dualcell-mesh", ""); }

TEST(HostileScenes, SolveStage) {
  scenes_through("dualcell-solve", " --mesh " + quoted(h5 / "mesh.h5") + " --stress 0.01,0,0");
}

TEST(HostileScenes, SweepStage) { scenes_through("dualcell-sweep", " --mesh " + quoted(h5 / "mesh.h5")); }

// Paths that are not files: endless, empty, a folder, absent.
TEST(HostileScenes, DevicesFoldersAndMissingFiles) {
  testing::ScratchDir dir;
  const fs::path out = dir / "out";
  struct Case {
    std::string config, expected;
  };
  for (const Case& c : std::vector<Case>{{"/dev/zero", "larger than 16 MiB"},
                                         {"/dev/null", "missing table [geometry]"},
                                         {scenes.string(), "is a directory"},
                                         {(dir / "absent.toml").string(), "scene file not found"},
                                         {(dir / std::string(5000, 'k')).string(), "cannot access scene file"}}) {
    SCOPED_TRACE(c.config);
    reset(out);
    expect_refused(run(bin("dualcell-mesh") + " --config " + c.config + " --out " + quoted(out / "m.h5")),
                   "dualcell-mesh", c.expected);
    expect_empty(out);
  }
  reset(out);
  expect_refused(run(bin("dualcell-mesh") + " --config " + quoted(h5 / "tiny.toml") + " --out " +
                     quoted(out / std::string(5000, 'k'))),
                 "dualcell-mesh", "cannot write output");
  expect_empty(out);
  const std::string scene = quoted(h5 / "tiny.toml"), mesh = quoted(h5 / "mesh.h5");
  for (const std::string device : {"/dev/zero", "/dev/null"}) {
    SCOPED_TRACE(device);
    reset(out);
    const std::string o = " --out " + quoted(out / "o.h5");
    expect_refused(run(bin("dualcell-solve") + " --config " + scene + " --mesh " + device + " --stress 1,0,0" + o),
                   "dualcell-solve", "not an HDF5 file");
    expect_refused(run(bin("dualcell-solve") + " --config " + scene + " --mesh " + mesh + " --bonds " + device +
                       " --stress 1,0,0" + o),
                   "dualcell-solve", "not an HDF5 file");
    expect_refused(run(bin("dualcell-sweep") + " --config " + scene + " --mesh " + device + o), "dualcell-sweep",
                   "not an HDF5 file");
    expect_refused(run(bin("dualcell-fit") + " --sweep " + device + o), "dualcell-fit", "not an HDF5 file");
    expect_refused(run(bin("dualcell-export") + " --format json --law " + device + " --out " + quoted(out / "o.json")),
                   "dualcell-export", "not an HDF5 file");
    expect_empty(out);
  }
}

// --- HDF5 inputs ---------------------------------------------------------------------------------

struct Command {
  std::string stage, args;  // args without --out
  std::string out_name;
  bool ok;  // accepted regardless of the row (json/csv of a law only calculix refuses)
};

// The commands that read a file of `kind`, as the manifest names them.
std::vector<Command> commands_for(const std::string& kind, const fs::path& file, const fs::path& points) {
  const std::string scene = " --config " + quoted(h5 / "tiny.toml");
  const std::string f = quoted(file);
  if (kind == "mesh")
    return {{"dualcell-solve", scene + " --mesh " + f + " --stress 0.01,0,0", "out.h5", false},
            {"dualcell-sweep", scene + " --mesh " + f, "out.h5", false}};
  if (kind == "solution")
    return {{"dualcell-solve", scene + " --mesh " + quoted(h5 / "mesh.h5") + " --bonds " + f + " --stress 0.01,0,0",
             "out.h5", false}};
  if (kind == "sweep") return {{"dualcell-fit", " --sweep " + f, "out.h5", false}};
  if (kind == "law")
    return {{"dualcell-export", " --law " + f + " --format json", "out.json", false},
            {"dualcell-export", " --law " + f + " --format csv", "out.csv", false},
            {"dualcell-export", " --law " + f + " --format calculix", "out.inp", false},
            {"dualcell-law", " --law " + f + " --strain " + quoted(points), "out.csv", false}};
  if (kind == "law-calculix")
    return {{"dualcell-export", " --law " + f + " --format json", "out.json", true},
            {"dualcell-export", " --law " + f + " --format csv", "out.csv", true},
            {"dualcell-export", " --law " + f + " --format calculix", "out.inp", false}};
  ADD_FAILURE() << "unknown kind " << kind;
  return {};
}

void h5_files_of(const std::set<std::string>& kinds) {
  testing::ScratchDir dir;
  const fs::path out = dir / "out";
  const fs::path points = dir.write("points.csv", "0.01,0,0\n");
  int seen = 0;
  for (const auto& row : manifest(h5 / "expected.tsv")) {
    ASSERT_EQ(row.fields.size(), 5u) << row.fields[0];
    const std::string &file = row.fields[0], &kind = row.fields[1];
    if (!kinds.count(kind)) continue;
    ++seen;
    for (const Command& c : commands_for(kind, h5 / file, points)) {
      SCOPED_TRACE(c.stage + c.args + " (" + row.fields[4] + ")");
      reset(out);
      const Outcome r = run(bin(c.stage) + " --quiet" + c.args + " --out " + quoted(out / c.out_name));
      if (c.ok || row.fields[2] == "ok") {
        expect_accepted(r);
        EXPECT_TRUE(fs::exists(out / c.out_name));
        expect_no_temporary(out);
      } else {
        expect_refused(r, c.stage, row.fields[3]);
        expect_empty(out);
      }
    }
  }
  EXPECT_GT(seen, 10);
}

TEST(HostileH5, ManifestNamesEveryFile) {
  std::set<std::string> listed;
  for (const auto& row : manifest(h5 / "expected.tsv")) {
    EXPECT_TRUE(listed.insert(row.fields[0]).second) << "twice: " << row.fields[0];
    EXPECT_TRUE(fs::exists(h5 / row.fields[0])) << row.fields[0];
  }
  for (const auto& e : fs::directory_iterator(h5)) {
    const std::string name = e.path().filename().string();
    if (name != "expected.tsv" && name != "tiny.toml") {
      EXPECT_TRUE(listed.count(name)) << name;
    }
  }
}

TEST(HostileH5, MeshFilesThroughSolveAndSweep) { h5_files_of({"mesh"}); }
TEST(HostileH5, SolutionFilesAsBonds) { h5_files_of({"solution"}); }
TEST(HostileH5, SweepFilesThroughFit) { h5_files_of({"sweep"}); }
TEST(HostileH5, LawFilesThroughExport) { h5_files_of({"law", "law-calculix"}); }

// --- nothing lost ------------------------------------------------------------------------------

const std::string periodic = "[load]\nboundary = \"periodic\"\n";

// A rerun refused after its outputs were registered (mesh.h5 registered, then mesh.xdmf found to
// be a folder) leaves the previous mesh.h5 byte-identical and no temporary.
TEST(HostileOutputs, RefusedRerunKeepsThePreviousFile) {
  testing::ScratchDir dir;
  const auto first = dir.write("first.toml", testing::scene_text(1, 1, 1, 0.3));
  const auto second = dir.write("second.toml", testing::scene_text(2, 2, 2, 0.3));
  const fs::path out = dir / "out";
  fs::create_directories(out);
  ASSERT_EQ(
      run(bin("dualcell-mesh") + " --quiet --config " + quoted(first) + " --out " + quoted(out / "m.h5")).exit_code, 0);
  const std::string before = slurp(out / "m.h5");
  fs::remove(out / "m.xdmf");
  fs::create_directories(out / "m.xdmf");
  expect_refused(run(bin("dualcell-mesh") + " --config " + quoted(second) + " --out " + quoted(out / "m.h5")),
                 "dualcell-mesh", "it is a directory");
  EXPECT_EQ(slurp(out / "m.h5"), before);
  expect_no_temporary(out);
}

// Killed while writing (the file-size limit raises SIGXFSZ in the middle of the HDF5 or text
// output; a process that ignores the signal sees EFBIG instead and refuses): the previous file
// stays byte-identical. A killed process cannot remove its temporary (<out>.tmp.<pid>); it is
// never taken for the output.
void expect_kill_keeps_previous(const std::string& what, const std::string& command, const fs::path& target,
                                long limit_bytes) {
  SCOPED_TRACE(what);
  ASSERT_TRUE(fs::exists(target));
  const std::string before = slurp(target);
  const Outcome r =
      run("prlimit --fsize=" + std::to_string(limit_bytes) + " -- " + command + " --out " + quoted(target));
  EXPECT_NE(r.exit_code, 0) << "the limit did not stop the write: " << r.err;
  if (r.exit_code == exit_input_error) {
    expect_no_temporary(target.parent_path());
  }
  EXPECT_EQ(slurp(target), before) << "the previous file changed";
}

TEST(HostileOutputs, KilledWhileWritingKeepsThePreviousFile) {
  testing::ScratchDir dir;
  const auto small = dir.write("small.toml", testing::scene_text(1, 1, 1, 0.3, periodic));
  const auto large = dir.write("large.toml", testing::scene_text(3, 3, 4, 0.3, periodic));
  const std::string mesh = bin("dualcell-mesh") + " --quiet --config ";
  ASSERT_EQ(run(mesh + quoted(small) + " --out " + quoted(dir / "mesh.h5")).exit_code, 0);
  expect_kill_keeps_previous("mesh", mesh + quoted(large), dir / "mesh.h5", 16384);

  const std::string solve = bin("dualcell-solve") + " --quiet --config " + quoted(small) + " --mesh " +
                            quoted(dir / "mesh.h5") + " --stress ";
  ASSERT_EQ(run(solve + "0.01,0,0 --out " + quoted(dir / "sol.h5")).exit_code, 0);
  expect_kill_keeps_previous("solve", solve + "0.02,0,0", dir / "sol.h5", 4096);

  const std::string fit = bin("dualcell-fit") + " --quiet --sweep " + quoted(h5 / "sweep.h5");
  ASSERT_EQ(run(fit + " --out " + quoted(dir / "law.h5")).exit_code, 0);
  expect_kill_keeps_previous("fit", fit, dir / "law.h5", 4096);

  const std::string json = bin("dualcell-export") + " --quiet --format json --law ";
  ASSERT_EQ(run(json + quoted(dir / "law.h5") + " --out " + quoted(dir / "law.json")).exit_code, 0);
  expect_kill_keeps_previous("export", json + quoted(h5 / "law.h5"), dir / "law.json", 512);
}

// A sweep killed while writing its final file keeps the previous sweep.h5; run again it resumes
// from its finished parts and writes the same data as an uninterrupted run.
TEST(HostileOutputs, KilledSweepKeepsThePreviousFileAndResumes) {
  testing::ScratchDir dir;
  const auto scene =
      dir.write("s.toml", testing::scene_text(1, 1, 1, 0.3,
                                              periodic + "[sweep]\ndirections_deg = [0, 30, 45, 60, 90, 120]\n"
                                                         "magnitudes = [-0.02, -0.01, 0.01, 0.02]\n"));
  const auto other =
      dir.write("other.toml", testing::scene_text(1, 1, 1, 0.3, periodic + "[sweep]\ndirections_deg = [0]\n"));
  ASSERT_EQ(
      run(bin("dualcell-mesh") + " --quiet --config " + quoted(scene) + " --out " + quoted(dir / "mesh.h5")).exit_code,
      0);
  const std::string sweep = bin("dualcell-sweep") + " --quiet --mesh " + quoted(dir / "mesh.h5") + " --config ";
  ASSERT_EQ(run(sweep + quoted(scene) + " --out " + quoted(dir / "whole.h5")).exit_code, 0);
  ASSERT_EQ(run(sweep + quoted(other) + " --out " + quoted(dir / "sweep.h5")).exit_code, 0);
  // Half the final size: every one-path part fits, the twelve-path file does not.
  const long limit = static_cast<long>(fs::file_size(dir / "whole.h5")) / 2;
  expect_kill_keeps_previous("sweep", sweep + quoted(scene), dir / "sweep.h5", limit);
  int parts = 0;
  for (const auto& e : fs::directory_iterator(dir / "sweep.h5.parts"))
    parts += e.path().extension() == ".h5" && e.path().filename().string().find(".tmp.") == std::string::npos;
  EXPECT_EQ(parts, 12);

  const Outcome resumed = run(sweep + quoted(scene) + " --out " + quoted(dir / "sweep.h5"));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_FALSE(fs::exists(dir / "sweep.h5.parts"));
  const auto a = io::read_sweep(dir / "whole.h5"), b = io::read_sweep(dir / "sweep.h5");
  ASSERT_EQ(a.size(), 12u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t p = 0; p < a.size(); ++p) {
    ASSERT_EQ(a[p].steps.size(), b[p].steps.size()) << p;
    for (std::size_t i = 0; i < a[p].steps.size(); ++i) {
      EXPECT_EQ(a[p].steps[i].load, b[p].steps[i].load);
      EXPECT_EQ(a[p].steps[i].stress, b[p].steps[i].stress);
      EXPECT_EQ(a[p].steps[i].strain, b[p].steps[i].strain);  // bitwise: the same computation
    }
  }
}

}  // namespace
}  // namespace dualcell
