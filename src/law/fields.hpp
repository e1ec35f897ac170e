#pragma once
// The objects of a Law, named as in law.h5, so that the file writer and reader (io/law_file)
// and the JSON/CSV exports (io/law_export) walk one list and cannot drift apart. The constituents
// and the provenance have their own lists (core/scene.hpp, core/provenance.hpp).
#include "core/fields.hpp"
#include "law/law.hpp"

namespace dualcell::law {

// One column of /law: either a double or an int member of DirectionLaw (the other is null).

inline constexpr Field<DirectionLaw, double, int> direction_columns[] = {
    {"direction_deg", &DirectionLaw::direction_deg},
    {"E_tension", &DirectionLaw::E_tension},
    {"E_tension_se", &DirectionLaw::E_tension_se},
    {"E_tension_r2", &DirectionLaw::E_tension_r2},
    {"n_tension", &DirectionLaw::n_tension},
    {"E_compression", &DirectionLaw::E_compression},
    {"E_compression_se", &DirectionLaw::E_compression_se},
    {"E_compression_r2", &DirectionLaw::E_compression_r2},
    {"n_compression", &DirectionLaw::n_compression},
    {"nu_tension", &DirectionLaw::nu_tension},
    {"nu_tension_se", &DirectionLaw::nu_tension_se},
    {"nu_compression", &DirectionLaw::nu_compression},
    {"nu_compression_se", &DirectionLaw::nu_compression_se},
    {"onset_stress", &DirectionLaw::onset_stress},
    {"fuse_stress", &DirectionLaw::fuse_stress},
    {"fuse_stress_after", &DirectionLaw::fuse_stress_after},
    {"fuse_strain_jump", &DirectionLaw::fuse_strain_jump},
    {"fuse_strain_ratio", &DirectionLaw::fuse_strain_ratio},
    {"E_after_fuse", &DirectionLaw::E_after_fuse},
    {"E_after_fuse_se", &DirectionLaw::E_after_fuse_se},
};

// The two compliance fits, with the prefix of their objects in /law.
struct ComplianceMember {
  const char* prefix;
  ComplianceFit Law::*fit;
};

inline constexpr ComplianceMember compliance_members[] = {
    {"S_tension", &Law::tension},
    {"S_compression", &Law::compression},
};

// The two cone-wise fits, with their group in /law.
struct ConeMember {
  const char* name;
  ConeFit Law::*fit;
};

inline constexpr ConeMember cone_members[] = {
    {"cone", &Law::cone},
    {"cone_after_fuse", &Law::cone_after_fuse},
};

// The root attribute `format` of law.h5, and the JSON export's "format".
inline constexpr const char* format_name = "dualcell law 4";

// Stated in every law.h5 and export, so that a reader never has to guess the shear factor.
inline constexpr const char* shear_convention =
    "engineering shear (Voigt): (exx, eyy, gxy) = S (sxx, syy, sxy) with gxy = 2 exy; "
    "S is symmetric for an elastic law; index order xx, yy, xy";

}  // namespace dualcell::law
