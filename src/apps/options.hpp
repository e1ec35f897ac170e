#pragma once
// The command line of every stage, parsed as CLI11_PARSE does (--help and --version print and
// exit 0, an option error prints and exits non-zero), except that under an MPI launcher only
// the first rank prints and sets the exit code: `mpirun -np 4 dualcell-sweep --help` shows the
// help once. The other ranks stop quietly with 0, so that the launcher waits for the first
// rank's message instead of aborting the job when another rank's error code arrives first.
#include <CLI/CLI.hpp>
#include <cmath>
#include <optional>
#include <string>

#include "par/parallel.hpp"

namespace dualcell {

// A number option that must be finite: CLI::Range lets NaN through (every comparison with it
// is false). Used beside the range: ->check(CLI::Range(a, b))->check(finite_number).
inline const CLI::Validator finite_number(
    [](std::string& text) {
      double value = 0;
      return CLI::detail::lexical_cast(text, value) && std::isfinite(value) ? std::string()
                                                                            : "'" + text + "' is not a finite number";
    },
    "FINITE");

// The exit code when the stage must stop here (help shown, or an option error), else nothing.
inline std::optional<int> parse_options(CLI::App& app, int argc, char** argv) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (par::launcher_rank() != 0) return 0;
    return app.exit(e);
  }
  return std::nullopt;
}

}  // namespace dualcell
