// The benchmark's small-cell section: the compact laws of one law.h5 against its exact law, error
// against the cost of an evaluation (docs/method.md §16c).
#include <algorithm>
#include <cstdio>
#include <memory>
#include <sstream>

#include "core/error.hpp"
#include "core/json.hpp"
#include "core/text.hpp"
#include "fit/small_cell.hpp"
#include "io/law_file.hpp"
#include "law/reduced.hpp"
#include "study/bench_parts.hpp"

namespace dualcell::study::bench {

namespace {

// Microseconds per evaluation over the sample's strains, in the order of its rings, best of three
// passes; `begin` starts a pass (a fresh evaluator, whose first point is then cold) and returns
// the evaluation of one strain.
template <class Begin>
double microseconds_per_point(const law::CellSample& sample, Begin&& begin) {
  double best = 1e300;
  for (int pass = 0; pass < 3; ++pass) {
    auto evaluate = begin();
    int points = 0;
    const auto t0 = Clock::now();
    for (const Eigen::Vector3d& e : sample.strain)
      if (e.allFinite()) evaluate(e), ++points;
    best = std::min(best, 1e6 * seconds_since(t0) / std::max(points, 1));
  }
  return best;
}

// Warm strain-driven evaluations of a cell (each from the last one's active set).
double microseconds_per_point(const law::CondensedCell& cell, const law::CellSample& sample) {
  return microseconds_per_point(sample, [&] {
    const auto evaluator = std::make_shared<law::CellEvaluator>(cell);  // not movable: held by pointer
    return [evaluator, history = evaluator->unloaded()](const Eigen::Vector3d& e) mutable {
      evaluator->at_strain(e, history, law::BondMode::held);
    };
  });
}

// One form's row of the table (markdown and JSON, a line on stderr).
struct Table {
  std::ostringstream& md;
  std::vector<std::string> json;
  void row(const std::string& form, const law::CondensedCell* c, const law::ConeCheck& e, double us, double build) {
    md << "| " << form << " | " << (c ? std::to_string(c->n_rows()) : "–") << " | "
       << formatted("%.2f %%", 100 * e.max_error) << " | " << formatted("%.2f %%", 100 * e.rms_error) << " | "
       << formatted("%.3g", us) << " | " << formatted("%.3g", build) << " |\n";
    JsonObject o;
    o.add_text("form", form)
        .add("rows", std::to_string(c ? c->n_rows() : 0))
        .add("max_error", json_number(e.max_error))
        .add("rms_error", json_number(e.rms_error))
        .add("microseconds_per_point", json_number(us))
        .add("build_seconds", json_number(build));
    json.push_back(o.str(4));
    std::fprintf(stderr, "dualcell-bench:   %s: max %.2f %%, rms %.2f %%\n", form.c_str(), 100 * e.max_error,
                 100 * e.rms_error);
  }
  std::string list() const {
    std::string out = "[\n";
    for (std::size_t i = 0; i < json.size(); ++i) out += json[i] + (i + 1 < json.size() ? ",\n" : "\n");
    return out + "  ]";
  }
};

// A law whose small cell was fitted to full solves (no exact law to sample, docs/method.md §16c):
// the fit's own measure at the held-out paths, for the small cell and the cone-wise law, with the
// evaluation cost over the small cell's own sample of strains; where the law has an exact law
// after all (too large for the fit to sample, not to form), both also against it at 1 000
// directions, a check that needs none of the sweep's points.
void small_cell_from_fit(const std::filesystem::path& law_file, const law::Law& law, std::ostringstream& md,
                         JsonObject& json) {
  const law::CondensedCell& small = *law.small;
  const law::CellSample strains = law::sample_cell(small, 1000);
  md << "## Small cell\n\n"
     << law_file.string() << ": no exact law to sample (" << (law.cell ? "too many rows" : law.cell_note)
     << "); the compact laws against " << law::checked_against_text(law.small_check.against) << " at "
     << law.small_check.directions.size() << " stress directions, as the fit measured them (" << law.small_fit.rows
     << " rows fitted at " << law.small_fit.training_directions
     << " other directions). Evaluation: microseconds per warm strain-driven point over the small cell's own sample "
        "of 1 000 directions (best of 3 passes).\n\n"
        "| form | rows | max error | rms error | µs per point | build s |\n|---|---|---|---|---|---|\n";
  Table table{md, {}};
  if (law.cone.ok) {
    const double us = microseconds_per_point(
        strains, [&] { return [&](const Eigen::Vector3d& e) { law::evaluate(law.cone.law, e); }; });
    table.row("cone-wise law (" + law.cone.form + ")", nullptr, law.cone_check, us, 0);
  }
  table.row("small cell, fitted", &small, law.small_check, microseconds_per_point(small, strains),
            law.small_fit.seconds);
  if (law.cell) {
    std::fprintf(stderr, "dualcell-bench: sampling the exact law (%d rows) at 1 000 directions\n", law.cell->n_rows());
    const law::CellSample exact = law::sample_cell(*law.cell, 1000);
    if (law.cone.ok)
      table.row("cone-wise law, against the exact law", nullptr, law::check_cone(law.cone.law, exact), 0, 0);
    table.row("small cell, against the exact law", &small, law::check_reduced(small, exact), 0, 0);
  }
  md << "\n";
  json.add_text("law", law_file.string()).add("interface_rows", "null").add("forms", table.list());
}

}  // namespace

void small_cell(const std::filesystem::path& law_file, std::ostringstream& md, JsonObject& json) {
  const law::Law law = io::read_law(law_file);
  if (law.small && law.small_check.against == law::CheckedAgainst::held_out_solves)
    return small_cell_from_fit(law_file, law, md, json);
  if (!law.cell) throw InputError(law_file.string() + ": has no exact law (" + law.cell_note + ")");
  const law::CondensedCell& cell = *law.cell;
  if (cell.adhesion())
    throw InputError(
        law_file.string() +
        ": the cell has adhesion: its small cell carries a fuse, measured by the fit along the exact law's "
        "cascade paths (law.h5 /law/small_check; method.md §16d)");
  std::fprintf(stderr, "dualcell-bench: small cell of %s (%d rows): sampling the exact law\n", law_file.c_str(),
               cell.n_rows());
  // The fit's own sample sizes (fit/fit.cpp): 1 000 directions to check, 1 500 others to fit.
  const law::CellSample check = law::sample_cell(cell, 1000), training = law::sample_cell(cell, 1500);
  md << "## Small cell\n\n"
     << law_file.string() << ": the exact law (" << cell.n_rows() << " interface rows) against its compact forms at "
     << check.direction.size()
     << " stress directions (relative stress error at the exact strain, docs/method.md §16a); the bases and fits "
        "use "
     << training.direction.size()
     << " other directions. Evaluation: microseconds per warm strain-driven point (best of 3 passes).\n\n"
        "| form | rows | max error | rms error | µs per point | build s |\n|---|---|---|---|---|---|\n";
  Table table{md, {}};
  const auto row = [&](const std::string& form, const law::CondensedCell* c, const law::ConeCheck& e, double us,
                       double build) { table.row(form, c, e, us, build); };
  row("exact law", &cell, law::check_reduced(cell, check), microseconds_per_point(cell, check), 0);
  if (law.cone.ok) {
    const double us = microseconds_per_point(
        check, [&] { return [&](const Eigen::Vector3d& e) { law::evaluate(law.cone.law, e); }; });
    row("cone-wise law (" + law.cone.form + ")", nullptr, law::check_cone(law.cone.law, check), us, 0);
  }
  for (const bool by_body : {false, true})
    for (const int m : {16, 32, 64, 128}) {
      if (m >= cell.n_rows()) break;
      law::ReduceOptions o;
      o.tolerance = 0;
      o.max_rows = m;
      o.split_by_body = by_body;
      const law::ReducedCell r = law::reduce_cell(cell, training, o);
      row(std::string("exact law on its solutions") + (by_body ? ", fibre by fibre" : ""), &r.cell,
          law::check_reduced(r.cell, check), microseconds_per_point(r.cell, check), r.seconds);
    }
  // Each m continued from the rung of the smallest training maximum so far, as the fit's ladder.
  fit::SmallCell kept;
  for (const int m : {8, 16, 24, 32}) {
    if (2 * m >= cell.n_rows()) break;
    fit::SmallCellOptions o;
    o.rows = m;
    const fit::SmallCell s = fit::fit_small_cell(cell, training, o, nullptr, kept.ok ? &kept.cell : nullptr);
    if (!s.ok) continue;
    if (!kept.ok || s.training_max_error < kept.training_max_error) kept = s;
    row("small cell, fitted", &s.cell, law::check_reduced(s.cell, check), microseconds_per_point(s.cell, check),
        s.seconds);
  }
  md << "\n";
  json.add_text("law", law_file.string())
      .add("interface_rows", std::to_string(cell.n_rows()))
      .add("forms", table.list());
}

}  // namespace dualcell::study::bench

namespace dualcell::study {

std::string run_small_cell_only(const BenchOptions& options, const std::filesystem::path& law_file) {
  return bench::run_section_only(options, "small_cell", "", [&](std::ostringstream& md, JsonObject& json) {
    bench::small_cell(law_file, md, json);
  });
}

}  // namespace dualcell::study
