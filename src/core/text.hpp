#pragma once
// Numbers and values as text for one-line messages: the shortest form that reads back to the same
// double, and long quoted values cut to a readable length.
#include <string>
#include <vector>

namespace dualcell {

std::string shortest(double x);                           // "0.3", not "0.29999999999999999"
std::string shortest(const std::vector<double>& v);       // "[0.3, 1]"
std::string formatted(const char* format, double value);  // one number with a printf format ("%.6g")
std::string clipped(std::string text);                    // at most 60 bytes (+ "..."), cut at UTF-8 boundaries
std::string csv_number(double value);                     // %.17g, "nan", "inf", "-inf": reads back exactly
std::string one_line(std::string text);                   // newlines (\n, \r) as spaces: a message stays one line

}  // namespace dualcell
