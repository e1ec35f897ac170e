#pragma once
// XDMF 3 light-data files that point into an HDF5 file, so that ParaView (and meshio) open a
// triangle mesh with its fields. The XDMF references the HDF5 file by its base name, so the
// pair can be moved together.
#include <cstdint>
#include <string>
#include <vector>

namespace dualcell::io {

struct XdmfField {
  std::string name;
  std::string dataset;              // path inside the HDF5 file
  bool on_cells = true;             // Center="Cell" or "Node"
  std::vector<std::uint64_t> dims;  // shape of the dataset
  bool integer = false;
};

struct XdmfGrid {
  std::string name = "mesh";
  std::string nodes_dataset;  // N×2 (GeometryType XY) or N×3 (XYZ)
  std::uint64_t n_nodes = 0;
  int geometry_dim = 2;
  std::string triangles_dataset;  // T×3 (Triangle) or T×6 (Triangle_6), 0-based
  std::uint64_t n_triangles = 0;
  int nodes_per_triangle = 3;
  std::vector<XdmfField> fields;
};

// The text of an XDMF file describing `grids` stored in `h5_name` (base name of the HDF5 file),
// written by the caller's AtomicOutputs beside it.
std::string xdmf_text(const std::string& h5_name, const std::vector<XdmfGrid>& grids);

}  // namespace dualcell::io
