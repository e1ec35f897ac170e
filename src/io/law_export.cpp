#include "io/law_export.hpp"

#include <Eigen/Eigenvalues>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string_view>
#include <type_traits>

#include "core/error.hpp"
#include "core/json.hpp"
#include "core/text.hpp"
#include "io/card_text.hpp"
#include "law/condensed_members.hpp"
#include "law/fields.hpp"

namespace dualcell::io {

using namespace law;

std::string card_number(double value) { return formatted("%.12e", value); }

namespace {

// Three comment lines, one per row.
std::string matrix_comment(const Eigen::Matrix3d& m) {
  std::string out;
  for (int i = 0; i < 3; ++i)
    out += "**   " + formatted("%.9g", m(i, 0)) + ", " + formatted("%.9g", m(i, 1)) + ", " +
           formatted("%.9g", m(i, 2)) + "\n";
  return out;
}

}  // namespace

void check_name(const std::string& name) {
  // CalculiX and Abaqus names are at most 80 characters; the longest suffix is _COMPRESSION.
  bool ok = !name.empty() && name.size() <= 80 - 12 && std::isalpha(static_cast<unsigned char>(name[0]));
  for (const unsigned char c : name) ok = ok && (std::isalnum(c) || c == '_');
  if (!ok)
    throw InputError("--name " + name + ": expected a letter followed by letters, digits or _, at most 68 characters");
}

namespace {

std::string material_cards(const std::string& material_name, const std::string& fit_name, const SolidMaterial& m,
                           const Eigen::Matrix3d& S_ps) {
  std::string out = "**\n** " + material_name + ": the secant law of " + fit_name +
                    "; its plane-strain S (engineering shear), rows xx, yy, xy:\n" + matrix_comment(S_ps);
  out += "*MATERIAL, NAME=" + material_name + "\n";
  if (m.orthotropic) {
    const auto& k = m.constants;
    out += "** normal-shear coupling " + formatted("%.2g", m.coupling) +
           " (<= " + formatted("%.0e", coupling_tolerance) + ", dropped): engineering constants\n";
    out += "** E1, E2, E3, nu12, nu13, nu23, G12, G13 / G23\n";
    out += "*ELASTIC, TYPE=ENGINEERING CONSTANTS\n";
    const double first[] = {k.E1, k.E2, k.E3, k.nu12, k.nu13, k.nu23, k.G12, k.G13};
    for (int i = 0; i < 8; ++i) out += card_number(first[i]) + (i == 7 ? "\n" : ", ");
    out += card_number(k.G23) + "\n";
    return out;
  }
  out += "** normal-shear coupling " + formatted("%.2g", m.coupling) + " (> " + formatted("%.0e", coupling_tolerance) +
         "): engineering constants cannot hold it; full stiffness\n";
  out +=
      "** D1111, D1122, D2222, D1133, D2233, D3333, D1112, D2212 / D3312, D1212, D1113, D2213, D3313, D1213,\n"
      "** D1313, D1123 / D2223, D3323, D1223, D1323, D2323 (engineering shear: D1212 = G12)\n";
  out += "*ELASTIC, TYPE=ANISO\n";
  // The manual's order is the upper triangle of C column by column in the Voigt order
  // (11, 22, 33, 12, 13, 23), eight numbers per line.
  int written = 0;
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i <= j; ++i) {
      out += card_number(m.C(i, j));
      ++written;
      out += written % 8 == 0 || written == 21 ? "\n" : ", ";
    }
  return out;
}

}  // namespace

ExportFormat parse_export_format(const std::string& text) {
  if (text == "json") return ExportFormat::json;
  if (text == "csv") return ExportFormat::csv;
  if (text == "calculix") return ExportFormat::calculix;
  if (text == "umat") return ExportFormat::umat;
  throw InputError("--format " + text + ": expected json, csv, calculix or umat");
}

