// Nothing lost, ever (docs/reference/hostile-input.md): every stage's outputs against a
// write that fails (a file-size limit stepped over the file's growth, a full file system), an
// output path that is a device, a pipe or one of the stage's inputs, an empty output path,
// temporaries orphaned by a killed run; and the refusals of structures that can still move,
// that are too large, or that do not converge. Each refusal is one line and an exit code from
// core/exit_codes.hpp, the previous output stays byte-identical and no temporary is left.
#include <gtest/gtest.h>
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/statvfs.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <climits>
#include <cstring>
#include <fstream>
#include <sstream>

#include "core/exit_codes.hpp"
#include "hostile/hostile_util.hpp"
#include "io/hdf5.hpp"

namespace dualcell {
namespace {

namespace fs = std::filesystem;
using testing::bin;

const fs::path corpus_h5 = fs::path(testing::source_dir()) / "data" / "hostile" / "h5";

using testing::expect_no_temporary;
using testing::expect_refused;
using testing::Outcome;
using testing::slurp;

// Stages here write real files and solve: 60 s each at most (a hang is 124).
Outcome run(const std::string& command) { return testing::run_bounded(command, 60); }

std::string q(const fs::path& p) { return testing::quoted(p); }

// A stage as a user runs it: the command without --out, and the outputs it writes for a target.
struct Stage {
  std::string name, command;
  bool xdmf;  // writes <target>.xdmf beside <target>.h5
};

const std::string structure_scene =
    "[structure]\ncells = [4, 1]\nelements_per_cell = 1\n[edges.left]\ntype = \"fixed\"\n"
    "[edges.right]\ntype = \"traction\"\ntraction = [0, -0.001]\n[output]\nwatch = [4, 0]\n";

const std::string edges_extra =
    "[load]\nboundary = \"edges\"\n[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\n"
    "traction = [0, -0.01]\n[output]\nwatch = [2, 0]\n";

// The inputs every stage needs, made once in `dir`: the corpus' tiny cell, its mesh, sweep and
// law, a resolved block with boundary = "edges" and its mesh, and a small structure.
struct Inputs {
  fs::path dir, scene, mesh, sweep, law, edges, edges_mesh, structure;
  explicit Inputs(const fs::path& folder) : dir(folder) {
    scene = dir / "tiny.toml";
    fs::copy_file(corpus_h5 / "tiny.toml", scene);
    mesh = dir / "mesh.h5";
    sweep = dir / "sweep.h5";
    law = dir / "law.h5";
    EXPECT_EQ(run(bin("dualcell-mesh") + " --quiet --config " + q(scene) + " --out " + q(mesh)).exit_code, 0);
    EXPECT_EQ(run(bin("dualcell-sweep") + " --quiet --config " + q(scene) + " --mesh " + q(mesh) + " --out " + q(sweep))
                  .exit_code,
              0);
    EXPECT_EQ(run(bin("dualcell-fit") + " --quiet --sweep " + q(sweep) + " --out " + q(law)).exit_code, 0);
    edges = dir / "edges.toml";
    std::ofstream(edges) << testing::scene_text(2, 1, 1, 0.3, edges_extra);
    edges_mesh = dir / "edges-mesh.h5";
    EXPECT_EQ(run(bin("dualcell-mesh") + " --quiet --config " + q(edges) + " --out " + q(edges_mesh)).exit_code, 0);
    structure = dir / "beam.toml";
    std::ofstream(structure) << structure_scene;
  }

