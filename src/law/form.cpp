#include "law/form.hpp"

#include <stdexcept>

#include "core/error.hpp"
#include "core/text.hpp"

namespace dualcell::law {

LawForm pick_form(const Law& law, const std::string& asked, const std::string& source, std::string* note) {
  if (asked.empty()) {
    if (law.cell) return LawForm::cell;
    if (note) *note = "the cone-wise law: law.h5 has no exact law (" + one_line(law.cell_note) + ")";
  }
  LawForm form = LawForm::cone;
  if (!asked.empty()) {
    std::size_t k = 0;
    while (k < law_form_names.size() && asked != law_form_names[k]) ++k;
    if (k == law_form_names.size())
      throw InputError(
          "--form " + asked +
          ": must be \"cell\" (the exact law), \"small\" (its small cell) or \"cone\" (the cone-wise law)");
    form = static_cast<LawForm>(k);
  }
  switch (form) {
    case LawForm::cell:
      if (!law.cell)
        throw InputError(source + ": /law/cell: no exact law (" + one_line(law.cell_note) +
                         "): --form cell needs one (--form cone takes the cone-wise law)");
      break;
    case LawForm::small:
      if (!law.small)
        throw InputError(source + ": /law/small: no small cell (" + one_line(law.small_note) +
                         "): --form small needs one (--form cell takes the exact law)");
      break;
    case LawForm::cone:
      if (!law.cone.ok)
        throw InputError(source + ": /law/cone: no fitted cone-wise law" +
                         (law.cone.message.empty() ? std::string() : " (" + one_line(law.cone.message) + ")"));
      break;
  }
  return form;
}

const CondensedCell& cell_of(const Law& law, LawForm form) {
  const std::optional<CondensedCell>& cell = form == LawForm::small ? law.small : law.cell;
  if (form == LawForm::cone || !cell) throw std::logic_error("cell_of: the law has no cell of that form");
  return *cell;
}

}  // namespace dualcell::law
