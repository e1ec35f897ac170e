#include "par/parallel.hpp"

#include <sys/resource.h>

#include <algorithm>
#include <cstdlib>
#include <exception>
#include <vector>

#ifdef DUALCELL_HAVE_MPI
#include <mpi.h>
#endif

namespace dualcell::par {

namespace {

#ifdef DUALCELL_HAVE_MPI
// Launched by an MPI launcher: OpenMPI's mpirun sets OMPI_COMM_WORLD_SIZE, PMIx-based and
// Hydra (MPICH) launchers PMIX_RANK or PMI_RANK. Without one, MPI is not initialised at all:
// a singleton MPI_Init would start a runtime for nothing.
bool launched() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMIX_RANK") || std::getenv("PMI_RANK"); }
bool initialised_here = false;
#endif

}  // namespace

Session::Session() {
#ifdef DUALCELL_HAVE_MPI
  int already = 0;
  MPI_Initialized(&already);
  if (!already && launched()) {
    // OpenMP threads share the subdomain work of a rank, but only the thread that started the
    // stage calls MPI (between parallel regions): MPI_THREAD_FUNNELED, which OpenMPI provides.
    int provided = MPI_THREAD_SINGLE;
    MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided);
    initialised_here = true;
  }
#endif
}

Session::~Session() {
#ifdef DUALCELL_HAVE_MPI
  if (initialised_here) {
    MPI_Finalize();
    initialised_here = false;
  }
#endif
}

int launcher_rank() {
  for (const char* name : {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"})
    if (const char* value = std::getenv(name)) return std::atoi(value);
  return 0;
}

bool built_with_mpi() {
#ifdef DUALCELL_HAVE_MPI
  return true;
#else
  return false;
#endif
}

#ifdef DUALCELL_HAVE_MPI
namespace {
bool active() {
  int on = 0, off = 0;
  MPI_Initialized(&on);
  MPI_Finalized(&off);
  return on && !off;
}
}  // namespace
#endif

int rank() {
#ifdef DUALCELL_HAVE_MPI
  if (active()) {
    int r = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &r);
    return r;
  }
#endif
  return 0;
}

int size() {
#ifdef DUALCELL_HAVE_MPI
  if (active()) {
    int s = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &s);
    return s;
  }
#endif
  return 1;
}

struct SharedCounter::Impl {
#ifdef DUALCELL_HAVE_MPI
  MPI_Win window = MPI_WIN_NULL;
  long* value = nullptr;
#endif
};

SharedCounter::SharedCounter() : impl_(nullptr) {
#ifdef DUALCELL_HAVE_MPI
  if (size() > 1) {
    impl_ = new Impl;
    const MPI_Aint bytes = rank() == 0 ? sizeof(long) : 0;
    MPI_Win_allocate(bytes, sizeof(long), MPI_INFO_NULL, MPI_COMM_WORLD, &impl_->value, &impl_->window);
    if (rank() == 0) {
      MPI_Win_lock(MPI_LOCK_EXCLUSIVE, 0, 0, impl_->window);
      *impl_->value = 0;
      MPI_Win_unlock(0, impl_->window);
    }
    MPI_Barrier(MPI_COMM_WORLD);
  }
#endif
}

SharedCounter::~SharedCounter() {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    // MPI_Win_free is collective: on the way out of an error that this rank alone met, the
    // others would never join it and the rank would wait here instead of reaching run_stage's
    // MPI_Abort. The window goes with the job then.
    if (std::uncaught_exceptions() == 0) MPI_Win_free(&impl_->window);
    delete impl_;
  }
#endif
}

long SharedCounter::next() {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    const long one = 1;
    long previous = 0;
    MPI_Win_lock(MPI_LOCK_SHARED, 0, 0, impl_->window);
    MPI_Fetch_and_op(&one, &previous, MPI_LONG, 0, 0, MPI_SUM, impl_->window);
    MPI_Win_unlock(0, impl_->window);
    return previous;
  }
#endif
  return serial_++;
}

void SharedCounter::serve() const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    int flag = 0;  // a probe only (nothing is ever sent point to point): it runs MPI's progress
    MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
  }
#endif
}