  std::vector<Stage> stages() const {
    return {
        {"dualcell-mesh", bin("dualcell-mesh") + " --quiet --config " + q(scene), true},
        {"dualcell-solve",
         bin("dualcell-solve") + " --quiet --config " + q(scene) + " --mesh " + q(mesh) + " --stress 0.01,0,0", true},
        {"dualcell-solve", bin("dualcell-solve") + " --quiet --config " + q(edges) + " --mesh " + q(edges_mesh), true},
        {"dualcell-sweep", bin("dualcell-sweep") + " --quiet --config " + q(scene) + " --mesh " + q(mesh), false},
        {"dualcell-fit", bin("dualcell-fit") + " --quiet --sweep " + q(sweep), false},
        {"dualcell-export", bin("dualcell-export") + " --quiet --format umat --law " + q(law), false},
        {"dualcell-structure", bin("dualcell-structure") + " --quiet --config " + q(structure) + " --law " + q(law),
         true}};
  }
};

fs::path xdmf_of(const fs::path& h5) {
  fs::path x = h5;
  return x.replace_extension(".xdmf");
}

// The outputs of `stage` for `target` and their bytes now.
std::vector<std::pair<fs::path, std::string>> snapshot(const Stage& stage, const fs::path& target) {
  std::vector<std::pair<fs::path, std::string>> files{{target, slurp(target)}};
  if (stage.xdmf) files.emplace_back(xdmf_of(target), slurp(xdmf_of(target)));
  return files;
}

void expect_unchanged(const std::vector<std::pair<fs::path, std::string>>& before) {
  for (const auto& [file, bytes] : before) {
    ASSERT_TRUE(fs::is_regular_file(file)) << file << " is gone";
    EXPECT_TRUE(slurp(file) == bytes) << file << " changed";
  }
}

// --- failed writes ---------------------------------------------------------------------------

// A write refused by the file-size limit (the process ignores SIGXFSZ, so write() returns
// EFBIG), at sizes stepped over the whole file from 0 to its last byte: every stage refuses with
// one line naming the file and the reason, and the previous outputs stay byte-identical.
TEST(FailedWrites, ASizeLimitAnywhereInTheFileKeepsThePreviousOutput) {
  testing::ScratchDir dir;
  const Inputs in(dir.path());
  fs::create_directories(dir / "out");
  int runs = 0;
  for (const Stage& stage : in.stages()) {
    const fs::path target = dir / "out" / (stage.name == "dualcell-export" ? "law.f" : "out.h5");
    SCOPED_TRACE(stage.command);
    ASSERT_EQ(run(stage.command + " --out " + q(target)).exit_code, 0);
    const auto before = snapshot(stage, target);
    const long size = static_cast<long>(before.front().second.size());
    ASSERT_GT(size, 100);
    for (const long limit : {0L, 1L, 8L, size / 8, size / 4, size / 2, 3 * size / 4, size - 1}) {
      SCOPED_TRACE("file-size limit " + std::to_string(limit) + " of " + std::to_string(size) + " bytes");
      const Outcome r = run("bash -c \"trap '' XFSZ; exec prlimit --fsize=" + std::to_string(limit) + " -- " +
                            stage.command + " --out " + q(target) + "\"");
      expect_refused(r, stage.name, ": cannot write: File too large");
      expect_unchanged(before);
      expect_no_temporary(dir / "out");
      ++runs;
    }
    fs::remove_all(dir / "out" / "out.h5.parts");  // a sweep's finished parts, kept for a resume
  }
  EXPECT_EQ(runs, 56);
}

// A mount namespace of this test process alone (the stages it starts inherit it) with a small
// tmpfs, so that "No space left on device" is a real full file system. Needs CAP_SYS_ADMIN.
class FullDisk : public ::testing::Test {
 protected:
  void SetUp() override {
    if (::unshare(CLONE_NEWNS) != 0) GTEST_SKIP() << "no private mount namespace: " << std::strerror(errno);
    if (::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) != 0)
      GTEST_SKIP() << "cannot make the mounts private: " << std::strerror(errno);
    disk_ = dir_ / "disk";
    fs::create_directories(disk_);
    if (::mount("tmpfs", disk_.c_str(), "tmpfs", 0, "size=2m") != 0)
      GTEST_SKIP() << "cannot mount a tmpfs here: " << std::strerror(errno);
    mounted_ = true;
  }
  void TearDown() override {
    if (mounted_) ::umount2(disk_.c_str(), MNT_DETACH);
  }

  // Fills the disk but `free_pages` pages (4 KiB): a filler written until ENOSPC, then cut.
  void leave_free(long free_pages) {
    const fs::path filler = disk_ / "filler";
    fs::remove(filler);
    {
      std::ofstream f(filler, std::ios::binary);
      const std::string block(65536, 'x');
      while (f.write(block.data(), static_cast<std::streamsize>(block.size()))) {
      }
    }
    struct statvfs s {};
    const auto filled = fs::file_size(filler) / 4096 * 4096;
    fs::resize_file(filler, filled);
    ASSERT_EQ(::statvfs(disk_.c_str(), &s), 0);
    const long free_now = static_cast<long>(s.f_bavail * s.f_frsize / 4096);
    ASSERT_GE(static_cast<long>(filled / 4096) + free_now, free_pages);
    fs::resize_file(filler, filled - static_cast<std::uintmax_t>(std::max(0L, free_pages - free_now)) * 4096);
    ASSERT_EQ(::statvfs(disk_.c_str(), &s), 0);
    ASSERT_EQ(static_cast<long>(s.f_bavail * s.f_frsize / 4096), free_pages);
  }

