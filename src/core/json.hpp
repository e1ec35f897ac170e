#pragma once
// The one JSON writer of the project (law exports, benchmark summaries): strict JSON that
// Python's json.load reads. Values are built as text: a number, a string, an array or an
// object; NaN and infinities become null.
#include <Eigen/Core>
#include <string>
#include <vector>

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
  // `indent` spaces before every member line (nested objects pass their depth).
  std::string str(int indent = 2) const;

 private:
  std::vector<std::pair<std::string, std::string>> members_;
};

}  // namespace dualcell
