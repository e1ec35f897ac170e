#include "io/file_root.hpp"

#include <string_view>

#include "core/error.hpp"

namespace dualcell::io {

void check_format(const File& file, const char* format) {
  // "dualcell law 1" → "dualcell law"
  const std::string_view kind = std::string_view(format).substr(0, std::string_view(format).rfind(' '));
  const std::string expected = std::string(" expected '") + format + "')";
  if (!file.has_attribute("/", "format"))
    throw InputError(file.path().string() + ": not a " + std::string(kind) + " file (no root attribute format," +
                     expected);
  const std::string found = file.read_string_attribute("/", "format");
  if (found != format)
    throw InputError(file.path().string() + ": not a " + std::string(kind) + " file (root attribute format is '" +
                     found + "'," + expected);
}

void write_provenance(File& file, const char* format, const Provenance& provenance) {
  file.write_attribute("/", "format", std::string(format));
  for (const auto& field : provenance_fields)
    if (!(provenance.*field.text).empty()) file.write_attribute("/", field.attribute, provenance.*field.text);
}

Provenance read_provenance(const File& file, std::initializer_list<const char*> required) {
  for (const char* attribute : required) file.read_string_attribute("/", attribute);  // "missing attribute ..."
  Provenance provenance;
  for (const auto& field : provenance_fields)
    provenance.*field.text =
        file.has_attribute("/", field.attribute) ? file.read_string_attribute("/", field.attribute) : std::string();
  return provenance;
}

void write_constituents(File& file, const std::string& object, const Constituents& constituents) {
  for (const auto& field : constituent_fields) file.write_attribute(object, field.attribute, constituents.*field.value);
}

Constituents read_constituents(const File& file, const std::string& object) {
  Constituents constituents;
  for (const auto& field : constituent_fields)
    constituents.*field.value = file.read_double_attribute_value(object, field.attribute);
  return constituents;
}

}  // namespace dualcell::io
