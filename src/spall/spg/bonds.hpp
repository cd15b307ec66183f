#pragma once
// The bonds of SPG particles: for each particle, the particles whose kernel support covers it or
// is covered by it, as compressed rows aligned with everything stored per bond (shape functions,
// broken flags, rest lengths). Bond failure (seed 001 eq. 14, IDAM 1) marks a bond broken for good:
// its flag survives every rebuild of the rows, so a broken bond never re-forms.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/spg/parallel.hpp"

namespace spall::spg {

struct BondList {
  // Row i holds the bonds of particle i: neighbour[offsets[i] .. offsets[i+1]), ascending.
  std::vector<Index> offsets;
  std::vector<Index> neighbour;
  // mirror[k] is the position of the same bond in the other particle's row: for k in row i with
  // neighbour j, neighbour[mirror[k]] == i and mirror[k] lies in row j.
  std::vector<Index> mirror;
  std::vector<std::uint8_t> broken;  // 1 once the bond has failed
  std::vector<Real> rest_length;     // |x_i - x_j| when the bond formed (seed 001 eq. 14's |X_K - X_J|)

  void checkpoint(Archive& a) { a(offsets, neighbour, mirror, broken, rest_length); }

  Index size() const { return offsets.empty() ? 0 : static_cast<Index>(offsets.size()) - 1; }
  Index count(Index i) const { return offsets[i + 1] - offsets[i]; }
  Index broken_count(Index i) const;
};

// A broken bond as the pair (i, j), i < j. A sorted list of them outlives every rebuild of the rows.
using BondPair = std::pair<Index, Index>;

// Bonds from a symmetric neighbour list, keeping only the pairs for which `keep(i, j)` is true (it
// must be symmetric). A pair in `broken_pairs` (sorted) is broken, whether or not the neighbour
// list held it in between; a pair that `previous` held keeps its rest length; a new bond gets the
// distance in x as its rest length.
template <typename Keep>
BondList make_bonds(const neighbors::NeighborList& list, std::span<const Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs);
// The same without the mirrors: for rows that are completed elsewhere (under MPI each rank makes
// the rows of its own particles, and link_mirrors follows once every row is in).
template <typename Keep>
BondList make_bond_rows(const neighbors::NeighborList& list, std::span<const Vec3> x, Keep&& keep,
                        const BondList* previous, std::span<const BondPair> broken_pairs);

// Adds the broken bonds of `bonds` to the sorted list `broken_pairs`.
void record_broken_pairs(const BondList& bonds, std::vector<BondPair>& broken_pairs);

// The bond-failure rule of seed 001 eq. 14: bond K-J breaks when the bond average (q_K + q_J) / 2
// of the particles' failure quantity (IDAM 1: the effective plastic strain; bond_failure.hpp)
// exceeds `critical_value` (FS) and the relative stretch |x_K - x_J| / rest length exceeds
// `critical_stretch` (STRETCH). Both sides of a bond see the same numbers and break together.
// Judged on the rows of the particles [rows.begin, rows.end), breaking nothing: the positions of
// their intact bonds that break now, ascending. It reads those particles' and their partners'
// quantities and positions only (under MPI a rank judges its own particles' rows).
std::vector<Index> bonds_breaking(const BondList& bonds, std::span<const Real> quantity, std::span<const Vec3> x,
                                  Real critical_value, Real critical_stretch, parallel::Range rows);

// Fills mirror from offsets and neighbour (rows ascending, the pattern symmetric).
void link_mirrors(BondList& bonds);

// ---- implementation of the template ----

// The rest length of bond (i, j) in `previous`; found is false when it had no such bond.
Real previous_rest_length(const BondList& previous, Index i, Index j, bool& found);

template <typename Keep>
BondList make_bond_rows(const neighbors::NeighborList& list, std::span<const Vec3> x, Keep&& keep,
                        const BondList* previous, std::span<const BondPair> broken_pairs) {
  const Index n = static_cast<Index>(list.offsets.size()) - 1;
  BondList bonds;
  bonds.offsets.assign(n + 1, 0);
  for (Index i = 0; i < n; ++i) {
    Index c = 0;
    for (Index k = list.offsets[i]; k < list.offsets[i + 1]; ++k) c += keep(i, list.neighbors[k]) ? 1 : 0;
    bonds.offsets[i + 1] = bonds.offsets[i] + c;
  }
  const Index m = bonds.offsets[n];
  bonds.neighbour.resize(m);
  bonds.broken.assign(m, 0);
  bonds.rest_length.resize(m);
  parallel::for_each(n, [&](Index i) {
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
  return bonds;
}

template <typename Keep>
BondList make_bonds(const neighbors::NeighborList& list, std::span<const Vec3> x, Keep&& keep,
                    const BondList* previous, std::span<const BondPair> broken_pairs) {
  BondList bonds = make_bond_rows(list, x, keep, previous, broken_pairs);
  link_mirrors(bonds);
  return bonds;
}

}  // namespace spall::spg
