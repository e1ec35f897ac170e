#include "core/stage.hpp"

#include <cstdio>
#include <exception>
#include <new>

#include "core/error.hpp"

namespace dualcell {

int run_stage(const char* stage, const std::function<void()>& body) {
  try {
    body();
    return exit_ok;
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s: error: %s\n", stage, e.what());
    return exit_input_error;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "%s: error: out of memory\n", stage);
    return exit_internal_error;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s: internal error: %s\n", stage, e.what());
    return exit_internal_error;
  }
}

}  // namespace dualcell