  testing::ScratchDir dir_;
  fs::path disk_;
  bool mounted_ = false;
};

// With the disk full to within 0, 1, ... pages of what the outputs need (the .h5 fits and the
// .xdmf does not at the last step), every stage refuses with "No space left on device", keeps its
// previous outputs byte-identical and leaves no temporary.
TEST_F(FullDisk, EveryStageRefusesAndKeepsThePreviousOutput) {
  const Inputs in(dir_.path());
  int runs = 0;
  for (const Stage& stage : in.stages()) {
    SCOPED_TRACE(stage.command);
    fs::remove(disk_ / "filler");
    const fs::path target = disk_ / (stage.name == "dualcell-export" ? "law.f" : "out.h5");
    ASSERT_EQ(run(stage.command + " --out " + q(target)).exit_code, 0);
    const auto before = snapshot(stage, target);
    long needed = 0;
    for (const auto& [file, bytes] : before) needed += static_cast<long>((bytes.size() + 4095) / 4096);
    for (long free_pages = 0; free_pages < needed; ++free_pages) {
      SCOPED_TRACE(std::to_string(free_pages) + " free pages of the " + std::to_string(needed) + " needed");
      leave_free(free_pages);
      expect_refused(run(stage.command + " --out " + q(target)), stage.name, ": cannot write: No space left on device");
      expect_unchanged(before);
      expect_no_temporary(disk_);
      ++runs;
    }
    fs::remove_all(disk_ / "out.h5.parts");
  }
  EXPECT_GE(runs, 14);
}

// --- output paths ------------------------------------------------------------------------------

// An output that exists and is not a regular file (a character device like /dev/null, a FIFO)
// is refused before any work, for the .h5 and for the .xdmf beside it; the device stays a device.
TEST(OutputPaths, DevicesAndPipesAreRefusedAndStayWhatTheyAre) {
  testing::ScratchDir dir;
  const Inputs in(dir.path());
  fs::create_directories(dir / "out");
  std::vector<fs::path> specials;
  const fs::path fifo = dir / "out" / "fifo.h5";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  specials.push_back(fifo);
  const fs::path null = dir / "out" / "null.h5";  // a copy of /dev/null's node, where a mistake harms nothing
  if (::mknod(null.c_str(), S_IFCHR | 0666, ::makedev(1, 3)) == 0) specials.push_back(null);
  const fs::path twin = dir / "out" / "twin.h5";  // twin.xdmf is a FIFO
  ASSERT_EQ(::mkfifo((dir / "out" / "twin.xdmf").c_str(), 0600), 0);
  for (const Stage& stage : in.stages()) {
    SCOPED_TRACE(stage.command);
    for (const fs::path& special : specials) {
      expect_refused(run(stage.command + " --out " + q(special)), stage.name, "is not a regular file");
      struct stat s {};
      ASSERT_EQ(::stat(special.c_str(), &s), 0);
      EXPECT_TRUE(S_ISFIFO(s.st_mode) || S_ISCHR(s.st_mode)) << special << " was replaced";
    }
    if (stage.xdmf) {
      expect_refused(run(stage.command + " --out " + q(twin)), stage.name, "twin.xdmf: cannot write output");
      EXPECT_FALSE(fs::exists(twin));
    }
  }
  expect_no_temporary(dir / "out");
}

// An output that is one of the stage's inputs, however it is spelled (the same name, ./name, a
// hard link), is refused before any work and the input is left as it was.
TEST(OutputPaths, AnOutputThatIsAnInputIsRefused) {
  testing::ScratchDir dir;
  const Inputs in(dir.path());
  fs::create_hard_link(in.law, dir / "law-link.h5");
  struct Case {
    std::string stage, command;
    fs::path out, input;
  };
  const std::string solve =
      bin("dualcell-solve") + " --config " + q(in.scene) + " --mesh " + q(in.mesh) + " --stress 0.01,0,0";
  const std::vector<Case> cases{
      {"dualcell-fit", bin("dualcell-fit") + " --sweep " + q(in.sweep), in.sweep, in.sweep},
      {"dualcell-fit", bin("dualcell-fit") + " --sweep " + q(in.sweep), dir / "." / "sweep.h5", in.sweep},
      {"dualcell-export", bin("dualcell-export") + " --format json --law " + q(in.law), in.law, in.law},
      {"dualcell-export", bin("dualcell-export") + " --format json --law " + q(in.law), dir / "law-link.h5", in.law},
      {"dualcell-solve", solve, in.mesh, in.mesh},
      {"dualcell-solve", solve, in.scene, in.scene},
      {"dualcell-mesh", bin("dualcell-mesh") + " --config " + q(in.scene), in.scene, in.scene},
      {"dualcell-sweep", bin("dualcell-sweep") + " --config " + q(in.scene) + " --mesh " + q(in.mesh), in.mesh,
       in.mesh},
      {"dualcell-structure", bin("dualcell-structure") + " --config " + q(in.structure) + " --law " + q(in.law), in.law,
       in.law},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.command + " --out " + c.out.string());
    const std::string before = slurp(c.input);
    expect_refused(run(c.command + " --out " + q(c.out)), c.stage, "cannot write output: it is the input");
    EXPECT_TRUE(slurp(c.input) == before) << c.input << " changed";
  }
  expect_no_temporary(dir.path());
}

