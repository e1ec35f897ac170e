#include "io/file_root.hpp"

#include <string_view>

#include "core/error.hpp"
#include "io/fields_io.hpp"

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
  // Empty texts are not written.
  for_each_field(provenance_fields, provenance, [&](const auto& field, const std::string& text) {
    if (!text.empty()) file.write_attribute("/", field.name, text);
  });
}

Provenance read_provenance(const File& file, std::initializer_list<const char*> required) {
  for (const char* attribute : required) file.read_string_attribute("/", attribute);  // "missing attribute ..."
  Provenance provenance;
  for_each_field(provenance_fields, provenance, [&](const auto& field, std::string& text) {
    text = file.has_attribute("/", field.name) ? file.read_string_attribute("/", field.name) : std::string();
  });
  return provenance;
}

void write_constituents(File& file, const std::string& object, const Constituents& constituents) {
  write_attributes(file, object, constituent_fields, constituents);
  write_attributes(file, object, axial_constituent_fields, constituents);
}

Constituents read_constituents(const File& file, const std::string& object) {
  Constituents constituents;
  read_attributes(file, object, constituent_fields, constituents);
  if (file.has_attribute(object, axial_constituent_fields[0].name)) {
    read_attributes(file, object, axial_constituent_fields, constituents);
  } else {  // written before the phases could be transversely isotropic: isotropic phases
    constituents = with_isotropic_axes(constituents);
  }
  return constituents;
}

}  // namespace dualcell::io
