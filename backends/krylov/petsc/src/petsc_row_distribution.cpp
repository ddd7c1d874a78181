// PetscRowDistribution (hemivem/petsc_row_distribution.hpp): the check of the processes'
// layouts, the ghost exchange through a PETSc ghosted vector and the MPI collectives.
#include <hemivem/petsc_row_distribution.hpp>

#include <hemivem/error.hpp>

#include <petscvec.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "petsc_support.hpp"

namespace hemivem {

namespace {

using petsc::PetscRuntime;

/// What one process says of its rows, as every process gathers it: its range, its count of all
/// the rows, and the first defect of its ghosts (kind and ghost).
enum GhostDefect : std::int64_t { kGhostsFine = 0, kNotIncreasing = 1, kOutside = 2, kOwnedHere = 3 };
constexpr int kFields = 5;
/// The tag of what the first process sends (send_to).
constexpr int kFromFirstTag = 4242;

std::array<std::int64_t, kFields> describe(const RowLayout& layout) {
  std::array<std::int64_t, kFields> out{static_cast<std::int64_t>(layout.first),
                                        static_cast<std::int64_t>(layout.owned),
                                        static_cast<std::int64_t>(layout.global), kGhostsFine, 0};
  const Eigen::Index end = layout.first + layout.owned;
  for (std::size_t i = 0; i < layout.ghosts.size() && out[3] == kGhostsFine; ++i) {
    const Eigen::Index g = layout.ghosts[i];
    if (i > 0 && g <= layout.ghosts[i - 1])
      out[3] = kNotIncreasing;
    else if (g < 0 || g >= layout.global)
      out[3] = kOutside;
    else if (g >= layout.first && g < end)
      out[3] = kOwnedHere;
    out[4] = static_cast<std::int64_t>(g);
  }
  return out;
}

std::string range(std::int64_t first, std::int64_t owned) {
  return owned > 0 ? std::to_string(first) + ".." + std::to_string(first + owned - 1) : "none (first " +
                                                                                            std::to_string(first) + ")";
}

/// The first defect of the gathered layouts (the same on every process), empty when none.
std::string layout_defect(const std::vector<std::int64_t>& all, int processes) {
  const auto field = [&](int r, int f) { return all[static_cast<std::size_t>(r * kFields + f)]; };
  const std::int64_t global = field(0, 2);
  if (global < 0 || global > std::numeric_limits<PetscInt>::max())
    return "process 0 gives " + std::to_string(global) + " rows in all (PETSc counts at most " +
           std::to_string(std::numeric_limits<PetscInt>::max()) + ")";
  std::int64_t next = 0;
  for (int r = 0; r < processes; ++r) {
    const std::int64_t first = field(r, 0), owned = field(r, 1);
    const std::string who = "process " + std::to_string(r);
    if (field(r, 2) != global)
      return who + " gives " + std::to_string(field(r, 2)) + " rows in all, process 0 " + std::to_string(global);
    if (owned < 0) return who + " owns " + std::to_string(owned) + " rows";
    if (first != next)
      return who + "'s rows " + range(first, owned) + " do not start at row " + std::to_string(next) +
             (r == 0 ? std::string() : ", where process " + std::to_string(r - 1) + "'s end") +
             " (the ranges must be contiguous in the order of the ranks)";
    next = first + owned;
    if (next > global)
      return who + "'s rows " + range(first, owned) + " go beyond the " + std::to_string(global) + " rows in all";
  }
  if (next != global)
    return "the processes own " + std::to_string(next) + " rows of the " + std::to_string(global) + " in all";
  for (int r = 0; r < processes; ++r) {
    const std::string ghost = "process " + std::to_string(r) + "'s ghost " + std::to_string(field(r, 4));
    switch (field(r, 3)) {
      case kNotIncreasing:
        return ghost + " does not follow a smaller one (the ghosts must increase)";
      case kOutside:
        return ghost + " is not one of the " + std::to_string(global) + " rows";
      case kOwnedHere:
        return ghost + " is one of its own rows " + range(field(r, 0), field(r, 1));
      default:
        break;
    }
  }
  return {};
}

}  // namespace

struct PetscRowDistribution::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0;
  int size = 1;
  RowLayout layout;
  Vec ghosted = nullptr;  ///< owned entries, then the ghosts' (VecCreateGhost)

  Impl() { PetscRuntime::instance().attach(); }
  ~Impl() {
    if (ghosted && PetscRuntime::running()) {
      const petsc::QuietErrors quiet;
      VecDestroy(&ghosted);
    }
    PetscRuntime::instance().detach();
  }

  /// The ghosted vector of the layout.
  PetscErrorCode make_ghosted(std::string* error) {
    const std::vector<PetscInt> ghosts(layout.ghosts.begin(), layout.ghosts.end());
    HEMIVEM_PETSC(VecCreateGhost(comm, static_cast<PetscInt>(layout.owned), static_cast<PetscInt>(layout.global),
                                 static_cast<PetscInt>(ghosts.size()), ghosts.data(), &ghosted));
    return 0;
  }

  /// One ghost update of v (whose size fits).
  PetscErrorCode exchange(Eigen::VectorXd& v, std::string* error) const {
    PetscScalar* owned = nullptr;
    HEMIVEM_PETSC(VecGetArray(ghosted, &owned));
    std::copy(v.data(), v.data() + layout.owned, owned);
    HEMIVEM_PETSC(VecRestoreArray(ghosted, &owned));
    HEMIVEM_PETSC(VecGhostUpdateBegin(ghosted, INSERT_VALUES, SCATTER_FORWARD));
    HEMIVEM_PETSC(VecGhostUpdateEnd(ghosted, INSERT_VALUES, SCATTER_FORWARD));
    Vec local = nullptr;
    HEMIVEM_PETSC(VecGhostGetLocalForm(ghosted, &local));
    const PetscScalar* all = nullptr;
    HEMIVEM_PETSC(VecGetArrayRead(local, &all));
    std::copy(all + layout.owned, all + layout.owned + static_cast<Eigen::Index>(layout.ghosts.size()),
              v.data() + layout.owned);
    HEMIVEM_PETSC(VecRestoreArrayRead(local, &all));
    HEMIVEM_PETSC(VecGhostRestoreLocalForm(ghosted, &local));
    return 0;
  }
};

