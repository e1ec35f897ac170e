#pragma once
// The ply's nine engineering constants from the exact law of a cell that carries the strain and
// the shears along the fibres (docs/method.md §3c): per bond state and sign of the load, each a
// secant of the law at that state, as a 3D model's orthotropic card takes them. The ply's axis
// 1 is the fibres' z, its axes 2 and 3 the cell's x and y.
//
//   axis 1   σ̄ = 0, ε33 = ±e:                  E1 = σ33/ε33, ν12 = −εxx/ε33, ν13 = −εyy/ε33
//   axis 2   σxx = ±s, σyy = σxy = σ33 = 0:     E2 = σxx/εxx, ν23 = −εyy/εxx
//   axis 3   σyy = ±s, the others 0:            E3 = σyy/εyy
//   shear    σxy = ±s, the others 0:            G23 = σxy/γxy
//   along the fibres (no sign: frictionless contact carries no shear along z), τxz or τyz alone:
//            G12 = 1/(G⁻¹)₀₀, G13 = 1/(G⁻¹)₁₁, G = dτ/dΓ of the state
//
// σ33 = 0 by secant steps on ε33 (σ33 is increasing and piecewise linear in ε33 at a fixed σ̄),
// to 1e-9 of s. The loads are small (s: the open cell's stress at a strain of 1e-8) so that no
// bond breaks; a probe that breaks one is refused, not tabulated.
#include <string>
#include <vector>

#include "core/fields.hpp"
#include "law/condensed.hpp"

namespace dualcell::law {

// The bond states tabulated: the intact cell (with adhesion), the state the fuse leaves (the
// cascade under σxx = PlyTable::fuse_stress run to its end) and a cell without adhesion.
enum class PlyState { bonded = 0, after_fuse = 1, contact = 2 };
const char* to_string(PlyState s);

struct PlyConstants {
  PlyState state = PlyState::bonded;
  int sign = 1;    // +1 tension, −1 compression
  int broken = 0;  // pairs broken in the state
  double E1 = 0, E2 = 0, E3 = 0, nu12 = 0, nu13 = 0, nu23 = 0, G12 = 0, G13 = 0, G23 = 0;
  double sigma33_left = 0;  // the largest |σ33|/s the secant steps left
};

// The constants' names in the files' order (E1 … G23) and their members.
inline constexpr Field<PlyConstants, double> ply_constant_fields[] = {
    {"E1", &PlyConstants::E1},     {"E2", &PlyConstants::E2},     {"E3", &PlyConstants::E3},
    {"nu12", &PlyConstants::nu12}, {"nu13", &PlyConstants::nu13}, {"nu23", &PlyConstants::nu23},
    {"G12", &PlyConstants::G12},   {"G13", &PlyConstants::G13},   {"G23", &PlyConstants::G23},
};

// The bonded ply's thermal expansion per kelvin (docs/theory/model.md §1a): the macro strain of
// the bonded cell (strengths lifted) under ΔT alone at zero macro stress, σ̄ = 0 and ⟨σ33⟩ = 0,
// from two full solves (ΔT = 1 and ε33 = 1, ⟨σ33⟩ = 0 by superposition): α1 along the fibres, α2,
// α3 across them (the cell's x and y), α23 the engineering shear γxy per kelvin (0 for a cell
// symmetric about its axes; a random RVE's is its anisotropy). Only where both phases have their
// expansion; `ok` false and `note` saying why where the bonded cell has none (no adhesion, or
// normal rows that stay contact rows).
struct PlyExpansion {
  double alpha1 = 0, alpha2 = 0, alpha3 = 0, alpha23 = 0;
  int ok = 0;
  std::string note;
  bool asked() const { return ok || !note.empty(); }
};
inline constexpr Field<PlyExpansion, double, int, std::string> ply_expansion_fields[] = {
    {"alpha1", &PlyExpansion::alpha1},   {"alpha2", &PlyExpansion::alpha2}, {"alpha3", &PlyExpansion::alpha3},
    {"alpha23", &PlyExpansion::alpha23}, {"ok", &PlyExpansion::ok},         {"note", &PlyExpansion::note},
};

struct PlyTable {
  std::vector<PlyConstants> rows;  // empty: the cell does not carry the whole ply
  PlyExpansion expansion;          // the bonded ply's, where the phases have expansion coefficients
  double fuse_stress = 0;          // σxx of the after-fuse state: 4 × the onset along x (0 without adhesion)
  std::string note;                // why there are no rows, or why a state is missing
};

// The table of a cell with longitudinal = 1 and shear = 2 (else empty, with a note): bonded and
// after the fuse for a cell with adhesion, contact without; tension and compression each.
PlyTable ply_constants(const CondensedCell& cell);

}  // namespace dualcell::law
