// The documents' commands run as written: every indented command block that starts with a stage
// (or `mpirun -np N` and a stage) is extracted from README.md and from every page of docs/ (README
// first, then docs/**/*.md sorted by path, each file's blocks in their order) and run in that order,
// in one folder holding the small files the commands name (scene.toml, beam.toml, structure.toml,
// points.csv, and the default scene's path, pipelines/scenes/default.toml, holding scene.toml's
// small scene: the default scene's own run and printed figures are readme_figures_test.cpp's).
// The README's quick start comes first, so mesh.h5, sweep.h5 and law.h5 exist for every later
// page's commands.
// A synopsis is made runnable by dropping its optional [...] parts and filling its placeholders
// (sxx,syy,sxy, N, FILE); a choice a|b|c runs once per alternative. Every command must exit 0,
// so that an option renamed, a stage's order changed or a file name drifting in a document fails
// here. Left out: the two set-up commands (they are CI itself) and the cluster example that needs
// a host file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_util.hpp"

namespace dualcell {
namespace {

const char* stages[] = {"dualcell-mesh", "dualcell-solve",     "dualcell-sweep",
                        "dualcell-fit",  "dualcell-export",    "dualcell-structure",
                        "dualcell-law",  "dualcell-stability", "dualcell-bench"};

// The first token naming a stage: "dualcell-solve", not "dualcell-solve:" (an output line).
bool starts_with_stage(const std::string& line) {
  std::string rest = line;
  if (rest.rfind("mpirun -np ", 0) == 0) rest = rest.substr(rest.find(' ', 11) + 1);
  for (const char* stage : stages) {
    const std::string s(stage);
    if (rest.rfind(s, 0) == 0 && (rest.size() == s.size() || rest[s.size()] == ' ')) return true;
  }
  return false;
}

// A stage command as written in a document: the command and the file it is in.
struct Written {
  std::string command;
  std::string file;
};

// The documents whose commands run: README.md, then every .md below docs/, sorted by path.
std::vector<std::string> documents() {
  std::vector<std::string> docs;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(testing::source_dir() + "/docs"))
    if (entry.is_regular_file() && entry.path().extension() == ".md")
      docs.push_back(std::filesystem::relative(entry.path(), testing::source_dir()).generic_string());
  std::sort(docs.begin(), docs.end());
  docs.insert(docs.begin(), "README.md");
  return docs;
}

// The indented (4-space) code blocks of one document whose lines are commands, continuation lines
// of a synopsis joined to their command.
void add_commands(const std::string& file, std::vector<Written>& commands) {
  std::ifstream in(testing::source_dir() + "/" + file);
  EXPECT_TRUE(in) << file;
  std::string line;
  bool previous_blank = true, in_block = false;
  while (std::getline(in, line)) {
    const bool indented = line.rfind("    ", 0) == 0;
    if (indented && (in_block || previous_blank)) {
      in_block = true;
      const std::string text = line.substr(4);
      const std::size_t first = text.find_first_not_of(' ');
      if (first == std::string::npos || text[0] == '#') continue;
      if (starts_with_stage(text))
        commands.push_back({text, file});
      else if (first > 0 && !commands.empty() && commands.back().file == file && text[first] == '[') {
        commands.back().command.push_back(' ');  // a synopsis' continuation line
        commands.back().command.append(text, first);
      }
    } else {
      in_block = false;
    }
    previous_blank = line.find_first_not_of(' ') == std::string::npos;
  }
}

std::vector<Written> documented_commands() {
  std::vector<Written> commands;
  for (const std::string& file : documents()) add_commands(file, commands);
  return commands;
}

// A synopsis made runnable: [optional] parts dropped, placeholders filled, each alternative of
// a|b|c as its own command. (By hand, token by token: GCC 12 warns falsely inside std::regex
// and string concatenation under -Werror.)
std::vector<std::string> runnable(const std::string& command) {
  std::string plain;
  int depth = 0;
  for (const char c : command) {
    if (c == '[') ++depth;
    if (depth == 0) plain.push_back(c);
    if (c == ']') --depth;
  }
  std::vector<std::string> tokens;
  std::stringstream words(plain);
  std::string word;
  while (words >> word) tokens.push_back(word);
  std::vector<std::string> alternatives = {""};
  for (const std::string& token : tokens) {
    std::vector<std::string> choices;
    if (token == "sxx,syy,sxy")
      choices = {"0.01,0,0"};
    else if (token == "N")
      choices = {"1"};
    else if (token == "FILE")
      choices = {"law.out"};
    else if (token.find('|') != std::string::npos) {
      std::stringstream parts(token);
      std::string part;
      while (std::getline(parts, part, '|')) choices.push_back(part);
    } else {
      choices = {token};
    }
    std::vector<std::string> grown;
    for (const std::string& start : alternatives)
      for (const std::string& choice : choices) {
        std::string next = start;
        if (!next.empty()) next.push_back(' ');
        next.append(choice);
        grown.push_back(next);
      }
    alternatives = grown;
  }
  return alternatives;
}

TEST(Readme, EveryStageCommandRunsAsWritten) {
  const std::vector<Written> commands = documented_commands();
  ASSERT_GE(commands.size(), 9u) << "the documents' command blocks were not found";
  testing::ScratchDir dir;
  // One geometry for all: the periodic cell of scene.toml (also at the default scene's path) and
  // the resolved block of beam.toml share the mesh.h5 that the README's first command makes.
  const std::string scene = testing::scene_text(2, 1, 1, 0.3,
                                                "[interface]\nnormal_strength = 0.05\n[load]\nboundary = \"periodic\"\n"
                                                "[sweep]\ndirections_deg = [0, 45, 90]\nmagnitudes = [-0.2, -0.02, "
                                                "0.02, 0.2]\n");
  dir.write("scene.toml", scene);
  std::filesystem::create_directories(dir / "pipelines/scenes");
  dir.write("pipelines/scenes/default.toml", scene);
  dir.write("beam.toml", testing::scene_text(2, 1, 1, 0.3,
                                             "[load]\nboundary = \"edges\"\n[edges.left]\ntype = \"fixed\"\n"
                                             "[edges.right]\ntype = \"traction\"\ntraction = [0, -0.01]\n"));
  dir.write("structure.toml",
            "[structure]\ncells = [4, 1]\nelements_per_cell = 1\n[edges.left]\ntype = \"fixed\"\n"
            "[edges.right]\ntype = \"traction\"\ntraction = [0, -0.001]\n");
  // dualcell-law's points: one path of two states (small enough for --strain and --stress alike).
  dir.write("points.csv", "path,a,b,c\np,0.001,0,0\np,0.002,-0.0005,0.0001\n");
  const bool have_mpi = testing::mpi_runs();
  int ran = 0;
  for (const Written& written : commands) {
    if (written.command.find("--hostfile") != std::string::npos) continue;  // a cluster's
    for (std::string command : runnable(written.command)) {
      SCOPED_TRACE(written.file + ": " + written.command + "\n  run as: " + command);
      if (command.rfind("mpirun -np ", 0) == 0) {
        if (!have_mpi) continue;
        command = testing::mpiexec(2, 120) + command.substr(command.find(' ', 11) + 1);
      }
      std::string line = "cd ";
      line.append(dir.path().string()).append(" && PATH=").append(DUALCELL_BIN_DIR).append(":$PATH ");
      line.append(command).append(" --quiet");
      const auto r = testing::run_command(line);
      EXPECT_EQ(r.exit_code, 0) << r.output;
      ++ran;
    }
  }
  EXPECT_GE(ran, have_mpi ? 12 : 10);  // the two mpirun blocks need a build with MPI
}

}  // namespace
}  // namespace dualcell
