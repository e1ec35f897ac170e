#pragma once
// The ranks of a run (docs/method.md §16). Launched by mpirun/mpiexec in a build with MPI, a
// stage runs on MPI_COMM_WORLD; otherwise (no launcher, or a build without MPI) it is one rank
// and nothing here communicates, so every command keeps working without MPI and P = 1 is the
// serial program.
//
// Each rank keeps its own data (its scene, mesh, solver); what crosses ranks is said here:
// a shared counter that hands out work items in the order ranks ask for them, a barrier, and
// the agreement on an input error that every rank must see before any work starts.
#include <stdexcept>
#include <string>

#include "core/error.hpp"

namespace dualcell::par {

// MPI_Init when launched by an MPI launcher (and built with MPI); MPI_Finalize on destruction.
// One per process, held by run_stage for the whole stage.
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

bool built_with_mpi();
int rank();  // 0 without MPI
int size();  // 1 without MPI

// A counter at rank 0 that every rank increments atomically (MPI one-sided fetch-and-add):
// next() returns 0, 1, 2, ... across all ranks, each value once, in the order asked. Created
// and destroyed by every rank together (collective).
class SharedCounter {
 public:
  SharedCounter();
  ~SharedCounter();
  SharedCounter(const SharedCounter&) = delete;
  SharedCounter& operator=(const SharedCounter&) = delete;
  long next();

 private:
  struct Impl;
  Impl* impl_;
  long serial_ = 0;
};

void barrier();
// Collective: the sum of `mine` over the ranks, on every rank.
long sum(long mine);

// An input error every rank has seen (agree_on_error): run_stage prints it once, on rank 0,
// and every rank exits with the input-error code.
class CollectiveInputError : public InputError {
 public:
  using InputError::InputError;
};

// Collective: throws CollectiveInputError with the message of the lowest rank whose `mine` is
// not empty, on every rank; returns when every rank's is empty.
void agree_on_error(const std::string& mine);

// Stops every rank with `code` (MPI_Abort; std::exit without MPI).
[[noreturn]] void abort_all(int code);

}  // namespace dualcell::par
