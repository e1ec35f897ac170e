// dualcell-export: a law.h5 in the formats other programs read.
//
// JSON (everything in law.h5, for scripts), CSV (one row per direction) or CalculiX/Abaqus
// material cards: <name>_TENSION and <name>_COMPRESSION, 3D materials in the axes x, y, z = fibre
// direction whose plane-strain response is the fitted one (formulas: docs/guide/export.md, "3D
// constants", and src/io/law_export.hpp). The output is written to a temporary and renamed,
// so a refused or failed export leaves no file.
//
//   dualcell-export --law law.h5 --format calculix --out law.inp --name GLASS_EPOXY
#include <cstdio>

#include "apps/options.hpp"
#include "stage/export.hpp"
#include "stage/stage.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "dualcell-export: write a law.h5 as JSON, CSV, CalculiX/Abaqus material cards or a user-material card\n"
      "(layout and formulas: docs/guide/export.md)."};
  std::string law_file, format, out, name = "DUALCELL";
  bool quiet = false;
  app.add_option("--law", law_file, "law.h5 written by dualcell-fit")->required();
  app.add_option("--format", format,
                 "json: every object of law.h5 (NaN as null); csv: one row per direction; calculix: *MATERIAL "
                 "cards for plane-strain elements (material axes x, y, z = fibre); umat: the law (--form) as *MATERIAL "
                 "ABAQUS_<name>, *USER MATERIAL constants of src/umat/dualcell_umat.c")
      ->required()
      ->check(CLI::IsMember({"json", "csv", "calculix", "umat"}));
  app.add_option("--out", out, "output file, written atomically")->required();
  app.add_option("--name", name,
                 "calculix: base of the material names <name>_TENSION and <name>_COMPRESSION; umat: ABAQUS_<name>")
      ->capture_default_str();
  double max_law_error = std::numeric_limits<double>::quiet_NaN();
  bool force = false;
  app.add_option("--max-law-error", max_law_error,
                 "umat: refuse a cone-wise law whose stress error against the exact law or held-out sweep "
                 "directions (law.h5 /law/cone_check, /law/cone_after_fuse_check) exceeds this fraction, or that "
                 "was measured against neither; likewise a small cell (/law/small_check); default: the tolerance "
                 "the law was fitted to (dualcell-fit --law-tolerance, /law/small_fit), else 0.02")
      ->check(dualcell::number_in(0.0, 1.0));
  app.add_flag(
      "--force", force,
      "umat: write the cone-wise law or the small cell whatever its measured error; replace a cell file that holds "
      "another cell under --cell-id");
  std::string form;
  int cell_id = 1;
  app.add_option("--form", form,
                 "umat: cell, the exact law (its cell in dualcell-cell-<id>.txt beside --out), small, its small cell "
                 "(the same way), or cone, the cone-wise law with the fuse; default: cell where law.h5 has it")
      ->check(CLI::IsMember(dualcell::law_forms()));
  app.add_option("--cell-id", cell_id,
                 "umat --form cell or small: the id that names the cell's file (dualcell-cell-<id>.txt)")
      ->capture_default_str()
      ->check(dualcell::number_in(1, 999999));
  std::string breaks;
  app.add_option("--breaks", breaks,
                 "umat --form cell or small of a whole ply's law (layout 3): within, each material point's debond "
                 "cascade runs at every strain (default); between, its bonds are held within an increment and "
                 "what its cascade breaks at the increment's end breaks at the start of the next (a response a "
                 "Newton method converges on; repeat an increment at the same load to finish the cascade)")
      ->check(CLI::IsMember({"within", "between"}));
  double stress_free_temperature = 0;
  auto* t0 = app.add_option("--stress-free-temperature", stress_free_temperature,
                            "umat --form cell of a whole ply's law that carries a temperature change (layout 3): the "
                            "temperature at which the cell is stress-free, in the analysis' scale; the umat evaluates "
                            "each point at dT = T - T0 (the card's 6th constant)")
                 ->check(dualcell::number_in(-1e6, 1e6));
  app.add_flag("--quiet", quiet, "do not print what was written");
  if (const auto stop = dualcell::parse_options(app, argc, argv)) return *stop;

  return dualcell::run_stage("dualcell-export", [&] {
    using namespace dualcell;
    stage::ExportOptions options;
    options.law_file = law_file;
    options.out = out;
    options.format = io::parse_export_format(format);
    options.name = name;
    options.max_law_error = max_law_error;
    options.force = force;
    options.form = form;
    options.cell_id = cell_id;
    options.breaks = breaks;
    if (t0->count() > 0) options.stress_free_temperature = stress_free_temperature;
    const std::string written = stage::export_law(options);
    if (!quiet) std::printf("dualcell-export: %s -> %s (%s)\n", law_file.c_str(), out.c_str(), written.c_str());
  });
}
