#pragma once
// What every CalculiX card file of the export shares (io/law_export.cpp, io/umat_card.cpp): its
// numbers, its material names and its first comment lines.
#include <string>

#include "law/law.hpp"

namespace dualcell::io {

// CalculiX reads each number of a data line as a 20-character field and silently drops the rest
// (1.2345678901234567e+01 is read as 1.2345678901234567): %.12e is at most 19 characters.
std::string card_number(double value);
// An InputError unless `name` is a CalculiX material base name (a letter, then letters, digits or
// _, at most 68 characters: the longest suffix is _COMPRESSION of 80).
void check_name(const std::string& name);
// The comment lines every card file starts with: what, written by which version, from which law
// (its fit and sweep), the units.
std::string card_header(const law::Law& law, const std::string& source, const std::string& what);

}  // namespace dualcell::io
