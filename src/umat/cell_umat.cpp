#include "umat/cell_umat.h"

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "law/cell_text.hpp"
#include "law/condensed.hpp"

namespace {

using dualcell::law::CondensedCell;

// The laws read so far (or the reason one could not be), shared by every thread.
struct Loaded {
  std::shared_ptr<const CondensedCell> cell;
  std::string error;
};

std::mutex laws_mutex;
std::map<int, Loaded>& laws() {
  static std::map<int, Loaded> loaded;
  return loaded;
}

const Loaded& load(int id) {
  const std::lock_guard<std::mutex> lock(laws_mutex);
  auto [it, fresh] = laws().try_emplace(id);
  if (!fresh) return it->second;
  const char* dir = std::getenv("DUALCELL_CELL_DIR");
  const std::string path = std::string(dir && *dir ? dir : ".") + "/dualcell-cell-" + std::to_string(id) + ".txt";
  std::ifstream in(path);
  std::string error;
  if (!in) {
    error = "cannot be opened";
  } else {
    CondensedCell cell = dualcell::law::read_cell_text(in, error);
    if (error.empty() && cell.n_macro != 3)
      error = "the cell carries no shear (n_macro 2): a material point needs all three";
    if (error.empty()) it->second.cell = std::make_shared<const CondensedCell>(std::move(cell));
  }
  if (!error.empty()) {
    it->second.error = path + ": " + error;
    std::fprintf(stderr, "dualcell umat: %s\n", it->second.error.c_str());
  }
  return it->second;
}

int statev_needed(const CondensedCell& cell) { return 1 + cell.n_pairs + cell.n_macro + cell.n_rows(); }

}  // namespace

extern "C" int dualcell_cell_statev(int id) {
  const Loaded& law = load(id);
  return law.cell ? statev_needed(*law.cell) : -1;
}

extern "C" int dualcell_cell_law(int id, const double e[3], double* statev, int nstatv, double s[3], double D[9],
                                 double* W) {
  const Loaded& law = load(id);
  if (!law.cell) return 1;
  const CondensedCell& cell = *law.cell;
  if (nstatv < statev_needed(cell)) {
    static std::once_flag told;
    std::call_once(told, [&] {
      std::fprintf(stderr, "dualcell umat: law %d needs %d state variables (*DEPVAR), the material has %d\n", id,
                   statev_needed(cell), nstatv);
    });
    return 1;
  }
  thread_local std::map<int, std::unique_ptr<dualcell::law::CellEvaluator>> evaluators;
  auto& evaluator = evaluators[id];
  if (!evaluator) evaluator = std::make_unique<dualcell::law::CellEvaluator>(cell);

  // The state: the unloaded cell's bonds less the broken pairs, and the warm start.
  dualcell::law::CellHistory h = evaluator->unloaded();
  for (int p = 0; p < cell.n_pairs; ++p)
    if (statev[1 + p] >= 0.5) h.bonded[p] = 0;
  const int unknowns = cell.n_macro + cell.n_rows();
  const double* active = statev + 1 + cell.n_pairs;
  bool any = false;
  h.active.assign(unknowns, dualcell::qp::Bound::free);
  for (int j = 0; j < unknowns; ++j) {
    if (active[j] <= -0.5) h.active[j] = dualcell::qp::Bound::lower, any = true;
    if (active[j] >= 0.5) h.active[j] = dualcell::qp::Bound::upper, any = true;
  }
  if (!any) h.active.clear();

  const dualcell::law::CellResponse r = evaluator->at_strain(Eigen::Vector3d(e[0], e[1], e[2]), h);
  if (!r.ok) {
    static std::once_flag told;
    std::call_once(told, [&] { std::fprintf(stderr, "dualcell umat: law %d: %s\n", id, r.message.c_str()); });
    return 1;
  }
  for (int i = 0; i < 3; ++i) {
    s[i] = r.stress(i);
    for (int j = 0; j < 3; ++j) D[3 * i + j] = r.tangent(i, j);
  }
  *W = r.energy;
  statev[0] = r.broken;
  for (int p = 0; p < cell.n_pairs; ++p) statev[1 + p] = cell.bonded[p] && !h.bonded[p] ? 1 : 0;
  for (int j = 0; j < unknowns; ++j)
    statev[1 + cell.n_pairs + j] = j < static_cast<int>(h.active.size()) ? static_cast<double>(h.active[j]) : 0;
  return 0;
}
