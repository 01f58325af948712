// h5_same A.h5 B.h5 [--ignore NAME]...: whether two HDF5 files hold the same objects with the
// same types, shapes, bytes and attributes, read with the plain HDF5 C API (independently of
// nhc's own reader). NAME is a dataset path (/runs/seconds) or an attribute as PATH@NAME
// (/@wall_seconds). Prints the differences and the number of items compared; exit 0 when the
// files agree, 1 when they differ, 2 on bad arguments or unreadable files.
#include <hdf5.h>

#include <algorithm>
#include <cstring>
#include <iostream>
#include <set>
#include <string>
#include <vector>

namespace {

struct Item {
  std::vector<char> bytes;
  std::vector<hsize_t> dims;
  hid_t type = -1;  // owned
};

std::set<std::string> ignored;
long differences = 0, compared = 0;

void differ(const std::string& what) {
  std::cout << "differs: " << what << "\n";
  ++differences;
}

/// Reads a dataset or attribute as raw bytes of its file type.
Item read_dataset(hid_t file, const std::string& path) {
  Item item;
  const hid_t d = H5Dopen2(file, path.c_str(), H5P_DEFAULT);
  item.type = H5Dget_type(d);
  const hid_t space = H5Dget_space(d);
  item.dims.resize(static_cast<std::size_t>(H5Sget_simple_extent_ndims(space)));
  H5Sget_simple_extent_dims(space, item.dims.data(), nullptr);
  item.bytes.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)) * H5Tget_size(item.type));
  if (!item.bytes.empty()) H5Dread(d, item.type, H5S_ALL, H5S_ALL, H5P_DEFAULT, item.bytes.data());
  H5Sclose(space);
  H5Dclose(d);
  return item;
}

Item read_attribute(hid_t object, const std::string& name) {
  Item item;
  const hid_t a = H5Aopen(object, name.c_str(), H5P_DEFAULT);
  item.type = H5Aget_type(a);
  const hid_t space = H5Aget_space(a);
  item.dims.resize(static_cast<std::size_t>(std::max(0, H5Sget_simple_extent_ndims(space))));
  H5Sget_simple_extent_dims(space, item.dims.data(), nullptr);
  item.bytes.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)) * H5Tget_size(item.type));
  if (!item.bytes.empty()) H5Aread(a, item.type, item.bytes.data());
  H5Sclose(space);
  H5Aclose(a);
  return item;
}

void compare(const std::string& what, Item a, Item b) {
  ++compared;
  if (H5Tequal(a.type, b.type) <= 0) differ(what + " (type)");
  else if (a.dims != b.dims) differ(what + " (shape)");
  else if (a.bytes != b.bytes) differ(what + " (values)");
  H5Tclose(a.type);
  H5Tclose(b.type);
}

std::vector<std::string> attribute_names(hid_t object) {
  std::vector<std::string> names;
  H5Aiterate2(
      object, H5_INDEX_NAME, H5_ITER_INC, nullptr,
      [](hid_t, const char* name, const H5A_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->push_back(name);
        return 0;
      },
      &names);
  return names;
}

std::vector<std::string> object_paths(hid_t file) {
  std::vector<std::string> paths{"/"};
  H5Lvisit(
      file, H5_INDEX_NAME, H5_ITER_INC,
      [](hid_t, const char* name, const H5L_info_t*, void* data) -> herr_t {
        static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
        return 0;
      },
      &paths);
  return paths;
}

void compare_attributes(hid_t fa, hid_t fb, const std::string& path) {
  const hid_t oa = H5Oopen(fa, path.c_str(), H5P_DEFAULT), ob = H5Oopen(fb, path.c_str(), H5P_DEFAULT);
  const std::vector<std::string> na = attribute_names(oa), nb = attribute_names(ob);
  for (const std::string& n : na) {
    const std::string what = path + "@" + n;
    if (ignored.count(what)) continue;
    if (std::find(nb.begin(), nb.end(), n) == nb.end()) {
      differ(what + " (only in the first file)");
      continue;
    }
    compare(what, read_attribute(oa, n), read_attribute(ob, n));
  }
  for (const std::string& n : nb)
    if (!ignored.count(path + "@" + n) && std::find(na.begin(), na.end(), n) == na.end())
      differ(path + "@" + n + " (only in the second file)");
  H5Oclose(oa);
  H5Oclose(ob);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> files;
  for (int k = 1; k < argc; ++k) {
    if (std::strcmp(argv[k], "--ignore") == 0 && k + 1 < argc) ignored.insert(argv[++k]);
    else files.push_back(argv[k]);
  }
  if (files.size() != 2) {
    std::cerr << "usage: h5_same A.h5 B.h5 [--ignore PATH | --ignore PATH@ATTRIBUTE]...\n";
    return 2;
  }
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  const hid_t fa = H5Fopen(files[0].c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t fb = H5Fopen(files[1].c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (fa < 0 || fb < 0) {
    std::cerr << "h5_same: cannot open " << (fa < 0 ? files[0] : files[1]) << " as HDF5\n";
    return 2;
  }
  const std::vector<std::string> pa = object_paths(fa), pb = object_paths(fb);
  for (const std::string& p : pa) {
    if (ignored.count(p)) continue;
    if (std::find(pb.begin(), pb.end(), p) == pb.end()) {
      differ(p + " (only in " + files[0] + ")");
      continue;
    }
    const hid_t o = H5Oopen(fa, p.c_str(), H5P_DEFAULT);
    const bool is_dataset = H5Iget_type(o) == H5I_DATASET;
    H5Oclose(o);
    if (is_dataset) compare(p, read_dataset(fa, p), read_dataset(fb, p));
    compare_attributes(fa, fb, p);
  }
  for (const std::string& p : pb)
    if (!ignored.count(p) && std::find(pa.begin(), pa.end(), p) == pa.end()) differ(p + " (only in " + files[1] + ")");
  H5Fclose(fa);
  H5Fclose(fb);
  std::cout << compared << " datasets and attributes compared, " << differences << " differ\n";
  return differences == 0 ? 0 : 1;
}
