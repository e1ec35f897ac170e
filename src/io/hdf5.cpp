#include "io/hdf5.hpp"

#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <cstring>
#include <numeric>

#include "core/error.hpp"

namespace dualcell::io {

namespace {

// HDF5 prints its error stack to stderr by default; the project reports one clear line instead.
void silence_hdf5() {
  static const bool silenced = [] {
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
    return true;
  }();
  (void)silenced;
}

hsize_t product(const std::vector<hsize_t>& dims) {
  return std::accumulate(dims.begin(), dims.end(), hsize_t{1}, std::multiplies<>());
}

}  // namespace

std::string shape_text(const Shape& shape) {
  std::string s = "(";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i) s += "×";
    s += shape[i] == any_extent ? "n" : std::to_string(shape[i]);
  }
  return s + ")";
}

Handle& Handle::operator=(Handle&& o) noexcept {
  if (this != &o) {
    if (id_ >= 0 && close_) close_(id_);
    id_ = o.id_;
    close_ = o.close_;
    o.id_ = H5I_INVALID_HID;
  }
  return *this;
}

Handle::~Handle() {
  if (id_ >= 0 && close_) close_(id_);
}

void File::fail(const std::string& object, const std::string& what) const {
  throw InputError(path_.string() + ": " + object + ": " + what);
}

// The memory of a file made by File::create. HDF5's core driver allocates and grows it through
// these callbacks, and on closing the file hands it to image_free, which keeps it: the closed
// file's bytes, its superblock final, without the copy H5Fget_file_image would make.
struct File::Image {
  void* data = nullptr;
  std::size_t allocated = 0;
  bool closed = false;
};

void File::ImageDeleter::operator()(Image* image) const {
  if (image) std::free(image->data);
  delete image;
}

namespace {

void* image_malloc(std::size_t size, H5FD_file_image_op_t, void* udata) {
  auto* image = static_cast<File::Image*>(udata);
  void* p = std::malloc(size);
  if (p) image->allocated = size;
  return p;
}

void* image_memcpy(void* dest, const void* src, std::size_t size, H5FD_file_image_op_t, void*) {
  return std::memcpy(dest, src, size);
}

void* image_realloc(void* ptr, std::size_t size, H5FD_file_image_op_t, void* udata) {
  auto* image = static_cast<File::Image*>(udata);
  void* p = std::realloc(ptr, size);
  if (p) image->allocated = size;
  return p;
}

herr_t image_free(void* ptr, H5FD_file_image_op_t op, void* udata) {
  auto* image = static_cast<File::Image*>(udata);
  if (op != H5FD_FILE_IMAGE_OP_FILE_CLOSE) {
    std::free(ptr);
    return 0;
  }
  if (ptr != image->data) std::free(image->data);  // the last close is the file's
  image->data = ptr;
  image->closed = true;
  return 0;
}

// HDF5 copies the callbacks' user data with every copy of the property list; ours is one Image
// that the File owns, shared by every copy.
void* image_udata_copy(void* udata) { return udata; }
herr_t image_udata_free(void*) { return 0; }

}  // namespace

File::File(Handle file, std::filesystem::path path, std::unique_ptr<Image, ImageDeleter> image)
    : image_(std::move(image)), file_(std::move(file)), path_(std::move(path)) {}

File File::create(const std::filesystem::path& path) {
  silence_hdf5();
  // The 1.8 file format: attributes beyond 64 KiB (a long scene's text) go to dense storage
  // instead of failing, and metadata carry checksums, so corruption is detected on reading.
  // In memory, grown 4 MiB at a time.
  std::unique_ptr<Image, ImageDeleter> image(new Image);
  Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
  H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V18);
  H5Pset_fapl_core(fapl.get(), std::size_t{4} << 20, 0);
  // Closing closes every object of the file at once, so that the memory is handed over then and
  // never later (at library exit, after the File is gone).
  H5Pset_fclose_degree(fapl.get(), H5F_CLOSE_STRONG);
  H5FD_file_image_callbacks_t callbacks{image_malloc,     image_memcpy,     image_realloc, image_free,
                                        image_udata_copy, image_udata_free, image.get()};
  if (H5Pset_file_image_callbacks(fapl.get(), &callbacks) < 0)
    throw InputError(path.string() + ": cannot create HDF5 file in memory");
  // HDF5 first opens the name it is given without creating it (to find a file it has open
  // already), and the core driver would read an existing file of that name into memory: the
  // name given is one that exists nowhere, so that no file on disk is ever touched.
  static std::atomic<long> files{0};
  const std::string name = path.string() + ".in-memory." + std::to_string(::getpid()) + "." + std::to_string(++files);
  Handle f(H5Fcreate(name.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, fapl.get()), H5Fclose);
  if (!f.valid()) throw InputError(path.string() + ": cannot create HDF5 file");
  return File(std::move(f), path, std::move(image));
}