PetscRowDistribution::PetscRowDistribution(RowLayout layout) : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  if (const std::string& why = PetscRuntime::instance().start(); !why.empty())
    throw Error("the distributed rows need PETSc: " + why);
  m.comm = PETSC_COMM_WORLD;
  m.rank = petsc::comm_rank(m.comm);
  m.size = petsc::comm_size(m.comm);
  m.layout = std::move(layout);

  const std::array<std::int64_t, kFields> mine = describe(m.layout);
  std::vector<std::int64_t> all(static_cast<std::size_t>(m.size * kFields));
  MPI_Allgather(mine.data(), kFields, MPI_INT64_T, all.data(), kFields, MPI_INT64_T, m.comm);
  if (const std::string defect = layout_defect(all, m.size); !defect.empty())
    throw InternalError("inconsistent row layout over " + std::to_string(m.size) + " processes: " + defect);

  const petsc::QuietErrors quiet;
  std::string error;
  const std::string failure = petsc::first_problem(m.comm, m.make_ghosted(&error) != 0 ? error : std::string());
  if (!failure.empty()) throw Error("the ghost exchange of the distributed rows: " + failure);
}

PetscRowDistribution::~PetscRowDistribution() = default;

int PetscRowDistribution::rank() const { return impl_->rank; }
int PetscRowDistribution::size() const { return impl_->size; }
const RowLayout& PetscRowDistribution::layout() const { return impl_->layout; }

double PetscRowDistribution::sum(double value) const {
  double out = 0.0;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_SUM, impl_->comm);
  return out;
}

double PetscRowDistribution::max(double value) const {
  double out = 0.0;
  MPI_Allreduce(&value, &out, 1, MPI_DOUBLE, MPI_MAX, impl_->comm);
  return out;
}

void PetscRowDistribution::update_ghosts(Eigen::VectorXd& v) const {
  const Impl& m = *impl_;
  const std::string misfit =
      v.size() == columns() ? std::string()
                            : "update_ghosts() got a vector of " + std::to_string(v.size()) + " entries for " +
                                  std::to_string(m.layout.owned) + " owned rows and " +
                                  std::to_string(m.layout.ghosts.size()) + " ghosts";
  if (const std::string problem = petsc::first_problem(m.comm, misfit); !problem.empty()) throw InternalError(problem);
  const petsc::QuietErrors quiet;
  std::string error;
  if (m.exchange(v, &error) != 0) throw Error("update_ghosts(): " + error);
}

Eigen::VectorXd PetscRowDistribution::all_gather(const Eigen::VectorXd& mine) const {
  const std::vector<double> all = petsc::all_gather(impl_->comm, mine.data(), static_cast<std::int64_t>(mine.size()));
  return Eigen::Map<const Eigen::VectorXd>(all.data(), static_cast<Eigen::Index>(all.size()));
}

Eigen::VectorXd PetscRowDistribution::gather_to_first(const Eigen::VectorXd& mine) const {
  const std::vector<double> all =
      petsc::all_gather(impl_->comm, mine.data(), static_cast<std::int64_t>(mine.size()), true);
  return Eigen::Map<const Eigen::VectorXd>(all.data(), static_cast<Eigen::Index>(all.size()));
}

void PetscRowDistribution::send_to(int to, std::span<const char> bytes) const {
  const Impl& m = *impl_;
  if (m.rank != 0 || to <= 0 || to >= m.size)
    throw InternalError("send_to(" + std::to_string(to) + ") from process " + std::to_string(m.rank) + " of " +
                        std::to_string(m.size));
  if (bytes.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InternalError("a message of " + std::to_string(bytes.size()) + " bytes: more than MPI counts in an int");
  MPI_Send(bytes.data(), static_cast<int>(bytes.size()), MPI_BYTE, to, kFromFirstTag, m.comm);
}

std::vector<char> PetscRowDistribution::receive_from_first() const {
  const Impl& m = *impl_;
  if (m.rank == 0) throw InternalError("receive_from_first() on the first process");
  MPI_Status status;
  MPI_Probe(0, kFromFirstTag, m.comm, &status);
  int count = 0;
  MPI_Get_count(&status, MPI_BYTE, &count);
  std::vector<char> bytes(static_cast<std::size_t>(count));
  MPI_Recv(bytes.data(), count, MPI_BYTE, 0, kFromFirstTag, m.comm, MPI_STATUS_IGNORE);
  return bytes;
}

void PetscRowDistribution::broadcast_from_first(std::vector<char>& bytes) const {
  const Impl& m = *impl_;
  std::uint64_t count = bytes.size();
  MPI_Bcast(&count, 1, MPI_UINT64_T, 0, m.comm);
  if (m.rank != 0) bytes.assign(static_cast<std::size_t>(count), 0);
  constexpr std::uint64_t most = std::numeric_limits<int>::max();
  for (std::uint64_t at = 0; at < count; at += most)
    MPI_Bcast(bytes.data() + at, static_cast<int>(std::min(most, count - at)), MPI_BYTE, 0, m.comm);
}

}  // namespace hemivem