namespace {

// A matrix as an array of rows (any size; NaN and ±inf as null).
std::string json_rows(const Eigen::MatrixXd& M) {
  std::vector<std::string> rows;
  for (Eigen::Index i = 0; i < M.rows(); ++i) {
    std::vector<double> row(static_cast<std::size_t>(M.cols()));
    for (Eigen::Index j = 0; j < M.cols(); ++j) row[static_cast<std::size_t>(j)] = M(i, j);
    rows.push_back(json_array(row));
  }
  return json_list(rows);
}

template <class T>
std::string json_ints(const std::vector<T>& v) {
  std::vector<std::string> items;
  for (const T& x : v) items.push_back(std::to_string(static_cast<long>(x)));
  return json_list(items);
}

std::string json_vector(const Eigen::VectorXd& v) {
  return json_array(std::vector<double>(v.data(), v.data() + v.size()));
}

// A cell in the exact law's form (/law/cell, /law/small) as a JSON object with the names of
// law.h5; the bounds' ±inf (an unbounded row) as null.
std::string cell_json(const law::CondensedCell& c) {
  JsonObject cell;
  law::for_each_member(c, [&](const law::Member& m, const auto& value) {
    using T = std::remove_cvref_t<decltype(value)>;
    // Without an optional part its members are left out, as in law.h5.
    if (law::left_out(c, m)) return;
    if constexpr (law::CountMember<T>)
      cell.add(m.name, std::to_string(value));
    else if constexpr (law::RealMember<T>)
      cell.add(m.name, json_number(value));
    else if constexpr (std::is_same_v<T, Eigen::VectorXd>)
      cell.add(m.name, json_vector(value));
    else if constexpr (law::ArrayMember<T>)
      cell.add(m.name, json_rows(value));
    else if constexpr (law::ListMember<T>)
      cell.add(m.name, json_ints(value));
  });
  return cell.add("bytes", std::to_string(c.bytes())).str(4);
}

// A compact law's check (/law/cone_check, /law/small_check, ...), against the exact law or the
// sweep's held-out directions.
JsonObject check_json(const law::ConeCheck& k) {
  return JsonObject()
      .add_text("against", law::checked_against_text(k.against))
      .add("directions", std::to_string(k.directions.size()))
      .add("max_error", json_number(k.max_error))
      .add("rms_error", json_number(k.rms_error))
      .add("worst", json_array(std::vector<double>{k.worst(0), k.worst(1), k.worst(2)}));
}

// The exact law (/law/cell) and its replay of the sweep (/law/cell_replay), as nested objects
// with the names of law.h5.
void add_exact_law(JsonObject& o, const Law& law) {
  o.add_text("cell_note", law.cell_note);
  if (!law.cell) return;
  o.add("cell", cell_json(*law.cell));
  for (const law::CellReplayMember& m : law::cell_replay_members) {
    if (!law::carries(*law.cell, m)) continue;
    o.add(m.name, JsonObject().add_fields(law::cell_replay_fields, law.*m.replay).str(4));
  }
  // The ply's nine constants per bond state and sign (/law/ply), where the cell carries them.
  if (!law.ply.rows.empty()) {
    std::vector<std::string> rows;
    for (const law::PlyConstants& c : law.ply.rows) {
      JsonObject row;
      row.add_text("state", law::to_string(c.state)).add("sign", std::to_string(c.sign));
      row.add("broken", std::to_string(c.broken));
      row.add_fields(law::ply_constant_fields, c);
      rows.push_back(row.add("sigma33_left", json_number(c.sigma33_left)).str(6));
    }
    o.add("ply", JsonObject().add("fuse_stress", json_number(law.ply.fuse_stress)).add("rows", json_list(rows)).str(4));
  }
}

// The compact laws' checks (/law/cone_check, /law/cone_after_fuse_check), against the exact law
// or the sweep's held-out directions.
void add_cone_checks(JsonObject& o, const Law& law) {
  if (law.cone_check.directions.empty()) return;
  o.add("cone_check", check_json(law.cone_check)
                          .add("sweep_fit_max_error", json_number(law.cone_check.sweep_fit_max_error))
                          .add("sweep_fit_rms_error", json_number(law.cone_check.sweep_fit_rms_error))
                          .str(4));
  if (!law.cone_after_fuse_check.directions.empty())
    o.add("cone_after_fuse_check", check_json(law.cone_after_fuse_check).str(4));
}

// The small cell (/law/small), how it was fitted (/law/small_fit) and its checks (/law/small_check,
// and for the whole ply /law/small_ply_check), or the note that says why there is none: what
// law.h5 has of it, with its names.
void add_small_cell(JsonObject& o, const Law& law) {
  o.add_text("small_note", law.small_note);
  if (!law.small) return;
  o.add("small", cell_json(*law.small));
  o.add("small_fit", JsonObject().add_fields(law::small_cell_fit_fields, law.small_fit).str(4));
  o.add("small_check", check_json(law.small_check).str(4));
  if (law.small_ply_check.directions > 0)
    o.add("small_ply_check", JsonObject().add_fields(law::ply_check_fields, law.small_ply_check).str(4));
}

// The onset surface (/law/onset) as a JSON object: facets and their pairs, and the check
// against each path's own onset.
std::string onset_json(const OnsetSurface& onset) {
  const auto rows = [](const auto& row, std::size_t n) {
    std::vector<std::string> items;
    for (std::size_t k = 0; k < n; ++k) items.push_back(json_array(row(k)));
    return json_list(items);
  };
  const auto ints = [](const std::vector<int>& v) {
    std::vector<std::string> items;
    for (int x : v) items.push_back(std::to_string(x));
    return json_list(items);
  };
  JsonObject surface;
  surface.add("linear", onset.linear ? "1" : "0").add_text("message", onset.message);
  if (onset.linear)
    surface
        .add("facets", rows(
                           [&](std::size_t k) {
                             const auto g = onset.facets.row(static_cast<Eigen::Index>(k));
                             return std::vector<double>{g(0), g(1), g(2)};
                           },
                           onset.pair.size()))
        .add("pair", ints(onset.pair))
        .add("tangential", ints(onset.tangential));
  if (!onset.path_stress.empty())
    surface
        .add("path_stress", rows(
                                [&](std::size_t k) {
                                  const Eigen::Vector3d& N = onset.path_stress[k];
                                  return std::vector<double>{N(0), N(1), N(2)};
                                },
                                onset.path_stress.size()))
        .add("onset", json_array(onset.path_onset))
        .add("sweep_onset", json_array(onset.path_sweep_onset));
  return surface.str(4);
}

}  // namespace