// An empty output path is refused before any work: one line, no progress, nothing written.
TEST(OutputPaths, AnEmptyOutputIsRefusedFirst) {
  testing::ScratchDir dir;
  const Inputs in(dir.path());
  for (Stage stage : in.stages()) {
    SCOPED_TRACE(stage.command);
    const auto quiet = stage.command.find(" --quiet");
    stage.command.erase(quiet, 8);  // progress lines would show work done before the refusal
    expect_refused(run(stage.command + " --out ''"), stage.name, "output path is empty");
  }
  expect_no_temporary(dir.path());
}

// Temporaries of runs that were killed (their process is gone) are removed by the next run that
// writes the same output; those of a process still running, or of another host, are left alone.
TEST(OutputPaths, OrphanedTemporariesAreRemovedByTheNextRun) {
  testing::ScratchDir dir;
  const Inputs in(dir.path());
  const pid_t dead = ::fork();
  if (dead == 0) ::_exit(0);
  ASSERT_GT(dead, 0);
  ::waitpid(dead, nullptr, 0);
  char host[HOST_NAME_MAX + 1] = {};
  ASSERT_EQ(::gethostname(host, sizeof host - 1), 0);
  const fs::path out = dir / "law2.h5";
  const std::string d = std::to_string(dead), live = std::to_string(::getpid());
  const std::vector<std::string> orphans{"law2.h5.tmp." + std::string(host) + "." + d, "law2.h5.tmp." + d};
  const std::vector<std::string> kept{"law2.h5.tmp." + std::string(host) + "." + live, "law2.h5.tmp.another-host." + d,
                                      "law.h5.tmp." + d, "law2.h5.tmp." + std::to_string(dead + 1)};
  for (const auto& name : orphans) std::ofstream(dir / name) << "half a file";
  for (const auto& name : kept) std::ofstream(dir / name) << "someone else's";
  // Named as before hosts were named, a temporary is an orphan only when it is also older than a
  // day (it names no host: a fresh one might be another host's); law2.h5.tmp.<pid + 1> is fresh.
  fs::last_write_time(dir / orphans[1], fs::file_time_type::clock::now() - std::chrono::hours(48));
  ASSERT_EQ(run(bin("dualcell-fit") + " --quiet --sweep " + q(in.sweep) + " --out " + q(out)).exit_code, 0);
  for (const auto& name : orphans) EXPECT_FALSE(fs::exists(dir / name)) << name;
  for (const auto& name : kept) EXPECT_TRUE(fs::exists(dir / name)) << name;
}

// --- structures --------------------------------------------------------------------------------

struct StructureRun {
  testing::ScratchDir& dir;
  Outcome operator()(const std::string& scene_text, const fs::path& law = corpus_h5 / "law.h5") const {
    const auto scene = dir.write("s.toml", scene_text);
    return run(bin("dualcell-structure") + " --quiet --config " + q(scene) + " --law " + q(law) + " --out " +
               q(dir / "st.h5"));
  }
};

