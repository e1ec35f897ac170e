#pragma once
// The law's evaluation as one call (dualcell-law): a law.h5 at the points of a CSV file.
#include <filesystem>
#include <string>

namespace dualcell::stage {

// dualcell-law: a law evaluated at the points of a CSV file (io/points_csv.hpp), strain- or
// stress-driven, in its exact form (the condensed cell, /law/cell), as its small cell
// (/law/small, evaluated as the exact law is) or as the cone-wise law with the fuse (/law/cone
// and /law/cone_after_fuse as the umat evaluates it).
struct LawPointsOptions {
  std::filesystem::path law_file, points_file, out;
  bool strain_driven = true;
  // "cell", "small", "cone" or "" for the default (law::pick_form: the exact law where the law
  // has one, else the cone-wise law).
  std::string form;
  // Rows of four numbers, the fourth the strain ε33 along the fibres (a cell that carries it:
  // [load] macro = "full"); the output gains σ33 and the tangent's ε33 column.
  bool eps33 = false;
  // Rows of six numbers (εxx, εyy, γxy, ε33, γxz, γyz), strain-driven only: the whole ply's law
  // (a cell with the strain and the shear along the fibres, [load] macro = "full" and periodic);
  // the output is (σxx, σyy, σxy, σ33, τxz, τyz) and the 6 × 6 tangent in that order.
  bool full = false;
  // A temperature change held at every row (kelvin from the stress-free state; the cell form of a
  // law whose cell carries it, docs/theory/model.md §1a): each path, and each row without one,
  // starts from the cooled cell (the cool-down at zero stress first).
  double delta_T = 0;
  // Every new free set of the exact law's QP factorised, none bordered (qp/dense_qp.hpp): the
  // reference the bordered solves are measured against.
  bool factorise_each = false;
};
struct LawPointsSummary {
  std::string form;            // the form evaluated (law::law_form_names)
  int rows = 0, paths = 0;     // paths: loading paths with history (rows without a path count one each)
  double seconds = 0;          // of the evaluations alone
  long qp_iterations = 0;      // the cell form's active-set subproblems, all rows
  long qp_factorisations = 0;  // of which needed a new factorisation
  long qp_updates = 0;         // and of which were solved by bordering a kept one
};
// Writes `out` atomically: per input row, over the components it carries (the in-plane three;
// with eps33 and ε33; with full and γxz, γyz, in the law's order), the other quantity (in the plane
// the strain where the rows are stresses; σ33, τxz, τyz), the tangent over the same components by
// row (C11 … Ckk, engineering shear; the ε33 entries strain-driven only, NaN stress-driven) and the
// broken bonds (cell: pairs broken; cone: 1 once fused).
LawPointsSummary evaluate_law(const LawPointsOptions& options);

}  // namespace dualcell::stage