std::string law_json(const Law& law) {
  JsonObject o;
  o.add_text("format", format_name);
  for_each_field(provenance_fields, law.provenance, [&](const auto& field, const std::string& text) {
    if (!text.empty()) o.add_text(field.name, text);
  });
  o.add_text("units", law.units);
  o.add_text("stress_state", law.stress_state);
  o.add_text("shear_convention", shear_convention);
  o.add_fields(constituent_fields, law.constituents);
  o.add_fields(axial_constituent_fields, law.constituents);
  // The bonded ply's thermal expansion (/law/expansion), where the phases have theirs.
  if (law.ply.expansion.asked())
    o.add("expansion", JsonObject().add_fields(law::ply_expansion_fields, law.ply.expansion).str(4));
  o.add_columns(direction_columns, law.directions);
  for (const auto& m : compliance_members) {
    const ComplianceFit& fit = law.*m.fit;
    const std::string p = m.prefix;
    o.add(p, json_array(fit.S));
    o.add(p + "_se", json_array(fit.S_se));
    o.add(p + "_rank", std::to_string(fit.rank));
    o.add(p + "_relative_residual", json_number(fit.relative_residual));
    o.add(p + "_direction_residual", json_array(fit.direction_residual));
    o.add(p + "_spd", fit.symmetric_positive_definite ? "1" : "0");
    o.add(p + "_n_points", std::to_string(fit.n_points));
  }
  o.add("cone_rank_one_ratio", json_number(law.cone_rank_one_ratio));
  o.add("cone_wise_linear", law.cone_wise_linear ? "1" : "0");
  o.add("cone_normal", json_array(std::vector<double>{law.cone_normal(0), law.cone_normal(1), law.cone_normal(2)}));
  o.add("cone_beta", json_number(law.cone_beta));
  const auto normals = [](const std::vector<Eigen::Vector3d>& c) {
    std::vector<std::string> rows;
    for (const auto& v : c) rows.push_back(json_array(std::vector<double>{v(0), v(1), v(2)}));
    return json_list(rows);
  };
  for (const auto& m : law::cone_members) {
    const law::ConeFit& fit = law.*m.fit;
    o.add(m.name, JsonObject()
                      .add("C_c", json_array(fit.law.C_c))
                      .add("q", normals(fit.law.q))
                      .add("beta", json_array(fit.law.beta))
                      .add_text("form", fit.form)
                      .add("relative_residual", json_number(fit.relative_residual))
                      .add("one_plane_residual", json_number(fit.one_plane_residual))
                      .add("struts_residual", json_number(fit.struts_residual))
                      .add("direction_residual", json_array(fit.direction_residual))
                      .add("n_points", std::to_string(fit.n_points))
                      .add("ok", fit.ok ? "1" : "0")
                      .add_text("message", fit.message)
                      .str(4));
  }
  o.add("onset", onset_json(law.onset));
  add_exact_law(o, law);
  add_cone_checks(o, law);
  add_small_cell(o, law);
  return o.str() + "\n";
}