// A structure or resolved block that its edges and supports do not hold against every rigid
// motion is bad input, named before anything is factorised: which motion is free, what holds it.
TEST(FreeStructures, TheMotionLeftFreeIsNamed) {
  testing::ScratchDir dir;
  const StructureRun structure{dir};
  const std::string beam = "[structure]\ncells = [4, 1]\nelements_per_cell = 1\n";
  expect_refused(structure(beam + "[[support]]\nat = [0, 0]\nfix = \"xy\"\n[[point_load]]\nat = [4, 1]\n"
                                  "force = [0, -1]\n"),
                 "dualcell-structure", "leave a rigid-body motion free, a rotation about (0, 0): hold a second point");
  expect_refused(structure(beam + "[edges.bottom]\ntype = \"roller\"\n[edges.top]\ntype = \"traction\"\n"
                                  "traction = [0.1, 0]\n"),
                 "dualcell-structure", "free, the translation along x: hold x somewhere");
  expect_refused(structure(beam + "[edges.left]\ntype = \"roller\"\n[edges.right]\ntype = \"traction\"\n"
                                  "traction = [0.1, 0]\n"),
                 "dualcell-structure", "free, the translation along y");
  EXPECT_FALSE(fs::exists(dir / "st.h5"));

  // Positions are in the law's unit: with cells of size 2, a support at [0, 4] is half-way up the
  // left edge of a 4 × 4-cell block (8 high), not at its top, and with the top edge held in x it
  // holds every rigid motion.
  const fs::path wide = dir / "wide-law.h5";
  fs::copy_file(corpus_h5 / "law.h5", wide);
  io::File::open_write(wide).write_attribute("/law", "cell_size", 2.0);
  const std::string held =
      "[structure]\ncells = [4, 4]\nelements_per_cell = 1\n[edges.top]\ntype = "
      "\"displacement\"\nux = 0.01\n[[support]]\nat = [0, 4]\nfix = \"xy\"\n";
  const Outcome accepted = structure(held, wide);
  // (Its solution is a rigid rotation about the support, stress-free: Newton judges it by the
  // residual it started from, since both forces vanish there.)
  EXPECT_EQ(accepted.exit_code, exit_ok) << accepted.err;
  // The same scene in cells of size 1: the support is on the top edge, which holds x only.
  expect_refused(structure(held), "dualcell-structure", "free, a rotation about");
  fs::remove(dir / "st.h5");
  fs::remove(dir / "st.xdmf");

  // A resolved block held only at a fibre's centre: the matrix would float free of it.
  const auto scene = dir.write("block.toml", testing::scene_text(2, 1, 1, 0.3,
                                                                 "[load]\nboundary = \"edges\"\n[[support]]\n"
                                                                 "at = [0.5, 0.5]\nfix = \"xy\"\n[[point_load]]\n"
                                                                 "at = [2, 1]\nforce = [0, -0.01]\n"));
  for (const std::string& stage : {std::string("dualcell-mesh"), std::string("dualcell-solve")}) {
    const std::string extra = stage == "dualcell-solve" ? " --mesh " + q(corpus_h5 / "mesh.h5") : "";
    expect_refused(run(bin(stage) + " --config " + q(scene) + extra + " --out " + q(dir / "x.h5")), stage,
                   "(a support inside a fibre holds that fibre only)");
  }
  if (testing::mpi_runs()) {
    const auto r = testing::run_command(testing::mpiexec(2, 60) + bin("dualcell-solve") + " --config " + q(scene) +
                                        " --mesh " + q(corpus_h5 / "mesh.h5") + " --out " + q(dir / "x.h5"));
    EXPECT_EQ(r.exit_code, exit_input_error) << r.output;
    EXPECT_EQ(testing::occurrences(r.output, "dualcell-solve: error:"), 1u) << r.output;
    EXPECT_EQ(testing::occurrences(r.output, "rigid-body motion free"), 1u) << r.output;
  }
  EXPECT_FALSE(fs::exists(dir / "x.h5"));
}