struct Group::Impl {
#ifdef DUALCELL_HAVE_MPI
  MPI_Comm comm = MPI_COMM_NULL;
  bool owned = false;  // from MPI_Comm_split: freed with the last Group that holds it
  ~Impl() {
    int finalised = 0;
    MPI_Finalized(&finalised);
    // Collective like MPI_Win_free (see ~SharedCounter): skipped on the way out of an error.
    if (owned && !finalised && std::uncaught_exceptions() == 0) MPI_Comm_free(&comm);
  }
#endif
};

Group::Group() = default;

Group Group::world() {
  Group g;
#ifdef DUALCELL_HAVE_MPI
  if (par::size() > 1) {
    g.impl_ = std::make_shared<Impl>();
    g.impl_->comm = MPI_COMM_WORLD;
    g.rank_ = par::rank();
    g.size_ = par::size();
  }
#endif
  return g;
}

Group Group::split(int colour) const {
  Group g;
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    MPI_Comm part = MPI_COMM_NULL;
    MPI_Comm_split(impl_->comm, colour, rank_, &part);
    int r = 0, s = 1;
    MPI_Comm_rank(part, &r);
    MPI_Comm_size(part, &s);
    if (s == 1) {
      MPI_Comm_free(&part);
      return g;
    }
    g.impl_ = std::make_shared<Impl>();
    g.impl_->comm = part;
    g.impl_->owned = true;
    g.rank_ = r;
    g.size_ = s;
  }
#else
  (void)colour;
#endif
  return g;
}

void Group::gather(const double* mine, double* all, const std::vector<int>& counts,
                   const std::vector<int>& displs) const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    const bool in_place = mine == all + displs[rank_];
    MPI_Allgatherv(in_place ? MPI_IN_PLACE : mine, counts[rank_], MPI_DOUBLE, all, counts.data(), displs.data(),
                   MPI_DOUBLE, impl_->comm);
    return;
  }
#endif
  if (mine != all + displs[0]) std::copy(mine, mine + counts[0], all + displs[0]);
}

double Group::max(double mine) const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_DOUBLE, MPI_MAX, impl_->comm);
#endif
  return mine;
}

long Group::max(long mine) const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) MPI_Allreduce(MPI_IN_PLACE, &mine, 1, MPI_LONG, MPI_MAX, impl_->comm);
#endif
  return mine;
}

long Group::broadcast(long value, int root) const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) MPI_Bcast(&value, 1, MPI_LONG, root, impl_->comm);
#else
  (void)root;
#endif
  return value;
}

std::vector<double> Group::gather(const std::vector<double>& mine) const {
  std::vector<double> all(mine.size() * size_);
#ifdef DUALCELL_HAVE_MPI
  if (impl_) {
    MPI_Allgather(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), static_cast<int>(mine.size()),
                  MPI_DOUBLE, impl_->comm);
    return all;
  }
#endif
  all = mine;
  return all;
}

void Group::barrier() const {
#ifdef DUALCELL_HAVE_MPI
  if (impl_) MPI_Barrier(impl_->comm);
#endif
}

void barrier() {
#ifdef DUALCELL_HAVE_MPI
  if (size() > 1) MPI_Barrier(MPI_COMM_WORLD);
#endif
}

long sum(long mine) {
#ifdef DUALCELL_HAVE_MPI
  if (size() > 1) {
    long total = 0;
    MPI_Allreduce(&mine, &total, 1, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
    return total;
  }
#endif
  return mine;
}

void agree_on_error(const std::string& mine) {
#ifdef DUALCELL_HAVE_MPI
  if (size() > 1) {
    // The lowest rank with an error, then its message to every rank.
    const int candidate = mine.empty() ? size() : rank();
    int first = size();
    MPI_Allreduce(&candidate, &first, 1, MPI_INT, MPI_MIN, MPI_COMM_WORLD);
    if (first == size()) return;
    int length = rank() == first ? static_cast<int>(mine.size()) : 0;
    MPI_Bcast(&length, 1, MPI_INT, first, MPI_COMM_WORLD);
    std::vector<char> text(mine.begin(), mine.end());
    text.resize(length);
    MPI_Bcast(text.data(), length, MPI_CHAR, first, MPI_COMM_WORLD);
    throw CollectiveInputError(std::string(text.begin(), text.end()));
  }
#endif
  if (!mine.empty()) throw CollectiveInputError(mine);
}

void abort_all(int code) {
#ifdef DUALCELL_HAVE_MPI
  if (size() > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

long peak_rss_bytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss * 1024L;  // Linux: KiB
}

}  // namespace dualcell::par
