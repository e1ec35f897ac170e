#pragma once
// A thin RAII layer over the HDF5 C API: one handle type that closes what it owns, and a File
// with the few typed reads and writes the stages need. Datasets are row-major (C order), as
// h5dump and every HDF5 reader expect. Every read states the shape it expects; a missing or
// mis-shaped object is an InputError naming the file, the object, the shape expected and the
// shape found, so that no format reader checks shapes by hand.
#include <hdf5.h>

#include <cstdint>
#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace dualcell::io {

// Owns one hid_t and closes it with the matching H5*close.
class Handle {
 public:
  Handle() = default;
  Handle(hid_t id, herr_t (*close)(hid_t)) : id_(id), close_(close) {}
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), close_(o.close_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept;
  ~Handle();
  hid_t get() const { return id_; }
  hid_t release() {  // the id, no longer closed by this handle
    const hid_t id = id_;
    id_ = H5I_INVALID_HID;
    return id;
  }
  bool valid() const { return id_ >= 0; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  herr_t (*close_)(hid_t) = nullptr;
};

// A dataset shape: extents, row-major; any_extent matches every length (e.g. {any_extent, 3}).
using Shape = std::vector<hsize_t>;
inline constexpr hsize_t any_extent = ~hsize_t{0};
std::string shape_text(const Shape& shape);  // "(4×3)", "(n×3)" for any_extent

class File {
 public:
  // A new file, built in memory (HDF5's core driver without a backing store): HDF5 never
  // writes to the disk, so a full disk cannot leave it with a half-closed file; close_to_image()
  // hands the bytes to AtomicOutputs, which writes them with every write checked. `path` is
  // where it will be written, named in messages.
  static File create(const std::filesystem::path& path);
  static File open_read(const std::filesystem::path& path);
  static File open_write(const std::filesystem::path& path);  // existing file, read-write

  const std::filesystem::path& path() const { return path_; }
  bool exists(const std::string& object) const;
  void create_group(const std::string& group);  // with intermediate groups
  void remove(const std::string& object);

  // Datasets: `dims` is the shape (1 or 2 entries); data is row-major.
  void write(const std::string& name, const std::vector<double>& data, const std::vector<hsize_t>& dims);
  void write(const std::string& name, const std::vector<std::int64_t>& data, const std::vector<hsize_t>& dims);
  // The whole dataset, checked against `expected` ("<file>: <name>: expected shape (n×3)<why>,
  // found (4×2) (truncated or corrupt?)"); `found`, when given, receives the actual shape.
  std::vector<double> read_doubles(const std::string& name, const Shape& expected, const std::string& why = "",
                                   Shape* found = nullptr) const;
  std::vector<std::int64_t> read_ints(const std::string& name, const Shape& expected, const std::string& why = "",
                                      Shape* found = nullptr) const;
  Shape shape(const std::string& name) const;

  // Attributes on an existing object ("/" for the root).
  void write_attribute(const std::string& object, const std::string& name, const std::string& value);
  void write_attribute(const std::string& object, const std::string& name, double value);
  void write_attribute(const std::string& object, const std::string& name, std::int64_t value);
  void write_attribute(const std::string& object, const std::string& name, const std::vector<double>& value);
  void write_attribute(const std::string& object, const std::string& name, const std::vector<std::int64_t>& value);
  bool has_attribute(const std::string& object, const std::string& name) const;
  std::string read_string_attribute(const std::string& object, const std::string& name) const;
  // Numeric attributes of exactly `count` values (0: one or more), else an InputError
  // "<file>: <object>: attribute <name>: expected 3 values, found 2".
  std::vector<double> read_double_attribute(const std::string& object, const std::string& name,
                                            std::size_t count = 0) const;
  std::vector<std::int64_t> read_int_attribute(const std::string& object, const std::string& name,
                                               std::size_t count = 0) const;
  double read_double_attribute_value(const std::string& object, const std::string& name) const {
    return read_double_attribute(object, name, 1)[0];
  }
  std::int64_t read_int_attribute_value(const std::string& object, const std::string& name) const {
    return read_int_attribute(object, name, 1)[0];
  }

  // Closes a file made by create() and returns its complete bytes (valid while this File lives),
  // for AtomicOutputs to write. Nothing may be read or written afterwards.
  std::string_view close_to_image();

  File(File&&) noexcept = default;
  // No move assignment: it would free the old file's memory before closing the old file.
  File& operator=(File&&) = delete;

  struct Image;  // the core driver's memory, kept when HDF5 closes the file (hdf5.cpp)
  struct ImageDeleter {
    void operator()(Image* image) const;
  };

 private:
  File(Handle file, std::filesystem::path path, std::unique_ptr<Image, ImageDeleter> image = {});
  [[noreturn]] void fail(const std::string& object, const std::string& what) const;
  Handle open_attribute(const std::string& object, const std::string& name) const;
  std::unique_ptr<Image, ImageDeleter> image_;  // declared before file_: destroyed after it
  Handle file_;
  std::filesystem::path path_;
};

}  // namespace dualcell::io
