#pragma once
// The forms a law takes (docs/guide/laws.md): the exact law (/law/cell), its small cell
// (/law/small), both cells evaluated alike, and the cone-wise law with the fuse (/law/cone). One
// name each, as every stage's --form spells it, and one rule for which form a stage uses.
#include <array>
#include <string>

#include "law/law.hpp"

namespace dualcell::law {

enum class LawForm { cell, small, cone };
inline constexpr std::array<const char*, 3> law_form_names = {"cell", "small", "cone"};
inline const char* to_string(LawForm form) { return law_form_names[static_cast<std::size_t>(form)]; }

// The form a stage uses: `asked`, one of law_form_names, or "" for the default, the exact law
// where the law has one and else the cone-wise law (`note`, when given, then says why). An
// InputError naming `source` and the object when the name is none of them or the law has not
// that form, with the note law.h5 keeps of why.
LawForm pick_form(const Law& law, const std::string& asked, const std::string& source, std::string* note = nullptr);

// The cell of a cell form (/law/cell or /law/small), which pick_form made sure is there.
const CondensedCell& cell_of(const Law& law, LawForm form);

}  // namespace dualcell::law