std::string law_csv(const Law& law) {
  std::string out;
  for (const auto& c : direction_columns) out += std::string(c.name) + ",";
  out += "S_tension_direction_residual,S_compression_direction_residual";
  for (const auto& m : law::cone_members) out += std::string(",") + m.name + "_direction_residual";
  out += "\n";
  for (std::size_t i = 0; i < law.directions.size(); ++i) {
    const auto& d = law.directions[i];
    for_each_field(direction_columns, d, [&](const auto&, const auto& v) {
      if constexpr (std::is_same_v<std::remove_cvref_t<decltype(v)>, double>)
        out += csv_number(v) + ",";
      else
        out += std::to_string(v) + ",";
    });
    // The residual vectors hold one entry per direction (write_law and read_law check it).
    out +=
        csv_number(law.tension.direction_residual.at(i)) + "," + csv_number(law.compression.direction_residual.at(i));
    for (const auto& m : law::cone_members) {
      const auto& residual = (law.*m.fit).direction_residual;
      out += ',';
      out += csv_number(i < residual.size() ? residual[i] : std::numeric_limits<double>::quiet_NaN());
    }
    out += "\n";
  }
  return out;
}

std::string card_header(const Law& law, const std::string& source, const std::string& what) {
  return "** dualcell " + what + ", written by dualcell-export " + code_version + "\n** from " + one_line(source) +
         " (" + format_name + "; fit by " + one_line(law.provenance.code_version) + "; sweep " +
         one_line(law.provenance.sweep_file) + ", hash " + one_line(law.provenance.sweep_hash) +
         ")\n** units: " + one_line(law.units) + "\n";
}

namespace {

// The longest suffix of a ply card's name.
constexpr std::size_t ply_suffix = std::string_view("_PLY_AFTER_FUSE_COMPRESSION").size();

// Whether the orthotropic compliance of a ply's constants is positive definite (CalculiX does not
// check, and a set of secants from loads that close different contacts need not be).
bool positive_definite(const law::PlyConstants& c) {
  Eigen::Matrix<double, 6, 6> S = Eigen::Matrix<double, 6, 6>::Zero();
  const double E[3] = {c.E1, c.E2, c.E3};
  for (int i = 0; i < 3; ++i) S(i, i) = 1 / E[i];
  S(0, 1) = S(1, 0) = -c.nu12 / c.E1;
  S(0, 2) = S(2, 0) = -c.nu13 / c.E1;
  S(1, 2) = S(2, 1) = -c.nu23 / c.E2;
  S(3, 3) = 1 / c.G12, S(4, 4) = 1 / c.G13, S(5, 5) = 1 / c.G23;
  return S.allFinite() && Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>>(S).eigenvalues().minCoeff() > 0;
}

// The ply's cards from the exact law (/law/ply): one material per bond state and sign, the fibres
// along the material's axis 1 (as a laminate's *ORIENTATION takes a ply).
std::string ply_cards(const Law& law, const std::string& name) {
  std::string out =
      "**\n** The whole ply from the exact law (/law/ply, docs/method.md §3c): its nine engineering constants per\n"
      "** bond state and load sign, secants of the law at the state. These cards' axes are the ply's: 1 = z, the\n"
      "** fibres; 2 = x, 3 = y (give the plies an *ORIENTATION whose first axis is the fibre direction).\n";
  if (law.ply.fuse_stress > 0)
    out += "** after fuse: the bonds that sxx = " + formatted("%.6g", law.ply.fuse_stress) +
           " (4 x the onset along x) left.\n";
  for (const law::PlyConstants& c : law.ply.rows) {
    std::string state = law::to_string(c.state);
    for (char& ch : state) ch = ch == ' ' ? '_' : static_cast<char>(std::toupper(static_cast<unsigned char>(ch)));
    const std::string material = name + "_PLY_" + state + (c.sign > 0 ? "_TENSION" : "_COMPRESSION");
    out += "**\n** " + material + ": " + std::to_string(c.broken) + " pairs broken\n";
    if (!positive_definite(c)) {
      out +=
          "** no card: its orthotropic compliance is not positive definite (secants of loads that close\n"
          "** different contacts); a ply loaded both ways takes the law itself (the umat, layout 3)\n";
      continue;
    }
    out += "*MATERIAL, NAME=" + material + "\n*ELASTIC, TYPE=ENGINEERING CONSTANTS\n";
    // Eight constants on the first line, the ninth (G23) on the next, as *ELASTIC takes them.
    std::size_t k = 0;
    for_each_field(law::ply_constant_fields, c, [&](const auto&, double v) {
      out += card_number(v) + (k == 7 ? ",\n" : k == 8 ? "\n" : ", ");
      ++k;
    });
    // The bonded ply's expansion (/law/expansion, docs/theory/model.md §1a), in the same axes;
    // the thermal strain is α (T − T0), T0 the stress-free (cure) temperature of the analysis's
    // *INITIAL CONDITIONS, TYPE=TEMPERATURE. A broken state has no expansion of its own (the
    // contact's response to ΔT depends on its sign).
    const law::PlyExpansion& a = law.ply.expansion;
    if (c.state == law::PlyState::bonded && a.ok)
      out += "*EXPANSION, TYPE=ORTHO\n" + card_number(a.alpha1) + ", " + card_number(a.alpha2) + ", " +
             card_number(a.alpha3) + "\n** (the cell's alpha23 = " + formatted("%.3g", a.alpha23) +
             " per K, a shear, has no place in TYPE=ORTHO)\n";
  }
  return out;
}

}  // namespace

