// dualcell-law: a law evaluated at given states, as a larger-scale code would evaluate it.
//
// Each row of the points file is one macro strain (εxx, εyy, γxy) or macro stress (σxx, σyy,
// σxy), engineering shear; rows with the same value in an optional first column `path` form one
// loading path from the unloaded cell, its history (the broken bonds) carried along it; rows
// without it each start unloaded. The output has, per row, the other quantity, the consistent
// tangent dσ/dε (9 entries, row by row) and the broken bonds; with --eps33 each row has the strain
// ε33 along the fibres fourth, and σ33 and the tangent's ε33 column come out too; with --full each row
// is the whole ply's strain (εxx, εyy, γxy, ε33, γxz, γyz) and the six stresses and the 6 × 6
// tangent come out. With --delta-T the cell carries a temperature change, held, each path starting
// from the cooled cell. --form cell (the default) is the
// exact law, the cell condensed onto its interface rows; --form small its small cell (the same form
// with few rows, fitted to it); --form cone the compact cone-wise law.
//
//   dualcell-law --law law.h5 --strain points.csv --out values.csv [--form cell|small|cone]

#include <cstdio>

#include "apps/options.hpp"
#include "core/error.hpp"
#include "stage/evaluate.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-law: evaluate a law.h5 at macro strains or stresses from a CSV file, with history along\n"
      "paths (format: docs/guide/evaluate.md)."};
  dualcell::stage::LawPointsOptions options;
  std::string law_file, strain_file, stress_file, out;
  bool quiet = false;
  app.add_option("--law", law_file, "law.h5 written by dualcell-fit")->required();
  auto* strain =
      app.add_option("--strain", strain_file, "CSV of macro strains εxx, εyy, γxy (optional path column first)");
  auto* stress =
      app.add_option("--stress", stress_file, "CSV of macro stresses σxx, σyy, σxy (optional path column first)");
  strain->excludes(stress);
  stress->excludes(strain);
  app.add_option("--out", out, "output CSV file")->required();
  app.add_option("--form", options.form,
                 "cell: the exact condensed law; small: its small cell; cone: the compact cone-wise law; default: "
                 "cell where law.h5 has it, else cone")
      ->check(CLI::IsMember(dualcell::law_forms()));
  app.add_flag("--eps33", options.eps33,
               "each row has a fourth number, the strain e33 along the fibres (a law fitted with [load] macro = "
               "\"full\"); the output gains szz and the tangent's e33 column");
  app.add_flag("--full", options.full,
               "each row has six numbers, exx, eyy, gxy, e33, gxz, gyz (a law fitted with [load] macro = \"full\" "
               "on the periodic boundary; strain-driven): the output is sxx, syy, sxy, szz, sxz, syz and the 6 x 6 "
               "tangent");
  app.add_option("--delta-T", options.delta_T,
                 "a temperature change held at every row, kelvin from the stress-free state (a cure's cool-down is "
                 "negative; the cell form of a law whose phases expand): each path starts from the cooled cell")
      ->check(dualcell::number_in(-1000, 1000));
  app.add_flag("--factorise-each", options.factorise_each,
               "the exact law's QP factorises every new free set instead of bordering the kept factorisation "
               "(the reference the bordered solves are measured against; slower)");
  app.add_flag("--quiet", quiet, "do not print the summary");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-law", [&] {
    using namespace dualcell;
    if (strain_file.empty() && stress_file.empty()) throw InputError("one of --strain and --stress is required");
    options.law_file = law_file;
    options.strain_driven = !strain_file.empty();
    options.points_file = options.strain_driven ? strain_file : stress_file;
    options.out = out;
    const stage::LawPointsSummary s = stage::evaluate_law(options);
    if (!quiet)
      std::printf(
          "dualcell-law: %d rows (%d paths), %s form, %s-driven -> %s, %.3g ms per row (%ld QP subproblems, "
          "%ld factorisations, %ld bordered)\n",
          s.rows, s.paths, s.form.c_str(), options.strain_driven ? "strain" : "stress", out.c_str(),
          s.rows > 0 ? 1e3 * s.seconds / s.rows : 0.0, s.qp_iterations, s.qp_factorisations, s.qp_updates);
  });
}
