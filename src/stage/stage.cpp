#include "stage/stage.hpp"

#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "core/error.hpp"
#include "core/hash.hpp"
#include "core/memory.hpp"
#include "io/mesh_file.hpp"
#include "par/parallel.hpp"

namespace dualcell {

namespace {

// The message as one printable line of bounded length, whatever it quotes (a key holding a
// newline, a multi-line string, a 1 MB value or path): control characters are escaped, and a
// long message keeps its beginning and its end (where the reason is), cut at UTF-8 boundaries.
std::string one_line(const std::string& text) {
  constexpr std::size_t head = 600, tail = 300;
  std::string out;
  for (const char c : text) {
    const auto u = static_cast<unsigned char>(c);
    if (c == '\n')
      out += "\\n";
    else if (c == '\r')
      out += "\\r";
    else if (c == '\t')
      out += ' ';
    else if (u < 0x20 || u == 0x7F) {
      char hex[8];
      std::snprintf(hex, sizeof hex, "\\x%02X", u);
      out += hex;
    } else
      out += c;
  }
  if (out.size() <= head + tail + 100) return out;
  const auto continuation = [&](std::size_t i) { return (static_cast<unsigned char>(out[i]) & 0xC0) == 0x80; };
  std::size_t a = head, b = out.size() - tail;
  while (a > 0 && continuation(a)) --a;
  while (b < out.size() && continuation(b)) ++b;
  return out.substr(0, a) + " [... " + std::to_string(b - a) + " bytes ...] " + out.substr(b);
}

}  // namespace

int run_stage(const char* stage, const std::function<void()>& body, Ranks sharing) {
  // Under an MPI launcher a stage that shares its work runs on every rank. An error every rank
  // has agreed on (par::agree_on_error) is printed once, by rank 0, and every rank exits
  // normally with its code; an error of one rank alone is printed by that rank, which then
  // stops all (no rank may wait for it for ever). A stage that does not share its work runs
  // on rank 0 as if alone (nothing in it is collective).
  par::Session session;
  if (sharing == Ranks::rank0_only && par::rank() != 0) return exit_ok;
  const bool ranks = sharing == Ranks::share && par::size() > 1;
  const auto fail = [&](int code, const std::string& text) {
    if (ranks) {
      std::fprintf(stderr, "%s: rank %d of %d: %s\n", stage, par::rank(), par::size(), text.c_str());
      std::fflush(stderr);
      par::abort_all(code);
    }
    std::fprintf(stderr, "%s: %s\n", stage, text.c_str());
    return code;
  };
  try {
    body();
    return exit_ok;
  } catch (const par::CollectiveInputError& e) {
    if (par::rank() == 0) std::fprintf(stderr, "%s: error: %s\n", stage, one_line(e.what()).c_str());
    return exit_input_error;
  } catch (const InputError& e) {
    return fail(exit_input_error, "error: " + one_line(e.what()));
  } catch (const std::bad_alloc&) {
    // The stages refuse what their estimates say will not fit before they allocate; what still
    // runs out asked for more than is free here (other processes hold the rest): the input's
    // size, not a fault of the stage.
    return fail(exit_input_error, "error: out of memory: the input needs more than is free of " + memory_bound_text() +
                                      " (fewer cells, elements, rows or points; or more MPI ranks)");
  } catch (const std::exception& e) {
    return fail(exit_internal_error, "internal error: " + one_line(e.what()));
  }
}

namespace stage {

void print_warnings(const char* stage, const Scene& scene) {
  if (par::rank() != 0) return;  // every rank reads the scene; one says so
  for (const auto& w : scene.warnings) std::fprintf(stderr, "%s: warning: %s\n", stage, w.c_str());
}

SceneAndMesh load_scene_and_mesh(const char* stage, const std::string& scene_file, const std::string& mesh_file) {
  SceneAndMesh in;
  in.scene = load_scene(scene_file);
  print_warnings(stage, in.scene);
  in.mesh = io::read_mesh(mesh_file).mesh;
  const std::string mismatch = io::geometry_mismatch(in.mesh, in.scene);
  if (!mismatch.empty())
    throw InputError(mesh_file + ": made from a different scene than " + scene_file + ": " + mismatch);
  in.mesh_file = mesh_file;
  in.mesh_hash = file_hash(mesh_file);
  return in;
}

}  // namespace stage

}  // namespace dualcell
