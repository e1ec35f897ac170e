#pragma once
// The command line of every stage, parsed as CLI11_PARSE does (--help and --version print and
// exit 0, an option error prints and exits non-zero), except that under an MPI launcher only
// the first rank prints and sets the exit code: `mpirun -np 4 dualcell-sweep --help` shows the
// help once. The other ranks stop quietly with 0, so that the launcher waits for the first
// rank's message instead of aborting the job when another rank's error code arrives first.
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/exit_codes.hpp"
#include "core/text.hpp"
#include "law/form.hpp"
#include "par/parallel.hpp"

namespace dualcell {

// A number option within [lo, hi], and finite (CLI::Range alone lets NaN through, every
// comparison with it being false, and calls a word "not in range"): one check, one message that
// names what is wrong, e.g. "--law-tolerance: 'abc' is not a number".
inline CLI::Validator number_in(double lo, double hi) {
  return CLI::Validator(
      [lo, hi](std::string& text) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(text, value)) return "'" + text + "' is not a number";
        if (!std::isfinite(value)) return "'" + text + "' is not a finite number";
        if (!(value >= lo && value <= hi))
          return "'" + text + "' is out of range [" + shortest(lo) + ", " + shortest(hi) + "]";
        return {};
      },
      "NUMBER in [" + shortest(lo) + ", " + shortest(hi) + "]");
}

// The names --form takes (law::law_form_names), for CLI::IsMember.
inline std::vector<std::string> law_forms() {
  return std::vector<std::string>(law::law_form_names.begin(), law::law_form_names.end());
}

// The exit code when the stage must stop here (help shown, or an option error), else nothing.
// An option error is one line as every other input error, "<stage>: error: <what> (see --help)",
// and exits 1 (exit_input_error).
inline std::optional<int> parse_options(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (par::launcher_rank() != 0) return 0;
    if (e.get_exit_code() == 0) return app.exit(e);  // --help, --version
    const std::string stage = std::filesystem::path(argc > 0 ? argv[0] : "dualcell").filename().string();
    std::fprintf(stderr, "%s: error: %s (see --help)\n", stage.c_str(), e.what());
    return exit_input_error;
  }
  return std::nullopt;
}

}  // namespace dualcell
