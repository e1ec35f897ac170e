#include "io/xdmf.hpp"

#include <sstream>

namespace dualcell::io {

namespace {

std::string dims_text(const std::vector<std::uint64_t>& dims) {
  std::string s;
  for (std::size_t i = 0; i < dims.size(); ++i) {
    if (i) s += ' ';
    s += std::to_string(dims[i]);
  }
  return s;
}

}  // namespace

std::string xdmf_text(const std::string& h5_name, const std::vector<XdmfGrid>& grids) {
  std::ostringstream out;
  out << "<?xml version=\"1.0\" ?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n";
  for (const XdmfGrid& g : grids) {
    out << "    <Grid Name=\"" << g.name << "\" GridType=\"Uniform\">\n"
        << "      <Topology TopologyType=\"" << (g.nodes_per_triangle == 6 ? "Triangle_6" : "Triangle")
        << "\" NumberOfElements=\"" << g.n_triangles << "\">\n"
        << "        <DataItem Dimensions=\"" << g.n_triangles << " " << g.nodes_per_triangle
        << "\" NumberType=\"Int\" Precision=\"8\" "
        << "Format=\"HDF\">" << h5_name << ":" << g.triangles_dataset << "</DataItem>\n"
        << "      </Topology>\n"
        << "      <Geometry GeometryType=\"" << (g.geometry_dim == 2 ? "XY" : "XYZ") << "\">\n"
        << "        <DataItem Dimensions=\"" << g.n_nodes << " " << g.geometry_dim
        << "\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":" << g.nodes_dataset
        << "</DataItem>\n      </Geometry>\n";
    for (const XdmfField& f : g.fields) {
      const bool vector = f.dims.size() == 2 && f.dims[1] > 1;
      const char* type = !vector ? "Scalar" : f.dims[1] == 3 ? "Vector" : f.dims[1] == 6 ? "Tensor6" : "Matrix";
      out << "      <Attribute Name=\"" << f.name << "\" AttributeType=\"" << type << "\" Center=\""
          << (f.on_cells ? "Cell" : "Node") << "\">\n"
          << "        <DataItem Dimensions=\"" << dims_text(f.dims) << "\" NumberType=\""
          << (f.integer ? "Int" : "Float") << "\" Precision=\"8\" Format=\"HDF\">" << h5_name << ":" << f.dataset
          << "</DataItem>\n      </Attribute>\n";
    }
    out << "    </Grid>\n";
  }
  out << "  </Domain>\n</Xdmf>\n";
  return out.str();
}

}  // namespace dualcell::io
