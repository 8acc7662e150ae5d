#pragma once
// Numbers from an HDF5 file another stage wrote (coarse-grained fields, gridded flows): a dataset of
// doubles with its shape, or a numeric attribute. A missing or unreadable item is an InputError
// naming the file and the item, so a wrong or truncated file is reported, never read as garbage.
// (Snapshots and checkpoints, which dem/ writes and reads itself, use their own typed readers.)
#include <hdf5.h>

#include <string>
#include <vector>

namespace grainscale::dem {

/// Dataset `name` of the open `file` (`path` names it in errors) as doubles, row-major; its shape in
/// `dims`. Values are not checked: NaN may mean "no data" in a field file.
std::vector<double> read_hdf5_doubles(hid_t file, const std::string& path, const std::string& name,
                                      std::vector<hsize_t>& dims);

/// The first `n` doubles of attribute `name` of object `object` (a group or dataset path).
std::vector<double> read_hdf5_attribute(hid_t file, const std::string& path, const std::string& object,
                                        const char* name, std::size_t n = 1);

}  // namespace grainscale::dem
