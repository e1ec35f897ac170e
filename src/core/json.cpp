#include "core/json.hpp"

#include <cmath>
#include <cstdio>

namespace dualcell {

std::string json_number(double value) {
  if (!std::isfinite(value)) return "null";
  char text[32];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

std::string json_string(const std::string& text) {
  std::string out = "\"";
  for (const unsigned char c : text) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\r':
        out += "\\r";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (c < 0x20) {
          char escaped[8];
          std::snprintf(escaped, sizeof escaped, "\\u%04x", c);
          out += escaped;
        } else {
          out += static_cast<char>(c);
        }
    }
  }
  return out + "\"";
}

std::string json_list(const std::vector<std::string>& items) {
  std::string out = "[";
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i) out += ", ";
    out += items[i];
  }
  out += ']';
  return out;
}

std::string json_array(const std::vector<double>& values) {
  std::vector<std::string> items;
  for (double v : values) items.push_back(json_number(v));
  return json_list(items);
}

std::string json_array(const Eigen::Matrix3d& m) {
  std::vector<std::string> rows;
  for (int i = 0; i < 3; ++i) rows.push_back(json_array(std::vector<double>{m(i, 0), m(i, 1), m(i, 2)}));
  return json_list(rows);
}

JsonObject& JsonObject::add(const std::string& key, const std::string& json_value) {
  members_.emplace_back(key, json_value);
  return *this;
}

std::string JsonObject::str(int indent) const {
  const std::string pad(indent, ' ');
  std::string out = "{";
  for (std::size_t i = 0; i < members_.size(); ++i) {
    out += i ? ",\n" : "\n";
    out += pad;
    out += json_string(members_[i].first);
    out += ": ";
    out += members_[i].second;
  }
  if (!members_.empty()) {
    out += '\n';
    out.append(indent >= 2 ? indent - 2 : 0, ' ');
  }
  out += '}';
  return out;
}

}  // namespace dualcell