// Sizes beyond the mesh limit are refused from the scene, before anything is allocated; an
// integer beyond 64 bits is quoted as written; a position off the mesh names its file and line.
TEST(FreeStructures, SizesIntegersAndPositionsAreRefusedAsWritten) {
  testing::ScratchDir dir;
  const StructureRun structure{dir};
  const std::string held = "[edges.left]\ntype = \"fixed\"\n[edges.right]\ntype = \"traction\"\ntraction = [0, -1]\n";
  for (const std::string cells : {"[100000, 100]", "[100000, 100000]"})
    expect_refused(structure("[structure]\ncells = " + cells + "\n" + held), "dualcell-structure",
                   "cells = " + cells + ": with elements_per_cell = 2 (p2) the structure would have");
  expect_refused(structure("[structure]\ncells = [2, 1]\nelements_per_cell = 4294967298\n" + held),
                 "dualcell-structure", "elements_per_cell = 4294967298: must be an integer in [1, 64]");
  expect_refused(structure("[structure]\ncells = [2, 1]\n" + held + "[[support]]\nat = [0.3, 0.123]\n"),
                 "dualcell-structure", "s.toml:9: [[support]] 1 at (0.3, 0.123): no node there");
  expect_refused(structure("[structure]\ncells = [2, 1]\n" + held + "[output]\nwatch = [7, 0]\n"), "dualcell-structure",
                 "s.toml:9: [output] watch at (7, 0): no node there");
  // A law whose cell is 1e-300 wide is refused for that, not later for a position.
  const fs::path tiny = dir / "tiny-law.h5";
  fs::copy_file(corpus_h5 / "law.h5", tiny);
  io::File::open_write(tiny).write_attribute("/law", "cell_size", 1e-300);
  expect_refused(structure("[structure]\ncells = [2, 1]\n" + held, tiny), "dualcell-structure",
                 "/law attribute cell_size = 1e-300: a structure needs a cell size in");
  EXPECT_FALSE(fs::exists(dir / "st.h5"));
}

// A step that does not converge (Newton steps exhausted, or a load so large that the energy is
// not finite) is written and marked, and the stage exits with exit_not_converged, as
// dualcell-solve does.
TEST(FreeStructures, ANonConvergedStructureIsWrittenMarkedAndExitsNotConverged) {
  testing::ScratchDir dir;
  const StructureRun structure{dir};
  for (const std::string& extra :
       {std::string("[edges.right]\ntype = \"traction\"\ntraction = [0, -0.001]\n[solver]\nmax_newton_steps = 1\n"
                    "tolerance = 1e-15\n"),
        std::string("[edges.right]\ntype = \"traction\"\ntraction = [0, -1e300]\n")}) {
    SCOPED_TRACE(extra);
    fs::remove(dir / "st.h5");
    const Outcome r =
        structure("[structure]\ncells = [4, 1]\nelements_per_cell = 1\n[edges.left]\ntype = \"fixed\"\n" + extra);
    EXPECT_EQ(r.exit_code, exit_not_converged) << r.err;
    EXPECT_NE(r.err.find("did not converge"), std::string::npos) << r.err;
    ASSERT_TRUE(fs::exists(dir / "st.h5"));
    const auto converged = io::File::open_read(dir / "st.h5").read_ints("/steps/converged", {1});
    EXPECT_EQ(converged[0], 0);
  }
}

// --- under mpirun --------------------------------------------------------------------------------

// --help and an option error print once, not once per rank.
TEST(OutputPaths, HelpAndOptionErrorsPrintOnceUnderMpirun) {
  if (testing::run_command("command -v mpiexec").exit_code != 0) GTEST_SKIP() << "no mpiexec";
  for (const std::string stage : {"dualcell-sweep", "dualcell-solve", "dualcell-fit"}) {
    SCOPED_TRACE(stage);
    const auto help = testing::run_command(testing::mpiexec(2, 60) + bin(stage) + " --help");
    EXPECT_EQ(help.exit_code, 0) << help.output;
    EXPECT_EQ(testing::occurrences(help.output, "--out"),
              testing::occurrences(testing::run_command(bin(stage) + " --help").output, "--out"))
        << help.output;
    const auto bad = testing::run_command(testing::mpiexec(2, 60) + bin(stage) + " --no-such-option");
    EXPECT_EQ(bad.exit_code, exit_input_error) << bad.output;
    EXPECT_EQ(testing::occurrences(bad.output, "(see --help)"), 1u) << bad.output;
  }
}

}  // namespace
}  // namespace dualcell