std::string_view File::close_to_image() {
  if (!image_ || !file_.valid()) fail("/", "internal error: not an open file made in memory");
  // Closing hands the driver's memory to image_free. Nothing of the file is open any more
  // (every handle of a read or write is scoped), so the close is complete.
  if (H5Fclose(file_.release()) < 0) fail("/", "internal error: cannot close the HDF5 file in memory");
  // The file ends where its superblock says (HDF5 file format, superblock version 2 at offset 0:
  // version at byte 8, size of offsets at byte 9, base address at bytes 12-19, end-of-file
  // address at bytes 28-35, little-endian); the driver's memory beyond it is allocation slack.
  const auto* bytes = static_cast<const unsigned char*>(image_->data);
  const auto address = [&](int at) {
    std::uint64_t value = 0;
    for (int i = 7; i >= 0; --i) value = value << 8 | bytes[at + i];
    return value;
  };
  if (!image_->closed || !bytes || image_->allocated < 48 || bytes[8] != 2 || bytes[9] != 8 || address(12) != 0)
    fail("/", "internal error: HDF5 left no closed file image of the expected format");
  const std::uint64_t end = address(28);
  if (end < 48 || end > image_->allocated) fail("/", "internal error: HDF5 file image of inconsistent size");
  return {static_cast<const char*>(image_->data), static_cast<std::size_t>(end)};
}

File File::open_read(const std::filesystem::path& path) {
  silence_hdf5();
  std::error_code ec;  // a name too long for the file system is a message, not an exception
  if (!std::filesystem::exists(path, ec)) throw InputError(path.string() + ": file not found");
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path.string() + ": not an HDF5 file (or truncated/corrupt)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose);
  if (!f.valid()) throw InputError(path.string() + ": cannot open HDF5 file (truncated or corrupt?)");
  return File(std::move(f), path);
}

File File::open_write(const std::filesystem::path& path) {
  silence_hdf5();
  if (H5Fis_hdf5(path.c_str()) <= 0) throw InputError(path.string() + ": not an HDF5 file (or truncated/corrupt)");
  Handle f(H5Fopen(path.c_str(), H5F_ACC_RDWR, H5P_DEFAULT), H5Fclose);
  if (!f.valid()) throw InputError(path.string() + ": cannot open HDF5 file for writing");
  return File(std::move(f), path);
}

bool File::exists(const std::string& object) const {
  if (object == "/") return true;
  // Check each prefix: H5Lexists fails on a path whose intermediate group is missing.
  std::size_t pos = 0;
  while ((pos = object.find('/', pos + 1)) != std::string::npos)
    if (H5Lexists(file_.get(), object.substr(0, pos).c_str(), H5P_DEFAULT) <= 0) return false;
  return H5Lexists(file_.get(), object.c_str(), H5P_DEFAULT) > 0;
}

