#pragma once
// The bonds of SPG particles: for each particle, the particles whose kernel support covers it or
// is covered by it, as compressed rows aligned with everything stored per bond (shape functions,
// broken flags, rest lengths). Bond failure (seed 001 eq. 14, IDAM 1) marks a bond broken for good:
// its pair is kept (every rank's alike) and flags it in every rebuild of the rows, so a broken bond
// never re-forms.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/range_array.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/spg/parallel.hpp"

namespace spall::spg {

struct BondList {
  // Row i holds the bonds of particle i: entries offsets[i] .. offsets[i+1], every particle's row
  // counted. The entries' arrays hold the rows of one stretch of particles, indexed by entry as
  // whole arrays would be: every row on one process, under MPI those a rank reads (spg::Part).
  std::vector<Index> offsets;
  RangeArray<Index> neighbour;  // ascending within a row
  // mirror[k] is the position of the same bond in the other particle's row: for k in row i with
  // neighbour j, neighbour[mirror[k]] == i and mirror[k] lies in row j. Of the rows whose
  // partners' rows are held (link_mirrors).
  RangeArray<Index> mirror;
  RangeArray<std::uint8_t> broken;   // 1 once the bond has failed
  RangeArray<Real> rest_length;      // |x_i - x_j| when the bond formed (seed 001 eq. 14's |X_K - X_J|)

  Index size() const { return offsets.empty() ? 0 : static_cast<Index>(offsets.size()) - 1; }
  // Every row's entries together.
  Index entry_count() const { return offsets.empty() ? 0 : offsets.back(); }
  Index count(Index i) const { return offsets[i + 1] - offsets[i]; }
  Index broken_count(Index i) const;
  // The entries of the rows of particles [rows.begin, rows.end).
  parallel::Range entries(parallel::Range rows) const {
    return {offsets[rows.begin], offsets[std::max(rows.begin, rows.end)]};
  }
  // The position of bond (i, j) in row i (held), -1 where the row has no such bond.
  Index find(Index i, Index j) const;
  // From now on the neighbours, flags and rest lengths of the entries [begin, end) are held, those
  // held before keeping their values (the others come in from their ranks).
  void hold(parallel::Range held) {
    neighbour.hold(held.begin, held.end);
    broken.hold(held.begin, held.end);
    rest_length.hold(held.begin, held.end);
  }
};

// A broken bond as the pair (i, j), i < j. A sorted list of them outlives every rebuild of the rows.
using BondPair = std::pair<Index, Index>;

// The lengths of the rows of particles `rows` in the bonds that a symmetric neighbour list gives,
// keeping only the pairs for which `keep(i, j)` is true (it must be symmetric); the other rows 0.
template <typename Keep>
std::vector<Index> bond_row_lengths(const neighbors::NeighborList& list, Keep&& keep, parallel::Range rows);
// Offsets from every row's length.
std::vector<Index> row_offsets(std::span<const Index> length);
// Fills the rows of particles `rows` (offsets set from bond_row_lengths, the arrays holding those
// rows' entries). A pair in `broken_pairs` (sorted) is broken, whether or not the neighbour list
// held it in between; a pair that `previous` held in row i keeps its rest length; a new bond gets
// the distance in x as its rest length.
template <typename Keep>
void fill_bond_rows(BondList& bonds, const neighbors::NeighborList& list, StretchView<Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs, parallel::Range rows);
// Every row's bonds, as one process makes them, with the mirrors linked.
template <typename Keep>
BondList make_bonds(const neighbors::NeighborList& list, StretchView<Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs);

// The bond-failure rule of seed 001 eq. 14: bond K-J breaks when the bond average (q_K + q_J) / 2
// of the particles' failure quantity (IDAM 1: the effective plastic strain; bond_failure.hpp)
// exceeds `critical_value` (FS) and the relative stretch |x_K - x_J| / rest length exceeds
// `critical_stretch` (STRETCH). Both sides of a bond see the same numbers and break together.
// Judged on the rows of the particles [rows.begin, rows.end), breaking nothing: the intact bonds
// that break now, as pairs, sorted, each once. It reads those particles' and their partners'
// quantities and positions only (under MPI a rank judges its own particles' rows).
std::vector<BondPair> bonds_breaking(const BondList& bonds, StretchView<Real> quantity, StretchView<Vec3> x,
                                     Real critical_value, Real critical_stretch, parallel::Range rows);

// Marks the bonds `pairs` (sorted, each in the rows of both its particles) broken in the rows
// held (`held[i]` 1 where row i is, among the particles the view holds; every row where `held` is
// of no particle) and adds them to the sorted list `broken_pairs`.
void break_bonds(BondList& bonds, StretchView<std::uint8_t> held, std::span<const BondPair> pairs,
                 std::vector<BondPair>& broken_pairs);

// Fills mirror for the rows of particles `rows` (their partners' rows held; the pattern symmetric),
// which it holds from now on.
void link_mirrors(BondList& bonds, parallel::Range rows);

// ---- implementation of the templates ----

// The rest length of bond (i, j) in `previous`; found is false when it had no such bond.
Real previous_rest_length(const BondList& previous, Index i, Index j, bool& found);

template <typename Keep>
std::vector<Index> bond_row_lengths(const neighbors::NeighborList& list, Keep&& keep, parallel::Range rows) {
  std::vector<Index> length(list.offsets.size() - 1, 0);
  parallel::for_each(rows, [&](Index i) {
    Index c = 0;
    for (Index k = list.offsets[i]; k < list.offsets[i + 1]; ++k) c += keep(i, list.neighbors[k]) ? 1 : 0;
    length[i] = c;
  }, particle_loops);
  return length;
}

template <typename Keep>
void fill_bond_rows(BondList& bonds, const neighbors::NeighborList& list, StretchView<Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs, parallel::Range rows) {
  parallel::for_each(rows, [&](Index i) {
    Index out = bonds.offsets[i];
    for (Index k = list.offsets[i]; k < list.offsets[i + 1]; ++k) {
      const Index j = list.neighbors[k];
      if (!keep(i, j)) continue;
      bonds.neighbour[out] = j;
      bool found = false;
      const Real rest = previous ? previous_rest_length(*previous, i, j, found) : 0;
      bonds.rest_length[out] = found ? rest : (x[i] - x[j]).norm();
      const BondPair pair = i < j ? BondPair{i, j} : BondPair{j, i};
      bonds.broken[out] = std::binary_search(broken_pairs.begin(), broken_pairs.end(), pair) ? 1 : 0;
      ++out;
    }
  }, particle_loops);
}

template <typename Keep>
BondList make_bonds(const neighbors::NeighborList& list, StretchView<Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs) {
  const parallel::Range every{0, static_cast<Index>(list.offsets.size()) - 1};
  BondList bonds;
  bonds.offsets = row_offsets(bond_row_lengths(list, keep, every));
  bonds.neighbour.assign(bonds.entry_count(), 0);
  bonds.broken.assign(bonds.entry_count(), 0);
  bonds.rest_length.assign(bonds.entry_count(), 0);
  fill_bond_rows(bonds, list, x, keep, previous, broken_pairs, every);
  link_mirrors(bonds, every);
  return bonds;
}

}  // namespace spall::spg
