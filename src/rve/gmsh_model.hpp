#pragma once
// The gmsh half of the RVE mesher (rve/mesher.hpp): OpenCASCADE geometry and triangles of a
// periodic rectangle with circular fibres, nothing of the project's types.
//
// It lives in a module of its own, libdualcell-gmsh.so beside the executables, loaded the first
// time an RVE is meshed. libgmsh and the OpenCASCADE and FLTK libraries it needs are built with
// immediate binding: linked into dualcell-mesh, their 155 000 relocations cost every start of the
// stage 0.08 s, a mapped cell's whole mesh stage 0.09 s of which 0.01 s was meshing.
// Request and Result cross the module's boundary; both sides are built by this project with the
// same compiler and library, and no exception crosses it (an error is Result::error).
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace dualcell::rve::gmsh_model {

struct Disk {
  double x = 0, y = 0, radius = 0;
};

struct Request {
  double Lx = 1, Ly = 1;                       // the rectangle [0, Lx] × [0, Ly]
  std::vector<Disk> images;                    // every fibre image that reaches into it
  double size_max = 0, size_min = 0;           // element size bounds
  std::function<double(double, double)> size;  // element size at (x, y), within the bounds
  bool p2 = false;                             // second-order triangles, mid-sides on the curves
};

// One surface of the fragmented geometry: the matrix (image −1) or the part of image `image`
// inside the rectangle; its triangles as rows of 3 or 6 gmsh node tags (corners, then the
// mid-sides of (0,1), (1,2), (2,0)), in one array.
struct Surface {
  int image = -1;
  std::vector<std::size_t> triangles;
};

struct Result {
  std::vector<std::size_t> node_tags;
  std::vector<double> xyz;  // 3 per node tag
  std::vector<Surface> surfaces;
  std::string error;  // empty when meshed
};

// The module's one entry point, `extern "C"` so that dlsym finds it by this name.
using Entry = void (*)(const Request&, Result&);
inline constexpr const char* entry_name = "dualcell_gmsh_mesh";
inline constexpr const char* module_file = "libdualcell-gmsh.so";

// Loads the module (once per process; from the executable's directory) and meshes. A module that
// cannot be loaded is an error of the installation: std::runtime_error naming the file.
Result mesh(const Request& request);

}  // namespace dualcell::rve::gmsh_model
