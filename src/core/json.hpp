#pragma once
// The one JSON writer of the project (law exports, benchmark summaries): strict JSON that
// Python's json.load reads. Values are built as text: a number, a string, an array or an
// object; NaN and infinities become null.
#include <Eigen/Core>
#include <string>
#include <type_traits>
#include <vector>

#include "core/fields.hpp"

namespace dualcell {

std::string json_number(double value);  // shortest round-trip form (%.17g), null when not finite
std::string json_string(const std::string& text);
std::string json_array(const std::vector<double>& values);
std::string json_array(const Eigen::Matrix3d& m);              // rows: [[..], [..], [..]]
std::string json_list(const std::vector<std::string>& items);  // an array of JSON values

// Collects "key": value members and writes one object, a member per line.
class JsonObject {
 public:
  // `json_value` is JSON text already (json_number(x), std::to_string(n), json_string(s), ...).
  JsonObject& add(const std::string& key, const std::string& json_value);
  JsonObject& add_text(const std::string& key, const std::string& text) { return add(key, json_string(text)); }
  // Every member of `record` by its table (core/fields.hpp), under its name: numbers, counts,
  // flags (true/false), texts and vectors (arrays).
  template <class Table, class Record>
  JsonObject& add_fields(const Table& table, const Record& record) {
    for_each_field(table, record, [&](const auto& field, const auto& v) {
      using T = std::remove_cvref_t<decltype(v)>;
      if constexpr (std::is_same_v<T, bool>)
        add(field.name, v ? "true" : "false");
      else if constexpr (std::is_integral_v<T>)
        add(field.name, std::to_string(v));
      else if constexpr (std::is_same_v<T, double>)
        add(field.name, json_number(v));
      else if constexpr (std::is_same_v<T, std::string>)
        add_text(field.name, v);
      else
        add(field.name, json_array(std::vector<double>(v.data(), v.data() + v.size())));
    });
    return *this;
  }
  // A list of records by its table, one member per field: the array of its values over the rows
  // (numbers and counts; a table of vectors or texts is not a column).
  template <class Table, class Record>
  JsonObject& add_columns(const Table& table, const std::vector<Record>& rows) {
    for (const auto& field : table)
      std::visit(
          [&](auto member) {
            std::string values = "[";
            for (std::size_t i = 0; i < rows.size(); ++i) {
              const auto& v = rows[i].*member;
              if constexpr (std::is_same_v<std::remove_cvref_t<decltype(v)>, double>)
                values += (i ? ", " : "") + json_number(v);
              else
                values += (i ? ", " : "") + std::to_string(v);
            }
            add(field.name, values + "]");
          },
          field.member);
    return *this;
  }
  // `indent` spaces before every member line (nested objects pass their depth).
  std::string str(int indent = 2) const;

 private:
  std::vector<std::pair<std::string, std::string>> members_;
};

}  // namespace dualcell
