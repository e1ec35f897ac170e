#include "umat/cell_umat.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <utility>

#include "core/hash.hpp"
#include "law/cell_text.hpp"
#include "law/condensed.hpp"

namespace {

using dualcell::law::CondensedCell;

// The laws read so far (or the reason one could not be), shared by every thread.
struct Loaded {
  std::shared_ptr<const CondensedCell> cell;
  std::uint64_t hash = 0;  // of the file's text
  std::string path, error;
};

std::mutex laws_mutex;
std::map<int, Loaded>& laws() {
  static std::map<int, Loaded> loaded;
  return loaded;
}

// Once per law and kind of failure: a message for every material point would flood the log.
void tell_once(int id, const char* kind, const std::string& message) {
  static std::mutex told_mutex;
  static std::set<std::pair<int, std::string>> told;
  const std::lock_guard<std::mutex> lock(told_mutex);
  if (told.insert({id, kind}).second) std::fprintf(stderr, "dualcell umat: %s\n", message.c_str());
}

const Loaded& load(int id) {
  const std::lock_guard<std::mutex> lock(laws_mutex);
  auto [it, fresh] = laws().try_emplace(id);
  if (!fresh) return it->second;
  Loaded& law = it->second;
  const char* dir = std::getenv("DUALCELL_CELL_DIR");
  law.path = std::string(dir && *dir ? dir : ".") + "/dualcell-cell-" + std::to_string(id) + ".txt";
  std::string error;
  try {
    std::ifstream in(law.path, std::ios::binary);
    if (!in) {
      error = "cannot be opened";
    } else {
      // Read whole to hash it: at most max_cell_rows rows, a few hundred MB of text at worst.
      std::ostringstream read;
      read << in.rdbuf();
      std::string text = std::move(read).str();
      law.hash = dualcell::text_hash_value(text);
      std::istringstream parse(std::move(text));
      CondensedCell cell = dualcell::law::read_cell_text(parse, error);
      if (error.empty() && cell.n_macro != 3)
        error = "the cell carries no shear (n_macro 2): a material point needs all three";
      if (error.empty()) law.cell = std::make_shared<const CondensedCell>(std::move(cell));
    }
  } catch (const std::bad_alloc&) {
    error = "out of memory while reading it";
  } catch (const std::exception& e) {
    error = e.what();
  }
  if (!error.empty()) {
    law.cell.reset();
    law.error = law.path + ": " + error;
    std::fprintf(stderr, "dualcell umat: %s\n", law.error.c_str());
  }
  return law;
}

// The card's two constants back to the hash: each an integer in [0, 2³²).
bool card_hash(const double constants[2], std::uint64_t& hash) {
  for (int i = 0; i < 2; ++i)
    if (!(constants[i] >= 0 && constants[i] < 4294967296.0 && constants[i] == std::floor(constants[i]))) return false;
  hash = static_cast<std::uint64_t>(constants[0]) << 32 | static_cast<std::uint64_t>(constants[1]);
  return true;
}

int statev_needed(const CondensedCell& cell) { return 1 + cell.n_pairs + cell.n_macro + cell.n_rows(); }

}  // namespace

extern "C" int dualcell_cell_statev(int id) {
  try {
    const Loaded& law = load(id);
    return law.cell ? statev_needed(*law.cell) : -1;
  } catch (...) {
    return -1;
  }
}

namespace {

int cell_law(int id, const double hash_constants[2], const double e[3], double* statev, int nstatv, double s[3],
             double D[9], double* W) {
  const Loaded& law = load(id);
  if (!law.cell) return 1;
  std::uint64_t expected = 0;
  if (!card_hash(hash_constants, expected)) {
    tell_once(id, "hash",
              "law " + std::to_string(id) +
                  ": the card's constants 6 and 7 are not a cell file's hash (a card written before "
                  "the hash: export the law again)");
    return 1;
  }
  if (expected != law.hash) {
    char text[160];
    std::snprintf(text, sizeof text, ": its hash is %016llx, the card's %016llx: the file was replaced after the card",
                  static_cast<unsigned long long>(law.hash), static_cast<unsigned long long>(expected));
    tell_once(id, "hash", law.path + text + " was written (export them together)");
    return 1;
  }
  const CondensedCell& cell = *law.cell;
  if (nstatv < statev_needed(cell)) {
    tell_once(id, "depvar",
              "law " + std::to_string(id) + " needs " + std::to_string(statev_needed(cell)) +
                  " state variables (*DEPVAR), the material has " + std::to_string(nstatv));
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
    tell_once(id, "qp", "law " + std::to_string(id) + ": " + r.message);
    return 1;
  }
  if (!r.stress.allFinite() || !r.tangent.allFinite() || !std::isfinite(r.energy)) {
    tell_once(id, "finite", "law " + std::to_string(id) + ": a non-finite stress or tangent (a strain beyond the law)");
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

}  // namespace

// Nothing escapes into the calling code (C or Fortran, which cannot catch it: an exception there
// would abort the whole analysis): every failure is a line and a return of 1, and the umat asks
// for a smaller increment.
extern "C" int dualcell_cell_law(int id, const double hash[2], const double e[3], double* statev, int nstatv,
                                 double s[3], double D[9], double* W) {
  try {
    return cell_law(id, hash, e, statev, nstatv, s, D, W);
  } catch (const std::bad_alloc&) {
    tell_once(id, "memory", "law " + std::to_string(id) + ": out of memory");
  } catch (const std::exception& error) {
    tell_once(id, "exception", "law " + std::to_string(id) + ": " + error.what());
  } catch (...) {
    tell_once(id, "exception", "law " + std::to_string(id) + ": an unknown failure");
  }
  return 1;
}