void File::create_group(const std::string& group) {
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle g(H5Gcreate2(file_.get(), group.c_str(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (!g.valid()) fail(group, "cannot create group");
}

void File::remove(const std::string& object) {
  if (exists(object) && H5Ldelete(file_.get(), object.c_str(), H5P_DEFAULT) < 0) fail(object, "cannot delete");
}

namespace {

void write_dataset(hid_t file, const std::string& name, const void* data, hid_t type, const std::vector<hsize_t>& dims,
                   const std::filesystem::path& path) {
  Handle space(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), H5Sclose);
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl.get(), 1);
  Handle set(H5Dcreate2(file, name.c_str(), type, space.get(), lcpl.get(), H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (!set.valid() || H5Dwrite(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    throw InputError(path.string() + ": " + name + ": cannot write dataset");
}

}  // namespace

void File::write(const std::string& name, const std::vector<double>& data, const std::vector<hsize_t>& dims) {
  if (product(dims) != data.size()) fail(name, "internal error: data size does not match shape " + shape_text(dims));
  write_dataset(file_.get(), name, data.data(), H5T_NATIVE_DOUBLE, dims, path_);
}

void File::write(const std::string& name, const std::vector<std::int64_t>& data, const std::vector<hsize_t>& dims) {
  if (product(dims) != data.size()) fail(name, "internal error: data size does not match shape " + shape_text(dims));
  write_dataset(file_.get(), name, data.data(), H5T_NATIVE_INT64, dims, path_);
}

std::vector<hsize_t> File::shape(const std::string& name) const {
  if (!exists(name)) fail(name, "missing dataset");
  Handle set(H5Dopen2(file_.get(), name.c_str(), H5P_DEFAULT), H5Dclose);
  if (!set.valid()) fail(name, "not a dataset (or its header is corrupt)");
  Handle space(H5Dget_space(set.get()), H5Sclose);
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) fail(name, "unreadable dataspace");
  std::vector<hsize_t> dims(rank);
  H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr);
  return dims;
}

namespace {

bool matches(const Shape& found, const Shape& expected) {
  if (found.size() != expected.size()) return false;
  for (std::size_t i = 0; i < found.size(); ++i)
    if (expected[i] != any_extent && expected[i] != found[i]) return false;
  return true;
}

template <typename T>
std::vector<T> read_dataset(const File& file, hid_t fid, const std::string& name, hid_t type, const Shape& expected,
                            const std::string& why, Shape* found, const char* type_name) {
  const Shape dims = file.shape(name);
  Handle set(H5Dopen2(fid, name.c_str(), H5P_DEFAULT), H5Dclose);
  Handle stored(H5Dget_type(set.get()), H5Tclose);
  const H5T_class_t cls = H5Tget_class(stored.get());
  const bool want_float = type == H5T_NATIVE_DOUBLE;
  if ((want_float && cls != H5T_FLOAT && cls != H5T_INTEGER) || (!want_float && cls != H5T_INTEGER))
    throw InputError(file.path().string() + ": " + name + ": expected " + type_name + " data");
  // A corrupt or hostile file may declare a huge shape with nothing stored (reading would fill
  // terabytes with the fill value): unfiltered data must be stored in full, compressed data
  // plausibly (at most 1024:1).
  const hsize_t element = H5Tget_size(stored.get()), storage = H5Dget_storage_size(set.get());
  Handle dcpl(H5Dget_create_plist(set.get()), H5Pclose);
  const hsize_t ratio = H5Pget_nfilters(dcpl.get()) > 0 ? 1024 : 1;
  hsize_t n = 1;
  bool overflow = false;
  for (hsize_t d : dims) overflow |= __builtin_mul_overflow(n, d, &n);
  if (overflow || element == 0 || n > storage / element * ratio)
    throw InputError(file.path().string() + ": " + name + ": declares shape " + shape_text(dims) + " but stores " +
                     std::to_string(storage) + " bytes (truncated or corrupt?)");
  if (!matches(dims, expected))
    throw InputError(file.path().string() + ": " + name + ": expected shape " + shape_text(expected) + why +
                     ", found " + shape_text(dims) + " (truncated or corrupt?)");
  std::vector<T> data(n);
  if (!data.empty() && H5Dread(set.get(), type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw InputError(file.path().string() + ": " + name + ": cannot read dataset (truncated or corrupt?)");
  if (found) *found = dims;
  return data;
}

}  // namespace

std::vector<double> File::read_doubles(const std::string& name, const Shape& expected, const std::string& why,
                                       Shape* found) const {
  return read_dataset<double>(*this, file_.get(), name, H5T_NATIVE_DOUBLE, expected, why, found, "floating-point");
}

std::vector<std::int64_t> File::read_ints(const std::string& name, const Shape& expected, const std::string& why,
                                          Shape* found) const {
  return read_dataset<std::int64_t>(*this, file_.get(), name, H5T_NATIVE_INT64, expected, why, found, "integer");
}

namespace {

void write_attr(hid_t file, const std::string& object, const std::string& name, hid_t type, hid_t space,
                const void* data, const std::filesystem::path& path) {
  if (H5Aexists_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT) > 0)
    H5Adelete_by_name(file, object.c_str(), name.c_str(), H5P_DEFAULT);
  Handle attr(H5Acreate_by_name(file, object.c_str(), name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
              H5Aclose);
  if (!attr.valid() || H5Awrite(attr.get(), type, data) < 0)
    throw InputError(path.string() + ": " + object + ": cannot write attribute " + name);
}

}  // namespace

void File::write_attribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type.get(), value.empty() ? 1 : value.size());
  H5Tset_strpad(type.get(), H5T_STR_NULLPAD);
  H5Tset_cset(type.get(), H5T_CSET_UTF8);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  const char empty = '\0';
  write_attr(file_.get(), object, name, type.get(), space.get(), value.empty() ? &empty : value.data(), path_);
}

void File::write_attribute(const std::string& object, const std::string& name, double value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(file_.get(), object, name, H5T_NATIVE_DOUBLE, space.get(), &value, path_);
}

void File::write_attribute(const std::string& object, const std::string& name, std::int64_t value) {
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  write_attr(file_.get(), object, name, H5T_NATIVE_INT64, space.get(), &value, path_);
}

void File::write_attribute(const std::string& object, const std::string& name, const std::vector<double>& value) {
  const hsize_t n = value.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(file_.get(), object, name, H5T_NATIVE_DOUBLE, space.get(), value.data(), path_);
}

void File::write_attribute(const std::string& object, const std::string& name, const std::vector<std::int64_t>& value) {
  const hsize_t n = value.size();
  Handle space(H5Screate_simple(1, &n, nullptr), H5Sclose);
  write_attr(file_.get(), object, name, H5T_NATIVE_INT64, space.get(), value.data(), path_);
}

bool File::has_attribute(const std::string& object, const std::string& name) const {
  return exists(object) && H5Aexists_by_name(file_.get(), object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

Handle File::open_attribute(const std::string& object, const std::string& name) const {
  if (!has_attribute(object, name)) fail(object, "missing attribute " + name);
  Handle attr(H5Aopen_by_name(file_.get(), object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (!attr.valid()) fail(object, "cannot open attribute " + name);
  return attr;
}

std::string File::read_string_attribute(const std::string& object, const std::string& name) const {
  Handle attr = open_attribute(object, name);
  Handle type(H5Aget_type(attr.get()), H5Tclose);
  if (H5Tget_class(type.get()) != H5T_STRING) fail(object, "attribute " + name + " is not a string");
  if (H5Tis_variable_str(type.get()) > 0) {
    char* text = nullptr;
    Handle memtype(H5Tcopy(H5T_C_S1), H5Tclose);
    H5Tset_size(memtype.get(), H5T_VARIABLE);
    H5Tset_cset(memtype.get(), H5Tget_cset(type.get()));  // h5py writes UTF-8; no conversion exists
    if (H5Aread(attr.get(), memtype.get(), &text) < 0) fail(object, "cannot read attribute " + name);
    std::string value = text ? text : "";
    H5free_memory(text);
    return value;
  }
  const std::size_t size = H5Tget_size(type.get());
  std::string value(size, '\0');
  if (H5Aread(attr.get(), type.get(), value.data()) < 0) fail(object, "cannot read attribute " + name);
  value.resize(value.find('\0') == std::string::npos ? size : value.find('\0'));
  return value;
}

namespace {

template <typename T>
std::vector<T> read_numeric_attribute(const Handle& attr, hid_t type) {
  Handle space(H5Aget_space(attr.get()), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  std::vector<T> value(n > 0 ? n : 0);
  if (!value.empty() && H5Aread(attr.get(), type, value.data()) < 0) value.clear();
  return value;
}

}  // namespace

std::vector<double> File::read_double_attribute(const std::string& object, const std::string& name,
                                                std::size_t count) const {
  Handle attr = open_attribute(object, name);
  auto value = read_numeric_attribute<double>(attr, H5T_NATIVE_DOUBLE);
  if (value.empty()) fail(object, "cannot read numeric attribute " + name);
  if (count > 0 && value.size() != count)
    fail(object, "attribute " + name + ": expected " + std::to_string(count) + (count == 1 ? " value" : " values") +
                     ", found " + std::to_string(value.size()));
  return value;
}

std::vector<std::int64_t> File::read_int_attribute(const std::string& object, const std::string& name,
                                                   std::size_t count) const {
  Handle attr = open_attribute(object, name);
  auto value = read_numeric_attribute<std::int64_t>(attr, H5T_NATIVE_INT64);
  if (value.empty()) fail(object, "cannot read integer attribute " + name);
  if (count > 0 && value.size() != count)
    fail(object, "attribute " + name + ": expected " + std::to_string(count) + (count == 1 ? " value" : " values") +
                     ", found " + std::to_string(value.size()));
  return value;
}

}  // namespace dualcell::io
