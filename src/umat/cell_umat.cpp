#include "umat/cell_umat.h"

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

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
    // What the file is and its size before a byte is read: a device (/dev/zero, or a link to it)
    // or a file beyond the largest cell the limits allow would otherwise be read whole to hash it.
    std::error_code code;
    const std::filesystem::file_status status = std::filesystem::status(law.path, code);
    const std::uintmax_t largest = dualcell::law::max_cell_text_bytes();
    std::ifstream in;
    if (!code && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status)) {
      error = "is not a regular file (a directory, a device or a pipe): a cell file is the text dualcell-export writes";
    } else if (std::uintmax_t bytes = std::filesystem::file_size(law.path, code); !code && bytes > largest) {
      error = std::to_string(bytes) + " bytes, more than the largest cell the limits allow (" +
              std::to_string(largest) + " bytes at " + std::to_string(dualcell::law::max_cell_rows) + " rows)";
    } else if (in.open(law.path, std::ios::binary); !in) {
      error = "cannot be opened";
    } else {
      // Read whole to hash it: at most max_cell_text_bytes.
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

// The whole ply's law: the strain and the shears along the fibres.
bool is_ply(const CondensedCell& cell) { return cell.longitudinal == 1 && cell.shear == 2; }

int statev_needed(const CondensedCell& cell) {
  return 1 + cell.n_pairs + cell.n_macro + cell.n_rows() + (is_ply(cell) ? cell.shear_rows : 0);
}

}  // namespace

extern "C" int dualcell_cell_is_ply(int id) {
  try {
    const Loaded& law = load(id);
    return law.cell ? (is_ply(*law.cell) ? 1 : 0) : -1;
  } catch (...) {
    return -1;
  }
}

extern "C" int dualcell_cell_statev(int id) {
  try {
    const Loaded& law = load(id);
    return law.cell ? statev_needed(*law.cell) : -1;
  } catch (...) {
    return -1;
  }
}

