#pragma once
// The one HDF5 writer and reader of a record table (core/fields.hpp): a record's members as
// attributes of an object, as datasets of a group (one per member: shape (1), or (k) for a
// vector of k), or a list of records as columns (shape (n), or (n, k)). A double is float64, a
// count int64, a flag int64 0/1, a text a string attribute. Reading checks each shape, and each
// count against its field's min_count and the largest value its type holds.
#include <cstdint>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

#include "core/error.hpp"
#include "core/fields.hpp"
#include "io/hdf5.hpp"

namespace dualcell::io {

namespace fields_detail {

// A count read from a file, within [min_count, the largest T] (a flag: 0 or 1).
template <class T>
T count_in_range(const File& f, const std::string& name, std::int64_t v, int min_count) {
  if (v < min_count || v > static_cast<std::int64_t>(std::numeric_limits<T>::max()))
    throw InputError(f.path().string() + ": " + name + ": value " + std::to_string(v) + " out of range [" +
                     std::to_string(min_count) + ", " + std::to_string(std::numeric_limits<T>::max()) + "]");
  return static_cast<T>(v);
}

}  // namespace fields_detail

// The members of `record` as attributes of `object`, named prefix + name; with `unit`, only the
// fields of that unit.
template <class Table, class Record>
void write_attributes(File& f, const std::string& object, const Table& table, const Record& record,
                      const std::string& prefix = "", const char* unit = nullptr) {
  for_each_field(table, record, [&](const auto& field, const auto& v) {
    using T = std::remove_cvref_t<decltype(v)>;
    if (unit && std::string(field.unit) != unit) return;
    const std::string name = prefix + field.name;
    if constexpr (std::is_same_v<T, double> || std::is_same_v<T, std::string>)
      f.write_attribute(object, name, v);
    else if constexpr (std::is_integral_v<T>)
      f.write_attribute(object, name, static_cast<std::int64_t>(v));
    else
      f.write_attribute(object, name, std::vector<double>(v.data(), v.data() + v.size()));
  });
}

template <class Table, class Record>
void read_attributes(const File& f, const std::string& object, const Table& table, Record& record,
                     const std::string& prefix = "", const char* unit = nullptr) {
  for_each_field(table, record, [&](const auto& field, auto& v) {
    using T = std::remove_cvref_t<decltype(v)>;
    if (unit && std::string(field.unit) != unit) return;
    const std::string name = prefix + field.name;
    if constexpr (std::is_same_v<T, double>)
      v = f.read_double_attribute_value(object, name);
    else if constexpr (std::is_same_v<T, std::string>)
      v = f.read_string_attribute(object, name);
    else if constexpr (std::is_same_v<T, bool>)
      v = fields_detail::count_in_range<bool>(f, object + " " + name, f.read_int_attribute_value(object, name), 0);
    else if constexpr (std::is_integral_v<T>)
      v = fields_detail::count_in_range<T>(f, object + " " + name, f.read_int_attribute_value(object, name),
                                           field.min_count);
    else
      v = Eigen::Map<const T>(f.read_double_attribute(object, name, T::SizeAtCompileTime).data());
  });
}

// The members of `record` as datasets group/name.
template <class Table, class Record>
void write_datasets(File& f, const std::string& group, const Table& table, const Record& record) {
  for_each_field(table, record, [&](const auto& field, const auto& v) {
    using T = std::remove_cvref_t<decltype(v)>;
    const std::string name = group + "/" + field.name;
    if constexpr (std::is_same_v<T, double>)
      f.write(name, std::vector<double>{v}, {1});
    else if constexpr (std::is_integral_v<T>)
      f.write(name, std::vector<std::int64_t>{static_cast<std::int64_t>(v)}, {1});
    else
      f.write(name, std::vector<double>(v.data(), v.data() + v.size()), {static_cast<hsize_t>(v.size())});
  });
}

template <class Table, class Record>
void read_datasets(const File& f, const std::string& group, const Table& table, Record& record) {
  for_each_field(table, record, [&](const auto& field, auto& v) {
    using T = std::remove_cvref_t<decltype(v)>;
    const std::string name = group + "/" + field.name;
    if constexpr (std::is_same_v<T, double>)
      v = f.read_doubles(name, {1})[0];
    else if constexpr (std::is_same_v<T, bool>)
      v = fields_detail::count_in_range<bool>(f, name, f.read_ints(name, {1})[0], 0);
    else if constexpr (std::is_integral_v<T>)
      v = fields_detail::count_in_range<T>(f, name, f.read_ints(name, {1})[0], field.min_count);
    else
      v = Eigen::Map<const T>(f.read_doubles(name, {static_cast<hsize_t>(T::SizeAtCompileTime)}).data());
  });
}

// The records `rows` as one column per member, group/name, n rows.
template <class Table, class Record>
void write_columns(File& f, const std::string& group, const Table& table, const std::vector<Record>& rows) {
  const hsize_t n = rows.size();
  for (const auto& field : table) {
    std::visit(
        [&](auto member) {
          using T = std::remove_cvref_t<decltype(std::declval<const Record&>().*member)>;
          const std::string name = group + "/" + field.name;
          if constexpr (std::is_integral_v<T>) {
            std::vector<std::int64_t> column;
            for (const Record& r : rows) column.push_back(static_cast<std::int64_t>(r.*member));
            f.write(name, column, {n});
          } else {
            constexpr int k = components_of<T>();
            std::vector<double> column;
            for (const Record& r : rows) {
              if constexpr (k == 1)
                column.push_back(r.*member);
              else
                column.insert(column.end(), (r.*member).data(), (r.*member).data() + k);
            }
            f.write(name, column, k == 1 ? Shape{n} : Shape{n, static_cast<hsize_t>(k)});
          }
        },
        field.member);
  }
}

// Reads the columns into `rows`, sized to the n rows every column must have (`like`: the column
// that set n, for the message).
template <class Table, class Record>
void read_columns(const File& f, const std::string& group, const Table& table, std::vector<Record>& rows,
                  const std::string& like) {
  const hsize_t n = rows.size();
  for (const auto& field : table) {
    std::visit(
        [&](auto member) {
          using T = std::remove_cvref_t<decltype(std::declval<Record&>().*member)>;
          const std::string name = group + "/" + field.name;
          if constexpr (std::is_integral_v<T>) {
            const auto v = f.read_ints(name, {n}, " like " + like);
            for (hsize_t i = 0; i < n; ++i) {
              if constexpr (std::is_same_v<T, bool>)
                rows[i].*member = v[i] != 0;
              else if (v[i] < field.min_count || v[i] > static_cast<std::int64_t>(std::numeric_limits<T>::max()))
                throw InputError(f.path().string() + ": " + name + ": entry " + std::to_string(i) + " = " +
                                 std::to_string(v[i]) + " is not a count");
              else
                rows[i].*member = static_cast<T>(v[i]);
            }
          } else {
            constexpr int k = components_of<T>();
            const auto v = f.read_doubles(name, k == 1 ? Shape{n} : Shape{n, static_cast<hsize_t>(k)}, " like " + like);
            for (hsize_t i = 0; i < n; ++i) {
              if constexpr (k == 1)
                rows[i].*member = v[i];
              else
                rows[i].*member = Eigen::Map<const T>(v.data() + k * i);
            }
          }
        },
        field.member);
  }
}

}  // namespace dualcell::io
