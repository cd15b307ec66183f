#pragma once
// ParaView output: a .vtu file per output time (VTK XML UnstructuredGrid, binary appended data,
// one vertex cell per point, then the cells of any hexahedron or tetrahedron blocks), or under MPI
// a .pvtu that joins the ranks' .vtu pieces, and a .pvd series that lists them with their times.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "spall/core/types.hpp"
#include "spall/discretization/field_set.hpp"

namespace spall::io::output {

// Writes the points as VTK_VERTEX cells (cell i is point i) with `fields` as point data, then the
// cells of `cell_blocks` (connectivity in indices of `points`) with their fields as cell data; a
// cell field is one array over all cells, with the fill value (discretization/field_set.hpp) on
// the cells that do not have it. Through a temporary file. Throws std::invalid_argument for a
// field or block whose size or names do not fit, OutputError (naming the path) when the
// file cannot be written.
void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<discretization::Field>& fields,
               const std::vector<discretization::CellBlock>& cell_blocks = {});

// The .pvtu that makes pieces of one dataset, each a .vtu that write_vtu wrote with these point
// fields and cell blocks (values aside: only names, types and components count), one dataset in
// ParaView: an MPI run's output time, a piece per rank. `pieces` are relative to the .pvtu's
// folder. Through a temporary file; throws OutputError (naming the path) when it cannot be written.
void write_pvtu(const std::filesystem::path& path, const std::vector<std::string>& pieces,
                const std::vector<discretization::Field>& fields,
                const std::vector<discretization::CellBlock>& cell_blocks = {});

class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path path) : path_(std::move(path)) {}
  // Adds a dataset (path relative to the .pvd file) and rewrites the .pvd, so that a series
  // stays openable when a run stops early. Throws OutputError when it cannot be written.
  void add(double time, const std::string& relative_file);

  using Entries = std::vector<std::pair<double, std::string>>;
  const Entries& entries() const { return entries_; }
  // The series as a checkpoint had it, written over the .pvd (a restart drops what was added after).
  void restore(Entries entries);

 private:
  void write() const;

  std::filesystem::path path_;
  Entries entries_;
};

}  // namespace spall::io::output