namespace {

// Active-set entries of the state (−1, 0, 1) into a warm start (empty when all free).
void read_active(const double* state, int n, std::vector<dualcell::qp::Bound>& active) {
  bool any = false;
  active.assign(n, dualcell::qp::Bound::free);
  for (int j = 0; j < n; ++j) {
    if (state[j] <= -0.5) active[j] = dualcell::qp::Bound::lower, any = true;
    if (state[j] >= 0.5) active[j] = dualcell::qp::Bound::upper, any = true;
  }
  if (!any) active.clear();
}

void write_active(const std::vector<dualcell::qp::Bound>& active, int n, double* state) {
  for (int j = 0; j < n; ++j) state[j] = j < static_cast<int>(active.size()) ? static_cast<double>(active[j]) : 0;
}

// The law at the in-plane strain (n = 3: ε11, ε22, γ12) or the whole ply's (n = 6, Abaqus's
// order), σ and D (n × n, row by row) in the same order.
int cell_law(int id, const double hash_constants[2], int n, const double* e, double delta_T, double* statev, int nstatv,
             double* s, double* D, double* W, bool between) {
  const Loaded& law = load(id);
  if (!law.cell) return 1;
  std::uint64_t expected = 0;
  if (!card_hash(hash_constants, expected)) {
    tell_once(id, "hash",
              "law " + std::to_string(id) +
                  ": the card's constants are not a cell file's hash (a card written before "
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
  if ((n == 6) != is_ply(cell)) {
    tell_once(id, "layout",
              "law " + std::to_string(id) +
                  (n == 6 ? ": the cell is in-plane only (its card is layout 2)"
                          : ": the cell is the whole ply's (its card is layout 3)"));
    return 1;
  }
  if (nstatv < statev_needed(cell)) {
    tell_once(id, "depvar",
              "law " + std::to_string(id) + " needs " + std::to_string(statev_needed(cell)) +
                  " state variables (*DEPVAR), the material has " + std::to_string(nstatv));
    return 1;
  }
  thread_local std::map<int, std::unique_ptr<dualcell::law::CellEvaluator>> evaluators;
  auto& evaluator = evaluators[id];
  if (!evaluator) evaluator = std::make_unique<dualcell::law::CellEvaluator>(cell);

  // The state: the unloaded cell's bonds less the broken pairs, and the warm starts.
  dualcell::law::CellHistory h = evaluator->unloaded();
  for (int p = 0; p < cell.n_pairs; ++p)
    if (statev[1 + p] >= 0.5) h.bonded[p] = 0;
  const int unknowns = cell.n_macro + cell.n_rows(), shear_rows = n == 6 ? cell.shear_rows : 0;
  double* active = statev + 1 + cell.n_pairs;
  read_active(active, unknowns, h.active);
  read_active(active + unknowns, shear_rows, h.active_z);

  // The macro state in the law's order (xx, yy, xy, zz, xz, yz) from Abaqus's (11, 22, 33, 12,
  // 13, 23), strain-driven, the in-plane part at load factor 1 and the rest held; the response
  // goes back through the same map.
  using dualcell::MacroState;
  static constexpr int law_of[6] = {0, 1, 3, 2, 4, 5};
  MacroState state = MacroState::strain(Eigen::Vector3d::Zero());
  for (int i = 0; i < n; ++i) {
    const int k = n == 6 ? law_of[i] : i;
    if (k < 3)
      state.value(k) = e[i];
    else
      state.hold(static_cast<MacroState::Component>(k), e[i]);
  }
  if (delta_T != 0) state.hold(MacroState::dT, delta_T);
  // Within the increment (the default) the point's debond cascade at this strain; between
  // increments the bonds held (a bonded row at its strength carries its strength), and the pairs
  // the cascade at this strain would break are only marked, to break at the start of the next
  // increment (cell_umat.h).
  const dualcell::law::BondMode mode = between ? dualcell::law::BondMode::held : dualcell::law::BondMode::cascade;
  const dualcell::law::CellResponse r = evaluator->at(state, h, mode);
  if (!r.ok) {
    tell_once(id, "qp", "law " + std::to_string(id) + ": " + r.message);
    return 1;
  }
  std::vector<std::uint8_t> pending;
  if (between) {
    dualcell::law::CellHistory next = h;
    const dualcell::law::CellResponse c = evaluator->at(state, next, dualcell::law::BondMode::cascade);
    if (!c.ok) {
      tell_once(id, "qp", "law " + std::to_string(id) + ": " + c.message);
      return 1;
    }
    pending.assign(static_cast<std::size_t>(cell.n_pairs), 0);
    for (int p = 0; p < cell.n_pairs; ++p) pending[p] = h.bonded[p] && !next.bonded[p];
  }
  // The law's order; in-plane only the first three of σ and the top 3 × 3 of the tangent count.
  const Eigen::Matrix<double, 6, 1> sigma = dualcell::law::ply_stress(r);
  const Eigen::Matrix<double, 6, 6> tangent = dualcell::law::ply_tangent(r);
  if (!sigma.head(n).allFinite() || !tangent.topLeftCorner(n, n).allFinite() || !std::isfinite(r.energy)) {
    tell_once(id, "finite", "law " + std::to_string(id) + ": a non-finite stress or tangent (a strain beyond the law)");
    return 1;
  }
  for (int i = 0; i < n; ++i) {
    const int a = n == 6 ? law_of[i] : i;
    s[i] = sigma(a);
    for (int j = 0; j < n; ++j) D[n * i + j] = tangent(a, n == 6 ? law_of[j] : j);
  }
  *W = r.energy;
  statev[0] = r.broken;
  for (int p = 0; p < cell.n_pairs; ++p)
    statev[1 + p] = cell.bonded[p] && !h.bonded[p] ? 1 : !pending.empty() && pending[p] ? 2 : 0;
  write_active(h.active, unknowns, active);
  write_active(h.active_z, shear_rows, active + unknowns);
  return 0;
}

// Nothing escapes into the calling code (C or Fortran, which cannot catch it: an exception there
// would abort the whole analysis): every failure is a line and a return of 1, and the umat asks
// for a smaller increment.
int guarded(int id, const double hash[2], int n, const double* e, double delta_T, double* statev, int nstatv, double* s,
            double* D, double* W, int between) {
  try {
    return cell_law(id, hash, n, e, delta_T, statev, nstatv, s, D, W, between != 0);
  } catch (const std::bad_alloc&) {
    tell_once(id, "memory", "law " + std::to_string(id) + ": out of memory");
  } catch (const std::exception& error) {
    tell_once(id, "exception", "law " + std::to_string(id) + ": " + error.what());
  } catch (...) {
    tell_once(id, "exception", "law " + std::to_string(id) + ": an unknown failure");
  }
  return 1;
}

}  // namespace

extern "C" void dualcell_umat_refuse(const char* message) {
  try {
    tell_once(-1, message, message);
  } catch (...) {
    // Out of memory for the line itself: the refusal still stands (the umat returns).
  }
}

extern "C" int dualcell_cell_law(int id, const double hash[2], const double e[3], double* statev, int nstatv,
                                 double s[3], double D[9], double* W, int between) {
  return guarded(id, hash, 3, e, 0.0, statev, nstatv, s, D, W, between);
}

extern "C" int dualcell_cell_law6(int id, const double hash[2], const double e[6], double delta_T, double* statev,
                                  int nstatv, double s[6], double D[36], double* W, int between) {
  return guarded(id, hash, 6, e, delta_T, statev, nstatv, s, D, W, between);
}