std::string law_calculix(const Law& law, const std::string& name, const std::string& source) {
  check_name(name);
  if (!law.ply.rows.empty() && name.size() > 80 - ply_suffix)
    throw InputError(
        "--name " + name + ": at most " + std::to_string(80 - ply_suffix) +
        " characters for a law with the ply's cards (the longest name is <name>_PLY_AFTER_FUSE_COMPRESSION)");
  const SolidMaterial tension = solid_material(law.tension.S, law, source, "S_tension");
  const SolidMaterial compression = solid_material(law.compression.S, law, source, "S_compression", -1);
  const OutOfPlane z = out_of_plane(law);
  std::string out = card_header(law, source, "law for CalculiX/Abaqus");
  out +=
      "** Material axes: 1 = x, 2 = y (the plane of the cells), 3 = z = fibre direction.\n"
      "** " +
      name + "_TENSION and " + name +
      "_COMPRESSION are the secant laws fitted to the tension and the\n"
      "** compression paths (bimodular: choose by the sign of the load). Plane-strain elements (CPE*,\n"
      "** eps33 = 0) in the x-y plane reproduce the fitted plane-strain compliance S exactly:\n"
      "**   S11 = Sps11 + S13^2/S33, S22 = Sps22 + S23^2/S33, S12 = Sps12 + S13 S23/S33, 1/G12 = Sps33,\n"
      "** with S13 = -nu31/E3, S23 = -nu32/E3, S33 = 1/E3 and G13, G23 out of plane, ";
  if (z.from_cell) {
    out +=
        "from the cell's exact law (the ply's\n** constants, /law/ply: E3 = its E1, nu31 = nu12, nu32 = nu13, "
        "G13 = G12, G23 = G13; " +
        std::string(law.cell && law.cell->adhesion() ? "bonded" : "the contact state of each sign") + "):\n";
    for (const int sign : {1, -1}) {
      const OutOfPlane w = out_of_plane(law, sign);
      out += "**   " + std::string(sign > 0 ? "tension" : "compression") + ": E3 = " + formatted("%.6g", w.E3) +
             ", nu31 = " + formatted("%.6g", w.nu31) + ", nu32 = " + formatted("%.6g", w.nu32) +
             ", G13 = " + formatted("%.6g", w.G13) + ", G23 = " + formatted("%.6g", w.G23) + "\n";
    }
  } else {
    out +=
        "by the rule of mixtures:\n"
        "**   E3 = Vf Ef + (1 - Vf) Em, nu31 = nu32 = Vf nuf + (1 - Vf) num, 1/G13 = 1/G23 = Vf/Gf + (1 - Vf)/Gm,\n"
        "**   each phase's along the fibres (E_L, nu_LT, G_LT; isotropic: E, nu, G = E/(2 (1 + nu))),\n";
    out += "** with Vf = " + formatted("%.6g", law.constituents.fibre_volume_fraction) +
           ", fibre E = " + formatted("%.6g", law.constituents.fibre_E_L) +
           ", nu = " + formatted("%.6g", law.constituents.fibre_nu_LT) +
           ", matrix E = " + formatted("%.6g", law.constituents.matrix_E_L) +
           ", nu = " + formatted("%.6g", law.constituents.matrix_nu_LT) + ": E3 = " + formatted("%.6g", z.E3) +
           ", nu31 = " + formatted("%.6g", z.nu31) + ", G13 = G23 = " + formatted("%.6g", z.G13) + "\n";
  }
  out += material_cards(name + "_TENSION", "S_tension", tension, law.tension.S);
  out += material_cards(name + "_COMPRESSION", "S_compression", compression, law.compression.S);
  if (!law.ply.rows.empty()) out += ply_cards(law, name);
  return out;
}

}  // namespace dualcell::io
